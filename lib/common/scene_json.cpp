// Scene files: strict JSON reading. Every key is known, every number finite and in range, so a typo
// in a scene file is an error with the key's path, never a silently ignored setting.
#include "common/scene_json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

namespace weft::scenes {
namespace {

using nlohmann::json;

// Thrown inside the parser only; parse_scene turns it into the returned message.
struct SceneError {
    std::string message;
};

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw SceneError{where + ": " + what}; }

// An object whose keys must all be in `known`.
const json& object(const json& j, const std::string& where, std::initializer_list<const char*> known) {
    if (!j.is_object()) fail(where, "must be an object");
    const std::set<std::string> allowed(known.begin(), known.end());
    for (const auto& [key, value] : j.items())
        if (!allowed.count(key)) fail(where, "unknown key '" + key + "'");
    return j;
}

double number(const json& j, const std::string& where, double lo, double hi) {
    if (!j.is_number()) fail(where, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, "must be finite");
    if (v < lo || v > hi) {
        std::ostringstream s;
        s << "must be in [" << lo << ", " << hi << "], got " << v;
        fail(where, s.str());
    }
    return v;
}

template <class T>
void read(const json& o, const char* key, const std::string& where, double lo, double hi, T* out) {
    if (o.contains(key)) *out = T(number(o[key], where + "." + key, lo, hi));
}

void read_bool(const json& o, const char* key, const std::string& where, bool* out) {
    if (!o.contains(key)) return;
    if (!o[key].is_boolean()) fail(where + "." + key, "must be true or false");
    *out = o[key].get<bool>();
}

std::string text(const json& j, const std::string& where) {
    if (!j.is_string()) fail(where, "must be a string");
    return j.get<std::string>();
}

constexpr double kFar_m = 1e5;  // positions beyond 100 km are a mistake, not a scene

Vec3 vec3(const json& j, const std::string& where, double limit = kFar_m) {
    if (!j.is_array() || j.size() != 3) fail(where, "must be an array of 3 numbers");
    return {float(number(j[0], where + "[0]", -limit, limit)), float(number(j[1], where + "[1]", -limit, limit)),
            float(number(j[2], where + "[2]", -limit, limit))};
}

std::vector<int32_t> indices(const json& j, const std::string& where) {
    if (!j.is_array()) fail(where, "must be an array of integers");
    std::vector<int32_t> out;
    for (size_t i = 0; i < j.size(); ++i) {
        const std::string w = where + "[" + std::to_string(i) + "]";
        if (!j[i].is_number_integer()) fail(w, "must be an integer");
        out.push_back(int32_t(number(j[i], w, -4096, 4095)));
    }
    return out;
}

GridSource parse_grid(const json& j, const std::string& where) {
    object(j, where, {"n", "width_m", "length_m", "orientation", "y_m", "areal_density_kg_m2", "offset_m", "pins",
                      "pin_rows", "pin_columns"});
    GridSource g;
    read(j, "n", where, 2, 4096, &g.n);
    read(j, "width_m", where, 1e-3, 1e3, &g.width_m);
    read(j, "length_m", where, 1e-3, 1e3, &g.length_m);
    read(j, "y_m", where, -kFar_m, kFar_m, &g.y_m);
    read(j, "areal_density_kg_m2", where, 1e-4, 1e3, &g.areal_density_kg_m2);
    if (j.contains("orientation")) {
        const std::string o = text(j["orientation"], where + ".orientation");
        if (o != "horizontal" && o != "vertical") fail(where + ".orientation", "must be horizontal or vertical");
        g.vertical = o == "vertical";
    }
    if (j.contains("offset_m")) g.offset_m = vec3(j["offset_m"], where + ".offset_m");
    if (j.contains("pins")) {
        const json& pins = j["pins"];
        if (!pins.is_array()) fail(where + ".pins", "must be an array of [row, column] pairs");
        for (size_t i = 0; i < pins.size(); ++i) {
            const std::vector<int32_t> rc = indices(pins[i], where + ".pins[" + std::to_string(i) + "]");
            if (rc.size() != 2) fail(where + ".pins[" + std::to_string(i) + "]", "must be [row, column]");
            g.pins.push_back({rc[0], rc[1]});
        }
    }
    if (j.contains("pin_rows")) g.pin_rows = indices(j["pin_rows"], where + ".pin_rows");
    if (j.contains("pin_columns")) g.pin_columns = indices(j["pin_columns"], where + ".pin_columns");
    return g;
}

void parse_solver(const json& j, const std::string& where, ClothDesc* d) {
    object(j, where, {"sweeps", "substeps", "iterations", "relaxation", "coarse_level", "coarse_iterations", "projection", "tethers",
                      "tethers_before_sweeps", "tether_slack", "contact_tethers"});
    read(j, "sweeps", where, 1, 1000, &d->sweeps);
    // Naming substeps or iterations makes the split explicit (BudgetPolicy::explicit_split).
    if (j.contains("substeps") || j.contains("iterations")) {
        d->policy = BudgetPolicy::explicit_split;
        d->substeps = 1;
        d->iterations = d->sweeps;
        read(j, "substeps", where, 1, 64, &d->substeps);
        read(j, "iterations", where, 0, 1000, &d->iterations);
    }
    read(j, "relaxation", where, kMinRelaxation, kMaxRelaxation, &d->relaxation);
    if (j.contains("coarse_level")) {  // absent: automatic (CoarseLevel)
        bool coarse = false;
        read_bool(j, "coarse_level", where, &coarse);
        d->coarse_level = coarse ? CoarseLevel::on : CoarseLevel::off;
    }
    read(j, "coarse_iterations", where, 1, 16, &d->coarse_iterations);
    read_bool(j, "tethers", where, &d->tethers);
    read_bool(j, "tethers_before_sweeps", where, &d->tethers_before_sweeps);
    read_bool(j, "contact_tethers", where, &d->contact_tethers);
    read(j, "tether_slack", where, 0.0, 10.0, &d->tether_slack);
    if (j.contains("projection")) {
        const std::string p = text(j["projection"], where + ".projection");
        if (p == "exact") d->projection = SpringProjection::exact;
        else if (p == "sqrt_free") d->projection = SpringProjection::sqrt_free;
        else fail(where + ".projection", "must be exact or sqrt_free");
    }
}

ClothSpec parse_cloth(const json& j, const std::string& where) {
    object(j, where, {"name", "grid", "asset", "translation_m", "solver", "compliance_m_per_n", "damping_per_s",
                      "drag_coefficient", "lift_coefficient", "tethers_per_particle", "coarse_spacing_m",
                      "self_collision", "self_thickness_m", "self_friction", "worn_over", "layer_thickness_m",
                      "layer_friction"});
    ClothSpec c;
    c.name = j.contains("name") ? text(j["name"], where + ".name") : where;
    if (j.contains("grid") == j.contains("asset")) fail(where, "needs exactly one of 'grid' and 'asset'");
    if (j.contains("grid")) {
        c.grid = parse_grid(j["grid"], where + ".grid");
    } else {
        c.asset_path = text(j["asset"], where + ".asset");
    }
    if (j.contains("translation_m")) c.desc.translation_m = vec3(j["translation_m"], where + ".translation_m");
    if (j.contains("solver")) parse_solver(j["solver"], where + ".solver", &c.desc);
    c.compliance_given = j.contains("compliance_m_per_n");
    c.damping_given = j.contains("damping_per_s");
    if (j.contains("compliance_m_per_n")) {
        const std::string w = where + ".compliance_m_per_n";
        const json& k = object(j["compliance_m_per_n"], w, {"stretch", "shear", "bend"});
        read(k, "stretch", w, 0.0, 1e3, &c.desc.compliance_m_per_n[0]);
        read(k, "shear", w, 0.0, 1e3, &c.desc.compliance_m_per_n[1]);
        read(k, "bend", w, 0.0, 1e3, &c.desc.compliance_m_per_n[2]);
    }
    read(j, "damping_per_s", where, 0.0, 1e3, &c.desc.damping_per_s);
    read(j, "drag_coefficient", where, 0.0, 100.0, &c.desc.drag_coefficient);
    read(j, "lift_coefficient", where, 0.0, 100.0, &c.desc.lift_coefficient);
    read(j, "tethers_per_particle", where, 0, 2, &c.cook.tethers_per_particle);
    read(j, "coarse_spacing_m", where, 0.0, 1e3, &c.cook.coarse_spacing_m);
    read_bool(j, "self_collision", where, &c.desc.self_collision);
    read(j, "self_thickness_m", where, kMinSelfThickness_m, kMaxSelfThickness_m, &c.desc.self_thickness_m);
    read(j, "self_friction", where, 0.0, 10.0, &c.desc.self_friction);
    if (j.contains("worn_over")) {
        const json& w = j["worn_over"];
        if (!w.is_array() || w.size() > kMaxWornOver)
            fail(where + ".worn_over", "must be a list of at most " + std::to_string(kMaxWornOver) + " cloth names");
        for (size_t k = 0; k < w.size(); ++k) c.worn_over.push_back(text(w[k], where + ".worn_over[" + std::to_string(k) + "]"));
    }
    read(j, "layer_thickness_m", where, kMinSelfThickness_m, kMaxSelfThickness_m, &c.desc.layer_thickness_m);
    read(j, "layer_friction", where, 0.0, 10.0, &c.desc.layer_friction);
    return c;
}

ColliderDesc parse_collider(const json& j, const std::string& where) {
    object(j, where, {"shape", "center_m", "from_m", "to_m", "point_m", "normal", "radius_m", "inflation_m", "friction"});
    if (!j.contains("shape")) fail(where, "needs a 'shape'");
    const std::string shape = text(j["shape"], where + ".shape");
    ColliderDesc c;
    auto need = [&](const char* key) -> Vec3 {
        if (!j.contains(key)) fail(where, std::string("a ") + shape + " needs '" + key + "'");
        return vec3(j[key], where + "." + key);
    };
    if (shape == "sphere") {
        c.shape = ColliderShape::sphere;
        c.p0 = need("center_m");
    } else if (shape == "capsule" || shape == "cylinder") {
        c.shape = shape == "capsule" ? ColliderShape::capsule : ColliderShape::cylinder;
        c.p0 = need("from_m");
        c.p1 = need("to_m");
    } else if (shape == "plane") {
        c.shape = ColliderShape::plane;
        c.p0 = need("point_m");
        c.p1 = vec3(j.contains("normal") ? j["normal"] : json::array({0, 1, 0}), where + ".normal", 1e3);
        const float len = std::sqrt(c.p1.x * c.p1.x + c.p1.y * c.p1.y + c.p1.z * c.p1.z);
        if (!(len > 1e-6f)) fail(where + ".normal", "must not be zero");
        c.p1 = {c.p1.x / len, c.p1.y / len, c.p1.z / len};
    } else {
        fail(where + ".shape", "must be sphere, capsule, cylinder or plane");
    }
    read(j, "radius_m", where, 0.0, 1e3, &c.radius_m);
    read(j, "inflation_m", where, 0.0, 1e3, &c.inflation_m);
    read(j, "friction", where, 0.0, 10.0, &c.friction);
    return c;
}

BodySpec parse_body(const json& j, const std::string& where) {
    object(j, where, {"mannequin", "mesh", "animation", "blend_to", "period_s", "ramp_s", "thickness_m", "margin_m",
                      "friction", "collision", "limb_capsules", "limb_capsule_sections", "ground"});
    BodySpec b;
    if (j.contains("mannequin") == j.contains("mesh")) fail(where, "needs exactly one of 'mannequin' and 'mesh'");
    if (j.contains("mannequin")) {
        object(j["mannequin"], where + ".mannequin", {});
        b.mannequin = true;
    } else {
        b.mesh_path = text(j["mesh"], where + ".mesh");
    }
    if (j.contains("animation")) {
        const std::string a = text(j["animation"], where + ".animation");
        if (a == "still") b.animation = BodyAnimation::still;
        else if (a == "walk") b.animation = BodyAnimation::walk;
        else if (a == "blend") b.animation = BodyAnimation::blend;
        else if (a == "bend_and_sit") b.animation = BodyAnimation::bend_and_sit;
        else fail(where + ".animation", "must be still, walk, bend_and_sit or blend");
    }
    if ((b.animation == BodyAnimation::walk || b.animation == BodyAnimation::bend_and_sit) && !b.mannequin)
        fail(where + ".animation", "only the mannequin walks, bends and sits");
    if (b.animation == BodyAnimation::blend) {
        if (!j.contains("blend_to")) fail(where, "a blend needs 'blend_to'");
        b.blend_to_path = text(j["blend_to"], where + ".blend_to");
    } else if (j.contains("blend_to")) {
        fail(where + ".blend_to", "only a blend animation takes it");
    }
    read(j, "period_s", where, 0.01, 1e4, &b.period_s);
    read(j, "ramp_s", where, 0.0, 1e4, &b.ramp_s);
    if (j.contains("limb_capsules")) {
        const json& bones = j["limb_capsules"];
        if (!bones.is_array() || bones.size() > 64) fail(where + ".limb_capsules", "must be an array of at most 64 bone names");
        if (!b.mannequin) fail(where + ".limb_capsules", "only the mannequin has bones");
        for (size_t i = 0; i < bones.size(); ++i)
            b.limb_capsules.push_back(text(bones[i], where + ".limb_capsules[" + std::to_string(i) + "]"));
    }
    read(j, "limb_capsule_sections", where, 1.0, 8.0, &b.limb_capsule_sections);
    read(j, "thickness_m", where, 1e-5, 0.5, &b.thickness_m);
    read(j, "margin_m", where, 0.0, 0.5, &b.margin_m);
    read(j, "friction", where, 0.0, 10.0, &b.friction);
    if (j.contains("ground")) {
        if (!j["ground"].is_boolean()) fail(where + ".ground", "must be true or false");
        b.ground = j["ground"].get<bool>();
    }
    if (j.contains("collision") && !body_collision_from_name(text(j["collision"], where + ".collision"), &b.collision))
        fail(where + ".collision", "must be exact, cached_planes or skin_constraints");
    return b;
}

Scene parse(const json& root, const std::string& base_dir) {
    object(root, "scene", {"format", "version", "name", "description", "dt_s", "frames", "gravity_m_s2",
                           "air_density_kg_m3", "wind_m_s", "simd", "cloths", "colliders", "body"});
    if (!root.contains("format") || root["format"] != "weft-scene") fail("scene.format", "must be \"weft-scene\"");
    if (!root.contains("version") || !root["version"].is_number_integer() || root["version"] != 1)
        fail("scene.version", "must be 1 (the only version this build reads)");
    Scene s;
    s.base_dir = base_dir;
    if (root.contains("name")) s.name = text(root["name"], "scene.name");
    if (root.contains("description")) text(root["description"], "scene.description");
    read(root, "dt_s", "scene", 1e-5, 1.0, &s.dt_s);
    read(root, "frames", "scene", 0, 1e7, &s.frames);
    if (root.contains("gravity_m_s2")) s.gravity_m_s2 = vec3(root["gravity_m_s2"], "scene.gravity_m_s2", 1e3);
    read(root, "air_density_kg_m3", "scene", 0.0, 1e3, &s.air_density_kg_m3);
    if (root.contains("wind_m_s")) s.wind_m_s = vec3(root["wind_m_s"], "scene.wind_m_s", 1e3);
    if (root.contains("simd")) {
        const std::string p = text(root["simd"], "scene.simd");
        if (p == "automatic") s.simd = SimdPath::automatic;
        else if (p == "scalar") s.simd = SimdPath::scalar;
        else if (p == "avx2") s.simd = SimdPath::avx2;
        else fail("scene.simd", "must be automatic, scalar or avx2");
    }
    if (!root.contains("cloths") || !root["cloths"].is_array() || root["cloths"].empty())
        fail("scene.cloths", "must be a non-empty array");
    if (root["cloths"].size() > 1024) fail("scene.cloths", "more than 1024 cloths");
    for (size_t i = 0; i < root["cloths"].size(); ++i)
        s.cloths.push_back(parse_cloth(root["cloths"][i], "scene.cloths[" + std::to_string(i) + "]"));
    if (root.contains("colliders")) {
        const json& c = root["colliders"];
        if (!c.is_array()) fail("scene.colliders", "must be an array");
        if (c.size() > 1024) fail("scene.colliders", "more than 1024 colliders");
        for (size_t i = 0; i < c.size(); ++i)
            s.colliders.push_back(parse_collider(c[i], "scene.colliders[" + std::to_string(i) + "]"));
    }
    if (root.contains("body")) s.body = parse_body(root["body"], "scene.body");
    return s;
}

}  // namespace

std::string parse_scene(std::string_view json_text, const std::string& base_dir, Scene* out) {
    // Depth-limited: a hostile file of nested arrays must not exhaust the stack.
    int depth = 0, max_depth = 0;
    for (char ch : json_text) {
        if (ch == '[' || ch == '{') max_depth = std::max(max_depth, ++depth);
        else if (ch == ']' || ch == '}') --depth;
    }
    if (max_depth > 64) return "scene nests deeper than 64 levels";
    try {
        const json root = json::parse(json_text.begin(), json_text.end());
        *out = parse(root, base_dir);
        return {};
    } catch (const SceneError& e) {
        return e.message;
    } catch (const std::exception& e) {
        return std::string("not a valid JSON scene: ") + e.what();
    }
}

std::string load_scene_file(const std::string& path, Scene* out) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return "cannot open scene file '" + path + "'";
    std::ostringstream text;
    text << file.rdbuf();
    const std::string base = std::filesystem::path(path).parent_path().string();
    return parse_scene(text.str(), base.empty() ? "." : base, out);
}

}  // namespace weft::scenes
