// An asset's start pose and triangles in the caller's particle order (weft/cloth_asset.h).
#include "error.h"
#include "weft/cloth_asset.h"

namespace weft {

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
