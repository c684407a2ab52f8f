// The per-pass kernels, as one table per SIMD path. The step calls through the table once per pass
// (never per particle); each table is the same templates instantiated for one wide float type.
#pragma once

#include <cstdint>

#include "weft/cloth_asset.h"
#include "weft/types.h"

namespace weft {

// One cloth's particle state, structure-of-arrays, indexed by asset slot. Every array holds
// `slot_count` floats (a multiple of kSimdWidth); padding slots have inverse mass 0.
struct Particles {
    uint32_t slot_count = 0;
    float* x = nullptr;  // position at t, metres
    float* y = nullptr;
    float* z = nullptr;
    float* previous_x = nullptr;  // position at t - h (Verlet keeps no velocity)
    float* previous_y = nullptr;
    float* previous_z = nullptr;
    float* inverse_mass = nullptr;  // 1/kg, 0 = pinned
    float* wind_x = nullptr;        // wind acceleration this substep, m/s^2 (wind feature only)
    float* wind_y = nullptr;
    float* wind_z = nullptr;
    float* normal_x = nullptr;      // unit vertex normal at the end of the step (normals feature only)
    float* normal_y = nullptr;
    float* normal_z = nullptr;
    // Tangents feature only (render/normals.h): the unit tangent along +u, Gram-Schmidt against the
    // normal, and w = +1 or -1, the side dP/dv lies on (Lengyel's handedness), per slot.
    float* tangent_x = nullptr;
    float* tangent_y = nullptr;
    float* tangent_z = nullptr;
    float* tangent_w = nullptr;
    float* bitangent_x = nullptr;  // the pass's sum of dP/dv, per slot (scratch)
    float* bitangent_y = nullptr;
    float* bitangent_z = nullptr;
    // Per triangle lane, in the walk's order (as ClothAsset::wind_rest_area: the runs' lanes, then
    // the triangles done one at a time): dP/du = g0 e1 + g1 e2 and dP/dv = g2 e1 + g3 e2, with
    // e1 = P1 - P0, e2 = P2 - P0, each times the triangle's uv area (Lengyel's solve, weighted by
    // area: the 1/det cancels). Found at add_cloth from the asset's uv (tangent_uv_gradients).
    float* uv_gradient[4] = {};
};

// What the distance kernels move: positions and inverse masses by slot. A cloth's particles, or
// its coarse level's nodes (by node slot), so both levels share one projection kernel.
struct PointSet {
    float* x = nullptr;
    float* y = nullptr;
    float* z = nullptr;
    const float* inverse_mass = nullptr;
};
inline PointSet points_of(const Particles& p) { return {p.x, p.y, p.z, p.inverse_mass}; }

// One set of distance constraints in lanes (ClothAsset: the springs, or the coarse level's).
struct ConstraintLanes {
    const float* rest_length = nullptr;
    const float* lane_weight = nullptr;  // 1 real, 0 padding
    const uint32_t* index_a = nullptr;   // slots of the PointSet
    const uint32_t* index_b = nullptr;
};
inline ConstraintLanes spring_lanes(const ClothAsset& a) {
    return {a.rest_length, a.lane_weight, a.index_a, a.index_b};
}
inline ConstraintLanes coarse_lanes(const ClothAsset& a) {
    return {a.coarse_rest_length, a.coarse_lane_weight, a.coarse_index_a, a.coarse_index_b};
}

// The coarse level's state for one cloth: node positions and their displacement this substep.
struct CoarseState {
    float* x = nullptr;  // [coarse_slot_count] by node slot (the solve's layout)
    float* y = nullptr;
    float* z = nullptr;
    float* dx = nullptr;  // by node (row-major on a lattice); during the solve by node slot
    float* dy = nullptr;
    float* dz = nullptr;
    // Lattice form: the coarse rows around the current plane row, interpolated to every plane
    // column, as kCoarseColumnRows rows of `column_stride` floats: two coarse rows (x, y, z each)
    // and their difference (integrate/verlet.h).
    uint32_t* particle_slot = nullptr;  // [coarse_slot_count] the particle slot of each node slot
    // Contact tethers (ClothDesc::contact_tethers, constraints/contact_tethers.h), by node slot: the
    // node slot of the anchor (a node in contact or pinned; itself when none) and the
    // tether's rest length, metres (+inf: none). Null in the state handed to the solve when off.
    uint32_t* anchor = nullptr;
    float* anchor_rest = nullptr;
    uint32_t* holds = nullptr;  // 1 when the node touches a collider or is pinned (after the last step)
    float* column_rows = nullptr;
    uint32_t column_stride = 0;  // floats, at least lattice_plane_cols + kSimdWidth
};
// Padding after the node arrays: the lattice form reads up to 8 entries past a coarse row's nodes.
inline constexpr uint32_t kCoarseNodePadding = 40;
inline constexpr uint32_t kCoarseColumnRows = 9;
inline constexpr uint32_t coarse_column_stride(uint32_t lattice_plane_cols) {
    return (lattice_plane_cols + 2 * kSimdWidth - 1) / kSimdWidth * kSimdWidth;
}

// One cloth's bound skin constraints, in slot order, each array padded to a whole number of
// kSimdWidth lanes with copies of the last constraint (a copy computes and writes the same bits).
inline constexpr uint32_t kSkinArrays = 19;  // slot, 3 corners, 3 weights, 3 copies, 3 x 3 frame coordinates
struct SkinState {
    uint32_t count = 0;                 // constraints (the padding not counted)
    uint32_t* slot = nullptr;           // the constrained particle's slot
    uint32_t* corner[3] = {};           // the bound body triangle's vertices
    float* weight[3] = {};              // barycentric weights on it
    float* rest_offset_m = nullptr;     // copies of the caller's arrays, in this order
    float* max_distance_m = nullptr;
    float* backstop_m = nullptr;
    float* previous_point[3] = {};      // P at the previous step's hull, metres
    float* point[3] = {};               // P at this step's hull, metres
    float* normal[3] = {};              // N: unit, from this step's vertex normals
};

// project_skin's substep (constraints/skin.h).
struct SkinProjectArgs {
    float t_start = 0.0f, t_end = 1.0f;  // the substep's span of the step: where the hull is interpolated
    float friction = 0.0f;               // Coulomb coefficient against the backstop (the body's)
    // The root's carry this substep (ClothInstance::carry_*): it moved the particles' previous
    // positions already, so friction takes it off the skin's motion.
    bool carried = false;
    float carry_rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    Vec3 carry_pivot{}, carry_shift{};
};

// Verlet (seed section 1.1): x' = x + (x - x_prev) * (h / h_prev) * damping + (g + a_wind) * h2.
struct IntegrateArgs {
    float h2_s2;           // h^2; h^2 / 2 on a cloth's first step (see integrate_args in step.cpp)
    float velocity_scale;  // (h / h_prev) * exp(-damping h): time-corrected, damped
    Vec3 gravity;          // m/s^2
    bool wind;             // add the wind arrays
    bool planes_free;      // no slot of the lattice planes is pinned or empty (ClothInstance::held_plane_slots)
};

// XPBD distance projection over one batch (seed section 1.1, Macklin et al. 2016).
struct DistanceArgs {
    float compliance_over_h2;  // alpha / h^2, 1/kg
    float relaxation;          // scales the correction
    float compression_weight = 1.0f;  // scales a compressed constraint's correction (coarse level only)
};

// A collider in the form the kernel wants: a segment p0-p1 with a radius (sphere: p0 = p1),
// or a plane through p0 with normal `normal`.
struct ColliderKernelArgs {
    uint8_t shape;      // ColliderShape
    Vec3 p0, p1;        // segment ends, or plane point
    Vec3 normal;        // plane only
    float radius;       // inflated radius (plane: offset)
    float friction;     // Coulomb coefficient
    Vec3 motion;        // displacement of the collider over this substep (friction is relative)
};

// The box around a cloth's movable particles (inverse mass > 0: the ones a collider may move).
struct ParticleBounds {
    Vec3 lo, hi;  // metres; lo > hi on every axis when no particle moves
};

// The health pass's sums over the movable particles (health.h).
struct HealthSums {
    Vec3 lo, hi;             // their box, metres (lo > hi when none moves)
    float squared_m2 = 0.0f; // sum of |x - x_prev|^2 (NaN or infinite when a position is)
    float movable = 0.0f;    // how many
};

// One cloth's driven render mesh (WorldDesc::render_meshes), by render vertex.
struct RenderOutput {
    float* x = nullptr;  // position, metres
    float* y = nullptr;
    float* z = nullptr;
    float* normal_x = nullptr;  // unit normal
    float* normal_y = nullptr;
    float* normal_z = nullptr;
    float* corners = nullptr;  // [kRenderCornerFloats * slots]: the particles packed for the gathers (render/render_mesh.h)
};
inline constexpr uint32_t kRenderCornerFloats = 8;

struct WindArgs;
struct SkinFrameArgs;

struct Kernels {
    SimdPath path;
    // Verlet, plus the coarse level's displacement when `coarse` is not null.
    void (*integrate)(const Particles&, const IntegrateArgs&, const ClothAsset&, const CoarseState* coarse);
    // The coarse level's sweeps (`sweeps` of them) on its nodes' Verlet prediction; leaves the node
    // displacements in CoarseState::dx/dy/dz for `integrate`.
    void (*solve_coarse_level)(const Particles&, const IntegrateArgs&, const ClothAsset&, const CoarseState&,
                               float relaxation, uint32_t sweeps);
    // [0]: exact, [1]: sqrt_free (SpringProjection)
    // One sweep of the springs (constraints/distance.h: project_springs), args by ConstraintKind.
    void (*project_springs[2])(const PointSet&, const ConstraintLanes&, const ConstraintBatch*, uint32_t batch_count,
                               const DistanceArgs*);
    void (*project_tethers)(const Particles&, const ClothAsset&, const TetherBatch&, float slack);
    void (*collide)(const Particles&, const ColliderKernelArgs&);
    void (*apply_wind)(const Particles&, const ClothAsset&, const WindArgs&);
    // Skin constraints (constraints/skin.h): their skinned frames once a step, then max distance
    // and backstop (with friction) every substep.
    void (*particle_bounds)(const Particles&, ParticleBounds*);
    void (*health_sums)(const Particles&, HealthSums*);
    void (*skin_frames)(const SkinState&, const SkinFrameArgs&);
    void (*project_skin)(const Particles&, const SkinState&, const SkinProjectArgs&);
    void (*vertex_normals)(const Particles&, const ClothAsset&);
    // The normals and, in the same triangle walk, the tangents (Particles::tangent_*).
    void (*vertex_normals_tangents)(const Particles&, const ClothAsset&);
    // The render mesh from the particles and their vertex normals (render/render_mesh.h).
    void (*render_mesh)(const Particles&, const ClothAsset&, const RenderOutput&);
};

const Kernels& scalar_kernels();
// Null when the build or the CPU lacks AVX2 + FMA.
const Kernels* avx2_kernels();

}  // namespace weft
