// What a game reads of a cloth asset: its counts, fabric, start pose, texture coordinates,
// triangles and seams, all in the caller's particle order (the order of read_positions and
// read_normals). A game holds a ClothAsset (load_asset_in_place fills one) but never needs its
// solver layout (slots, lanes, batches: weft/cloth_asset.h, for cooking tools and debuggers).
#pragma once

#include <cstdint>

#include "weft/types.h"

namespace weft {

struct ClothAsset;

// The fabric a garment is made of (its cloth instances start from these). All values >= 0 and finite.
// The defaults are ClothDesc's (world.h): hard springs, damping 1/s, so an asset without a fabric
// steps as before; density, thickness and friction default to cotton on a frictionless body.
struct Fabric {
    float areal_density_kg_m2 = 0.150f;                // mass per rest area (cotton; Penava et al. 2014)
    float compliance_m_per_n[3] = {0.0f, 0.0f, 0.0f};  // XPBD compliance: stretch, shear, bend
    float damping_per_s = 1.0f;                        // dv/dt = -damping * v
    float thickness_m = 0.0f;                          // collision thickness of the fabric
    float friction = 0.0f;                             // Coulomb coefficient against colliders
};

// A read-only view into an asset (no copy: valid while the asset is). Arrays are null when absent.
struct AssetView {
    uint32_t particle_count = 0;
    uint32_t triangle_count = 0;
    bool has_fabric = false;  // false: `fabric` holds the defaults
    Fabric fabric;
    const float* uv = nullptr;  // [2 * particle_count] texture coordinates, metres on the flat panel
    uint32_t panel_count = 0;
    const uint16_t* panel = nullptr;  // [particle_count] the sewing panel each particle came from
    // Sewn seams: particle sewn_particle[k] was merged from several panels; a renderer splits it
    // into one vertex per source, at texture coordinates sewn_uv[2j..2j+1], j in
    // [sewn_uv_first[k], sewn_uv_first[k + 1]).
    uint32_t sewn_point_count = 0;
    const uint32_t* sewn_particle = nullptr;
    const uint32_t* sewn_uv_first = nullptr;
    const float* sewn_uv = nullptr;
    uint32_t attachment_count = 0;       // particles bound to a body (attach_cloth_to_body)
    uint32_t skin_constraint_count = 0;  // baked skin constraints (bind_asset_skin_constraints)
    // The finer render mesh weft-bake bound to the cloth (read_render_mesh drives it); 0: none.
    uint32_t render_vertex_count = 0;
    uint32_t render_triangle_count = 0;
    const uint32_t* render_triangles = nullptr;  // [3 * render_triangle_count] render vertices
    const float* render_uv = nullptr;            // [2 * render_vertex_count] texture coordinates
};
AssetView view_asset(const ClothAsset& asset);

// The start pose, metres: count = particle_count.
Result read_start_positions(const ClothAsset& asset, Vec3* out, uint32_t count);
// The triangles as caller particle indices, wound as the mesh that was cooked (their order may
// differ: the wind pass's runs come first): count = 3 * triangle_count.
Result read_triangles(const ClothAsset& asset, uint32_t* out, uint32_t count);

}  // namespace weft
