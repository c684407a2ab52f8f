// Scene files (docs/scene-format.md): the samples describe the seed experiments exactly, and a
// malformed scene is refused with the path of the offending key.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "common/scene_json.h"
#include "support/test_support.h"

namespace weft {
namespace {

using scenes::SeedScene;

std::string sample(const char* name) { return std::string(WEFT_SOURCE_DIR) + "/samples/scenes/" + name + ".json"; }

// The sample file and the seed experiment built by weft-bench give the same bits after 60 frames.
void check_sample_matches_seed(const char* file, SeedScene which) {
    scenes::Scene scene;
    const std::string error = scenes::load_scene_file(sample(file), &scene);
    INFO(error);
    REQUIRE(error.empty());
    scenes::SceneWorld from_file;
    REQUIRE(scenes::build_scene(scene, &from_file).empty());

    scenes::SceneOptions o = test::scene_options(100);
    o.sphere_friction = 0.5f;  // the issue's figure-8 setting, which the sample names
    const auto seed = test::make_scene(which, o);
    for (int f = 0; f < 60; ++f) {
        REQUIRE(step(from_file.world, scene.dt_s).ok());
        REQUIRE(step(seed->world, seed->dt_s).ok());
    }
    const auto a = test::read_all(from_file.world, from_file.cloths[0].id, from_file.cloths[0].asset->particle_count);
    const auto b = test::read_all(*seed);
    REQUIRE(a.size() == b.size());
    CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("samples/scenes/drape.json is the seed drape") { check_sample_matches_seed("drape", SeedScene::drape); }
TEST_CASE("samples/scenes/flag.json is the seed flag") { check_sample_matches_seed("flag", SeedScene::flag); }
TEST_CASE("samples/scenes/sphere.json is the seed sphere") { check_sample_matches_seed("sphere", SeedScene::sphere); }

TEST_CASE("a scene has exactly the features it names") {
    scenes::Scene scene;
    REQUIRE(scenes::load_scene_file(sample("drape"), &scene).empty());
    CHECK_FALSE(scene.wind_m_s.has_value());
    CHECK(scene.colliders.empty());
    REQUIRE(scenes::load_scene_file(sample("flag"), &scene).empty());
    CHECK(scene.wind_m_s.has_value());
    REQUIRE(scenes::load_scene_file(sample("sphere"), &scene).empty());
    REQUIRE(scene.colliders.size() == 1);
    CHECK(scene.colliders[0].friction == 0.5f);
}

TEST_CASE("explicit substeps or iterations make the split explicit") {
    scenes::Scene scene;
    const char* text = R"({"format": "weft-scene", "version": 1,
        "cloths": [{"grid": {"n": 4}, "solver": {"sweeps": 6, "substeps": 2}}]})";
    REQUIRE(scenes::parse_scene(text, ".", &scene).empty());
    const ClothDesc& d = scene.cloths[0].desc;
    CHECK(d.policy == BudgetPolicy::explicit_split);
    CHECK(d.substeps == 2);
    CHECK(d.iterations == 6);  // sweeps when iterations is not named
}

// Each malformed scene is refused and the message names what is wrong.
TEST_CASE("a scene's body collides by cached planes unless it names the exact pass") {
    const std::string head = R"({"format": "weft-scene", "version": 1, "cloths": [{"grid": {"n": 4}}], "body": {"mannequin": {})";
    for (const auto& [text, model] : {std::pair{head + "}}", BodyCollision::cached_planes},
                                      std::pair{head + R"(, "collision": "exact"}})", BodyCollision::exact},
                                      std::pair{head + R"(, "collision": "cached_planes"}})", BodyCollision::cached_planes},
                                      std::pair{head + R"(, "collision": "skin_constraints"}})", BodyCollision::skin_constraints}}) {
        scenes::Scene scene;
        const std::string error = scenes::parse_scene(text, ".", &scene);
        INFO(text, "\n", error);
        REQUIRE(error.empty());
        REQUIRE(scene.body);
        CHECK(scene.body->collision == model);
    }
}

namespace {

// A scene of one 4 x 4 grid on the mannequin whose body collides by `model`, built into `w`.
void build_grid_on_mannequin(const char* model, scenes::SceneWorld* w) {
    const std::string text = std::string(R"({"format": "weft-scene", "version": 1, "cloths": [{"grid": {"n": 4}}], )") +
                             R"("body": {"mannequin": {}, "collision": ")" + model + "\"}}";
    scenes::Scene scene;
    REQUIRE(scenes::parse_scene(text, ".", &scene).empty());
    test::require_scene(scene, w);
}

}  // namespace

