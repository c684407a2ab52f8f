// weft-sim --gltf read back (tinygltf): the morph targets reproduce the simulated positions frame
// by frame, the animation steps through them at the frames' times, the collider is its own mesh.
// The file is the fixture sim.writes_gltf_sphere's (the sphere scene, 9 frames, every 3rd kept);
// Khronos' validator checks its form (gltf.validator_accepts_exports), this its content.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tiny_gltf.h>

#include "common/scene.h"
#include "common/scene_json.h"

using namespace weft;

namespace {

// An accessor's floats (tightly packed float accessors only: what weft-sim writes).
std::vector<float> floats(const tinygltf::Model& model, int index) {
    const tinygltf::Accessor& a = model.accessors.at(size_t(index));
    REQUIRE(a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT);
    const tinygltf::BufferView& view = model.bufferViews.at(size_t(a.bufferView));
    const size_t count = a.count * size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
    std::vector<float> out(count);
    std::memcpy(out.data(), model.buffers.at(size_t(view.buffer)).data.data() + view.byteOffset + a.byteOffset,
                count * sizeof(float));
    return out;
}

// A .glb the fixtures wrote, and the sample scene it was run from, built afresh.
void load_run(const char* glb, const char* scene_name, tinygltf::Model* model, scenes::Scene* scene,
              scenes::SceneWorld* world) {
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    REQUIRE_MESSAGE(loader.LoadBinaryFromFile(model, &error, &warning, glb), error);
    REQUIRE(scenes::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/" + scene_name, scene).empty());
    REQUIRE(scenes::build_scene(*scene, world, {WEFT_SAMPLE_ASSETS_DIR}).empty());
}

}  // namespace

TEST_CASE("the glTF export plays back the simulated positions of every kept frame") {
    tinygltf::Model model;
    scenes::Scene scene;
    scenes::SceneWorld world;
    load_run(WEFT_GLTF_SPHERE, "sphere.json", &model, &scene, &world);
    std::vector<std::vector<Vec3>> kept{scenes::cloth_positions(world)[0]};  // frames 0, 3, 6, 9
    for (int frame = 1; frame <= 9; ++frame) {
        REQUIRE(step(world.world, scene.dt_s).ok());
        if (frame % 3 == 0) kept.push_back(scenes::cloth_positions(world)[0]);
    }

    // Two meshes: the cloth (3 morph targets) and the sphere.
    REQUIRE(model.meshes.size() == 2);
    const tinygltf::Primitive& cloth = model.meshes[0].primitives.at(0);
    REQUIRE(cloth.targets.size() == 3);
    const std::vector<float> base = floats(model, cloth.attributes.at("POSITION"));
    REQUIRE(base.size() == 3 * kept[0].size());
    CHECK(floats(model, cloth.attributes.at("TEXCOORD_0")).size() == 2 * kept[0].size());
    CHECK(floats(model, cloth.attributes.at("NORMAL")).size() == base.size());
    for (size_t k = 0; k < kept.size(); ++k) {
        const std::vector<float> delta = k == 0 ? std::vector<float>(base.size(), 0.0f)
                                                : floats(model, cloth.targets[k - 1].at("POSITION"));
        double worst_m = 0.0;
        for (size_t i = 0; i < kept[k].size(); ++i) {
            const float p[3] = {kept[k][i].x, kept[k][i].y, kept[k][i].z};
            for (int c = 0; c < 3; ++c) worst_m = std::max(worst_m, double(std::abs(base[3 * i + c] + delta[3 * i + c] - p[c])));
        }
        INFO("kept frame " << k);
        CHECK(worst_m < 1e-6);  // base + difference rounds once in float
    }
    // The cloth falls: the last kept frame is well below the first.
    CHECK(kept.back()[0].y < kept.front()[0].y - 0.05f);

    // One animation: at frame 3k's time, target k - 1 alone weighs 1.
    REQUIRE(model.animations.size() == 1);
    const tinygltf::AnimationSampler& sampler = model.animations[0].samplers.at(0);
    CHECK(sampler.interpolation == "STEP");
    CHECK(model.animations[0].channels.at(0).target_path == "weights");
    const std::vector<float> times = floats(model, sampler.input), weights = floats(model, sampler.output);
    REQUIRE(times.size() == 4);
    REQUIRE(weights.size() == 4 * 3);
    for (size_t k = 0; k < 4; ++k) {
        CHECK(times[k] == doctest::Approx(3.0 * k * scene.dt_s));
        for (size_t t = 0; t < 3; ++t) CHECK(weights[3 * k + t] == (k >= 1 && t == k - 1 ? 1.0f : 0.0f));
    }

    // The sphere, at its radius (0.5 m, without the inflation).
    const std::vector<float> sphere = floats(model, model.meshes[1].primitives.at(0).attributes.at("POSITION"));
    REQUIRE(sphere.size() > 300);
    for (size_t i = 0; i < sphere.size(); i += 3)
        REQUIRE(std::sqrt(sphere[i] * sphere[i] + sphere[i + 1] * sphere[i + 1] + sphere[i + 2] * sphere[i + 2]) ==
                doctest::Approx(0.5).epsilon(1e-5));
}

// The fixture sim.writes_gltf_skirt_walk: the dressed skirt on the walking mannequin, frames 0, 3
// and 6 kept. The body is its own mesh, posed per kept frame by morph targets, grey and untextured.
TEST_CASE("the glTF export carries the walking body as its own posed mesh") {
    tinygltf::Model model;
    scenes::Scene scene;
    scenes::SceneWorld world;
    load_run(WEFT_GLTF_SKIRT_WALK, "skirt-walk.json", &model, &scene, &world);
    REQUIRE(world.body);
    std::vector<std::vector<Vec3>> poses{world.body->pose.empty() ? world.body->rest : world.body->pose};
    for (int frame = 1; frame <= 6; ++frame) {
        REQUIRE(scenes::animate_body(world, float(frame) * scene.dt_s).empty());
        REQUIRE(step(world.world, scene.dt_s).ok());
        if (frame % 3 == 0) poses.push_back(world.body->pose);
    }

    int body_node = -1;
    for (size_t n = 0; n < model.nodes.size(); ++n)
        if (model.nodes[n].name == "body") body_node = int(n);
    REQUIRE(body_node >= 0);
    const tinygltf::Primitive& body = model.meshes.at(size_t(model.nodes[size_t(body_node)].mesh)).primitives.at(0);
    CHECK(body.attributes.count("TEXCOORD_0") == 0);
    CHECK(model.materials.at(size_t(body.material)).pbrMetallicRoughness.baseColorTexture.index < 0);
    REQUIRE(body.targets.size() == 2);
    const std::vector<float> base = floats(model, body.attributes.at("POSITION"));
    REQUIRE(base.size() == 3 * poses[0].size());
    const auto distance_m = [](const Vec3& a, const Vec3& b) {
        return std::sqrt(double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y) + double(a.z - b.z) * (a.z - b.z));
    };
    double moved_m = 0.0;
    for (size_t k = 0; k < poses.size(); ++k) {
        const std::vector<float> delta = k == 0 ? std::vector<float>(base.size(), 0.0f)
                                                : floats(model, body.targets[k - 1].at("POSITION"));
        double worst_m = 0.0;
        for (size_t v = 0; v < poses[k].size(); ++v) {
            const Vec3 p{base[3 * v] + delta[3 * v], base[3 * v + 1] + delta[3 * v + 1], base[3 * v + 2] + delta[3 * v + 2]};
            worst_m = std::max(worst_m, distance_m(p, poses[k][v]));
            moved_m = std::max(moved_m, distance_m(p, poses[0][v]));
        }
        CHECK_MESSAGE(worst_m < 1e-5, "kept frame " << k);
    }
    CHECK(moved_m > 1e-6);  // the walk has begun: the targets are not all zero
}
