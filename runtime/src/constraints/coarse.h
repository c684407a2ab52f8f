// The coarse-level correction (hierarchical position-based dynamics, Mueller 2008), once per
// substep before the fine sweeps:
//   1. read the nodes' predicted positions;
//   2. one Gauss-Seidel sweep over the coarse distance constraints (the same projection as the
//      fine springs, on the nodes' lumped masses);
//   3. move every particle by the weighted displacement of its nodes (a partition of unity), so the
//      whole cloth follows the coarse correction smoothly instead of only the node particles.
// The coarse cloth has no bend constraints (measured: they flare a draped skirt into an umbrella)
// and is bilateral (unilateral coarse constraints gave 100%+ local strain spikes).
#pragma once

#include <utility>

#include "constraints/distance.h"
#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Steps 1 and 2; leaves each node's displacement in state.dx/dy/dz. Scalar: a few hundred nodes.
inline void solve_coarse_level(const Particles& p, const ClothAsset& a, const CoarseState& st,
                               float relaxation) {
    using simd::Float1;
    const uint32_t nodes = a.coarse_node_count;
    for (uint32_t j = 0; j < nodes; ++j) {
        const uint32_t s = a.coarse_node_slot[j];
        st.x[j] = p.x[s];
        st.y[j] = p.y[s];
        st.z[j] = p.z[s];
    }
    const Float1 weight{relaxation}, alpha{0.0f};
    for (uint32_t c = 0; c < a.coarse_constraint_count; ++c) {
        const uint32_t i = a.coarse_a[c], j = a.coarse_b[c];
        Float1 xa{st.x[i]}, ya{st.y[i]}, za{st.z[i]}, xb{st.x[j]}, yb{st.y[j]}, zb{st.z[j]};
        project_distance<Float1, true>(xa, ya, za, Float1{a.coarse_inverse_mass[i]}, xb, yb, zb,
                                       Float1{a.coarse_inverse_mass[j]}, Float1{a.coarse_rest[c]}, weight,
                                       alpha);
        st.x[i] = xa.v, st.y[i] = ya.v, st.z[i] = za.v;
        st.x[j] = xb.v, st.y[j] = yb.v, st.z[j] = zb.v;
    }
    for (uint32_t j = 0; j < nodes; ++j) {
        const uint32_t s = a.coarse_node_slot[j];
        st.dx[j] = st.x[j] - p.x[s];
        st.dy[j] = st.y[j] - p.y[s];
        st.dz[j] = st.z[j] - p.z[s];
    }
}

// Step 3: x_i += sum_k weight_k(i) * displacement(node_k(i)). Pinned and padding slots have weight 0.
template <class F>
void apply_coarse_displacement(const Particles& p, const ClothAsset& a, const CoarseState& st) {
    using namespace simd;
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        F dx = splat(0.0f, F{}), dy = dx, dz = dx;
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            const F w = load(a.coarse_weight[k] + i, F{});
            const uint32_t* node = a.coarse_weight_node[k] + i;
            dx = mul_add(w, gather(st.dx, node, F{}), dx);
            dy = mul_add(w, gather(st.dy, node, F{}), dy);
            dz = mul_add(w, gather(st.dz, node, F{}), dz);
        }
        store(p.x + i, load(p.x + i, F{}) + dx);
        store(p.y + i, load(p.y + i, F{}) + dy);
        store(p.z + i, load(p.z + i, F{}) + dz);
    }
}

// Step 3 for the lattice form, separably: a coarse row's node displacements are interpolated to
// every plane column once (a 32-entry register lookup, no gathers), and each plane row then blends
// the two coarse rows around it with contiguous loads. Plane rows visit coarse rows in order, so two
// interpolated rows are kept and the next one is made only when the plane row crosses into it.
template <class F>
inline void interpolate_columns(const ClothAsset& a, const float* node_row, uint32_t parity, uint32_t column,
                                float* out) {
    using namespace simd;
    const uint32_t* node = a.coarse_col_node[parity] + column;
    const F left = lookup32(node_row, node, F{}), right = lookup32(node_row + 1, node, F{});
    store(out + column, mul_add(load(a.coarse_col_frac[parity] + column, F{}), right - left, left));
}

