// The coarse-level correction (hierarchical position-based dynamics, Mueller 2008), once per
// substep before the fine sweeps:
//   1. read the nodes' predicted positions;
//   2. one Gauss-Seidel sweep over the coarse distance constraints (the same projection as the
//      fine springs, on the nodes' lumped masses);
//   3. move every particle by the weighted displacement of its nodes (a partition of unity), so the
//      whole cloth follows the coarse correction smoothly instead of only the node particles; this
//      is done inside the integration pass (integrate/verlet.h), so step 1 predicts the nodes.
// The coarse projection uses the square-root-free form (distance.h): same rest state, measured
// the same on the sphere (stays at n = 50, 100, 200), 20% cheaper. The coarse cloth has no bend constraints (measured: they flare a draped skirt into an umbrella)
// and is bilateral (unilateral coarse constraints gave 100%+ local strain spikes).
#pragma once

#include <utility>

#include "constraints/distance.h"
#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Steps 1 and 2; leaves each node's displacement in state.dx/dy/dz (added to every particle by the
// integration pass, integrate/verlet.h). The nodes' positions are their Verlet prediction for this
// substep (`predict` is the integration's own formula, so a node lands exactly on its solved
// position). Scalar: a few hundred nodes.
template <class Predict>
inline void solve_coarse_level(const ClothAsset& a, const CoarseState& st, float relaxation, Predict predict) {
    using simd::Float1;
    const uint32_t nodes = a.coarse_node_count;
    for (uint32_t j = 0; j < nodes; ++j) {
        const uint32_t s = a.coarse_node_slot[j];
        const Vec3 x = predict(s);
        st.x[j] = st.dx[j] = x.x;  // dx, dy, dz hold the prediction until the sweep is done
        st.y[j] = st.dy[j] = x.y;
        st.z[j] = st.dz[j] = x.z;
    }
    const Float1 weight{relaxation}, alpha{0.0f};
    for (uint32_t c = 0; c < a.coarse_constraint_count; ++c) {
        const uint32_t i = a.coarse_a[c], j = a.coarse_b[c];
        Float1 xa{st.x[i]}, ya{st.y[i]}, za{st.z[i]}, xb{st.x[j]}, yb{st.y[j]}, zb{st.z[j]};
        project_distance<Float1, false>(xa, ya, za, Float1{a.coarse_inverse_mass[i]}, xb, yb, zb,
                                       Float1{a.coarse_inverse_mass[j]}, Float1{a.coarse_rest[c]}, weight,
                                       alpha);
        st.x[i] = xa.v, st.y[i] = ya.v, st.z[i] = za.v;
        st.x[j] = xb.v, st.y[j] = yb.v, st.z[j] = zb.v;
    }
    for (uint32_t j = 0; j < nodes; ++j) {
        st.dx[j] = st.x[j] - st.dx[j];
        st.dy[j] = st.y[j] - st.dy[j];
        st.dz[j] = st.z[j] - st.dz[j];
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

}  // namespace weft
