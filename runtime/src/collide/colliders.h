// Stage 4 of the seed's step (section 2.3): particles against analytic colliders.
//
// Detection and response are the seed's: a particle inside the inflated shape is moved to the
// closest point on its surface (sphere, eq. 5 and 7; finite cylinder without caps, eq. 6 and 8),
// a hard, perfectly inelastic position constraint. Capsules and planes follow the same rule.
// Friction (position-based Coulomb, Macklin et al. 2014, sec. 6.1): the particle's tangential
// displacement over the substep, relative to the collider, is cancelled while it is below
// friction * penetration depth (sticking) and shortened by that much otherwise (sliding).
#pragma once

#include <algorithm>
#include <limits>

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

// Friction's inputs that need no normal: the particle's displacement over the substep relative to
// the collider, e = x - (x_previous + motion), and |e|^2. Computed beside the normal's square root
// and division instead of after them (the pass is bound by that chain's latency, not by its count).
template <class F>
struct RelativeMotion {
    Vec3W<F> start;  // x_previous + motion: where a sticking particle stays (tangentially)
    Vec3W<F> e;      // x - start
    F e2;            // |e|^2
};
// The same with each lane's own collider motion (a body's surface moves differently at each contact).
template <class F>
inline RelativeMotion<F> relative_motion(const Particles& p, uint32_t i, const Vec3W<F>& x, const Vec3W<F>& motion) {
    using namespace simd;
    const Vec3W<F> start{load(p.previous_x + i, F{}) + motion.x, load(p.previous_y + i, F{}) + motion.y,
                         load(p.previous_z + i, F{}) + motion.z};
    const Vec3W<F> e{x.x - start.x, x.y - start.y, x.z - start.z};
    return {start, e, dot(e, e)};
}
template <class F>
inline RelativeMotion<F> relative_motion(const Particles& p, uint32_t i, const Vec3W<F>& x, const ColliderKernelArgs& c) {
    using namespace simd;
    return relative_motion(p, i, x, Vec3W<F>{splat(c.motion.x, F{}), splat(c.motion.y, F{}), splat(c.motion.z, F{})});
}

// The response with friction, given the unit normal n, the penetration and e's normal part
// e_n = n . e. The target x + n * penetration moved by e's tangent t = e - e_n n: a sticking lane
// (|t| <= friction * penetration, compared squared as |e|^2 - e_n^2) loses all of it and lands on
//   start + n * (penetration + e_n),
// a sliding lane keeps (1 - friction * penetration / |t|) of it; only a group with a sliding lane
// pays that square root and division (most contacts stick once the cloth rests).
template <class F, class Mask>
inline void respond_with_friction(const Particles& p, uint32_t i, const Vec3W<F>& x, const Vec3W<F>& n,
                                  F penetration, const RelativeMotion<F>& m, F e_n, Mask contact,
                                  const ColliderKernelArgs& c) {
    using namespace simd;
    const F limit = splat(c.friction, F{}) * penetration;
    const auto slides = neg_mul_add(e_n, e_n, m.e2) > limit * limit;
    const F along = penetration + e_n;
    Vec3W<F> r{mul_add(n.x, along, m.start.x), mul_add(n.y, along, m.start.y), mul_add(n.z, along, m.start.z)};
    if (any(slides & contact)) {
        const Vec3W<F> t{neg_mul_add(e_n, n.x, m.e.x), neg_mul_add(e_n, n.y, m.e.y), neg_mul_add(e_n, n.z, m.e.z)};
        const F keep = splat(1.0f, F{}) - limit / sqrt(dot(t, t));  // |t| > limit > 0 on sliding lanes
        r = {select(slides, mul_add(keep, t.x, r.x), r.x), select(slides, mul_add(keep, t.y, r.y), r.y),
             select(slides, mul_add(keep, t.z, r.z), r.z)};
    }
    store(p.x + i, select(contact, r.x, x.x));
    store(p.y + i, select(contact, r.y, x.y));
    store(p.z + i, select(contact, r.z, x.z));
}

// The response (seed eq. 7 and 8): lanes in contact move to the closest surface point,
// x + n * penetration, then friction; the other lanes keep their position.
template <class F, class Mask>
inline void resolve_contact(const Particles& p, uint32_t i, const Vec3W<F>& x, const Vec3W<F>& n, F penetration,
                            Mask contact, const ColliderKernelArgs& c) {
    using namespace simd;
    if (c.friction > 0.0f) {
        const RelativeMotion<F> m = relative_motion(p, i, x, c);
        respond_with_friction(p, i, x, n, penetration, m, dot(n, m.e), contact, c);
        return;
    }
    store(p.x + i, select(contact, mul_add(n.x, penetration, x.x), x.x));
    store(p.y + i, select(contact, mul_add(n.y, penetration, x.y), x.y));
    store(p.z + i, select(contact, mul_add(n.z, penetration, x.z), x.z));
}

