#include "common/skin_binding.h"

#include <vector>

namespace weft::scenes {

std::string bind_skin(World* world, ClothId cloth, BodyId body, const SkinBindingOptions& options, SkinBinding* out) {
    BodyView b;
    ClothView c;
    if (Result r = view_body(world, body, &b); !r.ok()) return r.message;
    if (Result r = view_cloth(world, cloth, &c); !r.ok()) return r.message;
    // The cloth's state in caller order, as cook_skin_binding takes a dressed garment.
    const ClothAsset& asset = *c.asset;
    std::vector<Vec3> positions(asset.particle_count);
    std::vector<float> inverse_masses(asset.particle_count);
    for (uint32_t p = 0; p < asset.particle_count; ++p) {
        const uint32_t s = asset.slot_of_particle[p];
        positions[p] = {c.x[s], c.y[s], c.z[s]};
        inverse_masses[p] = c.inverse_mass[s];
    }
    std::vector<uint32_t> triangles(3 * size_t(asset.triangle_count));
    if (!triangles.empty())
        if (Result r = read_triangles(asset, triangles.data(), uint32_t(triangles.size())); !r.ok()) return r.message;
    SkinBindingDesc desc;
    desc.particle_count = asset.particle_count;
    desc.positions = positions.data();
    desc.inverse_masses = inverse_masses.data();
    desc.triangles = triangles.empty() ? nullptr : triangles.data();
    desc.triangle_count = asset.triangle_count;
    desc.options = options;
    if (Result r = cook_skin_binding(b, desc, out); !r.ok()) return r.message;
    if (Result r = bind_skin_constraints(world, cloth, body, out->constraints()); !r.ok()) return r.message;
    return {};
}

}  // namespace weft::scenes
