#include "viewer/session.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "common/metrics.h"
#include "common/scene_json.h"
#include "render/scene_snapshot.h"

namespace weft::viewer {

PassGroup group_of(Pass pass) {
    switch (pass) {
        case Pass::wind: return PassGroup::wind;
        case Pass::integrate: return PassGroup::integrate;
        case Pass::collide:
        case Pass::body: return PassGroup::collisions;
        default: return PassGroup::constraints;  // coarse level, springs, tethers
    }
}

std::string Session::open(const std::string& path, const std::vector<std::string>& asset_dirs) {
    asset_dirs_ = asset_dirs;
    scene_ = {};
    if (path.ends_with(".weft")) {
        namespace fs = std::filesystem;
        scene_.name = fs::path(path).stem().string();
        scenes::ClothSpec& cloth = scene_.cloths.emplace_back();
        cloth.name = scene_.name;
        cloth.asset_path = fs::absolute(path).string();
        // A ground plane under the asset's lowest start point (or at y = 0 when that is above it).
        scenes::SceneWorld probe;
        if (std::string e = scenes::build_scene(scene_, &probe); !e.empty()) return e;
        const ClothAsset& a = *probe.cloths[0].asset;
        float lowest_m = 0.0f;
        for (uint32_t s = 0; s < a.slot_count; ++s) lowest_m = std::min(lowest_m, a.start_y[s]);
        ColliderDesc ground;
        ground.shape = ColliderShape::plane;
        ground.p0 = {0.0f, lowest_m - 0.05f, 0.0f};
        ground.p1 = {0.0f, 1.0f, 0.0f};
        ground.friction = 0.5f;
        scene_.colliders.push_back(ground);
    } else if (std::string e = scenes::load_scene_file(path, &scene_); !e.empty()) {
        return e;
    }
    scene_.profile = true;  // per-pass times for the timing bar
    controls_ = {};
    controls_.wind_on = scene_.wind_m_s.has_value();
    if (scene_.wind_m_s) {
        const Vec3 w = *scene_.wind_m_s;
        controls_.wind_speed_m_s = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
        controls_.wind_direction_deg = glm::degrees(std::atan2(w.z, w.x));
    }
    controls_.gravity_m_s2 = -scene_.gravity_m_s2.y;
    if (!scene_.colliders.empty()) controls_.inflation_m = scene_.colliders[0].inflation_m;
    const ClothDesc& desc = scene_.cloths[0].desc;
    controls_.explicit_split = desc.policy == BudgetPolicy::explicit_split;
    controls_.tethers = desc.tethers;
    if (std::string e = reset(); !e.empty()) return e;
    const SolverSplit s = split();  // the policy's choice is where the sliders start
    controls_.substeps = int(s.substeps);
    controls_.iterations = int(s.iterations);
    return {};
}

std::string Session::reset() {
    scenes::Scene scene = scene_;
    if (controls_.wind_on && !scene.wind_m_s) scene.wind_m_s = Vec3{};
    if (!controls_.wind_on) scene.wind_m_s.reset();
    world_ = {};
    if (std::string e = scenes::build_scene(scene, &world_, asset_dirs_); !e.empty()) return e;
    snapshot_ = render::snapshot_of_scene(scene_, world_);
    frame_ = 0;
    last_ = {};
    const Controls c = controls_;
    controls_.wind_on = scene.wind_m_s.has_value();
    return apply(c);
}

std::string Session::apply(const Controls& c) {
    if (c.wind_on != controls_.wind_on) {
        controls_ = c;
        return reset();
    }
    controls_ = c;
    World* w = world_.world;
    if (c.wind_on) {
        const float a = glm::radians(c.wind_direction_deg);
        if (Result r = set_wind(w, {c.wind_speed_m_s * std::cos(a), 0.0f, c.wind_speed_m_s * std::sin(a)}); !r.ok())
            return r.message;
    }
    if (Result r = set_gravity(w, {0.0f, -c.gravity_m_s2, 0.0f}); !r.ok()) return r.message;
    for (scenes::SceneCloth& cloth : world_.cloths) {
        ClothDesc d = cloth.desc;
        d.tethers = c.tethers;
        if (c.explicit_split) {
            d.policy = BudgetPolicy::explicit_split;
            d.substeps = uint32_t(c.substeps);
            d.iterations = uint32_t(c.iterations);
            d.sweeps = d.substeps * d.iterations;
        }
        if (Result r = set_cloth_settings(w, cloth.id, d); !r.ok()) return r.message;
    }
    for (size_t i = 0; i < scene_.colliders.size(); ++i) {
        ColliderDesc d = scene_.colliders[i];
        d.inflation_m = c.inflation_m;
        snapshot_.colliders[i] = d;
        if (Result r = set_collider(w, world_.colliders[i], d); !r.ok()) return r.message;
    }
    return {};
}

bool Session::step(std::string* error) {
    const WorldStats before = world_stats(world_.world);
    const auto t0 = std::chrono::steady_clock::now();
    const Result r = weft::step(world_.world, scene_.dt_s);
    const auto t1 = std::chrono::steady_clock::now();
    if (!r.ok()) {
        *error = r.message;
        return false;
    }
    ++frame_;
    const WorldStats after = world_stats(world_.world);
    last_ = {};
    last_.step_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    for (int p = 0; p < int(Pass::count); ++p)
        last_.pass_ms[int(group_of(Pass(p)))] += 1e-6 * double(after.pass_ns[p] - before.pass_ns[p]);
    for (const scenes::SceneCloth& c : world_.cloths) {
        ClothView view;
        view_cloth(world_.world, c.id, &view);
        last_.max_strain = std::max(last_.max_strain, metrics::stretch_strain(view).max);
        last_.max_penetration_m =
            std::max(last_.max_penetration_m,
                     metrics::max_penetration_m(view, snapshot_.colliders.data(), uint32_t(snapshot_.colliders.size())));
    }
    return true;
}

uint32_t Session::particles() const {
    uint32_t n = 0;
    for (const scenes::SceneCloth& c : world_.cloths) n += c.asset->particle_count;
    return n;
}

SolverSplit Session::split() const {
    SolverSplit s;
    cloth_solver_split(world_.world, world_.cloths[0].id, &s);
    return s;
}

const render::Snapshot& Session::snapshot() {
    for (size_t i = 0; i < world_.cloths.size(); ++i) {
        std::vector<Vec3>& p = snapshot_.cloths[i].positions;
        read_positions(world_.world, world_.cloths[i].id, p.data(), uint32_t(p.size()));
    }
    return snapshot_;
}

}  // namespace weft::viewer