// What a model needs is reserved only by the scenes that use it: the cached planes 76 bytes a
// particle slot, skin constraints 76 bytes a constraint (kSkinArrays floats).
TEST_CASE("a scene's world holds the cached planes or the skin constraints only when its body collides by them") {
    scenes::SceneWorld exact, planes, skin;
    build_grid_on_mannequin("exact", &exact);
    build_grid_on_mannequin("cached_planes", &planes);
    build_grid_on_mannequin("skin_constraints", &skin);
    const ClothAsset& asset = *exact.cloths[0].asset;
    CHECK(exact.memory_bytes + 76 * size_t(asset.slot_count) <= planes.memory_bytes);
    CHECK(exact.memory_bytes + 76 * size_t(asset.particle_count) <= skin.memory_bytes);
}

// body.collision skin_constraints: build_scene binds every free particle and the step searches nothing.
// A grid's asset has no baked skin constraints, so the scene builder cooks a binding itself (a
// dressed garment's baked ones: tests/test_sew.cpp).
TEST_CASE("a scene whose body collides by skin constraints binds its cloth's free particles") {
    scenes::SceneWorld w;
    build_grid_on_mannequin("skin_constraints", &w);
    CHECK(w.cloths[0].asset->skin.count == 0);
    REQUIRE(w.cloths[0].skin);
    ClothView view;
    REQUIRE(view_cloth(w.world, w.cloths[0].id, &view).ok());
    uint32_t free_particles = 0;
    for (uint32_t p = 0; p < view.asset->particle_count; ++p)
        free_particles += view.inverse_mass[view.asset->slot_of_particle[p]] > 0.0f;
    CHECK(w.cloths[0].skin->particle.size() == free_particles);
    REQUIRE(step(w.world, w.dt_s).ok());
    CHECK(world_stats(w.world).body_queried == 0);
}

// body.limb_capsules: one capsule collider a bone and section, moved with the walk, refused by name
// when the mannequin has no such bone.
TEST_CASE("a scene's limb capsules are colliders that follow the walking mannequin's bones") {
    const std::string head = R"({"format": "weft-scene", "version": 1, "cloths": [{"grid": {"n": 4}}], )";
    scenes::Scene scene;
    REQUIRE(scenes::parse_scene(head + R"("body": {"mannequin": {}, "animation": "walk", "ramp_s": 0,
        "limb_capsules": ["thigh.L", "thigh.R"], "limb_capsule_sections": 3}})", ".", &scene).empty());
    scenes::SceneWorld w;
    REQUIRE(scenes::build_scene(scene, &w).empty());
    REQUIRE(w.body->limb_colliders.size() == 6);
    REQUIRE(scenes::animate_body(w, 0.275f).empty());  // a quarter stride: the thighs swung
    std::vector<body::LimbCapsule> expect;
    body::walk_capsules(*static_cast<const body::Mannequin*>(w.body->mannequin.get()), w.body->limb_capsules, 0.275f, &expect);
    for (size_t c = 0; c < expect.size(); ++c) {
        CHECK(w.body->posed_capsules[c].p0.z == expect[c].p0.z);
        CHECK(w.body->posed_capsules[c].p1.z == expect[c].p1.z);
        CHECK(std::abs(expect[c].p1.z - w.body->limb_capsules[c].p1.z) > 0.01f);  // moved
    }
    REQUIRE(step(w.world, w.dt_s).ok());

    scenes::Scene bad;
    REQUIRE(scenes::parse_scene(head + R"("body": {"mannequin": {}, "limb_capsules": ["tail"]}})", ".", &bad).empty());
    scenes::SceneWorld none;
    CHECK(scenes::build_scene(bad, &none).find("no bone named 'tail'") != std::string::npos);
}

