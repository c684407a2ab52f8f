// Determinism across builds (test_determinism.cpp: within one): the same inputs give the same bits
// whatever the SIMD path, the build (Release, or RelWithDebInfo with the sanitizers) and the
// compiler. The sample assets' bytes, and the positions after a fixed run of the seed scenes and of the dressed skirt walking on
// the mannequin are hashed (XXH64 of the caller-order floats) and compared with the values
// committed in tests/determinism.txt. A change that moves results on purpose (a new projection
// order, a new default) updates that file in the same commit; the failure message gives the line.
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "asset/xxh64.h"
#include "common/scene_json.h"
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;

namespace {

constexpr uint32_t kSteps = 60;

uint64_t hash_positions(const std::vector<Vec3>& p) { return xxh64(p.data(), p.size() * sizeof(Vec3), 0); }

std::string hex(uint64_t h) {
    char text[17];
    std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(h));
    return text;
}

// tests/determinism.txt: one "name hash" per line; '#' starts a comment.
std::map<std::string, std::string> committed_hashes() {
    std::ifstream in(std::string(WEFT_SOURCE_DIR) + "/tests/determinism.txt");
    std::map<std::string, std::string> out;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        std::string name, hash;
        if (fields >> name >> hash) out[name] = hash;
    }
    return out;
}

void check_committed(const std::string& name, uint64_t hash) {
    const std::map<std::string, std::string> committed = committed_hashes();
    const auto it = committed.find(name);
    INFO("tests/determinism.txt should hold the line: ", name, " ", hex(hash));
    REQUIRE(it != committed.end());
    CHECK(it->second == hex(hash));
}

uint64_t seed_scene_hash(scenes::SeedScene scene, SimdPath path) {
    auto w = make_scene(scene, scene_options(50, path));
    step_n(*w, kSteps);
    return hash_positions(read_all(*w));
}

#ifdef WEFT_SAMPLE_ASSETS_DIR  // the sample assets are baked by weft-bake: built with the tools only
uint64_t skirt_walk_hash(SimdPath path) {
    scenes::Scene scene;
    REQUIRE(scenes::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json", &scene).empty());
    scene.simd = path;
    scenes::SceneWorld world;
    REQUIRE(scenes::build_scene(scene, &world, {WEFT_SAMPLE_ASSETS_DIR}).empty());
    for (uint32_t frame = 1; frame <= kSteps; ++frame) {
        REQUIRE(scenes::animate_body(world, float(frame) * scene.dt_s).empty());
        REQUIRE(step(world.world, scene.dt_s).ok());
    }
    return hash_positions(scenes::cloth_positions(world)[0]);
}

// The bytes of an asset this build's weft-bake wrote (samples/assets.json).
uint64_t sample_asset_hash(const std::string& name) {
    std::ifstream in(std::string(WEFT_SAMPLE_ASSETS_DIR) + "/" + name + ".weft", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(!bytes.empty());
    return xxh64(bytes.data(), bytes.size(), 0);
}
#endif

}  // namespace

TEST_CASE("determinism: the seed scenes hash to the committed values on every SIMD path") {
    for (const scenes::SeedScene scene : {scenes::SeedScene::drape, scenes::SeedScene::flag, scenes::SeedScene::sphere}) {
        CAPTURE(scenes::scene_name(scene));
        const uint64_t scalar = seed_scene_hash(scene, SimdPath::scalar);
        for (const SimdPath path : available_paths()) CHECK(seed_scene_hash(scene, path) == scalar);
        check_committed(std::string("seed-") + scenes::scene_name(scene), scalar);
    }
}

#ifdef WEFT_SAMPLE_ASSETS_DIR
TEST_CASE("determinism: the dressed skirt walking hashes to the committed value on every SIMD path") {
    const uint64_t scalar = skirt_walk_hash(SimdPath::scalar);
    for (const SimdPath path : available_paths()) CHECK(skirt_walk_hash(path) == scalar);
    check_committed("skirt-walk", scalar);
}

// Whichever compiler built weft-bake, flat and sewn alike (the sewing runs the runtime's step).
TEST_CASE("determinism: weft-bake writes the sample assets' committed bytes") {
    for (const char* name : {"sheet", "flag", "skirt", "tee", "skirt-dressed", "tee-dressed"}) {
        CAPTURE(name);
        check_committed(std::string("asset-") + name, sample_asset_hash(name));
    }
}
#endif
