// Long-range attachments (Kim, Chentanez, Mueller 2012): unilateral maximum distances from each
// free particle to its nearest one or two pinned particles, measured on the rest mesh. They stop
// the stretch that a low iteration budget leaves, at one projection per particle.
//
// With two anchors A and B (lengths r_a, r_b) the particle is projected onto the intersection of
// the balls |x - A| <= r_a and |x - B| <= r_b, exactly, so neither limit is left violated (projecting
// onto one ball after the other would undo the first):
//   - the projection onto ball A, if it lies in ball B (or onto B, if it lies in A);
//   - otherwise the nearest point of the circle where the two spheres meet, or, where they only
//     touch, the point where they touch.
// Anchors are pinned (inverse mass 0), so the whole correction is the particle's.
#pragma once

#include "constraints/distance.h"
#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// The projection of x onto the ball around `centre` (offset d = x - centre, |d|^2 = len2, radius r)
// and whether it lies inside the other ball (within a relative 1e-5).
template <class F>
struct OntoBall {
    F x, y, z;
    decltype(F{} > F{}) inside_other;
};

template <class F>
inline OntoBall<F> project_onto_ball(F x, F y, F z, F dx, F dy, F dz, F len2, F r, F ox, F oy, F oz, F other_r) {
    using namespace simd;
    const F len = sqrt(len2);
    const F s = keep_if((len > r) & (len > splat(kMinSpringLength_m, F{})), (len - r) / len);
    OntoBall<F> out{neg_mul_add(s, dx, x), neg_mul_add(s, dy, y), neg_mul_add(s, dz, z), {}};
    const F qx = out.x - ox, qy = out.y - oy, qz = out.z - oz;
    const F tolerance = other_r * splat(1.0f + 1e-5f, F{});
    out.inside_other = tolerance * tolerance > mul_add(qx, qx, mul_add(qy, qy, qz * qz)) - splat(1e-12f, F{});
    return out;
}

// The two anchors of SIMD-wide lanes and the axis between them (unit n, length d, d^2, 1 / 2d; no
// axis where the anchors coincide).
template <class F>
struct TetherAnchors {
    F ax, ay, az, bx, by, bz, nx, ny, nz, d, d2, half_inv_d;
    decltype(F{} > F{}) axis_exists;
};

// The axis from the anchors' positions: for one batch (F = Float1, once, then splat) or for each
// lane (gathered anchors), with the same operations, so both give the same bits.
template <class F>
void tether_axis(TetherAnchors<F>& an) {
    using namespace simd;
    const F abx = an.bx - an.ax, aby = an.by - an.ay, abz = an.bz - an.az;
    an.d2 = abx * abx + aby * aby + abz * abz;
    an.d = sqrt(an.d2);
    an.axis_exists = an.d > splat(kMinSpringLength_m, F{});
    const F inv_d = keep_if(an.axis_exists, splat(1.0f, F{}) / an.d);  // 0 where the anchors coincide
    an.nx = abx * inv_d, an.ny = aby * inv_d, an.nz = abz * inv_d;
    an.half_inv_d = splat(0.5f, F{}) * inv_d;
}