// body.animation "bend_and_sit": the mannequin's clip (lib/body/mannequin.h) poses the body and its
// capsules; a mesh body cannot take it (it has no bones).
TEST_CASE("a scene's mannequin bends and sits: the body and its capsules take the clip's pose") {
    const std::string head = R"({"format": "weft-scene", "version": 1, "cloths": [{"grid": {"n": 4}}], )";
    scenes::Scene scene;
    REQUIRE(scenes::parse_scene(head + R"("body": {"mannequin": {}, "animation": "bend_and_sit", "ramp_s": 0,
        "limb_capsules": ["thigh.L"]}})", ".", &scene).empty());
    REQUIRE(scene.body->animation == scenes::BodyAnimation::bend_and_sit);
    scenes::SceneWorld w;
    REQUIRE(scenes::build_scene(scene, &w).empty());
    const float seated_s = 5.2f;
    REQUIRE(scenes::animate_body(w, seated_s).empty());
    const auto& m = *static_cast<const body::Mannequin*>(w.body->mannequin.get());
    std::vector<Vec3> pose;
    body::clip_pose(m, body::Clip::bend_and_sit, seated_s, &pose);
    REQUIRE(w.body->pose.size() == pose.size());
    // (entered from the rest pose with ramp_s 0: rest + (pose - rest), equal to rounding)
    CHECK(std::equal(pose.begin(), pose.end(), w.body->pose.begin(), [](Vec3 a, Vec3 b) {
        return std::abs(a.x - b.x) < 1e-6f && std::abs(a.y - b.y) < 1e-6f && std::abs(a.z - b.z) < 1e-6f;
    }));
    std::vector<body::LimbCapsule> expect;
    body::clip_capsules(m, body::Clip::bend_and_sit, w.body->limb_capsules, seated_s, &expect);
    CHECK(std::abs(w.body->posed_capsules[0].p1.z - expect[0].p1.z) < 1e-6f);
    CHECK(expect[0].p1.z - w.body->limb_capsules[0].p1.z > 0.1f);  // seated: mid-thigh well forward
    REQUIRE(step(w.world, w.dt_s).ok());

    scenes::Scene bad;
    CHECK(scenes::parse_scene(head + R"("body": {"mesh": "body.obj", "animation": "bend_and_sit"}})", ".", &bad)
              .find("only the mannequin") != std::string::npos);
}

// body.ground: the floor weft-bake dresses garments on, a plane under the body's soles.
TEST_CASE("a scene body's ground is a plane under its soles, as thick as its hull, with its friction") {
    const std::string head = R"({"format": "weft-scene", "version": 1, "cloths": [{"grid": {"n": 4}}], )";
    scenes::Scene scene;
    REQUIRE(scenes::parse_scene(head + R"("body": {"mannequin": {}, "ground": true, "thickness_m": 0.003, "friction": 0.4}})",
                                ".", &scene).empty());
    REQUIRE(scene.body->ground);
    scenes::SceneWorld w;
    REQUIRE(scenes::build_scene(scene, &w).empty());
    const std::vector<Vec3>& rest = w.body->rest;
    const ColliderDesc ground = ground_under_body(rest.data(), uint32_t(rest.size()), 0.003f, 0.4f);
    float lowest = rest[0].y;
    for (const Vec3& p : rest) lowest = std::min(lowest, p.y);
    CHECK(ground.shape == ColliderShape::plane);
    CHECK(ground.p0.y == lowest);
    CHECK(ground.p1.y == 1.0f);
    CHECK(ground.inflation_m == 0.003f);
    CHECK(ground.friction == 0.4f);
    REQUIRE(step(w.world, w.dt_s).ok());
    CHECK(remove_collider(w.world, w.body->ground).ok());  // the scene added it

    scenes::Scene plain;
    REQUIRE(scenes::parse_scene(head + R"("body": {"mannequin": {}}})", ".", &plain).empty());
    CHECK(!plain.body->ground);
    scenes::Scene bad;
    CHECK(scenes::parse_scene(head + R"("body": {"mannequin": {}, "ground": 1}})", ".", &bad).find("scene.body.ground") !=
          std::string::npos);
}

