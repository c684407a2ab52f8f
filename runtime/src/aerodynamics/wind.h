// Stage 1 of the seed's step (section 2.3), the fluid part of F_external (eq. 4): wind drag and
// lift per triangle (seed section 1.2, eq. 2 and 3), spread to the triangle's vertices as
// accelerations. Runs only in worlds created with the wind feature.
//
// Triangles on runs (a lattice cloth's quads: corners at constant slot offsets) go eight at a time
// with plain vector loads; the rest eight at a time with gathered corners and the last few one at a
// time, all through the same arithmetic, so the scalar and SIMD paths agree bit for bit (each run
// touches a vertex at most once, and the gathered lanes add their forces in triangle order, so
// every vertex sums its triangles in the same order on both paths).
#pragma once

#include <cstring>

#include "kernels.h"
#include "simd/float_w.h"
#include "triangle_groups.h"

namespace weft {

struct WindArgs {
    Vec3 wind_m_s;              // u, the air's velocity
    float air_density_kg_m3;    // rho
    float drag_coefficient;     // C_D
    float lift_coefficient;     // C_L
    float previous_substep_s;   // velocity is estimated as (x - x_prev) / this (0: at rest)
    float substep_s;            // the substep the force will act over
};

// The acceleration one lane group of triangles gives each of its corners (zero where the triangle
// is degenerate, the air still relative to it, or the lane padding).
template <class F>
inline void triangle_wind(const F (&x)[3], const F (&y)[3], const F (&z)[3], const F (&px)[3], const F (&py)[3],
                          const F (&pz)[3], const F (&w)[3], F weight, F rest_area, const WindArgs& args, F (&ax)[3],
                          F (&ay)[3], F (&az)[3]) {
    using namespace simd;
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{}), third = splat(1.0f / 3.0f, F{});
    const F inv_h = splat(args.previous_substep_s > 0.0f ? 1.0f / args.previous_substep_s : 0.0f, F{});
    // v_relative = v_object - u, the object's velocity estimated from positions (seed 2.3, step 1).
    const F vx = ((x[0] - px[0]) + (x[1] - px[1]) + (x[2] - px[2])) * inv_h * third - splat(args.wind_m_s.x, F{});
    const F vy = ((y[0] - py[0]) + (y[1] - py[1]) + (y[2] - py[2])) * inv_h * third - splat(args.wind_m_s.y, F{});
    const F vz = ((z[0] - pz[0]) + (z[1] - pz[1]) + (z[2] - pz[2])) * inv_h * third - splat(args.wind_m_s.z, F{});
    const F speed2 = mul_add(vx, vx, mul_add(vy, vy, vz * vz));
    const F e1x = x[1] - x[0], e1y = y[1] - y[0], e1z = z[1] - z[0];
    const F e2x = x[2] - x[0], e2y = y[2] - y[0], e2z = z[2] - z[0];
    const F nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;  // |n| = 2 S
    const F twice_area = sqrt(mul_add(nx, nx, mul_add(ny, ny, nz * nz)));
    const F tiny = splat(1e-12f, F{});
    const auto valid = (speed2 > tiny) & (twice_area > tiny) & (weight > zero);
    const F speed = sqrt(speed2);
    const F inv_speed = one / speed, inv_twice_area = one / twice_area;
    const F hx = vx * inv_speed, hy = vy * inv_speed, hz = vz * inv_speed;                  // v_hat
    const F mx = nx * inv_twice_area, my = ny * inv_twice_area, mz = nz * inv_twice_area;  // n_hat
    // S in (2) and (3): the triangle's area, but never more than its rest area (ClothAsset::wind_rest_area).
    const F area = min(splat(0.5f, F{}) * twice_area, rest_area);
    const F half_rho_area_v2 = splat(0.5f * args.air_density_kg_m3, F{}) * area * speed2;
    // theta is the angle between v_relative and the surface: sin(theta) = |n . v_hat|.
    const F n_dot_v = mul_add(mx, hx, mul_add(my, hy, mz * hz));
    // Drag (2): opposite v_relative, 1/2 C_D rho |v|^2 S sin(theta).
    const F drag = splat(-args.drag_coefficient, F{}) * half_rho_area_v2 * abs(n_dot_v);
    // Lift (3): perpendicular to v_relative, towards the downwind side of the surface; the
    // unnormalised direction n_d - (n_d . v_hat) v_hat already has length cos(theta). The side flips
    // when the flow crosses the surface: a ramp over |n . v_hat| < 0.05 keeps the force continuous.
    const F side = max(splat(-1.0f, F{}), min(one, n_dot_v * splat(-20.0f, F{})));
    const F dx = mx * side, dy = my * side, dz = mz * side;
    const F d_dot_v = mul_add(dx, hx, mul_add(dy, hy, dz * hz));
    const F lift = splat(args.lift_coefficient, F{}) * half_rho_area_v2;
    const F fx = mul_add(hx, drag, neg_mul_add(hx, d_dot_v, dx) * lift);
    const F fy = mul_add(hy, drag, neg_mul_add(hy, d_dot_v, dy) * lift);
    const F fz = mul_add(hz, drag, neg_mul_add(hz, d_dot_v, dz) * lift);
    // Stability: the force grows with |v_rel|^2, so an explicit step overshoots once
    // h * d|a|/d|v| = h * 2|a| / |v_rel| exceeds 1 (1.06 for the seed's flag at 40 m/s, dt 0.033 s).
    // Dividing by 1 + that is the linearised implicit (backward-Euler) response: the same force
    // where it is small, never an overshoot where it is not.
    const F w_max = max(w[0], max(w[1], w[2]));
    const F accel = sqrt(mul_add(fx, fx, mul_add(fy, fy, fz * fz))) * third * w_max;
    const F per_vertex = third / mul_add(splat(2.0f * args.substep_s, F{}), accel * inv_speed, one);
    for (int k = 0; k < 3; ++k) {  // keep_if last: an invalid lane's NaN never reaches the arrays
        const F s = per_vertex * w[k];
        ax[k] = keep_if(valid, fx * s);
        ay[k] = keep_if(valid, fy * s);
        az[k] = keep_if(valid, fz * s);
    }
}

