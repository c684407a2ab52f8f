// The coarse-level correction (hierarchical position-based dynamics, Mueller 2008), every substep
// before the fine sweeps:
//   1. predict the nodes' positions (the integration's own Verlet formula);
//   2. `coarse_iterations` Gauss-Seidel sweeps over the coarse distance constraints (the same
//      projection kernels as the fine springs, on the nodes' lumped masses, batch by batch over node
//      slots: on a lattice the coarse constraints are contiguous runs on the node lattice's parity
//      planes);
//   3. move every particle by the weighted displacement of its nodes (a partition of unity), so the
//      whole cloth follows the coarse correction smoothly instead of only the node particles; this
//      is done inside the integration pass (integrate/verlet.h), so step 1 predicts the nodes.
// The coarse projection uses the square-root-free form (distance.h): same rest state, measured
// the same on the sphere (stays at n = 50, 100, 200), 20% cheaper. The coarse cloth has no bend
// constraints (measured: they flare a draped skirt into an umbrella).
//
// A coarse constraint resists compression at kCoarseCompressionWeight of its stretch correction.
// Where the cloth curves or folds (over the sphere, in the folds of a hanging rim) the straight
// chord between two nodes is shorter than its flat rest length; fully bilateral, the coarse level
// pushes the nodes apart, the fine springs pull them back, and the 1.4 m disc on the sphere never
// came to rest (1.1 cm/s with 2 substeps x 3 coarse sweeps). Unilateral (weight 0) it rests, but
// the grid's worst spring on the sphere stretches 113-188%. A quarter: both at rest, and the grid's
// worst spring at n = 100 83% -> 64% (docs/solver.md).
#pragma once

#include <utility>

#include "constraints/contact_tethers.h"
#include "constraints/distance.h"
#include "integrate/predict.h"
#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

inline constexpr float kCoarseCompressionWeight = 0.25f;

// The node passes read the particle arrays at scattered slots, one scalar load per lane
// (gather_by_loads: faster than the hardware gather here).
//
// Step 1 for the node slots k..k+width: their nodes' Verlet prediction, straight into the node
// slots the sweep works on (st.x) and, kept for the displacement, into st.dx (by node slot until
// step 2 is done). Padding node slots predict some particle and are never moved (inverse mass 0).
template <class F>
inline void predict_coarse_nodes(const Particles& p, const IntegrateArgs& args, const CoarseState& st, uint32_t k) {
    using namespace simd;
    const uint32_t* slot = st.particle_slot + k;
    const F h2 = splat(args.h2_s2, F{}), velocity_scale = splat(args.velocity_scale, F{});
    F ax = splat(args.gravity.x, F{}), ay = splat(args.gravity.y, F{}), az = splat(args.gravity.z, F{});
    if (args.wind) {
        ax = ax + gather_by_loads(p.wind_x, slot, F{});
        ay = ay + gather_by_loads(p.wind_y, slot, F{});
        az = az + gather_by_loads(p.wind_z, slot, F{});
    }
    const auto is_free = gather_by_loads(p.inverse_mass, slot, F{}) > splat(0.0f, F{});
    const F x = gather_by_loads(p.x, slot, F{}), y = gather_by_loads(p.y, slot, F{}), z = gather_by_loads(p.z, slot, F{});
    const F px = select(is_free, verlet_predict(x, gather_by_loads(p.previous_x, slot, F{}), ax, velocity_scale, h2), x);
    const F py = select(is_free, verlet_predict(y, gather_by_loads(p.previous_y, slot, F{}), ay, velocity_scale, h2), y);
    const F pz = select(is_free, verlet_predict(z, gather_by_loads(p.previous_z, slot, F{}), az, velocity_scale, h2), z);
    store(st.x + k, px);
    store(st.y + k, py);
    store(st.z + k, pz);
    store(st.dx + k, px);
    store(st.dy + k, py);
    store(st.dz + k, pz);
}

// Step 3's input for the node slots k..k+width, in place: solved minus predicted position.
template <class F>
inline void coarse_slot_displacement(const CoarseState& st, uint32_t k) {
    using namespace simd;
    store(st.x + k, load(st.x + k, F{}) - load(st.dx + k, F{}));
    store(st.y + k, load(st.y + k, F{}) - load(st.dy + k, F{}));
    store(st.z + k, load(st.z + k, F{}) - load(st.dz + k, F{}));
}

// ... and by node (what the integration pass reads), for the nodes j..j+width.
template <class F>
inline void coarse_displacement(const ClothAsset& a, const CoarseState& st, uint32_t j) {
    using namespace simd;
    const uint32_t* slot = a.coarse_slot_of_node + j;
    store(st.dx + j, gather_by_loads(st.x, slot, F{}));
    store(st.dy + j, gather_by_loads(st.y, slot, F{}));
    store(st.dz + j, gather_by_loads(st.z, slot, F{}));
}

