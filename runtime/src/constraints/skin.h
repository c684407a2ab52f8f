// Skin constraints (weft/attachments.h: bind_skin_constraints): NvCloth's motion constraints and
// backstop, Jolt's skinned constraints. Each bound particle is projected onto the ball of radius
// max_distance_m around its skinned position (the offset hull's point P at the particle's
// barycentric weights, moved out by its rest offset along the interpolated normal N), then onto
// the half-space (x - P) . N >= -backstop_m behind the hull, with the body's friction against the
// skin's motion as a collider's for a particle with a max distance (a tee rests on the shoulders
// instead of sliding down them; a free hem brushing a leg slides, or it would follow that leg), and
// onto their intersection when the second projection left the first's ball.
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

// The backstop's friction (Coulomb, as the colliders': collide/colliders.h): the particle's
// displacement over the substep relative to the skin under it, e, loses its tangential part t while
// |t| <= friction * depth (sticking) and |t| shrinks by friction * depth otherwise (sliding). `x`
// is the particle before the backstop moved it `depth` along N, `to` after; the skin moved by
// `motion` over the substep. Only the `held` lanes (behind the backstop, with a max distance).
template <class F, class Mask>
inline void backstop_friction(const F x[3], F to[3], const F previous[3], const F motion[3], const F N[3], F depth,
                              Mask held, float friction) {
    using namespace simd;
    F e[3];
    for (int i = 0; i < 3; ++i) e[i] = x[i] - (previous[i] + motion[i]);
    const F e_n = mul_add(e[0], N[0], mul_add(e[1], N[1], e[2] * N[2]));
    F t[3];
    for (int i = 0; i < 3; ++i) t[i] = neg_mul_add(e_n, N[i], e[i]);
    const F t2 = mul_add(t[0], t[0], mul_add(t[1], t[1], t[2] * t[2]));
    const F limit = splat(friction, F{}) * depth;
    const auto slides = t2 > limit * limit;
    // Sticking lanes lose all of t; sliding lanes limit / |t| of it (|t| > limit >= 0 there).
    F share = splat(1.0f, F{});
    if (any(slides & held)) share = select(slides, limit / sqrt(max(t2, splat(1e-30f, F{}))), share);
    for (int i = 0; i < 3; ++i) to[i] = select(held, neg_mul_add(share, t[i], to[i]), to[i]);
}

// The skin's motion over the substep at P (its point at the substep's end, which moved by
// `motion`), less what the root's carry gave the particles there (R (P0 - pivot) + pivot + shift
// - P0 at the substep's start P0): friction's reference.
template <class F>
inline void skin_motion_less_carry(const SkinProjectArgs& args, const F P[3], F motion[3]) {
    using namespace simd;
    if (!args.carried) return;
    const float* r = args.carry_rotation;
    const float pivot[3] = {args.carry_pivot.x, args.carry_pivot.y, args.carry_pivot.z};
    const float shift[3] = {args.carry_shift.x, args.carry_shift.y, args.carry_shift.z};
    F d[3];
    for (int i = 0; i < 3; ++i) d[i] = (P[i] - motion[i]) - splat(pivot[i], F{});
    for (int i = 0; i < 3; ++i) {
        const F rotated = mul_add(splat(r[3 * i], F{}), d[0], mul_add(splat(r[3 * i + 1], F{}), d[1], splat(r[3 * i + 2], F{}) * d[2]));
        motion[i] = motion[i] - ((rotated - d[i]) + splat(shift[i], F{}));
    }
}

// Every substep, over args.t_start..t_end of the step (the hull's interpolation).
template <class F>
void project_skin(const Particles& p, const SkinState& s, const SkinProjectArgs& args) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    const F t = splat(args.t_end, F{}), span = splat(args.t_end - args.t_start, F{});
    for (uint32_t k0 = 0; k0 < s.count; k0 += W) {
        const uint32_t* slot = s.slot + k0;
        F P[3], N[3], x[3], step_motion[3];
        for (int i = 0; i < 3; ++i) {
            const F before = load(s.previous_point[i] + k0, F{});
            step_motion[i] = load(s.point[i] + k0, F{}) - before;
            P[i] = mul_add(t, step_motion[i], before);
            N[i] = load(s.normal[i] + k0, F{});
        }
        // Bound in slot order, most groups are eight consecutive slots: plain loads and stores.
        const bool consecutive = slot[F::width - 1] == slot[0] + (F::width - 1);
        float* const xyz[3] = {p.x, p.y, p.z};
        float* const previous_xyz[3] = {p.previous_x, p.previous_y, p.previous_z};
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
        F on_plane[3];
        for (int i = 0; i < 3; ++i) on_plane[i] = select(behind, mul_add(depth, N[i], x[i]), x[i]);
        const auto held = behind & (r < splat(kSkinNoMaxDistance_m, F{}));  // free particles slide
        if (args.friction > 0.0f && any(held)) {
            F previous[3], motion[3];
            for (int i = 0; i < 3; ++i) {
                previous[i] = consecutive ? load(previous_xyz[i] + slot[0], F{}) : gather_by_loads(previous_xyz[i], slot, F{});
                motion[i] = span * step_motion[i];
            }
            skin_motion_less_carry(args, P, motion);
            backstop_friction(x, on_plane, previous, motion, N, depth, held, args.friction);
        }
        for (int i = 0; i < 3; ++i) x[i] = on_plane[i];

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
