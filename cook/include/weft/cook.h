// Cooking (the library Weft::cook, weft_cook): what weft-bake and a game's own tools call to turn
// meshes into assets. It allocates and may take seconds, so it runs offline or at load time, never
// in a frame; the results own their arrays (std::vector) and point a ClothAsset into them. A game
// that only loads baked assets needs weft/weft.h alone.
#pragma once

#include <vector>

#include "weft/debug.h"
#include "weft/cloth_asset.h"

namespace weft {

// ---------------------------------------------------------------------------------------------
// A cloth: an in-memory triangle mesh -> a ClothAsset.

struct ClothMeshDesc {
    uint32_t particle_count = 0;
    const Vec3* positions = nullptr;  // [particle_count] start pose, metres
    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;  // [3 * triangle_count] caller particle indices

    // Exactly one of these: kg per particle, or 1/kg per particle. Mass 0 / inverse mass 0 pins.
    const float* masses = nullptr;
    const float* inverse_masses = nullptr;

    // Optional rest pose (e.g. the flat 2-D panel, z = 0); rest lengths are measured on it.
    const Vec3* rest_positions = nullptr;

    // Optional integer lattice coordinates (i, j) per particle, 2 ints each; (-1, -1) for none.
    // Particles on a lattice are ordered in four parity planes so that every spring family of the
    // lattice becomes contiguous runs (docs/architecture.md). Without it the caller order is kept.
    const int32_t* lattice = nullptr;
    // Optional slot stride of a parity plane's rows (lattice rows 2r and 2r + 1 share plane row r):
    // plane node (r, c) goes to slot r * stride + c of its plane. 0: the lattice's own width in
    // plane columns (a box). A narrower stride lets each plane row run on into the next (a helix):
    // weft-bake packs garment panels for one so that slanted sides leave no holes at row ends
    // (docs/pattern-format.md). Coordinates that meet at one slot go last, like duplicates.
    uint32_t lattice_plane_stride = 0;

    // Optional garment data, copied into the asset as given (ClothAsset documents each).
    const float* uv = nullptr;  // [2 * particle_count]
    uint32_t seam_point_count = 0;
    const uint32_t* seam_first = nullptr;   // [seam_point_count + 1], seam_first[0] = 0, 2..8 apart
    const uint32_t* seam_source = nullptr;  // [seam_first[seam_point_count]] caller particles
    uint32_t panel_count = 0;
    const uint16_t* panel = nullptr;  // [particle_count], each < panel_count
    const Fabric* fabric = nullptr;   // null: the defaults
    uint32_t sewn_point_count = 0;    // sewn seams, copied as given (ClothAsset documents them)
    const uint32_t* sewn_particle = nullptr;
    const uint32_t* sewn_uv_first = nullptr;
    const float* sewn_uv = nullptr;
    uint32_t attachment_count = 0;    // body attachments, copied as given (ClothAsset documents them)
    const uint32_t* attached_particle = nullptr;
    const uint32_t* attached_triangle = nullptr;
    const float* attached_weight = nullptr;
    SkinConstraints skin;             // skin constraints, copied as given (ClothAsset documents them)

