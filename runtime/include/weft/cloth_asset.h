// The cloth asset's solver layout: what cooking tools write and debuggers read. A game reads an
// asset through weft/asset_view.h.
//
// Three kinds of data are kept apart (as Jolt does):
//   ClothAsset   - this file: topology, rest lengths, masses, constraint batches. Read-only,
//                  shared by every instance of the same garment, never copied by the world.
//   cloth state  - per instance, inside the world's memory block (positions, previous positions).
//   step scratch - none: every pass works in place.
//
// An asset comes from a baked file loaded in place (weft/asset_file.h) or from `cook_cloth` (an
// in-memory triangle mesh, weft/cook.h: the cooking library). Both give the same plain struct of pointers into memory the caller owns.
#pragma once

#include "weft/asset_view.h"
#include "weft/types.h"

namespace weft {

// Lanes per SIMD batch. Runs are padded to a multiple of this so the AVX2 pass needs no tail loop.
inline constexpr uint32_t kSimdWidth = 8;
// The widest padding an asset may be cooked for (CookOptions::simd_width): 16 lanes for a 16-wide
// target; its runs are also multiples of 8, so the 8-wide runtime steps it unchanged.
inline constexpr uint32_t kMaxSimdWidth = 16;

// Marks an internal particle slot that holds no caller particle (padding).
inline constexpr uint32_t kNoParticle = 0xFFFFFFFFu;

// Spring kinds (seed section 1.1). Each has its own compliance in the cloth instance.
enum class ConstraintKind : uint8_t { stretch = 0, shear = 1, bend = 2 };

// Coarse nodes that move one particle (ClothAsset::coarse_weight).
inline constexpr uint32_t kCoarseWeights = 4;

// How a batch's lanes find their particles.
enum class BatchLayout : uint8_t {
    run = 0,      // lane k joins particle slots a0 + k and b0 + k: plain vector loads, no gathers
    indexed = 1,  // lane k joins index_a[first + k] and index_b[first + k]: the general path
};

// A batch of particle-disjoint distance constraints: every lane can be projected at once.
// Batches are solved in array order (Gauss-Seidel across batches, Jacobi inside one).
struct ConstraintBatch {
    uint32_t first_lane = 0;  // into the asset's lane arrays
    uint32_t lane_count = 0;  // runs: a multiple of the asset's simd_width (padding lanes: lane_weight 0)
    uint32_t a0 = 0, b0 = 0;  // runs only: first particle slot of each side
    ConstraintKind kind = ConstraintKind::stretch;
    BatchLayout layout = BatchLayout::run;
    uint16_t colour = 0;  // batches of one colour touch disjoint particles (kOverflowColour: they may not)
};
// The colour of the constraints that fit no other: they share particles, so they are solved last,
// one lane at a time.
inline constexpr uint16_t kOverflowColour = 0xFFFF;

// Long-range attachments (Kim, Chentanez, Mueller 2012): particle particle0 + k may not move
// further than tether_rest[0][first_lane + k] from the pinned particle anchor[0] nor further than
// tether_rest[1][first_lane + k] from anchor[1] (its nearest and its farthest pinned particle, in
// either order; the same particle and length when it has one tether). Both limits are met exactly by one projection onto the
// intersection of the two balls, so the pass leaves no particle beyond either tether.
// anchor[0] == kTetherLaneAnchors: each lane has its own anchors, tether_anchor[side][first_lane + k]
// (tether_anchor() reads either kind).
inline constexpr uint32_t kTetherLaneAnchors = 0xFFFFFFFFu;
struct TetherBatch {
    uint32_t first_lane = 0;
    uint32_t lane_count = 0;  // a multiple of the asset's simd_width; padding lanes: infinite lengths
    uint32_t particle0 = 0;
    uint32_t anchor[2] = {0, 0};  // slots, or kTetherLaneAnchors (both)
};

// Triangles as a run for the wind pass: lane k is the triangle (a0 + k, b0 + k, c0 + k), so a lattice
// cloth's wind is computed with plain vector loads (its quads' corners sit in the parity planes at
// constant offsets, like its springs).
struct TriangleRun {
    uint32_t first_lane = 0;  // into wind_lane_weight
    uint32_t lane_count = 0;  // a multiple of the asset's simd_width; padding lanes have weight 0
    uint32_t a0 = 0, b0 = 0, c0 = 0;
};

// Seam points (seed paper 4.1.2 and 4.2, eq. 10): a seam point replaces its 2 or 3 source boundary
// particles (up to kMaxSeamSources where more panels meet); its target is the mean of the sources.
// Sewing moves the sources to the target and merges them.
inline constexpr uint32_t kMaxSeamSources = 8;

// Skin constraints (NvCloth's motion constraints and backstop, Jolt's skinned constraints): each
// bound free particle k stays within a ball around its skinned position and in front of the body's
// surface there. The skinned surface point P is body triangle triangle[k] of the offset hull at
// barycentric weights weight[3k..3k+2] (the hull interpolated from the previous step's pose to
// this one's, as attachments are), N the unit normal interpolated there from the hull's vertex
// normals (this step's pose). After the springs and tethers of every substep:
//   max distance: |x - (P + rest_offset_m N)| <= max_distance_m  (projected onto the ball)
//   backstop:     (x - P) . N >= -backstop_m                     (projected onto the half-space)
// The backstop is a half-space (a plane behind the hull point along N) rather than NvCloth's or
// Jolt's backstop sphere: on the thin limbs of a body a sphere large enough to be flat near the
// surface reaches through the limb (docs/decisions/2026-11-26-body-collision-models.md).
// weft-bake --body stores them in the asset (ClothAsset::skin); weft/attachments.h binds them.
struct SkinConstraints {
    uint32_t count = 0;
    const uint32_t* particle = nullptr;     // [count] caller particles, free (inverse mass > 0), each once
    const uint32_t* triangle = nullptr;     // [count] body triangles
    const float* weight = nullptr;          // [3 * count] barycentric on the triangle, sum 1
    const float* rest_offset_m = nullptr;   // [count] signed distance of the particle along N at rest
    const float* max_distance_m = nullptr;  // [count] >= 0: radius of the ball around P + rest_offset_m N
    const float* backstop_m = nullptr;      // [count] how far behind the hull (along -N) the particle may go
};

// A max distance this large limits nothing: the particle is held by its backstop alone (a hem
// hanging off the body, a panel the pattern lets swing: docs/pattern-format.md, "skin").
inline constexpr float kSkinNoMaxDistance_m = 1e3f;

// A finer mesh for rendering, bound to the cloth's triangles by weft-bake (--render-mesh,
// --render-subdivide) as APEX and Chaos bind theirs: render vertex v is the point of cloth triangle
// cloth_triangle[v] (an index into ClothAsset::triangles) at barycentric weights
// (1 - weight_1 - weight_2, weight_1, weight_2) of its corners, moved offset_m[v] along the
// normalised interpolated vertex normal there; its normal is that interpolated normal. Bound on the
// asset's start pose (the render mesh is authored in that space). Stored and validated; the step
// drives it in a world with WorldDesc::render_meshes (read_render_mesh).
struct RenderMesh {
    uint32_t vertex_count = 0;
    const uint32_t* cloth_triangle = nullptr;  // [vertex_count] < ClothAsset::triangle_count
    const float* weight_1 = nullptr;           // [vertex_count] barycentric weight of corner 1
    const float* weight_2 = nullptr;           // [vertex_count] of corner 2
    const float* offset_m = nullptr;           // [vertex_count] along the normal, metres
    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;       // [3 * triangle_count] render vertices, wound as the cloth
    const float* uv = nullptr;                 // [2 * vertex_count] texture coordinates
};

// The asset proper. Every array is indexed by internal particle slot unless said otherwise; slots
// are the order chosen at cook time so that constraint batches become contiguous runs.
struct ClothAsset {
    uint32_t particle_count = 0;  // caller particles
    uint32_t slot_count = 0;      // length of every per-slot array (>= particle_count, padded)
    const uint32_t* slot_of_particle = nullptr;  // [particle_count] caller index -> slot
    const uint32_t* particle_of_slot = nullptr;  // [slot_count] slot -> caller index or kNoParticle

