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

template <class F>
void project_tethers(const Particles& p, const ClothAsset& asset, const TetherBatch& batch, float slack) {
    using namespace simd;
    const uint32_t ia = batch.anchor[0], ib = batch.anchor[1];
    const float ax = p.x[ia], ay = p.y[ia], az = p.z[ia];
    const float bx = p.x[ib], by = p.y[ib], bz = p.z[ib];
    // The spheres' common axis (scalar, once per batch).
    const float abx = bx - ax, aby = by - ay, abz = bz - az;
    const float d2 = abx * abx + aby * aby + abz * abz;
    const float d = std::sqrt(d2);
    const bool has_axis = d > kMinSpringLength_m;
    const float inv_d = has_axis ? 1.0f / d : 0.0f;
    const auto axis_exists = splat(has_axis ? 1.0f : 0.0f, F{}) > splat(0.0f, F{});  // once per batch

    const F Ax = splat(ax, F{}), Ay = splat(ay, F{}), Az = splat(az, F{});
    const F Bx = splat(bx, F{}), By = splat(by, F{}), Bz = splat(bz, F{});
    const F nx = splat(abx * inv_d, F{}), ny = splat(aby * inv_d, F{}), nz = splat(abz * inv_d, F{});
    const F D2 = splat(d2, F{}), half_inv_d = splat(0.5f * inv_d, F{});
    const F scale = splat(1.0f + slack, F{});
    const F zero = splat(0.0f, F{});
    const F min_len = splat(kMinSpringLength_m, F{});
    const float* const rest_a = asset.tether_rest[0] + batch.first_lane;
    const float* const rest_b = asset.tether_rest[1] + batch.first_lane;
    const uint32_t particle0 = batch.particle0, lanes = batch.lane_count;

    for (uint32_t k = 0; k < lanes; k += F::width) {
        const uint32_t i = particle0 + k;
        const F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
        const auto is_free = load(p.inverse_mass + i, F{}) > zero;
        const F ra = load(rest_a + k, F{}) * scale, rb = load(rest_b + k, F{}) * scale;  // +inf: padding

        // Most particles sit inside both balls: nothing to do, and no square root to find out.
        const F dax = x - Ax, day = y - Ay, daz = z - Az;
        const F dbx = x - Bx, dby = y - By, dbz = z - Bz;
        const F la2 = mul_add(dax, dax, mul_add(day, day, daz * daz));
        const F lb2 = mul_add(dbx, dbx, mul_add(dby, dby, dbz * dbz));
        if (!any((la2 > ra * ra) | (lb2 > rb * rb))) continue;

        // Projection onto ball A, and whether it lies in ball B (then it is the answer).
        const OntoBall<F> pa = project_onto_ball(x, y, z, dax, day, daz, la2, ra, Bx, By, Bz, rb);
        F rx = pa.x, ry = pa.y, rz = pa.z;
        if (!all(pa.inside_other)) {
            // Projection onto ball B, and whether it lies in ball A.
            const OntoBall<F> pb = project_onto_ball(x, y, z, dbx, dby, dbz, lb2, rb, Ax, Ay, Az, ra);
            // The circle where the spheres meet: centre A + n t, radius sqrt(r_a^2 - t^2).
            const F t = (D2 + ra * ra - rb * rb) * half_inv_d;
            const F rc2 = neg_mul_add(t, t, ra * ra);
            const F cx = mul_add(nx, t, Ax), cy = mul_add(ny, t, Ay), cz = mul_add(nz, t, Az);
            const F ux = x - cx, uy = y - cy, uz = z - cz;
            const F un = mul_add(ux, nx, mul_add(uy, ny, uz * nz));
            const F vx = neg_mul_add(un, nx, ux), vy = neg_mul_add(un, ny, uy), vz = neg_mul_add(un, nz, uz);
            const F lv = sqrt(mul_add(vx, vx, mul_add(vy, vy, vz * vz)));
            const auto circle_ok = (rc2 > zero) & (lv > min_len) & axis_exists;
            const F sc = sqrt(max(rc2, zero)) / lv;
            const F pcx = mul_add(vx, sc, cx), pcy = mul_add(vy, sc, cy), pcz = mul_add(vz, sc, cz);
            // Balls that only touch (a particle on the straight line between its anchors, e.g. the
            // top edge of a cloth hung by two corners) or no longer meet (anchors pulled apart):
            // the point on the axis that splits the gap in proportion to the lengths.
            const F axis_t = ra * splat(d, F{}) / (ra + rb);
            const F px_axis = mul_add(nx, axis_t, Ax), py_axis = mul_add(ny, axis_t, Ay), pz_axis = mul_add(nz, axis_t, Az);
            const auto a_ok = pa.inside_other, b_ok = pb.inside_other;
            rx = select(a_ok, pa.x, select(b_ok, pb.x, select(circle_ok, pcx, px_axis)));
            ry = select(a_ok, pa.y, select(b_ok, pb.y, select(circle_ok, pcy, py_axis)));
            rz = select(a_ok, pa.z, select(b_ok, pb.z, select(circle_ok, pcz, pz_axis)));
        }
        store(p.x + i, select(is_free, rx, x));
        store(p.y + i, select(is_free, ry, y));
        store(p.z + i, select(is_free, rz, z));
    }
}

}  // namespace weft
