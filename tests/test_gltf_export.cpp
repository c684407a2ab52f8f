// weft-sim --gltf read back (tinygltf): the morph targets reproduce the simulated positions frame
// by frame, the animation steps through them at the frames' times, the collider is its own mesh.
// The file is the fixture sim.writes_gltf_sphere's (the sphere scene, 9 frames, every 3rd kept);
// Khronos' validator checks its form (gltf.validator_accepts_exports), this its content.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

#include <tiny_gltf.h>

#include "scene.h"
#include "scene_json.h"

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

}  // namespace

TEST_CASE("the glTF export plays back the simulated positions of every kept frame") {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    REQUIRE_MESSAGE(loader.LoadBinaryFromFile(&model, &error, &warning, WEFT_GLTF_SPHERE), error);

    scenes::Scene scene;
    REQUIRE(scenes::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/sphere.json", &scene).empty());
    scenes::SceneWorld world;
    REQUIRE(scenes::build_scene(scene, &world).empty());
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