    const float* start_x = nullptr;  // [slot_count] start positions, metres
    const float* start_y = nullptr;
    const float* start_z = nullptr;
    const float* inverse_mass = nullptr;  // [slot_count] 1/kg; 0 = pinned (and for padding slots)

    // Distance constraints, one lane each (runs include padding lanes).
    uint32_t lane_count = 0;
    const float* rest_length = nullptr;  // [lane_count] metres, measured on the rest (flat) mesh
    const float* lane_weight = nullptr;  // [lane_count] 1 for a real constraint, 0 for padding
    const uint32_t* index_a = nullptr;   // [lane_count] slots (runs too, for validation and metrics)
    const uint32_t* index_b = nullptr;
    uint32_t batch_count = 0;
    const ConstraintBatch* batches = nullptr;
    uint32_t colour_count = 0;

    // Real constraints per kind (padding excluded) and how many sit on runs.
    uint32_t constraint_count[kConstraintKindCount] = {};
    uint32_t constraints_on_runs = 0;

    uint32_t tether_lane_count = 0;
    const float* tether_rest[2] = {nullptr, nullptr};  // [tether_lane_count] metres, +inf on padding
    uint32_t tether_batch_count = 0;
    const TetherBatch* tether_batches = nullptr;
    uint32_t tethered_particles = 0;  // real lanes
    // Per-lane anchors (slots, pinned; padding lanes repeat a real one) for the batches whose
    // anchor[0] is kTetherLaneAnchors: tether_lane_count entries when any batch is one, else 0.
    uint32_t tether_anchor_lane_count = 0;
    const uint32_t* tether_anchor[2] = {nullptr, nullptr};

    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;  // [3 * triangle_count] slots, caller winding

