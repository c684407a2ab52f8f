// Stage 2 of the seed's step (section 2.3): position Verlet with damping.
//   x(t+h) = x(t) + (x(t) - x(t-h)) * (h / h_prev) * exp(-damping h) + (g + a_wind) h^2
// The h / h_prev factor keeps the implied velocity right when the frame time changes; exp(-d h)
// makes damping a rate in 1/s, independent of how the budget is split into substeps.
//
// When the cloth has a coarse level, its correction (constraints/coarse.h, solved beforehand on
// the nodes' own Verlet prediction) is added in this same pass: one trip through the particle
// arrays instead of two.
#pragma once

#include <utility>

#include "constraints/coarse.h"
#include "integrate/predict.h"
#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// One lane group at slot i. Lanes below `done_lanes` already hold this pass's result (the group
// overlaps the previous one at a row's end) and are kept: a row's tail costs one more full group
// instead of masked loads and stores (vmaskmovps, measured slower than the whole group here).
template <class F, bool kWind>
inline void integrate_lanes(const Particles& p, const IntegrateArgs& args, uint32_t i, F cx, F cy, F cz,
                            uint32_t done_lanes = 0) {
    using namespace simd;
    const F h2 = splat(args.h2_s2, F{});
    const F velocity_scale = splat(args.velocity_scale, F{});
    F ax = splat(args.gravity.x, F{}), ay = splat(args.gravity.y, F{}), az = splat(args.gravity.z, F{});
    if constexpr (kWind) {
        ax = ax + load(p.wind_x + i, F{});
        ay = ay + load(p.wind_y + i, F{});
        az = az + load(p.wind_z + i, F{});
    }
    const auto is_free = load(p.inverse_mass + i, F{}) > splat(0.0f, F{});  // pinned particles stay put
    const F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
    const F px = load(p.previous_x + i, F{}), py = load(p.previous_y + i, F{}), pz = load(p.previous_z + i, F{});
    F nx = select(is_free, verlet_predict(x, px, ax, velocity_scale, h2) + cx, x);
    F ny = select(is_free, verlet_predict(y, py, ay, velocity_scale, h2) + cy, y);
    F nz = select(is_free, verlet_predict(z, pz, az, velocity_scale, h2) + cz, z);
    if (done_lanes > 0) {
        const auto fresh = lanes_from(done_lanes, F{});
        nx = select(fresh, nx, px);
        ny = select(fresh, ny, py);
        nz = select(fresh, nz, pz);
    }
    // x(t+h) overwrites x(t-h), which is no longer needed; the caller then swaps the two arrays, so
    // x(t) becomes the previous position without being copied (3 stores a lane instead of 6).
    store(p.previous_x + i, nx);
    store(p.previous_y + i, ny);
    store(p.previous_z + i, nz);
}

// No coarse level: a flat pass over slots [first, end), lane groups then single lanes.
template <class F, bool kWind>
void integrate_slots(const Particles& particles, const IntegrateArgs& integrate_args, uint32_t first, uint32_t end) {
    const Particles p = particles;  // local copies: see integrate_with_coarse_lattice
    const IntegrateArgs args = integrate_args;
    const F zero = simd::splat(0.0f, F{});
    uint32_t i = first;
    for (; i + F::width <= end; i += F::width) integrate_lanes<F, kWind>(p, args, i, zero, zero, zero);
    const simd::Float1 zero1{0.0f};
    for (; i < end; ++i) integrate_lanes<simd::Float1, kWind>(p, args, i, zero1, zero1, zero1);
}

// General coarse form: each slot gathers the displacement of its kCoarseWeights nodes.
template <class F, bool kWind>
void integrate_with_coarse_weights(const Particles& particles, const IntegrateArgs& integrate_args,
                                   const ClothAsset& a, const CoarseState& st) {
    using namespace simd;
    const Particles p = particles;  // local copies: see integrate_with_coarse_lattice
    const IntegrateArgs args = integrate_args;
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        F cx = splat(0.0f, F{}), cy = cx, cz = cx;
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            const F w = load(a.coarse_weight[k] + i, F{});
            const uint32_t* node = a.coarse_weight_node[k] + i;
            cx = mul_add(w, gather(st.dx, node, F{}), cx);
            cy = mul_add(w, gather(st.dy, node, F{}), cy);
            cz = mul_add(w, gather(st.dz, node, F{}), cz);
        }
        integrate_lanes<F, kWind>(p, args, i, cx, cy, cz);
    }
}