    // Optional rest shape per triangle: its three corners on the flat panels, [3 * triangle_count]
    // (a sewn garment's particle on a seam has one flat position per panel). When given, a
    // stretch/shear spring's rest length is its edge's length in its triangles (their mean), a bend
    // spring's the distance of the two opposite corners with both triangles unfolded flat about
    // their edge; rest_positions (or positions) then serve only tethers and the coarse level.
    const Vec3* rest_corners = nullptr;
};

// The constraint pass's estimated cost per sweep, ns: every run lane (padding included) at
// kRunLaneNs, every indexed lane at kIndexedLaneNs. Measured with `weft-bench baked` on the AVX2
// path: an indexed lane costs about 7.6 run lanes. The cook cuts runs by them; the baker ranks its
// packings by them (tools/bake/bake.h: run_cost_ns).
inline constexpr double kRunLaneNs = 0.71, kIndexedLaneNs = 5.4;

struct CookOptions {
    // Tethers per free particle: 1 = to its nearest pinned particle, 2 = also to its farthest (two
    // anchors far apart bound it in two directions); straight-line lengths on the rest mesh, or
    // with rest_corners (a sewn garment) lengths along the flat panels, never shorter than the
    // straight line in any pose. 0 = no tethers in the asset.
    uint32_t tethers_per_particle = 2;
    // Allow runs to bridge gaps of up to this many missing constraints with padding lanes.
    uint32_t max_run_gap = 4;
    // Shortest run worth a SIMD batch; shorter sequences go to the indexed path.
    uint32_t min_run_lanes = 2 * kSimdWidth;
    // Spacing of the coarse level's nodes along the mesh, metres; 0 = no coarse level.
    float coarse_spacing_m = 0.13f;
    // Lanes every run and padded count is a multiple of: kSimdWidth (8), or 16 for a 16-wide target.
    uint32_t simd_width = kSimdWidth;
};

// Owns the arrays a SkinConstraints points into (cook_skin_binding fills it; CookedCloth keeps one).
struct SkinBinding {
    std::vector<uint32_t> particle, triangle;
    std::vector<float> weight, rest_offset_m, max_distance_m, backstop_m;
    SkinConstraints constraints() const {
        if (particle.empty()) return {};
        return {uint32_t(particle.size()), particle.data(),      triangle.data(), weight.data(),
                rest_offset_m.data(),      max_distance_m.data(), backstop_m.data()};
    }
};

// Owns the arrays a cooked ClothAsset points into. Move-only.
class CookedCloth {
public:
    CookedCloth() = default;
    CookedCloth(const CookedCloth&) = delete;
    CookedCloth& operator=(const CookedCloth&) = delete;
    // Moving a vector keeps its buffer, so the moved asset's pointers stay valid.
    CookedCloth(CookedCloth&&) noexcept = default;
    CookedCloth& operator=(CookedCloth&&) noexcept = default;

    const ClothAsset& asset() const { return asset_; }

    // Storage; filled by cook_cloth. Public so tools can serialise it.
    std::vector<uint32_t> slot_of_particle, particle_of_slot;
    std::vector<float> start_x, start_y, start_z, inverse_mass;
    std::vector<float> rest_length, lane_weight;
    std::vector<uint32_t> index_a, index_b;
    std::vector<ConstraintBatch> batches;
    std::vector<float> tether_rest[2];
    std::vector<TetherBatch> tether_batches;
    std::vector<uint32_t> tether_anchor[2];
    std::vector<uint32_t> triangles;
    std::vector<TriangleRun> wind_runs;
    std::vector<float> wind_lane_weight, wind_rest_area;
    uint32_t wind_run_triangles = 0;
    std::vector<uint32_t> coarse_node_slot, coarse_slot_of_node, coarse_node_of_slot;
    std::vector<float> coarse_inverse_mass;
    std::vector<float> coarse_rest_length, coarse_lane_weight;
    std::vector<uint32_t> coarse_index_a, coarse_index_b;
    std::vector<ConstraintBatch> coarse_batches;
    uint32_t coarse_colour_count = 0, coarse_constraint_count = 0;
    std::vector<uint32_t> coarse_weight_node[kCoarseWeights];
    std::vector<float> coarse_weight[kCoarseWeights];
    uint32_t coarse_lattice_cols = 0, lattice_plane_rows = 0, lattice_plane_cols = 0;
    std::vector<uint32_t> coarse_row_node[2], coarse_col_node[2];
    std::vector<float> coarse_row_frac[2], coarse_col_frac[2];
    uint32_t simd_width = kSimdWidth;
    std::vector<float> uv;
    std::vector<uint32_t> seam_first, seam_source;
    std::vector<uint16_t> panel;
    uint32_t panel_count = 0;
    bool has_fabric = false;
    Fabric fabric;
    std::vector<uint32_t> sewn_particle, sewn_uv_first;
    std::vector<float> sewn_uv;
    std::vector<uint32_t> attached_particle, attached_triangle;
    std::vector<float> attached_weight;
    SkinBinding skin;
    // The render mesh (bind_render_mesh fills them; ClothAsset::render documents them).
    std::vector<uint32_t> render_cloth_triangle, render_triangles;
    std::vector<float> render_weight_1, render_weight_2, render_offset, render_uv;