TEST_CASE("malformed scenes are refused with the key's path") {
    const std::string head = R"({"format": "weft-scene", "version": 1, )";
    const std::string cloth = R"("cloths": [{"grid": {"n": 4}}])";
    struct Case {
        std::string text, expect;
    };
    const std::string deep = std::string(10000, '[') + std::string(10000, ']');
    const Case cases[] = {
        {"", "not a valid JSON"},
        {"{", "not a valid JSON"},
        {deep, "deeper than 64"},
        {"[]", "must be an object"},
        {R"({"format": "weft-scene", "version": 2, "cloths": []})", "scene.version"},
        {R"({"version": 1})", "scene.format"},
        {head + R"("cloths": []})", "scene.cloths"},
        {head + cloth + R"(, "dt": 0.033})", "unknown key 'dt'"},
        {head + cloth + R"(, "dt_s": -1})", "scene.dt_s"},
        {head + cloth + R"(, "dt_s": 1e308})", "scene.dt_s"},
        {head + cloth + R"(, "dt_s": "fast"})", "must be a number"},
        {head + cloth + R"(, "gravity_m_s2": [0, -9.8]})", "scene.gravity_m_s2"},
        {head + cloth + R"(, "wind_m_s": [0, NaN, 0]})", "not a valid JSON"},
        {head + cloth + R"(, "simd": "avx512"})", "scene.simd"},
        {head + R"("cloths": [{}]})", "exactly one of 'grid' and 'asset'"},
        {head + R"("cloths": [{"grid": {"n": 4}, "asset": "a.weft"}]})", "exactly one"},
        {head + R"("cloths": [{"grid": {"n": 1}}]})", "scene.cloths[0].grid.n"},
        {head + R"("cloths": [{"grid": {"n": 4, "pins": [[0]]}}]})", "[row, column]"},
        {head + R"("cloths": [{"grid": {"n": 4, "pins": [[0.5, 1]]}}]})", "must be an integer"},
        {head + R"("cloths": [{"grid": {"n": 4}, "solver": {"sweeps": 0}}]})", "solver.sweeps"},
        {head + R"("cloths": [{"grid": {"n": 4}, "solver": {"substeps": 65}}]})", "solver.substeps"},
        {head + R"("cloths": [{"grid": {"n": 4}, "solver": {"projection": "fast"}}]})", "solver.projection"},
        {head + R"("cloths": [{"grid": {"n": 4}, "compliance_m_per_n": {"twist": 1}}]})", "unknown key 'twist'"},
        {head + cloth + R"(, "colliders": [{"shape": "torus"}]})", "colliders[0].shape"},
        {head + cloth + R"(, "colliders": [{"shape": "sphere"}]})", "needs 'center_m'"},
        {head + cloth + R"(, "colliders": [{"shape": "plane", "point_m": [0,0,0], "normal": [0,0,0]}]})", "normal"},
        {head + cloth + R"(, "colliders": [{"shape": "sphere", "center_m": [0,0,0], "friction": -1}]})", "friction"},
        {head + cloth + R"(, "body": {"mannequin": {}, "collision": "spheres"}})", "scene.body.collision"},
        {head + cloth + R"(, "body": {"mannequin": {}, "collision": 1}})", "scene.body.collision"},
        {head + cloth + R"(, "body": {"mannequin": {}, "limb_capsules": "thigh.L"}})", "scene.body.limb_capsules"},
        {head + cloth + R"(, "body": {"mannequin": {}, "limb_capsules": [1]}})", "scene.body.limb_capsules[0]"},
        {head + cloth + R"(, "body": {"mesh": "b.obj", "limb_capsules": ["thigh.L"]}})", "only the mannequin has bones"},
        {head + cloth + R"(, "body": {"mannequin": {}, "limb_capsules": ["thigh.L"], "limb_capsule_sections": 0}})",
         "scene.body.limb_capsule_sections"},
    };
    for (const Case& c : cases) {
        scenes::Scene scene;
        scene.name = "untouched";
        const std::string error = scenes::parse_scene(c.text, ".", &scene);
        INFO("scene: ", c.text.substr(0, 200), "\nerror: ", error);
        CHECK(error.find(c.expect) != std::string::npos);
        CHECK(scene.name == "untouched");  // nothing written on failure
    }
}

TEST_CASE("a grid pin outside the grid fails when the scene is built, not in the step") {
    scenes::Scene scene;
    REQUIRE(scenes::parse_scene(R"({"format": "weft-scene", "version": 1,
        "cloths": [{"name": "c", "grid": {"n": 4, "pins": [[0, 4]]}}]})", ".", &scene).empty());
    scenes::SceneWorld w;
    const std::string error = scenes::build_scene(scene, &w);
    CHECK(error.find("cloth 'c'") != std::string::npos);
    CHECK(error.find("outside the grid") != std::string::npos);
}

}  // namespace
}  // namespace weft