// Lattice coarse form: plane row by plane row, blending the two coarse rows around it (each
// already interpolated to every plane column) with contiguous loads.
template <class F, bool kWind>
inline void integrate_lattice_lanes(const Particles& p, const IntegrateArgs& args, float* const lower[3],
                                    float* const upper[3], float frac, uint32_t slot, uint32_t c,
                                    uint32_t done_lanes = 0) {
    using namespace simd;
    const F f = splat(frac, F{});
    F d[3];
    for (int axis = 0; axis < 3; ++axis) {
        const F l = load(lower[axis] + c, F{}), u = load(upper[axis] + c, F{});
        d[axis] = mul_add(f, u - l, l);
    }
    integrate_lanes<F, kWind>(p, args, slot, d[0], d[1], d[2], done_lanes);
}

template <class F, bool kWind>
void integrate_with_coarse_lattice(const Particles& particles, const IntegrateArgs& integrate_args,
                                   const ClothAsset& a, const CoarseState& st) {
    // Local copies: the pass's stores cannot alias them, so the array pointers and the constants stay
    // in registers instead of being reloaded after every store.
    const Particles p = particles;
    const IntegrateArgs args = integrate_args;
    const uint32_t rows = a.lattice_plane_rows, cols = a.lattice_plane_cols;
    for (uint32_t column_parity = 0; column_parity < 2; ++column_parity) {
        // Fine rows in order (plane row r of row parity 0, then of parity 1): the coarse rows only
        // grow, so each is interpolated to the plane columns once per column parity.
        float* lower[3] = {st.column_rows[0], st.column_rows[1], st.column_rows[2]};
        float* upper[3] = {st.column_rows[3], st.column_rows[4], st.column_rows[5]};
        uint32_t loaded = ~0u;  // coarse row held in `lower` (loaded + 1 in `upper`)
        for (uint32_t r = 0; r < rows; ++r) {
            for (uint32_t row_parity = 0; row_parity < 2; ++row_parity) {
                const uint32_t coarse_row = a.coarse_row_node[row_parity][r];
                if (loaded != ~0u && coarse_row == loaded + 1) {  // slide the window up one coarse row
                    for (int axis = 0; axis < 3; ++axis) std::swap(lower[axis], upper[axis]);
                    interpolate_coarse_row<F>(a, st, coarse_row + 1, column_parity, upper);
                } else if (coarse_row != loaded) {
                    interpolate_coarse_row<F>(a, st, coarse_row, column_parity, lower);
                    interpolate_coarse_row<F>(a, st, coarse_row + 1, column_parity, upper);
                }
                loaded = coarse_row;
                const float frac = a.coarse_row_frac[row_parity][r];
                const uint32_t base = ((row_parity * 2 + column_parity) * rows + r) * cols;
                uint32_t c = 0;
                for (; c + F::width <= cols; c += F::width)
                    integrate_lattice_lanes<F, kWind>(p, args, lower, upper, frac, base + c, c);
                if (c < cols && cols >= F::width) {  // the row's tail: one group overlapping the last
                    integrate_lattice_lanes<F, kWind>(p, args, lower, upper, frac, base + cols - F::width,
                                                      cols - F::width, F::width - (cols - c));
                } else {  // rows narrower than a lane group
                    for (; c < cols; ++c)
                        integrate_lattice_lanes<simd::Float1, kWind>(p, args, lower, upper, frac, base + c, c);
                }
            }
        }
    }
    integrate_slots<F, kWind>(p, args, 4 * rows * cols, p.slot_count);  // padding after the planes
}

template <class F, bool kWind>
void integrate_dispatch(const Particles& p, const IntegrateArgs& args, const ClothAsset& a, const CoarseState* st) {
    if (st == nullptr) {
        integrate_slots<F, kWind>(p, args, 0, p.slot_count);
    } else if (a.coarse_lattice_cols > 0) {
        integrate_with_coarse_lattice<F, kWind>(p, args, a, *st);
    } else {
        integrate_with_coarse_weights<F, kWind>(p, args, a, *st);
    }
}

// `coarse`: the coarse level's displacements to add, or null. Writes x(t+h) into the previous-position
// arrays: swap them with the position arrays afterwards (integrate() in step.cpp does).
template <class F>
void integrate_verlet(const Particles& p, const IntegrateArgs& args, const ClothAsset& a, const CoarseState* coarse) {
    if (args.wind) {
        integrate_dispatch<F, true>(p, args, a, coarse);
    } else {
        integrate_dispatch<F, false>(p, args, a, coarse);
    }
}

}  // namespace weft
