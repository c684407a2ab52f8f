// Contact tethers: long-range attachments (Kim, Chentanez, Mueller 2012) not only to pinned
// particles but to whatever holds the cloth at that moment, on the coarse level's nodes.
//
// After each step a node holds when its particle is pinned or in contact with a collider that has
// friction: within kContactReach_m of the inflated surface (twice that for a node that held the
// step before, so that the contact set's edge does not flicker). Every other node keeps an anchor,
// a holding node, and the length of a path to it along the coarse edges (their rest lengths),
// improved by one relaxation over the coarse lanes per step, forward and backward on alternate steps (Bellman-Ford,
// carried from step to step; an anchor that stopped holding is dropped). A recorded length is the
// length of a real path on the rest mesh, so a tether never asks for less than the cloth allows, on
// any mesh and any start pose. During the next step's coarse solves, after the coarse sweep, each
// node is projected into the ball of that radius around its anchor (the anchor itself does not
// move, as a pin would not); the coarse displacement then carries the correction to every particle.
//
// Measured (docs/solver.md): a strict sticking test (tangential motion below 1e-5 to 1e-3 m per
// substep) finds almost no node while the cloth lands, so the tethers never form; straight-line
// lengths from the start pose were no better and are wrong for a draped start pose.
//
// Fixed work: the node slots once per collider and the coarse lanes once, per step; one ball
// projection per node slot per substep. Nothing allocates; the order is fixed (deterministic), and
// the per-step part is the same scalar code on both paths.
#pragma once

#include <cmath>
#include <limits>

#include "kernels.h"
#include "simd/float_w.h"
#include "weft/world.h"

namespace weft {

inline constexpr float kContactReach_m = 0.01f;

// Before the colliders mark: remember who held (bit 1), and pinned nodes hold (bit 0). Padding
// node slots never join a real coarse lane, so what they hold does not matter.
inline void begin_holding_nodes(const Particles& p, const ClothAsset& a, const CoarseState& st) {
    for (uint32_t k = 0; k < a.coarse_slot_count; ++k)
        st.holds[k] = ((st.holds[k] & 1u) << 1) | (p.inverse_mass[st.particle_slot[k]] > 0.0f ? 0u : 1u);
}

// Marks the node slots whose particle touches collider `c` (its inflated surface within the reach;
// a plane is the half-space below p0 with normal p1, as in the collision pass).
inline void mark_contact_nodes(const Particles& p, const ClothAsset& a, const CoarseState& st, const ColliderDesc& c) {
    const ColliderShape shape = c.shape;
    const float axis[3] = {c.p1.x - c.p0.x, c.p1.y - c.p0.y, c.p1.z - c.p0.z};
    const float axis_len2 = shape == ColliderShape::sphere ? 0.0f : axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2];
    const float radius = shape == ColliderShape::plane ? c.inflation_m : c.radius_m + c.inflation_m;
    for (uint32_t k = 0; k < a.coarse_slot_count; ++k) {
        const float reach = radius + ((st.holds[k] & 2u) ? 2.0f * kContactReach_m : kContactReach_m);  // > 0
        const uint32_t s = st.particle_slot[k];
        const float rel[3] = {p.x[s] - c.p0.x, p.y[s] - c.p0.y, p.z[s] - c.p0.z};
        if (shape == ColliderShape::plane) {
            if (rel[0] * c.p1.x + rel[1] * c.p1.y + rel[2] * c.p1.z <= reach) st.holds[k] |= 1u;
        } else {
            float t = 0.0f;
            if (shape != ColliderShape::sphere && axis_len2 > 0.0f) {
                t = (rel[0] * axis[0] + rel[1] * axis[1] + rel[2] * axis[2]) / axis_len2;
                if (shape == ColliderShape::cylinder && !(t > 0.0f && t < 1.0f)) continue;  // no caps
                t = std::fmax(0.0f, std::fmin(t, 1.0f));
            }
            const float d[3] = {rel[0] - t * axis[0], rel[1] - t * axis[1], rel[2] - t * axis[2]};
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= reach * reach) st.holds[k] |= 1u;
        }
    }
}

// After the colliders marked: holding nodes anchor themselves, anchors that stopped holding are
// dropped, then the path lengths are relaxed along the coarse lanes once, `forward` or backward
// (the caller alternates; the field is carried from step to step, so one direction a step is enough).
inline void update_contact_anchors(const ClothAsset& a, const CoarseState& st, bool forward) {
    const float none = std::numeric_limits<float>::infinity();
    for (uint32_t k = 0; k < a.coarse_slot_count; ++k) st.holds[k] &= 1u;
    for (uint32_t k = 0; k < a.coarse_slot_count; ++k) {
        if (st.holds[k]) {
            st.anchor[k] = k;
            st.anchor_rest[k] = 0.0f;
        } else if (!st.holds[st.anchor[k]]) {
            st.anchor[k] = k;
            st.anchor_rest[k] = none;
        }
    }
    auto relax = [&](uint32_t l) {
        if (!(a.coarse_lane_weight[l] > 0.0f)) return;  // padding
        const uint32_t i = a.coarse_index_a[l], j = a.coarse_index_b[l];
        const float r = a.coarse_rest_length[l];
        if (st.anchor_rest[i] + r < st.anchor_rest[j]) {
            st.anchor_rest[j] = st.anchor_rest[i] + r;
            st.anchor[j] = st.anchor[i];
        } else if (st.anchor_rest[j] + r < st.anchor_rest[i]) {
            st.anchor_rest[i] = st.anchor_rest[j] + r;
            st.anchor[i] = st.anchor[j];
        }
    };
    if (forward) {
        for (uint32_t l = 0; l < a.coarse_lane_count; ++l) relax(l);
    } else {
        for (uint32_t l = a.coarse_lane_count; l-- > 0;) relax(l);
    }
}

// The ball projection for the node slots k..k+width, on the coarse solve's positions (after its
// sweep): a free node farther than anchor_rest from its anchor moves onto that sphere.
template <class F>
inline void project_contact_tethers(const ClothAsset& a, const CoarseState& st, uint32_t k) {
    using namespace simd;
    const F x = load(st.x + k, F{}), y = load(st.y + k, F{}), z = load(st.z + k, F{});
    const F ax = gather(st.x, st.anchor + k, F{}), ay = gather(st.y, st.anchor + k, F{}),
            az = gather(st.z, st.anchor + k, F{});
    const F dx = x - ax, dy = y - ay, dz = z - az;
    const F len2 = mul_add(dx, dx, mul_add(dy, dy, dz * dz));
    const F r = load(st.anchor_rest + k, F{});  // +inf: no anchor
    const auto far = (len2 > r * r) & (load(a.coarse_inverse_mass + k, F{}) > splat(0.0f, F{}));
    if (!any(far)) return;
    const F scale = r / sqrt(max(len2, splat(1e-30f, F{})));  // len2 > r^2 on the lanes that use it
    store(st.x + k, select(far, mul_add(dx, scale, ax), x));
    store(st.y + k, select(far, mul_add(dy, scale, ay), y));
    store(st.z + k, select(far, mul_add(dz, scale, az), z));
}

}  // namespace weft