// Adds the lane group's corner accelerations (corner k of lane l at slot[k][l]) to the wind arrays.
template <class F>
inline void accumulate_wind(const Particles& p, const uint32_t (&corner)[3], const F (&ax)[3], const F (&ay)[3],
                            const F (&az)[3]) {
    using namespace simd;
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = corner[k];
        store(p.wind_x + i, load(p.wind_x + i, F{}) + ax[k]);
        store(p.wind_y + i, load(p.wind_y + i, F{}) + ay[k]);
        store(p.wind_z + i, load(p.wind_z + i, F{}) + az[k]);
    }
}

// One lane group whose corners k sit at slots corner[k] (+ lane for F wider than one).
template <class F>
inline void wind_lanes(const Particles& p, const uint32_t (&corner)[3], F weight, F rest_area, const WindArgs& args) {
    using namespace simd;
    F x[3], y[3], z[3], px[3], py[3], pz[3], w[3], ax[3], ay[3], az[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = corner[k];
        x[k] = load(p.x + i, F{}), y[k] = load(p.y + i, F{}), z[k] = load(p.z + i, F{});
        px[k] = load(p.previous_x + i, F{}), py[k] = load(p.previous_y + i, F{}), pz[k] = load(p.previous_z + i, F{});
        w[k] = load(p.inverse_mass + i, F{});
    }
    triangle_wind(x, y, z, px, py, pz, w, weight, rest_area, args, ax, ay, az);
    accumulate_wind(p, corner, ax, ay, az);
}

// F::width triangles (3 slots each at `triangle`) with gathered corners. The accelerations are
// added lane by lane, corner by corner, in triangle order: the order the one-at-a-time path adds
// them in, so both give the same sums bit for bit (lanes may share a vertex).
template <class F>
inline void wind_gathered(const Particles& p, const uint32_t* triangle, const float* rest_area, const WindArgs& args) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    uint32_t corner[3][W];
    for (uint32_t l = 0; l < W; ++l)
        for (int k = 0; k < 3; ++k) corner[k][l] = triangle[3 * l + uint32_t(k)];
    F x[3], y[3], z[3], px[3], py[3], pz[3], w[3], ax[3], ay[3], az[3];
    for (int k = 0; k < 3; ++k) {
        x[k] = gather(p.x, corner[k], F{}), y[k] = gather(p.y, corner[k], F{}), z[k] = gather(p.z, corner[k], F{});
        px[k] = gather(p.previous_x, corner[k], F{}), py[k] = gather(p.previous_y, corner[k], F{});
        pz[k] = gather(p.previous_z, corner[k], F{}), w[k] = gather(p.inverse_mass, corner[k], F{});
    }
    triangle_wind(x, y, z, px, py, pz, w, splat(1.0f, F{}), load(rest_area, F{}), args, ax, ay, az);
    float fx[3][W], fy[3][W], fz[3][W];
    for (int k = 0; k < 3; ++k) store(fx[k], ax[k]), store(fy[k], ay[k]), store(fz[k], az[k]);
    for (uint32_t l = 0; l < W; ++l)
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = corner[k][l];
            p.wind_x[i] += fx[k][l];
            p.wind_y[i] += fy[k][l];
            p.wind_z[i] += fz[k][l];
        }
}

// Fills p.wind_{x,y,z} for every slot (zero where no triangle pushes).
template <class F>
void apply_wind(const Particles& p, const ClothAsset& a, const WindArgs& args) {
    const size_t bytes = sizeof(float) * p.slot_count;
    std::memset(p.wind_x, 0, bytes);
    std::memset(p.wind_y, 0, bytes);
    std::memset(p.wind_z, 0, bytes);
    const float* const rest_area = a.wind_rest_area + a.wind_lane_count - a.wind_run_triangles;  // by triangle
    for_each_triangle_group<F>(
        a,
        [&](const uint32_t (&corner)[3], uint32_t lane) {
            wind_lanes<F>(p, corner, simd::load(a.wind_lane_weight + lane, F{}), simd::load(a.wind_rest_area + lane, F{}),
                          args);
        },
        [&](uint32_t t) { wind_gathered<F>(p, a.triangles + 3 * t, rest_area + t, args); },
        [&](const uint32_t (&corner)[3], uint32_t t) {
            wind_lanes<simd::Float1>(p, corner, simd::Float1{1.0f}, simd::Float1{rest_area[t]}, args);
        });
}

}  // namespace weft