    // The wind pass's view of the triangles: runs first (the first wind_run_triangles entries of
    // `triangles` are the runs' real lanes), then triangles[wind_run_triangles..] one at a time.
    uint32_t wind_run_count = 0;
    const TriangleRun* wind_runs = nullptr;
    uint32_t wind_lane_count = 0;
    const float* wind_lane_weight = nullptr;  // [wind_lane_count] 1 real, 0 padding
    // The area each triangle has on the rest mesh, m^2: wind_lane_count entries for the runs' lanes
    // (0 on padding), then one per triangle done one at a time (triangles[wind_run_triangles..]).
    // The wind force is computed on at most this area: a triangle stretched far past its rest shape
    // (a torn cloth at too small a budget) must not catch ever more wind and run away.
    const float* wind_rest_area = nullptr;
    uint32_t wind_run_triangles = 0;

    // The coarse level (hierarchical position-based dynamics, Mueller 2008): a sparse subset of the
    // particles (nodes, about coarse_spacing_m apart) joined by distance constraints, solved once per
    // substep before the fine sweeps; every particle then moves by the weighted displacement of up
    // to kCoarseWeights nearby nodes. It carries a correction across the cloth in one sweep that the
    // fine springs would need tens of sweeps to propagate. Absent when coarse_node_count is 0.
    uint32_t coarse_node_count = 0;
    const uint32_t* coarse_node_slot = nullptr;    // [coarse_node_count] the node's particle slot
    // The coarse solve keeps its nodes in node slots, as the fine level keeps particles in slots: on
    // a lattice, the node lattice's four parity planes, so that every family of coarse constraints
    // becomes contiguous runs for the same kernels as the fine springs; otherwise node j in slot j.
    uint32_t coarse_slot_count = 0;                // >= coarse_node_count, a multiple of kSimdWidth
    const uint32_t* coarse_slot_of_node = nullptr; // [coarse_node_count]
    const uint32_t* coarse_node_of_slot = nullptr; // [coarse_slot_count] (padding: node 0, never moved)
    const float* coarse_inverse_mass = nullptr;    // [coarse_slot_count] 1/kg, 0 = pinned node or padding
    // The coarse constraints in lanes and batches over node slots, laid out like the fine springs.
    uint32_t coarse_constraint_count = 0;          // real constraints (padding lanes excluded)
    uint32_t coarse_lane_count = 0;
    const float* coarse_rest_length = nullptr;     // [coarse_lane_count] metres
    const float* coarse_lane_weight = nullptr;     // [coarse_lane_count] 1 real, 0 padding
    const uint32_t* coarse_index_a = nullptr;      // [coarse_lane_count] node slots
    const uint32_t* coarse_index_b = nullptr;
    uint32_t coarse_batch_count = 0;
    const ConstraintBatch* coarse_batches = nullptr;
    uint32_t coarse_colour_count = 0;
    const uint32_t* coarse_weight_node[kCoarseWeights] = {};  // [slot_count] node (0 where weight is 0)
    const float* coarse_weight[kCoarseWeights] = {};          // [slot_count] partition of unity, 0 on pinned

