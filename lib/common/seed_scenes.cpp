#include "common/seed_scenes.h"

#include <cmath>
#include <cstdlib>

namespace weft::scenes {

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
        o.coarse_level = CoarseLevel::off;
        o.contact_tethers = false;
    } else {
        o.explicit_split = false;
        o.tethers = true;
    }
}

Scene seed_scene(SeedScene which, const SceneOptions& o) {
    Scene scene;
    scene.name = scene_name(which);
    scene.simd = o.simd;
    scene.profile = o.profile;
    scene.normals = o.normals;
    ClothSpec cloth;
    cloth.name = scene.name;
    GridSource grid;
    grid.n = o.n;
    switch (which) {
        case SeedScene::drape:  // 2 m square, horizontal at 2 m, the two corners of one edge pinned
            grid.pins = {{0, 0}, {0, -1}};
            break;
        case SeedScene::flag:  // 2 m x 1.2 m, top edge at 3 m, pinned along its pole (column 0)
            grid.length_m = 1.2f;
            grid.vertical = true;
            grid.y_m = 3.0f;
            grid.areal_density_kg_m2 = o.flag_density_kg_m2;
            grid.pin_columns = {0};
            break;
        case SeedScene::sphere: {  // 2 m square, no pins, flat at y = 1 m above a 0.5 m sphere
            grid.y_m = 1.0f;
            grid.offset_m = {o.sphere_offset_m, 0.0f, 0.0f};
            ColliderDesc sphere;
            sphere.shape = ColliderShape::sphere;
            sphere.p0 = {0.0f, 0.0f, 0.0f};
            sphere.radius_m = 0.5f;
            sphere.inflation_m = o.sphere_inflation_m;
            sphere.friction = o.sphere_friction;
            scene.colliders.push_back(sphere);
            break;
        }
    }
    if (which == SeedScene::flag) {
        // Along +x, 10 degrees off the flag's plane: wind exactly in the plane of a flat flag meets
        // it edge-on (theta = 0, no drag, and no side for the lift), and nothing would ever tilt it.
        const float yaw = 10.0f * 3.14159265f / 180.0f;
        scene.wind_m_s = Vec3{o.wind_m_s * std::cos(yaw), 0.0f, o.wind_m_s * std::sin(yaw)};
    }
    cloth.grid = grid;
    cloth.cook.tethers_per_particle = o.tethers_per_particle;
    cloth.cook.coarse_spacing_m = o.coarse_spacing_m;
    ClothDesc& cd = cloth.desc;
    cd.sweeps = o.sweeps;
    cd.policy = o.explicit_split ? BudgetPolicy::explicit_split : BudgetPolicy::automatic;
    cd.substeps = o.substeps;
    cd.iterations = o.iterations;
    cd.tethers = o.tethers;
    cd.tethers_before_sweeps = o.tethers_before_sweeps;
    cd.relaxation = o.relaxation;
    cd.coarse_level = o.coarse_level;
    cd.coarse_iterations = o.coarse_iterations;
    cd.contact_tethers = o.contact_tethers;
    cd.damping_per_s = o.damping_per_s;
    cd.projection = o.projection;
    cd.compliance_m_per_n[0] = o.stretch_compliance_m_per_n;
    cd.compliance_m_per_n[1] = o.shear_compliance_m_per_n;
    cd.compliance_m_per_n[2] = o.bend_compliance_m_per_n;
    scene.cloths.push_back(std::move(cloth));
    return scene;
}

std::string make_seed_world(SeedScene which, const SceneOptions& o, SeedWorld* out) {
    out->scene = which;
    if (o.n < 2) return "n must be at least 2";
    SceneWorld built;
    if (std::string error = build_scene(seed_scene(which, o), &built); !error.empty()) return error;
    // Moving the vectors keeps their buffers, so the world's pointer to the asset stays valid.
    out->mesh = std::move(built.cloths[0].mesh);
    out->cooked = std::move(built.cloths[0].cooked);
    out->memory = std::move(built.memory);
    out->world = built.world;
    out->cloth = built.cloths[0].id;
    out->dt_s = built.dt_s;
    return {};
}

Scene heap_scene() {
    Scene s;
    s.name = "heap";
    s.dt_s = 1.0f / 60.0f;
    ClothSpec c;
    c.name = "sheet";
    GridSource g;
    g.n = 50;
    g.width_m = g.length_m = 1.0f;
    g.vertical = true;
    g.y_m = 1.14f;
    g.offset_m = {-0.5f, 0.0f, 0.0f};
    c.grid = g;
    c.desc.policy = BudgetPolicy::explicit_split;
    c.desc.substeps = 8;
    c.desc.iterations = 1;
    s.cloths.push_back(c);
    ColliderDesc bar;
    bar.shape = ColliderShape::capsule;
    bar.p0 = {-0.7f, 0.05f, -0.03f};
    bar.p1 = {0.7f, 0.05f, -0.03f};
    bar.radius_m = 0.05f;
    bar.inflation_m = 0.004f;
    bar.friction = 0.3f;
    s.colliders.push_back(bar);
    ColliderDesc ground;
    ground.shape = ColliderShape::plane;
    ground.p0 = {0.0f, 0.0f, 0.0f};
    ground.p1 = {0.0f, 1.0f, 0.0f};
    ground.inflation_m = 0.004f;
    ground.friction = 0.5f;
    s.colliders.push_back(ground);
    return s;
}

}  // namespace weft::scenes
