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

// One lane group at slot i: x(t+h) from x(t), x(t-h) and the coarse displacement c. kPinned: some
// slot of the pass may be pinned (or empty), so each lane checks its inverse mass; without, the
// inverse-mass load, compare and three selects are skipped (same bits: every lane is free).
template <class F>
struct Predicted {
    F x, y, z;
};
template <class F, bool kWind, bool kPinned = true>
inline Predicted<F> predict_lanes(const Particles& p, const IntegrateArgs& args, uint32_t i, F cx, F cy, F cz) {
    using namespace simd;
    const F h2 = splat(args.h2_s2, F{});
    const F velocity_scale = splat(args.velocity_scale, F{});
    F ax = splat(args.gravity.x, F{}), ay = splat(args.gravity.y, F{}), az = splat(args.gravity.z, F{});
    if constexpr (kWind) {
        ax = ax + load(p.wind_x + i, F{});
        ay = ay + load(p.wind_y + i, F{});
        az = az + load(p.wind_z + i, F{});
    }
    const F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
    const F px = load(p.previous_x + i, F{}), py = load(p.previous_y + i, F{}), pz = load(p.previous_z + i, F{});
    const Predicted<F> n{verlet_predict(x, px, ax, velocity_scale, h2) + cx,
                         verlet_predict(y, py, ay, velocity_scale, h2) + cy,
                         verlet_predict(z, pz, az, velocity_scale, h2) + cz};
    if constexpr (kPinned) {
        const auto is_free = load(p.inverse_mass + i, F{}) > splat(0.0f, F{});  // pinned particles stay put
        return {select(is_free, n.x, x), select(is_free, n.y, y), select(is_free, n.z, z)};
    } else {
        return n;
    }
}

// x(t+h) overwrites x(t-h), which is no longer needed; the caller then swaps the two arrays, so
// x(t) becomes the previous position without being copied (3 stores a lane instead of 6).
template <class F>
inline void store_predicted(const Particles& p, uint32_t i, const Predicted<F>& n) {
    simd::store(p.previous_x + i, n.x);
    simd::store(p.previous_y + i, n.y);
    simd::store(p.previous_z + i, n.z);
}

template <class F, bool kWind>
inline void integrate_lanes(const Particles& p, const IntegrateArgs& args, uint32_t i, F cx, F cy, F cz) {
    store_predicted(p, i, predict_lanes<F, kWind>(p, args, i, cx, cy, cz));
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
// already interpolated to every plane column) with contiguous loads: L + frac * (U - L).
template <class F, bool kWind, bool kPinned>
inline Predicted<F> predict_lattice_lanes(const Particles& p, const IntegrateArgs& args, const float* lower,
                                          const float* delta, uint32_t stride, F frac, uint32_t slot, uint32_t c) {
    using namespace simd;
    const float* l = lower + c;
    const float* d = delta + c;
    return predict_lanes<F, kWind, kPinned>(p, args, slot, mul_add(frac, load(d, F{}), load(l, F{})),
                                   mul_add(frac, load(d + stride, F{}), load(l + stride, F{})),
                                   mul_add(frac, load(d + 2 * stride, F{}), load(l + 2 * stride, F{})));
}

template <class F, bool kWind, bool kPinned>
void integrate_with_coarse_lattice(const Particles& particles, const IntegrateArgs& integrate_args,
                                   const ClothAsset& a, const CoarseState& st) {
    // Local copies: the pass's stores cannot alias them, so the array pointers and the constants stay
    // in registers instead of being reloaded after every store.
    const Particles p = particles;
    const IntegrateArgs args = integrate_args;
    const uint32_t rows = a.lattice_plane_rows, cols = a.lattice_plane_cols;
    const uint32_t stride = st.column_stride;
    // CoarseState::column_rows: two interpolated coarse rows (lower and upper, swapped as the window
    // slides up) and upper - lower.
    float* const delta = st.column_rows + 6 * stride;
    for (uint32_t column_parity = 0; column_parity < 2; ++column_parity) {
        // Fine rows in order (plane row r of row parity 0, then of parity 1): the coarse rows only
        // grow, so each is interpolated to the plane columns once per column parity.
        float* lower = st.column_rows;
        float* upper = st.column_rows + 3 * stride;
        uint32_t loaded = ~0u;  // coarse row held in `lower` (loaded + 1 in `upper`)
        for (uint32_t r = 0; r < rows; ++r) {
            for (uint32_t row_parity = 0; row_parity < 2; ++row_parity) {
                const uint32_t coarse_row = a.coarse_row_node[row_parity][r];
                if (coarse_row != loaded) {
                    if (loaded != ~0u && coarse_row == loaded + 1) {  // slide the window up one coarse row
                        std::swap(lower, upper);
                    } else {
                        interpolate_coarse_row<F>(a, st, coarse_row, column_parity, lower, nullptr, nullptr, stride);
                    }
                    interpolate_coarse_row<F>(a, st, coarse_row + 1, column_parity, upper, lower, delta, stride);
                    loaded = coarse_row;
                }
                const uint32_t base = ((row_parity * 2 + column_parity) * rows + r) * cols;
                if (cols >= F::width) {
                    // The row's tail: one group overlapping the last full one (lattice_lane_groups),
                    // computed before the full groups are stored (same inputs, same bits on the shared
                    // lanes), so no load waits on a store it half overlaps and no lanes need masking.
                    const F frac = simd::splat(a.coarse_row_frac[row_parity][r], F{});
                    const uint32_t last = cols - F::width;
                    const Predicted<F> tail =
                        predict_lattice_lanes<F, kWind, kPinned>(p, args, lower, delta, stride, frac, base + last, last);
                    for (uint32_t c = 0; c < last; c += F::width)
                        store_predicted(p, base + c, predict_lattice_lanes<F, kWind, kPinned>(p, args, lower, delta, stride,
                                                                                     frac, base + c, c));
                    store_predicted(p, base + last, tail);
                } else {  // rows narrower than a lane group
                    const simd::Float1 frac{a.coarse_row_frac[row_parity][r]};
                    for (uint32_t c = 0; c < cols; ++c)
                        store_predicted(p, base + c, predict_lattice_lanes<simd::Float1, kWind, kPinned>(
                                                         p, args, lower, delta, stride, frac, base + c, c));
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
    } else if (a.coarse_lattice_cols > 0 && args.planes_free) {
        integrate_with_coarse_lattice<F, kWind, false>(p, args, a, *st);
    } else if (a.coarse_lattice_cols > 0) {
        integrate_with_coarse_lattice<F, kWind, true>(p, args, a, *st);
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
