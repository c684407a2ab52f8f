// Skin constraints (weft/attachments.h: bind_skin_constraints): NvCloth's motion constraints and
// backstop, Jolt's skinned constraints. Each bound particle is projected onto the ball of radius
// max_distance_m around its skinned position (the offset hull's point P at the particle's
// barycentric weights, moved out by its rest offset along the interpolated normal N), then onto
// the half-space (x - P) . N >= -backstop_m behind the hull, and onto their intersection when the
// second projection left the first's ball.
//
// Two passes, as Jolt's SkinVertices / ApplySkinConstraints: once a step, skin_frames finds every
// constraint's P at the previous and the current hull and its N (the only pass that gathers from
// the body); every substep, project_skin interpolates P between the two and projects. Bind keeps
// the constraints in slot order with their own copies of the per-constraint numbers (the bound
// triangle's vertices among them), so both passes read them as vectors. Lanes run across
// constraints (eight at a time on AVX2); the scalar and AVX2 paths do the same IEEE operations
// per particle.
#pragma once

#include <algorithm>
#include <cstdint>

#include "kernels.h"
#include "simd/float_w.h"
#include "weft/attachments.h"

namespace weft {

// The body a cloth's skin constraints follow, this step. Each array is readable 16 bytes past a
// vertex's start (the body's arrays carry that padding for Embree).
struct SkinFrameArgs {
    const float* hull = nullptr;           // [4 * vertices]: the body's offset hull this step (x, y, z, motion)
    const float* previous_hull = nullptr;  // [4 * vertices]: the hull at the previous step; null: previous_point holds it
    const float* normals = nullptr;        // [3 * vertices]: unit vertex normals of this step's hull
};

// Once a step: P at both hulls and N, per constraint (padding lanes included); P at the previous
// hull only when the caller has not kept it from the last step.
template <class F>
void skin_frames(const SkinState& s, const SkinFrameArgs& args) {
    using namespace simd;
    const uint32_t padded = (s.count + kSimdWidth - 1) / kSimdWidth * kSimdWidth;
    for (uint32_t k0 = 0; k0 < padded; k0 += F::width) {
        F before[3] = {splat(0.0f, F{}), splat(0.0f, F{}), splat(0.0f, F{})};
        F now[3] = {before[0], before[1], before[2]};
        F N[3] = {before[0], before[1], before[2]};
        for (int c = 0; c < 3; ++c) {
            const uint32_t* corner = s.corner[c] + k0;
            const F wc = load(s.weight[c] + k0, F{});
            F v[3];
            if (args.previous_hull != nullptr) {
                gather_xyz(args.previous_hull, 4, corner, &v[0], &v[1], &v[2]);
                for (int i = 0; i < 3; ++i) before[i] = mul_add(wc, v[i], before[i]);
            }
            gather_xyz(args.hull, 4, corner, &v[0], &v[1], &v[2]);
            for (int i = 0; i < 3; ++i) now[i] = mul_add(wc, v[i], now[i]);
            gather_xyz(args.normals, 3, corner, &v[0], &v[1], &v[2]);
            for (int i = 0; i < 3; ++i) N[i] = mul_add(wc, v[i], N[i]);
        }
        const F inverse_length = splat(1.0f, F{}) / sqrt(mul_add(N[0], N[0], mul_add(N[1], N[1], N[2] * N[2])));
        for (int i = 0; i < 3; ++i) {
            if (args.previous_hull != nullptr) store(s.previous_point[i] + k0, before[i]);
            store(s.point[i] + k0, now[i]);
            store(s.normal[i] + k0, N[i] * inverse_length);
        }
    }
}

// Every substep: t is how far into the step the substep ends (0..1), the hull's interpolation.
template <class F>
void project_skin(const Particles& p, const SkinState& s, float t_step) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    const F t = splat(t_step, F{});
    for (uint32_t k0 = 0; k0 < s.count; k0 += W) {
        const uint32_t* slot = s.slot + k0;
        F P[3], N[3], x[3];
        for (int i = 0; i < 3; ++i) {
            const F before = load(s.previous_point[i] + k0, F{});
            P[i] = mul_add(t, load(s.point[i] + k0, F{}) - before, before);
            N[i] = load(s.normal[i] + k0, F{});
        }
        // Bound in slot order, most groups are eight consecutive slots: plain loads and stores.
        const bool consecutive = slot[F::width - 1] == slot[0] + (F::width - 1);
        float* const xyz[3] = {p.x, p.y, p.z};
        for (int i = 0; i < 3; ++i)
            x[i] = consecutive ? load(xyz[i] + slot[0], F{}) : gather_by_loads(xyz[i], slot, F{});

        // Max distance: onto the ball around the skinned position S = P + offset N.
        const F r = load(s.max_distance_m + k0, F{}), rest = load(s.rest_offset_m + k0, F{});
        F S[3], d[3];
        for (int i = 0; i < 3; ++i) S[i] = mul_add(rest, N[i], P[i]), d[i] = x[i] - S[i];
        // Compared squared: the square root and division only for a group with a lane outside
        // (a lane inside keeps x either way, so every path writes the same bits).
        const F length2 = mul_add(d[0], d[0], mul_add(d[1], d[1], d[2] * d[2]));
        const auto outside_ball = length2 > r * r;
        if (any(outside_ball)) {
            const F length = sqrt(length2);
            const F shrink = (length - r) / max(length, splat(1e-30f, F{}));
            for (int i = 0; i < 3; ++i) x[i] = select(outside_ball, neg_mul_add(shrink, d[i], x[i]), x[i]);
        }

        // Backstop: in front of the plane backstop_m behind P along N.
        const F height = mul_add(x[0] - P[0], N[0], mul_add(x[1] - P[1], N[1], (x[2] - P[2]) * N[2]));
        const F b = load(s.backstop_m + k0, F{});
        const F depth = splat(0.0f, F{}) - b - height;  // > 0: behind the backstop
        const auto behind = depth > splat(0.0f, F{});
        for (int i = 0; i < 3; ++i) x[i] = select(behind, mul_add(depth, N[i], x[i]), x[i]);

        // Both at once: a particle put on the backstop plane may have left the ball; then it goes
        // to the nearest point of the circle where the plane cuts the ball (centre C, radius rho),
        // which lies in both. A ball wholly behind the plane leaves the backstop's answer. Only a
        // group with a lane behind the backstop pays for it (as the ball above).
        if (any(behind)) {
            const F centre_height = rest + b;  // of S above the plane, along N
            const F rho2 = neg_mul_add(centre_height, centre_height, r * r);
            F e[3];
            for (int i = 0; i < 3; ++i) e[i] = x[i] - neg_mul_add(centre_height, N[i], S[i]);
            const F e2 = mul_add(e[0], e[0], mul_add(e[1], e[1], e[2] * e[2]));
            const auto onto_circle = behind & (e2 > rho2) & (rho2 > splat(0.0f, F{}));
            if (any(onto_circle)) {
                const F to_circle = sqrt(max(rho2, splat(0.0f, F{}))) / sqrt(max(e2, splat(1e-30f, F{})));
                for (int i = 0; i < 3; ++i)
                    x[i] = select(onto_circle, mul_add(e[i], to_circle, neg_mul_add(centre_height, N[i], S[i])), x[i]);
            }
        }

        // Padding lanes repeat the last constraint: the same inputs, so the same bits written twice.
        for (int i = 0; i < 3; ++i) {
            if (consecutive)
                store(xyz[i] + slot[0], x[i]);
            else
                scatter_by_stores(xyz[i], slot, x[i]);
        }
    }
}

}  // namespace weft