    // Points asset() at the vectors; call after changing them.
    void refresh_asset(uint32_t particle_count, uint32_t colour_count, const uint32_t counts[3],
                       uint32_t on_runs, uint32_t tethered_particles);
    void refresh_asset() {
        const ClothAsset a = asset_;
        refresh_asset(a.particle_count, a.colour_count, a.constraint_count, a.constraints_on_runs,
                      a.tethered_particles);
    }

private:
    ClothAsset asset_;
};

// Derives stretch/shear springs on every edge and a bend spring across every interior edge (seed
// section 1.1), orders particles for contiguous runs, colours the constraints into batches and
// computes tethers. Fails with a message on malformed meshes (bad indices, NaN, negative mass).
Result cook_cloth(const ClothMeshDesc& mesh, const CookOptions& options, CookedCloth* out);

// ---------------------------------------------------------------------------------------------
// Render meshes (ClothAsset::render): a finer mesh authored in the space of the cloth's start pose
// (the flat layout, or the dressed pose of weft-bake --body), bound to the cloth's triangles.

struct RenderMeshDesc {
    uint32_t vertex_count = 0;
    const Vec3* positions = nullptr;      // [vertex_count] metres, the start pose's space
    const float* uv = nullptr;            // [2 * vertex_count]; null: zeros
    uint32_t triangle_count = 0;
    const uint32_t* triangles = nullptr;  // [3 * triangle_count] render vertices
};

// Owns the arrays of a render mesh made in memory (subdivide_cloth_mesh, an OBJ reader).
struct RenderMeshSource {
    std::vector<Vec3> positions;
    std::vector<float> uv;
    std::vector<uint32_t> triangles;
    RenderMeshDesc desc() const {
        return {uint32_t(positions.size()), positions.data(), uv.empty() ? nullptr : uv.data(),
                uint32_t(triangles.size() / 3), triangles.data()};
    }
};

// The cloth's own mesh on its start pose, every triangle cut into four at its edges' midpoints
// `levels` times (0: the cloth's mesh itself). A vertex is split where its triangles' uv differ (a
// sewn seam particle: each triangle takes its own panel's uv, as the tangents do).
Result subdivide_cloth_mesh(const ClothAsset& asset, uint32_t levels, RenderMeshSource* out);

// Binds each render vertex to the closest cloth triangle on the start pose (a uniform grid over the
// triangles): its barycentric weights there and its signed offset along the interpolated vertex
// normal (the normals pass's, area-weighted), refined twice so that the runtime's reconstruction
// lands back on the vertex. A vertex whose reconstruction misses it by more than 1 mm (past the
// cloth's edge) or that lies more than 1 m off the cloth is refused. Stores the mesh in `cloth`
// (refresh_asset is called).
// `max_error_m` (optional): the largest distance between a vertex and its reconstruction at rest.
Result bind_render_mesh(const RenderMeshDesc& mesh, CookedCloth* cloth, double* max_error_m = nullptr);

// ---------------------------------------------------------------------------------------------
// Skin constraints: weft-bake --body runs it on the dressed garment and stores the result in the
// asset; a tool may run it for an asset baked without them.

struct SkinBindingOptions {
    // Radius of the ball around the particle's skinned rest position, metres (NvCloth's max
    // distance), before the particle's scale. docs/decisions/2026-11-26-body-collision-models.md.
    float max_distance_m = 0.03f;
    // Particles further than this off the hull at rest (a skirt's hem, a loose sleeve) hang free:
    // no max distance (a ball around a point skinned to the thigh drags the hem with the leg).
    float loose_offset_m = 0.02f;
    // How far behind the offset hull a particle may go, metres; negative: that far in front. The
    // backstop plane is tangent at the bound point only, and a particle sliding along it sinks into
    // a concave hull, so it stands 1.5 mm in front.
    float backstop_m = -0.0015f;
    // How far inside the hull a particle may end up by sliding within its max distance along its
    // backstop plane, where the hull curves up in front of that plane (a shoulder's edge, the neck's
    // foot): each particle's max distance is cut so that no point of the hull it can reach stands
    // more than this above the plane's height it may sink to. Metres, > 0.
    float max_sink_m = 0.001f;
    // A garment hung from pinned particles (attachments: a skirt's waistband) keeps its max
    // distances only this far from a pin along its edges (the hips under a waistband); further on it
    // hangs on its backstops alone (default_max_distance_scales). Metres.
    float hung_reach_m = 0.2f;
};

// The garment in its dressed pose on the body's rest pose, caller particle order.
struct SkinBindingDesc {
    uint32_t particle_count = 0;
    const Vec3* positions = nullptr;        // [particle_count] the dressed pose, metres
    const float* inverse_masses = nullptr;  // [particle_count] 0: pinned, not bound
    // Optional [particle_count] factor on max_distance_m (the pattern's per-panel "skin"
    // max_distance_scale); 0 gives that particle no max distance, only its backstop. Null: the
    // default, default_max_distance_scales.
    const float* max_distance_scale = nullptr;
    // The garment's triangles (3 caller particle indices each): how far along the cloth a particle of
    // a hung garment lies from its pins. Null: every particle of a hung garment hangs free.
    const uint32_t* triangles = nullptr;
    uint32_t triangle_count = 0;
    SkinBindingOptions options;
};

// Binds every free particle to the closest triangle of `body`'s offset hull as it is now (its rest
// pose: view_body), at the closest point's barycentric weights, and measures its signed distance
// along the interpolated normal there (the rest offset) as the step will. An exact closest-triangle
// search over a uniform grid of the triangles, in double precision: offline work. Deterministic:
// the same input gives the same arrays (of equally close triangles, the lowest index).
Result cook_skin_binding(const BodyView& body, const SkinBindingDesc& desc, SkinBinding* out);

// Each particle's factor on max_distance_m where nothing says otherwise ([desc.particle_count]):
// 1 for a garment the body holds up (no pinned particle: a tee on the shoulders). A garment hung
// from pinned particles (attachments: a skirt's waistband): 1 within options.hung_reach_m of a pin
// along its edges (shortest paths in the dressed pose), 0 further on, where it keeps only its
// backstops: its tethers hold it from its pins, and a ball around a point skinned to the leg its hem
// touched at rest drags the hem with that leg (docs/decisions/2026-12-07-hung-garments-swing.md).
std::vector<float> default_max_distance_scales(const SkinBindingDesc& desc);

// The floor a garment is dressed on (weft-bake --body): a plane facing up through the body's
// lowest vertex (its soles), inflated by the hull's thickness, with the body's friction. A game or
// scene that stands the body on it gives a floor-length hem the support it was draped on.
ColliderDesc ground_under_body(const Vec3* positions, uint32_t vertex_count, float thickness_m, float friction);

// ---------------------------------------------------------------------------------------------
// Diagnostics of a cooked asset's SIMD layout (weft-bake --runs, weft-bench corpus).

// Padding: SIMD lanes that do nothing, there so that every run is a whole number of SIMD groups.
// padding_ratio = padding lanes / all lanes executed, over one sweep of every batched pass the step
// runs for this asset (docs/asset-format.md): the constraint batches (lane_count lanes: run lanes,
// padding included, and indexed lanes; padding = weight 0), the coarse level (coarse_lane_count,
// weight 0), the tethers (tether_lane_count, both lengths +inf) and the wind (its run lanes plus
// the triangles it gathers or takes one at a time; padding = weight-0 run lanes). Padding slots
// are not lanes. A step of k iterations runs the constraint lanes k times per substep and the other
// passes once: `constraints` alone is the ratio for large k.
struct LanePadding {
    struct Pass {
        uint64_t padding_lanes = 0, all_lanes = 0;
        double ratio() const { return all_lanes > 0 ? double(padding_lanes) / double(all_lanes) : 0.0; }
    };
    Pass constraints, coarse, tethers, wind;
    uint64_t padding_lanes = 0, all_lanes = 0;  // the four passes together
    double ratio() const { return all_lanes > 0 ? double(padding_lanes) / double(all_lanes) : 0.0; }
};
LanePadding lane_padding(const ClothAsset& asset);

}  // namespace weft
