#include "seed_scenes.h"

#include <cmath>
#include <cstdlib>

namespace weft::scenes {

ClothMeshDesc GridMesh::desc() const {
    ClothMeshDesc d;
    d.particle_count = uint32_t(positions.size());
    d.positions = positions.data();
    d.triangle_count = uint32_t(triangles.size() / 3);
    d.triangles = triangles.data();
    d.masses = masses.data();
    d.lattice = lattice.data();
    return d;
}

void GridGarment::apply(ClothMeshDesc& d) const {
    d.uv = uv.data();
    d.seam_point_count = uint32_t(seam_first.size() - 1);
    d.seam_first = seam_first.data();
    d.seam_source = seam_source.data();
    d.panel_count = 2;
    d.panel = panel.data();
    d.fabric = &fabric;
}

GridGarment make_grid_garment(const GridMesh& grid) {
    GridGarment g;
    const uint32_t n = grid.n;
    for (uint32_t r = 0; r < n; ++r)
        for (uint32_t c = 0; c < n; ++c) {
            g.uv.push_back(float(c) / float(n - 1));
            g.uv.push_back(float(r) / float(n - 1));
            g.panel.push_back(uint16_t(2 * c >= n));
        }
    g.seam_first.push_back(0);
    auto seam = [&](std::initializer_list<uint32_t> sources) {
        g.seam_source.insert(g.seam_source.end(), sources);
        g.seam_first.push_back(uint32_t(g.seam_source.size()));
    };
    seam({grid.index(0, 0), grid.index(0, n - 1), grid.index(n - 1, 0)});  // a corner where three meet
    for (uint32_t r = 1; r + 1 < n; ++r) seam({grid.index(r, 0), grid.index(r, n - 1)});
    g.fabric.areal_density_kg_m2 = 0.2f;
    g.fabric.compliance_m_per_n[2] = 1e-4f;  // soft in bending
    g.fabric.damping_per_s = 0.5f;
    g.fabric.thickness_m = 0.0005f;
    g.fabric.friction = 0.4f;
    return g;
}

GridMesh make_grid(uint32_t n, float width_m, float length_m, bool vertical, float y_m, float density_kg_m2) {
    GridMesh g;
    g.n = n;
    const float dx = width_m / float(n - 1), dz = length_m / float(n - 1);
    for (uint32_t r = 0; r < n; ++r) {
        for (uint32_t c = 0; c < n; ++c) {
            if (vertical) {  // rows go down from the top, columns out from the pole at x = 0
                g.positions.push_back({float(c) * dx, y_m - float(r) * dz, 0.0f});
            } else {
                g.positions.push_back({-0.5f * width_m + float(c) * dx, y_m, -0.5f * length_m + float(r) * dz});
            }
            g.lattice.push_back(int32_t(r));
            g.lattice.push_back(int32_t(c));
        }
    }
    g.masses.assign(size_t(n) * n, 0.0f);
    const float triangle_mass = density_kg_m2 * 0.5f * dx * dz;
    for (uint32_t r = 0; r + 1 < n; ++r) {
        for (uint32_t c = 0; c + 1 < n; ++c) {
            const uint32_t a = g.index(r, c), b = g.index(r, c + 1), d = g.index(r + 1, c), e = g.index(r + 1, c + 1);
            for (uint32_t v : {a, d, b, b, d, e}) g.triangles.push_back(v);
            for (uint32_t v : {a, d, b, b, d, e}) g.masses[v] += triangle_mass / 3.0f;  // eq. (9)
        }
    }
    return g;
}

const char* scene_name(SeedScene scene) {
    switch (scene) {
        case SeedScene::drape: return "drape";
        case SeedScene::flag: return "flag";
        case SeedScene::sphere: return "sphere";
    }
    return "unknown";
}

const char* config_name(Config config) { return config == Config::plain ? "plain" : "default"; }

void apply_config(Config config, uint32_t sweeps, SceneOptions& o) {
    o.sweeps = sweeps;
    if (config == Config::plain) {
        o.explicit_split = true;
        o.substeps = 1;
        o.iterations = sweeps;
        o.relaxation = 1.0f;
        o.tethers = false;
        o.coarse_level = false;
    } else {
        o.explicit_split = false;
        o.tethers = true;
    }
}

std::string make_seed_world(SeedScene scene, const SceneOptions& o, SeedWorld* out) {
    out->scene = scene;
    if (o.n < 2) return "n must be at least 2";
    switch (scene) {
        case SeedScene::drape:  // 2 m square, horizontal, the two corners of one edge pinned
            out->mesh = make_grid(o.n, 2.0f, 2.0f, false, 2.0f);
            out->mesh.masses[out->mesh.index(0, 0)] = 0.0f;
            out->mesh.masses[out->mesh.index(0, o.n - 1)] = 0.0f;
            break;
        case SeedScene::flag:  // 2 m x 1.2 m, pinned along its pole (column 0)
            out->mesh = make_grid(o.n, 2.0f, 1.2f, true, 3.0f, o.flag_density_kg_m2);
            for (uint32_t r = 0; r < o.n; ++r) out->mesh.masses[out->mesh.index(r, 0)] = 0.0f;
            break;
        case SeedScene::sphere:  // 2 m square, no pins, flat at y = 1 m above a 0.5 m sphere
            out->mesh = make_grid(o.n, 2.0f, 2.0f, false, 1.0f);
            for (Vec3& p : out->mesh.positions) p.x += o.sphere_offset_m;
            break;
    }
    CookOptions cook;
    cook.tethers_per_particle = o.tethers_per_particle;
    cook.coarse_spacing_m = o.coarse_spacing_m;
    if (Result r = cook_cloth(out->mesh.desc(), cook, &out->cooked); !r.ok()) return r.message;
    const ClothAsset& asset = out->cooked.asset();

    WorldDesc wd;
    wd.max_cloths = 0;
    reserve_cloth(wd, asset);
    wd.max_colliders = scene == SeedScene::sphere ? 1 : 0;
    wd.wind = scene == SeedScene::flag;
    wd.simd = o.simd;
    wd.profile = o.profile;
    const MemoryRequirements need = world_memory_requirements(wd);
    if (need.bytes == 0) return "bad world description";
    out->memory = {static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment)), std::free};
    if (Result r = create_world(wd, out->memory.get(), need.bytes, &out->world); !r.ok()) return r.message;

    ClothDesc cd;
    cd.asset = &asset;
    cd.sweeps = o.sweeps;
    cd.policy = o.explicit_split ? BudgetPolicy::explicit_split : BudgetPolicy::automatic;
    cd.substeps = o.substeps;
    cd.iterations = o.iterations;
    cd.tethers = o.tethers;
    cd.tethers_before_sweeps = o.tethers_before_sweeps;
    cd.relaxation = o.relaxation;
    cd.coarse_level = o.coarse_level;
    cd.damping_per_s = o.damping_per_s;
    cd.projection = o.projection;
    cd.compliance_m_per_n[2] = o.bend_compliance_m_per_n;
    if (Result r = add_cloth(out->world, cd, &out->cloth); !r.ok()) return r.message;
    if (scene == SeedScene::sphere) {
        ColliderDesc sphere;
        sphere.shape = ColliderShape::sphere;
        sphere.p0 = {0.0f, 0.0f, 0.0f};
        sphere.radius_m = 0.5f;
        sphere.inflation_m = o.sphere_inflation_m;
        sphere.friction = o.sphere_friction;
        ColliderId id;
        if (Result r = add_collider(out->world, sphere, &id); !r.ok()) return r.message;
    }
    if (scene == SeedScene::flag) {
        // Along +x, 10 degrees off the flag's plane: wind exactly in the plane of a flat flag meets
        // it edge-on (theta = 0, no drag, and no side for the lift), and nothing would ever tilt it.
        const float yaw = 10.0f * 3.14159265f / 180.0f;
        const Vec3 wind{o.wind_m_s * std::cos(yaw), 0.0f, o.wind_m_s * std::sin(yaw)};
        if (Result r = set_wind(out->world, wind); !r.ok()) return r.message;
    }
    return {};
}

}  // namespace weft::scenes
