// Per-particle normals for renderers (world.h: compute_normals), from positions in caller order.
#include <cmath>

#include "world_internal.h"

namespace weft {

Result compute_normals(const ClothAsset& asset, const Vec3* positions, Vec3* out_normals, uint32_t count) {
    if (positions == nullptr || out_normals == nullptr)
        return make_error(ErrorCode::invalid_argument, "positions or out_normals is null");
    if (count != asset.particle_count)
        return make_error(ErrorCode::out_of_range, "count %u, the asset has %u particles", count, asset.particle_count);
    for (uint32_t i = 0; i < count; ++i) out_normals[i] = {};
    // A cross product's length is twice its triangle's area: summing them weights by area.
    for (uint32_t t = 0; t < asset.triangle_count; ++t) {
        const uint32_t* slot = asset.triangles + 3 * size_t(t);
        const uint32_t i0 = asset.particle_of_slot[slot[0]], i1 = asset.particle_of_slot[slot[1]],
                       i2 = asset.particle_of_slot[slot[2]];
        if (i0 >= count || i1 >= count || i2 >= count) continue;  // never in a validated asset
        const Vec3 p0 = positions[i0], p1 = positions[i1], p2 = positions[i2];
        const float ex = p1.x - p0.x, ey = p1.y - p0.y, ez = p1.z - p0.z;
        const float fx = p2.x - p0.x, fy = p2.y - p0.y, fz = p2.z - p0.z;
        const Vec3 n{ey * fz - ez * fy, ez * fx - ex * fz, ex * fy - ey * fx};
        for (const uint32_t i : {i0, i1, i2}) {
            out_normals[i].x += n.x;
            out_normals[i].y += n.y;
            out_normals[i].z += n.z;
        }
    }
    bool finite = true;
    for (uint32_t i = 0; i < count; ++i) {
        Vec3& n = out_normals[i];
        const float length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        finite = finite && std::isfinite(length);
        if (length > 0.0f) n = {n.x / length, n.y / length, n.z / length};
    }
    if (!finite) return make_error(ErrorCode::non_finite, "a position is not finite");
    return {};
}

}  // namespace weft