// Sphere (p0 only), capsule, or finite cylinder (no contact beyond the axis ends, eq. 6).
enum class SegmentShape { sphere, capsule, cylinder };

template <class F, SegmentShape kShape, bool kFriction>
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
        // The square root and the division both start from dist2 (1 / dist = dist * (1 / dist^2)),
        // so they overlap instead of waiting on each other.
        const F dist = sqrt(dist2);
        const F inv_dist = dist * (one / dist2);
        const F penetration = radius - dist;
        const Vec3W<F> n{d.x * inv_dist, d.y * inv_dist, d.z * inv_dist};
        if constexpr (kFriction) {
            const RelativeMotion<F> m = relative_motion(p, i, x, c);
            respond_with_friction(p, i, x, n, penetration, m, dot(d, m.e) * inv_dist, contact, c);
        } else {
            resolve_contact(p, i, x, n, penetration, contact, c);
        }
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

template <class F, SegmentShape kShape>
void collide_segment_with(const Particles& p, const ColliderKernelArgs& c) {
    if (c.friction > 0.0f) {
        collide_segment<F, kShape, true>(p, c);
    } else {
        collide_segment<F, kShape, false>(p, c);
    }
}

// The box around the movable particles. Min and max round nothing, so every path finds the same
// box and skips the same colliders.
template <class F>
void particle_bounds(const Particles& p, ParticleBounds* out) {
    using namespace simd;
    const F inf = splat(std::numeric_limits<float>::infinity(), F{}), zero = splat(0.0f, F{});
    const F minus_inf = zero - inf;
    F lo[3] = {inf, inf, inf}, hi[3] = {minus_inf, minus_inf, minus_inf};
    const float* const xyz[3] = {p.x, p.y, p.z};
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const auto movable = load(p.inverse_mass + i, F{}) > zero;
        for (int k = 0; k < 3; ++k) {
            const F v = load(xyz[k] + i, F{});
            lo[k] = min(lo[k], select(movable, v, inf));
            hi[k] = max(hi[k], select(movable, v, minus_inf));
        }
    }
    float l[3][F::width], h[3][F::width];
    for (int k = 0; k < 3; ++k) store(l[k], lo[k]), store(h[k], hi[k]);
    float box[2][3];
    for (int k = 0; k < 3; ++k) {
        box[0][k] = l[k][0], box[1][k] = h[k][0];
        for (uint32_t j = 1; j < F::width; ++j)
            box[0][k] = std::min(box[0][k], l[k][j]), box[1][k] = std::max(box[1][k], h[k][j]);
    }
    *out = {{box[0][0], box[0][1], box[0][2]}, {box[1][0], box[1][1], box[1][2]}};
}

// False when no particle inside `box` can touch the collider (its inflated shape's box, 1 mm wider
// against rounding, misses it): the kernel would move none, so skipping it changes no bit.
inline bool collider_may_touch(const ParticleBounds& box, const ColliderKernelArgs& c) {
    constexpr float kSlack_m = 1e-3f;
    const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    if (static_cast<ColliderShape>(c.shape) == ColliderShape::plane) {
        // The box corner deepest below the plane (NaN anywhere: not skipped).
        const float n[3] = {c.normal.x, c.normal.y, c.normal.z}, p0[3] = {c.p0.x, c.p0.y, c.p0.z};
        float height = 0.0f;
        for (int k = 0; k < 3; ++k) height += ((n[k] > 0.0f ? lo[k] : hi[k]) - p0[k]) * n[k];
        return !(height > c.radius + kSlack_m);
    }
    const float a[3] = {c.p0.x, c.p0.y, c.p0.z}, b[3] = {c.p1.x, c.p1.y, c.p1.z};
    const float reach = c.radius + kSlack_m;
    for (int k = 0; k < 3; ++k)
        if (lo[k] > std::max(a[k], b[k]) + reach || hi[k] < std::min(a[k], b[k]) - reach) return false;
    return true;
}

template <class F>
void collide(const Particles& p, const ColliderKernelArgs& c) {
    switch (static_cast<ColliderShape>(c.shape)) {
        case ColliderShape::plane: collide_plane<F>(p, c); break;
        case ColliderShape::cylinder: collide_segment_with<F, SegmentShape::cylinder>(p, c); break;
        case ColliderShape::sphere: collide_segment_with<F, SegmentShape::sphere>(p, c); break;
        case ColliderShape::capsule: collide_segment_with<F, SegmentShape::capsule>(p, c); break;
    }
}

}  // namespace weft