// Steps 1 and 2; leaves each node's displacement in state.dx/dy/dz (added to every particle by the
// integration pass, integrate/verlet.h).
template <class F>
void solve_coarse_level(const Particles& particles, const IntegrateArgs& integrate_args, const ClothAsset& a,
                        const CoarseState& state, float relaxation, uint32_t sweeps) {
    using namespace simd;
    const Particles p = particles;  // local copies: stores cannot alias them
    const IntegrateArgs args = integrate_args;
    const CoarseState st = state;
    const uint32_t nodes = a.coarse_node_count;
    // coarse_slot_count is a multiple of the SIMD width (cook_lanes pads the node slots).
    for (uint32_t k = 0; k < a.coarse_slot_count; k += F::width) predict_coarse_nodes<F>(p, args, st, k);

    const PointSet points{st.x, st.y, st.z, a.coarse_inverse_mass};
    const ConstraintLanes constraints = coarse_lanes(a);
    const DistanceArgs distance{0.0f, relaxation, kCoarseCompressionWeight};
    for (uint32_t sweep = 0; sweep < sweeps; ++sweep)
        for (uint32_t b = 0; b < a.coarse_batch_count; ++b) {
            const ConstraintBatch& batch = a.coarse_batches[b];
            if (batch.layout == BatchLayout::run) {
                project_run<F, false, true>(points, constraints, batch, distance);
            } else {
                project_indexed<F, false, true>(points, constraints, batch, distance);
            }
        }
    if (st.anchor != nullptr)  // contact tethers, when the cloth uses them (constraints/contact_tethers.h)
        for (uint32_t k = 0; k < a.coarse_slot_count; k += F::width) project_contact_tethers<F>(a, st, k);

    for (uint32_t k = 0; k < a.coarse_slot_count; k += F::width) coarse_slot_displacement<F>(st, k);
    uint32_t j = 0;
    for (; j + F::width <= nodes; j += F::width) coarse_displacement<F>(a, st, j);
    for (; j < nodes; ++j) coarse_displacement<Float1>(a, st, j);
}

// The lane groups a plane row of `cols` columns is processed in, everywhere the lattice form
// touches a row (the interpolated coarse rows and the integration pass): groups at 0, W, 2W, ...
// and one group overlapping the last full one at cols - W (narrower rows: one lane at a time).
// Every store and every later load of a row then covers the same lanes, so loads are served from
// the store buffer instead of waiting for half-overlapping stores to retire.
template <class F, class Visit>
inline void lattice_lane_groups(uint32_t cols, Visit visit) {
    if (cols < F::width) {
        for (uint32_t c = 0; c < cols; ++c) visit(simd::Float1{}, c);
        return;
    }
    const uint32_t last = cols - F::width;
    for (uint32_t c = 0; c < last; c += F::width) visit(F{}, c);
    visit(F{}, last);
}

// Step 3 for the lattice form, separably: a coarse row's node displacements are interpolated to
// every plane column once, and each plane row then blends the two coarse rows around it with
// contiguous loads (integrate/verlet.h). A lane group of plane columns spans at most 8 nodes (nodes
// are at least one plane column apart), so its nodes come from one load and one permute.
//
// Coarse row `coarse_row` interpolated to the plane columns of one column parity, into out[axis *
// stride + column]; with `lower` (the row below, same layout) also out - lower into `delta`.
template <class F>
void interpolate_coarse_row(const ClothAsset& a, const CoarseState& st, uint32_t coarse_row, uint32_t parity,
                            float* out, const float* lower, float* delta, uint32_t stride) {
    using namespace simd;
    const uint32_t offset = coarse_row * a.coarse_lattice_cols;
    const float* const node_row[3] = {st.dx + offset, st.dy + offset, st.dz + offset};
    const uint32_t* const node = a.coarse_col_node[parity];
    const float* const frac = a.coarse_col_frac[parity];
    for (uint32_t axis = 0; axis < 3; ++axis) {
        const uint32_t row = axis * stride;
        lattice_lane_groups<F>(a.lattice_plane_cols, [&](auto lanes, uint32_t c) {
            using W = decltype(lanes);
            const W left = gather_near(node_row[axis], node + c, W{});
            const W right = gather_near(node_row[axis] + 1, node + c, W{});
            const W value = mul_add(load(frac + c, W{}), right - left, left);
            store(out + row + c, value);
            if (lower != nullptr) store(delta + row + c, value - load(lower + row + c, W{}));
        });
    }
}

}  // namespace weft