template <class F>
void interpolate_coarse_row(const ClothAsset& a, const CoarseState& st, uint32_t coarse_row, uint32_t parity,
                            float* const out[3]) {
    const float* const node_row[3] = {st.dx + coarse_row * a.coarse_lattice_cols,
                                      st.dy + coarse_row * a.coarse_lattice_cols,
                                      st.dz + coarse_row * a.coarse_lattice_cols};
    const uint32_t cols = a.lattice_plane_cols;
    for (int axis = 0; axis < 3; ++axis) {
        uint32_t c = 0;
        for (; c + F::width <= cols; c += F::width) interpolate_columns<F>(a, node_row[axis], parity, c, out[axis]);
        for (; c < cols; ++c) interpolate_columns<simd::Float1>(a, node_row[axis], parity, c, out[axis]);
    }
}

template <class F>
inline void add_blended_rows(const Particles& p, float* const lower_row[3], float* const upper_row[3], float frac,
                             uint32_t slot, uint32_t c) {
    using namespace simd;
    const F f = splat(frac, F{});
    const auto is_free = load(p.inverse_mass + slot, F{}) > splat(0.0f, F{});
    float* const position[3] = {p.x + slot, p.y + slot, p.z + slot};
    for (int axis = 0; axis < 3; ++axis) {
        const F lower = load(lower_row[axis] + c, F{}), upper = load(upper_row[axis] + c, F{});
        const F x = load(position[axis], F{});
        store(position[axis], select(is_free, x + mul_add(f, upper - lower, lower), x));
    }
}

template <class F>
void apply_coarse_lattice(const Particles& p, const ClothAsset& a, const CoarseState& st) {
    const uint32_t rows = a.lattice_plane_rows, cols = a.lattice_plane_cols;
    for (uint32_t column_parity = 0; column_parity < 2; ++column_parity) {
        // Fine rows in order (plane row r of row parity 0, then of parity 1): coarse rows only grow.
        float* lower[3] = {st.column_rows[0], st.column_rows[1], st.column_rows[2]};
        float* upper[3] = {st.column_rows[3], st.column_rows[4], st.column_rows[5]};
        uint32_t loaded = ~0u;  // coarse row held in `lower` (loaded + 1 in `upper`)
        for (uint32_t r = 0; r < rows; ++r) {
            for (uint32_t row_parity = 0; row_parity < 2; ++row_parity) {
                const uint32_t coarse_row = a.coarse_row_node[row_parity][r];
                if (loaded != ~0u && coarse_row == loaded + 1) {  // slide the window up one coarse row
                    for (int axis = 0; axis < 3; ++axis) std::swap(lower[axis], upper[axis]);
                    interpolate_coarse_row<F>(a, st, coarse_row + 1, column_parity, upper);
                    loaded = coarse_row;
                } else if (coarse_row != loaded) {
                    interpolate_coarse_row<F>(a, st, coarse_row, column_parity, lower);
                    interpolate_coarse_row<F>(a, st, coarse_row + 1, column_parity, upper);
                    loaded = coarse_row;
                }
                const float frac = a.coarse_row_frac[row_parity][r];
                const uint32_t base = ((row_parity * 2 + column_parity) * rows + r) * cols;
                uint32_t c = 0;
                for (; c + F::width <= cols; c += F::width) add_blended_rows<F>(p, lower, upper, frac, base + c, c);
                for (; c < cols; ++c) add_blended_rows<simd::Float1>(p, lower, upper, frac, base + c, c);
            }
        }
    }
}

template <class F>
void apply_coarse(const Particles& p, const ClothAsset& a, const CoarseState& st) {
    if (a.coarse_lattice_cols > 0) {
        apply_coarse_lattice<F>(p, a, st);
    } else {
        apply_coarse_displacement<F>(p, a, st);
    }
}

}  // namespace weft
