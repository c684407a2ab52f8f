#include "render/scene_snapshot.h"

namespace weft::render {

Snapshot snapshot_of_scene(const scenes::Scene& scene, const scenes::SceneWorld& world) {
    Snapshot s;
    s.colliders = scene.colliders;
    std::vector<std::vector<Vec3>> positions = scenes::cloth_positions(world);
    for (size_t i = 0; i < world.cloths.size(); ++i) {
        const ClothAsset& asset = *world.cloths[i].asset;
        ClothSurface& cloth = s.cloths.emplace_back();
        cloth.positions = std::move(positions[i]);
        cloth.triangles = scenes::caller_triangles(asset);
        if (asset.uv) {
            cloth.uv.assign(asset.uv, asset.uv + 2 * size_t(asset.particle_count));
        } else {
            std::vector<Vec3> rest(asset.particle_count);
            for (uint32_t p = 0; p < asset.particle_count; ++p) {
                const uint32_t slot = asset.slot_of_particle[p];
                rest[p] = {asset.start_x[slot], asset.start_y[slot], asset.start_z[slot]};
            }
            cloth.uv = planar_uv(rest);
        }
    }
    if (world.body) {  // in its pose now (animate_body), else at rest
        const scenes::SceneBody& b = *world.body;
        s.bodies.push_back({b.pose.empty() ? b.rest : b.pose, b.triangles});
    }
    return s;
}

}  // namespace weft::render
