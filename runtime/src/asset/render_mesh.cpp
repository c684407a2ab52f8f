// What a game reads of an asset, in the caller's particle order (weft/asset_view.h).
#include "error.h"
#include "weft/cloth_asset.h"

namespace weft {

AssetView view_asset(const ClothAsset& a) {
    AssetView v;
    v.particle_count = a.particle_count;
    v.triangle_count = a.triangle_count;
    v.has_fabric = a.has_fabric;
    v.fabric = a.fabric;
    v.uv = a.uv;
    v.panel_count = a.panel_count;
    v.panel = a.panel;
    v.sewn_point_count = a.sewn_point_count;
    v.sewn_particle = a.sewn_particle;
    v.sewn_uv_first = a.sewn_uv_first;
    v.sewn_uv = a.sewn_uv;
    v.attachment_count = a.attachment_count;
    v.skin_constraint_count = a.skin.count;
    v.render_vertex_count = a.render.vertex_count;
    v.render_triangle_count = a.render.triangle_count;
    v.render_triangles = a.render.triangles;
    v.render_uv = a.render.uv;
    return v;
}

Result read_start_positions(const ClothAsset& asset, Vec3* out, uint32_t count) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (count != asset.particle_count)
        return make_error(ErrorCode::out_of_range, "count %u, asset has %u particles", count, asset.particle_count);
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t s = asset.slot_of_particle[i];
        out[i] = {asset.start_x[s], asset.start_y[s], asset.start_z[s]};
    }
    return {};
}

Result read_triangles(const ClothAsset& asset, uint32_t* out, uint32_t count) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (uint64_t(count) != 3 * uint64_t(asset.triangle_count))
        return make_error(ErrorCode::out_of_range, "count %u, asset has %u triangles (3 indices each)", count,
                          asset.triangle_count);
    for (uint32_t k = 0; k < count; ++k) out[k] = asset.particle_of_slot[asset.triangles[k]];
    return {};
}

}  // namespace weft
