// Stage 4 of the seed's step (section 2.3): particles against analytic colliders.
//
// Detection and response are the seed's: a particle inside the inflated shape is moved to the
// closest point on its surface (sphere, eq. 5 and 7; finite cylinder without caps, eq. 6 and 8),
// a hard, perfectly inelastic position constraint. Capsules and planes follow the same rule.
// Friction (position-based Coulomb, Macklin et al. 2014, sec. 6.1): the particle's tangential
// displacement over the substep, relative to the collider, is cancelled while it is below
// friction * penetration depth (sticking) and shortened by that much otherwise (sliding).
#pragma once

#include "kernels.h"
#include "simd/float_w.h"
#include "weft/world.h"

namespace weft {

template <class F>
struct Vec3W {
    F x, y, z;
};

template <class F>
inline F dot(const Vec3W<F>& a, const Vec3W<F>& b) {
    return simd::mul_add(a.x, b.x, simd::mul_add(a.y, b.y, a.z * b.z));
}

// Moves the contact target against the tangential motion it would otherwise keep. A sticking lane
// (|tangent| <= friction * penetration, compared squared) cancels its whole tangent; only a group
// with a sliding contact pays the square root and division of the shortening (most contacts stick
// once the cloth rests, and the divider is this pass's bottleneck).
template <class F, class Mask>
inline void apply_friction(Vec3W<F>& target, const Vec3W<F>& previous, const Vec3W<F>& normal,
                           F penetration, Mask contact, const ColliderKernelArgs& c) {
    using namespace simd;
    const Vec3W<F> disp{target.x - previous.x - splat(c.motion.x, F{}),
                        target.y - previous.y - splat(c.motion.y, F{}),
                        target.z - previous.z - splat(c.motion.z, F{})};
    const F normal_part = dot(disp, normal);
    const Vec3W<F> tangent{neg_mul_add(normal_part, normal.x, disp.x),
                           neg_mul_add(normal_part, normal.y, disp.y),
                           neg_mul_add(normal_part, normal.z, disp.z)};
    const F tangent_len2 = dot(tangent, tangent);
    const F limit = splat(c.friction, F{}) * penetration;
    const auto slides = tangent_len2 > limit * limit;  // so tangent_len2 > 0 where it is divided by
    F cancel = splat(1.0f, F{});
    if (any(slides & contact)) cancel = select(slides, limit / sqrt(tangent_len2), cancel);
    target.x = neg_mul_add(cancel, tangent.x, target.x);
    target.y = neg_mul_add(cancel, tangent.y, target.y);
    target.z = neg_mul_add(cancel, tangent.z, target.z);
}

// The response (seed eq. 7 and 8): lanes in contact move to the closest surface point,
// x + n * penetration, then friction; the other lanes keep their position.
template <class F, class Mask>
inline void resolve_contact(const Particles& p, uint32_t i, const Vec3W<F>& x, const Vec3W<F>& n, F penetration,
                            Mask contact, const ColliderKernelArgs& c) {
    using namespace simd;
    Vec3W<F> target{mul_add(n.x, penetration, x.x), mul_add(n.y, penetration, x.y), mul_add(n.z, penetration, x.z)};
    if (c.friction > 0.0f) {
        const Vec3W<F> previous{load(p.previous_x + i, F{}), load(p.previous_y + i, F{}), load(p.previous_z + i, F{})};
        apply_friction(target, previous, n, penetration, contact, c);
    }
    store(p.x + i, select(contact, target.x, x.x));
    store(p.y + i, select(contact, target.y, x.y));
    store(p.z + i, select(contact, target.z, x.z));
}

// Sphere (p0 only), capsule, or finite cylinder (no contact beyond the axis ends, eq. 6).
enum class SegmentShape { sphere, capsule, cylinder };

template <class F, SegmentShape kShape>
void collide_segment(const Particles& particles, const ColliderKernelArgs& collider) {
    using namespace simd;
    // Local copies: the pass's stores cannot alias them, so pointers and constants stay in registers.
    const Particles p = particles;
    const ColliderKernelArgs c = collider;
    const Vec3 axis{c.p1.x - c.p0.x, c.p1.y - c.p0.y, c.p1.z - c.p0.z};
    const float axis_len2 = axis.x * axis.x + axis.y * axis.y + axis.z * axis.z;
    const F inv_axis_len2 = splat(axis_len2 > 0.0f ? 1.0f / axis_len2 : 0.0f, F{});
    const Vec3W<F> p0{splat(c.p0.x, F{}), splat(c.p0.y, F{}), splat(c.p0.z, F{})};
    const Vec3W<F> ax{splat(axis.x, F{}), splat(axis.y, F{}), splat(axis.z, F{})};
    const F radius = splat(c.radius, F{}), radius2 = splat(c.radius * c.radius, F{});
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    const F min_distance2 = splat(1e-18f, F{});
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const Vec3W<F> x{load(p.x + i, F{}), load(p.y + i, F{}), load(p.z + i, F{})};
        const Vec3W<F> rel{x.x - p0.x, x.y - p0.y, x.z - p0.z};
        auto contact = load(p.inverse_mass + i, F{}) > zero;
        Vec3W<F> d = rel;  // from the closest axis point (the centre, for a sphere)
        if constexpr (kShape != SegmentShape::sphere) {
            F t = dot(rel, ax) * inv_axis_len2;
            if constexpr (kShape == SegmentShape::cylinder) {
                contact = contact & (t > zero) & (t < one);
            } else {
                t = max(zero, min(t, one));
            }
            d = {neg_mul_add(t, ax.x, rel.x), neg_mul_add(t, ax.y, rel.y), neg_mul_add(t, ax.z, rel.z)};
        }
        // Inside test on squared distances: no square root for the lanes that miss (most of them).
        const F dist2 = dot(d, d);
        contact = contact & (dist2 < radius2) & (dist2 > min_distance2);
        if (!any(contact)) continue;
        const F dist = sqrt(dist2);
        const F penetration = radius - dist;
        const F inv_dist = one / dist;  // one division, not three
        const Vec3W<F> n{d.x * inv_dist, d.y * inv_dist, d.z * inv_dist};
        resolve_contact(p, i, x, n, penetration, contact, c);
    }
}