    // Lattice form, set when every particle sits on one full rectangular lattice (the seed's grids):
    // nodes on a sub-lattice, node (I, J) = I * coarse_lattice_cols + J, and the displacement
    // interpolated bilinearly along each plane row with no gathers. The weights above then hold
    // the same bilinear weights (the general form, kept as the reference).
    uint32_t coarse_lattice_cols = 0;  // 0: use the general form
    uint32_t lattice_plane_rows = 0;   // slot of plane row r, column c: plane * rows * cols + r * cols + c
    uint32_t lattice_plane_cols = 0;
    const uint32_t* coarse_row_node[2] = {};  // [lattice_plane_rows] per row parity: coarse row I
    const float* coarse_row_frac[2] = {};     // [lattice_plane_rows] weight of coarse row I + 1
    const uint32_t* coarse_col_node[2] = {};  // [lattice_plane_cols] per column parity: coarse column J
    const float* coarse_col_frac[2] = {};     // [lattice_plane_cols] weight of coarse column J + 1

    // The lane width every padded count is a multiple of (CookOptions::simd_width): 8 or 16.
    uint32_t simd_width = kSimdWidth;

    // Garment data, all optional (null / 0 when absent) and in caller particle order, not slots.
    // Stored and validated; the step does not read them.
    const float* uv = nullptr;  // [2 * particle_count] texture coordinates (metres on the flat panel)
    uint32_t seam_point_count = 0;
    const uint32_t* seam_first = nullptr;   // [seam_point_count + 1] CSR offsets into seam_source
    uint32_t seam_source_count = 0;         // = seam_first[seam_point_count]
    const uint32_t* seam_source = nullptr;  // [seam_source_count] caller particles, 2..8 per point
    uint32_t panel_count = 0;
    const uint16_t* panel = nullptr;  // [particle_count] the sewing panel each particle came from
    bool has_fabric = false;          // false: `fabric` holds the defaults
    Fabric fabric;
    // Sewn seams (weft-bake --body, seed 4.2): every seam point merged into one particle with the
    // summed mass; the texture coordinates of all its sources are kept here (a renderer splits the
    // particle into one vertex per panel). A sewn asset has no unsewn seam points left.
    uint32_t sewn_point_count = 0;
    const uint32_t* sewn_particle = nullptr;  // [sewn_point_count] the particle the point became
    const uint32_t* sewn_uv_first = nullptr;  // [sewn_point_count + 1] CSR offsets, 2..8 apart
    uint32_t sewn_uv_count = 0;               // = sewn_uv_first[sewn_point_count]
    const float* sewn_uv = nullptr;           // [2 * sewn_uv_count] each source's uv (metres)
    // Body attachments (a waistband): particle attached_particle[k] is bound to triangle
    // attached_triangle[k] of the body the garment was dressed on, at barycentric weights
    // attached_weight[3k..3k+2] of its offset hull; such particles are pinned (inverse mass 0) and
    // follow the body (weft/body.h: attach_cloth_to_body).
    uint32_t attachment_count = 0;
    const uint32_t* attached_particle = nullptr;  // [attachment_count] caller particles, pinned
    const uint32_t* attached_triangle = nullptr;  // [attachment_count] body triangles
    const float* attached_weight = nullptr;       // [3 * attachment_count] barycentric, sum 1
    // Skin constraints baked on the dressed pose against the body's rest pose (weft-bake --body),
    // bound by weft/attachments.h: bind_asset_skin_constraints. skin.count 0: none.
    SkinConstraints skin;
    // A finer render mesh driven by the cloth (RenderMesh); vertex_count 0: none.
    RenderMesh render;

    uint32_t total_constraints() const {
        return constraint_count[0] + constraint_count[1] + constraint_count[2];
    }
};

// The pinned slot that lane k of tether batch t holds its particle to (side 0 or 1).
inline uint32_t tether_anchor(const ClothAsset& a, const TetherBatch& t, uint32_t k, uint32_t side) {
    return t.anchor[0] == kTetherLaneAnchors ? a.tether_anchor[side][t.first_lane + k] : t.anchor[side];
}

// Checks every invariant the solver relies on (indices in range, runs really contiguous and
// particle-disjoint, finite rest lengths, ...). The world calls it before it uses an asset.
Result validate_asset(const ClothAsset& asset);

}  // namespace weft
