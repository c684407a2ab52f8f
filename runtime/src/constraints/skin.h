// Skin constraints (weft/attachments.h: bind_skin_constraints): NvCloth's motion constraints and
// backstop, Jolt's skinned constraints. Each bound particle is projected onto the ball of radius
// max_distance_m around its skinned position (the offset hull's point P at the particle's
// barycentric weights, moved out by its rest offset along the interpolated normal N), then onto
// the half-space (x - P) . N >= -backstop_m behind the hull, and onto their intersection when the
// second projection left the first's ball. Lanes run across constraints (eight
// particles at a time on AVX2); every lane's data is gathered by loads and its particle written
// back lane by lane, so the scalar and AVX2 paths do the same IEEE operations per particle.
#pragma once

#include <algorithm>
#include <cstdint>

#include "kernels.h"
#include "weft/attachments.h"
#include "simd/float_w.h"

namespace weft {

// One cloth's skin constraints against one body, this substep.
struct SkinArgs {
    const float* hull = nullptr;           // [4 * vertices]: the body's offset hull this step (x, y, z, motion)
    const float* previous_hull = nullptr;  // [4 * vertices]: the hull at the previous step
    const float* normals = nullptr;        // [3 * vertices]: unit vertex normals of this step's hull
    const uint32_t* body_triangles = nullptr;
    SkinConstraints skin;
    float t = 1.0f;  // how far into the step this substep ends, 0..1 (the hull's interpolation)
};

template <class F>
void project_skin(const Particles& p, const ClothAsset& asset, const SkinArgs& args) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    const SkinConstraints& skin = args.skin;
    const F t = splat(args.t, F{});
    for (uint32_t k0 = 0; k0 < skin.count; k0 += W) {
        const uint32_t lanes = std::min(W, skin.count - k0);
        // The lanes' data; lanes past the end repeat the last constraint (computed, not written).
        uint32_t slot[W], hull_index[3][W], normal_index[3][W];
        alignas(32) float w[3][W], offset[W], radius[W], backstop[W];
        for (uint32_t l = 0; l < W; ++l) {
            const uint32_t k = k0 + std::min(l, lanes - 1);
            slot[l] = asset.slot_of_particle[skin.particle[k]];
            const uint32_t* tri = args.body_triangles + 3 * skin.triangle[k];
            for (int c = 0; c < 3; ++c) {
                hull_index[c][l] = 4 * tri[c];
                normal_index[c][l] = 3 * tri[c];
                w[c][l] = skin.weight[3 * k + c];
            }
            offset[l] = skin.rest_offset_m[k];
            radius[l] = skin.max_distance_m[k];
            backstop[l] = skin.backstop_m[k];
        }
        // P: the hull point at the weights, each corner interpolated from the previous pose (the
        // same operations as follow_attachments). N: the weighted vertex normals, normalised.
        F P[3] = {splat(0.0f, F{}), splat(0.0f, F{}), splat(0.0f, F{})};
        F N[3] = {splat(0.0f, F{}), splat(0.0f, F{}), splat(0.0f, F{})};
        for (int c = 0; c < 3; ++c) {
            const F wc = load(w[c], F{});
            for (int i = 0; i < 3; ++i) {
                const F now = gather_by_loads(args.hull + i, hull_index[c], F{});
                const F before = gather_by_loads(args.previous_hull + i, hull_index[c], F{});
                P[i] = mul_add(wc, mul_add(t, now - before, before), P[i]);
                N[i] = mul_add(wc, gather_by_loads(args.normals + i, normal_index[c], F{}), N[i]);
            }
        }
        const F inverse_length = splat(1.0f, F{}) / sqrt(mul_add(N[0], N[0], mul_add(N[1], N[1], N[2] * N[2])));
        for (F& n : N) n = n * inverse_length;
        F x[3] = {gather_by_loads(p.x, slot, F{}), gather_by_loads(p.y, slot, F{}), gather_by_loads(p.z, slot, F{})};

        // Max distance: onto the ball around the skinned position S = P + offset N.
        const F r = load(radius, F{}), rest = load(offset, F{});
        F S[3], d[3];
        for (int i = 0; i < 3; ++i) S[i] = mul_add(rest, N[i], P[i]), d[i] = x[i] - S[i];
        const F length = sqrt(mul_add(d[0], d[0], mul_add(d[1], d[1], d[2] * d[2])));
        const auto outside_ball = length > r;
        const F shrink = (length - r) / max(length, splat(1e-30f, F{}));
        for (int i = 0; i < 3; ++i) x[i] = select(outside_ball, neg_mul_add(shrink, d[i], x[i]), x[i]);

        // Backstop: in front of the plane backstop_m behind P along N.
        const F height = mul_add(x[0] - P[0], N[0], mul_add(x[1] - P[1], N[1], (x[2] - P[2]) * N[2]));
        const F b = load(backstop, F{});
        const F depth = splat(0.0f, F{}) - b - height;  // > 0: behind the backstop
        const auto behind = depth > splat(0.0f, F{});
        for (int i = 0; i < 3; ++i) x[i] = select(behind, mul_add(depth, N[i], x[i]), x[i]);

        // Both at once: a particle put on the backstop plane may have left the ball; then it goes
        // to the nearest point of the circle where the plane cuts the ball (centre C, radius rho),
        // which lies in both. A ball wholly behind the plane leaves the backstop's answer.
        const F centre_height = rest + b;  // of S above the plane, along N
        const F rho2 = neg_mul_add(centre_height, centre_height, r * r);
        F e[3];
        for (int i = 0; i < 3; ++i) e[i] = x[i] - neg_mul_add(centre_height, N[i], S[i]);
        const F e2 = mul_add(e[0], e[0], mul_add(e[1], e[1], e[2] * e[2]));
        const auto onto_circle = behind & (e2 > rho2) & (rho2 > splat(0.0f, F{}));
        const F to_circle = sqrt(max(rho2, splat(0.0f, F{}))) / sqrt(max(e2, splat(1e-30f, F{})));
        for (int i = 0; i < 3; ++i)
            x[i] = select(onto_circle, mul_add(e[i], to_circle, neg_mul_add(centre_height, N[i], S[i])), x[i]);

        alignas(32) float out[3][W];
        for (int i = 0; i < 3; ++i) store(out[i], x[i]);
        for (uint32_t l = 0; l < lanes; ++l) {
            p.x[slot[l]] = out[0][l];
            p.y[slot[l]] = out[1][l];
            p.z[slot[l]] = out[2][l];
        }
    }
}

}  // namespace weft