// Half-space below a plane through p0 with unit normal, offset by the inflation.
template <class F>
void collide_plane(const Particles& particles, const ColliderKernelArgs& collider) {
    using namespace simd;
    const Particles p = particles;  // local copies, as in collide_segment
    const ColliderKernelArgs c = collider;
    const Vec3W<F> n{splat(c.normal.x, F{}), splat(c.normal.y, F{}), splat(c.normal.z, F{})};
    const Vec3W<F> p0{splat(c.p0.x, F{}), splat(c.p0.y, F{}), splat(c.p0.z, F{})};
    const F offset = splat(c.radius, F{});
    const F zero = splat(0.0f, F{});
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const Vec3W<F> x{load(p.x + i, F{}), load(p.y + i, F{}), load(p.z + i, F{})};
        const Vec3W<F> rel{x.x - p0.x, x.y - p0.y, x.z - p0.z};
        const F penetration = offset - dot(rel, n);
        const auto contact = (load(p.inverse_mass + i, F{}) > zero) & (penetration > zero);
        if (!any(contact)) continue;
        resolve_contact(p, i, x, n, penetration, contact, c);
    }
}

template <class F>
void collide(const Particles& p, const ColliderKernelArgs& c) {
    switch (static_cast<ColliderShape>(c.shape)) {
        case ColliderShape::plane: collide_plane<F>(p, c); break;
        case ColliderShape::cylinder: collide_segment<F, SegmentShape::cylinder>(p, c); break;
        case ColliderShape::sphere: collide_segment<F, SegmentShape::sphere>(p, c); break;
        case ColliderShape::capsule: collide_segment<F, SegmentShape::capsule>(p, c); break;
    }
}

}  // namespace weft