// Projects lanes [i, i + F::width) (slots) onto their two balls (lengths ra, rb, +inf on padding).
template <class F>
[[gnu::always_inline]] inline void project_tether_lanes(const Particles& p, uint32_t i, F ra, F rb, const TetherAnchors<F>& an) {
    using namespace simd;
    const F zero = splat(0.0f, F{});
    const F min_len = splat(kMinSpringLength_m, F{});
    const F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
    const auto is_free = load(p.inverse_mass + i, F{}) > zero;

    // Most particles sit inside both balls: nothing to do, and no square root to find out.
    const F dax = x - an.ax, day = y - an.ay, daz = z - an.az;
    const F dbx = x - an.bx, dby = y - an.by, dbz = z - an.bz;
    const F la2 = mul_add(dax, dax, mul_add(day, day, daz * daz));
    const F lb2 = mul_add(dbx, dbx, mul_add(dby, dby, dbz * dbz));
    if (!any((la2 > ra * ra) | (lb2 > rb * rb))) return;

    // Projection onto ball A, and whether it lies in ball B (then it is the answer).
    const OntoBall<F> pa = project_onto_ball(x, y, z, dax, day, daz, la2, ra, an.bx, an.by, an.bz, rb);
    F rx = pa.x, ry = pa.y, rz = pa.z;
    if (!all(pa.inside_other)) {
        // Projection onto ball B, and whether it lies in ball A.
        const OntoBall<F> pb = project_onto_ball(x, y, z, dbx, dby, dbz, lb2, rb, an.ax, an.ay, an.az, ra);
        // The circle where the spheres meet: centre A + n t, radius sqrt(r_a^2 - t^2).
        const F t = (an.d2 + ra * ra - rb * rb) * an.half_inv_d;
        const F rc2 = neg_mul_add(t, t, ra * ra);
        const F cx = mul_add(an.nx, t, an.ax), cy = mul_add(an.ny, t, an.ay), cz = mul_add(an.nz, t, an.az);
        const F ux = x - cx, uy = y - cy, uz = z - cz;
        const F un = mul_add(ux, an.nx, mul_add(uy, an.ny, uz * an.nz));
        const F vx = neg_mul_add(un, an.nx, ux), vy = neg_mul_add(un, an.ny, uy), vz = neg_mul_add(un, an.nz, uz);
        const F lv = sqrt(mul_add(vx, vx, mul_add(vy, vy, vz * vz)));
        const auto circle_ok = (rc2 > zero) & (lv > min_len) & an.axis_exists;
        const F sc = sqrt(max(rc2, zero)) / lv;
        const F pcx = mul_add(vx, sc, cx), pcy = mul_add(vy, sc, cy), pcz = mul_add(vz, sc, cz);
        // Balls that only touch (a particle on the straight line between its anchors, e.g. the
        // top edge of a cloth hung by two corners) or no longer meet (anchors pulled apart):
        // the point on the axis that splits the gap in proportion to the lengths.
        const F axis_t = ra * an.d / (ra + rb);
        const F px_axis = mul_add(an.nx, axis_t, an.ax), py_axis = mul_add(an.ny, axis_t, an.ay),
                pz_axis = mul_add(an.nz, axis_t, an.az);
        const auto a_ok = pa.inside_other, b_ok = pb.inside_other;
        rx = select(a_ok, pa.x, select(b_ok, pb.x, select(circle_ok, pcx, px_axis)));
        ry = select(a_ok, pa.y, select(b_ok, pb.y, select(circle_ok, pcy, py_axis)));
        rz = select(a_ok, pa.z, select(b_ok, pb.z, select(circle_ok, pcz, pz_axis)));
    }
    store(p.x + i, select(is_free, rx, x));
    store(p.y + i, select(is_free, ry, y));
    store(p.z + i, select(is_free, rz, z));
}

template <class F>
void project_tethers(const Particles& p, const ClothAsset& asset, const TetherBatch& batch, float slack) {
    using namespace simd;
    const F scale = splat(1.0f + slack, F{});
    const float* const rest_a = asset.tether_rest[0] + batch.first_lane;
    const float* const rest_b = asset.tether_rest[1] + batch.first_lane;
    const uint32_t particle0 = batch.particle0, lanes = batch.lane_count;
    const auto rest = [&](uint32_t k, F* ra, F* rb) {
        *ra = load(rest_a + k, F{}) * scale, *rb = load(rest_b + k, F{}) * scale;  // +inf: padding
    };
    TetherAnchors<F> an;
    if (batch.anchor[0] != kTetherLaneAnchors) {  // one anchor pair for the batch: its axis once
        const uint32_t ia = batch.anchor[0], ib = batch.anchor[1];
        TetherAnchors<Float1> one;
        one.ax = {p.x[ia]}, one.ay = {p.y[ia]}, one.az = {p.z[ia]}, one.bx = {p.x[ib]}, one.by = {p.y[ib]}, one.bz = {p.z[ib]};
        tether_axis(one);
        an = {splat(one.ax.v, F{}), splat(one.ay.v, F{}), splat(one.az.v, F{}), splat(one.bx.v, F{}),
              splat(one.by.v, F{}), splat(one.bz.v, F{}), splat(one.nx.v, F{}), splat(one.ny.v, F{}),
              splat(one.nz.v, F{}), splat(one.d.v, F{}), splat(one.d2.v, F{}), splat(one.half_inv_d.v, F{}),
              splat(one.axis_exists.v ? 1.0f : 0.0f, F{}) > splat(0.0f, F{})};
        for (uint32_t k = 0; k < lanes; k += F::width) {
            F ra, rb;
            rest(k, &ra, &rb);
            project_tether_lanes(p, particle0 + k, ra, rb, an);
        }
        return;
    }
    // Each lane its own anchors (a dressed garment's few body attachments hold particles that lie
    // side by side in slots: one anchor pair per batch left its batches mostly padding).
    const uint32_t* const anchor_a = asset.tether_anchor[0] + batch.first_lane;
    const uint32_t* const anchor_b = asset.tether_anchor[1] + batch.first_lane;
    for (uint32_t k = 0; k < lanes; k += F::width) {
        an.ax = gather_by_loads(p.x, anchor_a + k, F{}), an.ay = gather_by_loads(p.y, anchor_a + k, F{}), an.az = gather_by_loads(p.z, anchor_a + k, F{});
        an.bx = gather_by_loads(p.x, anchor_b + k, F{}), an.by = gather_by_loads(p.y, anchor_b + k, F{}), an.bz = gather_by_loads(p.z, anchor_b + k, F{});
        tether_axis(an);
        F ra, rb;
        rest(k, &ra, &rb);
        project_tether_lanes(p, particle0 + k, ra, rb, an);
    }
}

}  // namespace weft
