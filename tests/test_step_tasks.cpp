// The step as tasks (weft/world.h, StepScheduler and the stage calls): a world of several dressed,
// walking characters gives the same bits however its work items are spread over threads, and the
// stage calls refuse what is out of order.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "asset/xxh64.h"
#include "common/crowd.h"
#include "common/thread_pool.h"
#include "test_support.h"

using namespace weft;
using namespace weft::test;

namespace {

constexpr uint32_t kFrames = 40;

scenes::CrowdOptions crowd_options(uint32_t characters) {
    scenes::CrowdOptions o;
    o.characters = characters;
    o.skirt_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json";
    o.tee_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/tee-walk.json";
    o.asset_dirs = {WEFT_SAMPLE_ASSETS_DIR};
    return o;
}

// XXH64 of every cloth's positions after kFrames frames, in cloth order.
uint64_t hash_crowd(scenes::Crowd& crowd) {
    uint64_t h = 0;
    for (const scenes::CrowdCharacter& who : crowd.characters)
        for (ClothId cloth : {who.skirt, who.tee}) {
            ClothView view;
            REQUIRE(view_cloth(crowd.world, cloth, &view).ok());
            const std::vector<Vec3> p = read_all(crowd.world, cloth, view.asset->particle_count);
            h = xxh64(p.data(), p.size() * sizeof(Vec3), h);
        }
    return h;
}

enum class Drive { step_alone, step_with_pool, items_backwards };

// The crowd stepped kFrames frames: by step() (with the pool's scheduler when `threads` > 0), or
// by the stage calls with every item run on its own, last item first.
uint64_t run_crowd(uint32_t characters, Drive drive, uint32_t threads, SimdPath path) {
    std::unique_ptr<tools::ThreadPool> pool;
    scenes::CrowdOptions o = crowd_options(characters);
    o.simd = path;
    if (drive == Drive::step_with_pool) {
        pool = std::make_unique<tools::ThreadPool>(threads);
        o.scheduler = pool->scheduler();
    }
    scenes::Crowd crowd;
    const std::string e = scenes::build_crowd(o, &crowd);
    INFO(e);
    REQUIRE(e.empty());
    for (uint32_t frame = 1; frame <= kFrames; ++frame) {
        REQUIRE(scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty());
        if (drive != Drive::items_backwards) {
            REQUIRE(step(crowd.world, crowd.dt_s).ok());
            continue;
        }
        REQUIRE(begin_step(crowd.world, crowd.dt_s).ok());
        for (StepStage stage : {StepStage::bodies, StepStage::cloths})
            for (uint32_t i = step_stage_items(crowd.world, stage); i-- > 0;)
                REQUIRE(run_step_items(crowd.world, stage, i, i + 1).ok());
        REQUIRE(end_step(crowd.world).ok());
    }
    return hash_crowd(crowd);
}

}  // namespace

TEST_CASE("step as tasks: three walking characters in skirt and tee give the same bits on 1, 2 and 7 threads") {
    for (const SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        const uint64_t alone = run_crowd(3, Drive::step_alone, 0, path);
        CHECK(run_crowd(3, Drive::step_with_pool, 1, path) == alone);
        CHECK(run_crowd(3, Drive::step_with_pool, 2, path) == alone);
        CHECK(run_crowd(3, Drive::step_with_pool, 7, path) == alone);
        CHECK(run_crowd(3, Drive::items_backwards, 0, path) == alone);
    }
}

TEST_CASE("step as tasks: a character's cloths do not depend on the others in the world") {
    // The first character of a crowd of three against the same character alone: its cloths
    // collide with its own body only (set_cloth_body), so the other two change nothing.
    const auto first_character = [](uint32_t characters) {
        scenes::Crowd crowd;
        REQUIRE(scenes::build_crowd(crowd_options(characters), &crowd).empty());
        for (uint32_t frame = 1; frame <= kFrames; ++frame) {
            REQUIRE(scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty());
            REQUIRE(step(crowd.world, crowd.dt_s).ok());
        }
        const ClothId skirt = crowd.characters[0].skirt;
        ClothView view;
        REQUIRE(view_cloth(crowd.world, skirt, &view).ok());
        return read_all(crowd.world, skirt, view.asset->particle_count);
    };
    const std::vector<Vec3> alone = first_character(1), among = first_character(3);
    REQUIRE(alone.size() == among.size());
    CHECK(std::equal(alone.begin(), alone.end(), among.begin(),
                     [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }));
}

TEST_CASE("step as tasks: the stage calls refuse what is out of order and change nothing") {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(2), &crowd).empty());
    World* w = crowd.world;
    CHECK(step_stage_items(w, StepStage::bodies) == 2);
    CHECK(step_stage_items(w, StepStage::cloths) == 4);
    CHECK(step_stage_items(nullptr, StepStage::cloths) == 0);
    CHECK(run_step_items(w, StepStage::cloths, 0, 1).code == ErrorCode::invalid_argument);  // no step open
    CHECK(end_step(w).code == ErrorCode::invalid_argument);
    CHECK(begin_step(w, 0.0f).code == ErrorCode::out_of_range);
    CHECK(begin_step(nullptr, 0.01f).code == ErrorCode::invalid_argument);

    REQUIRE(begin_step(w, crowd.dt_s).ok());
    CHECK(begin_step(w, crowd.dt_s).code == ErrorCode::invalid_argument);  // already open
    CHECK(step(w, crowd.dt_s).code == ErrorCode::invalid_argument);
    CHECK(run_step_items(w, StepStage::cloths, 2, 5).code == ErrorCode::out_of_range);
    CHECK(run_step_items(w, StepStage::cloths, 3, 2).code == ErrorCode::out_of_range);
    CHECK(run_step_items(w, static_cast<StepStage>(7), 0, 1).code == ErrorCode::invalid_argument);
    // Nothing that changes or reads the world while its items may be running.
    std::vector<Vec3> pose(crowd.skirt.body->rest.size(), Vec3{0.0f, 1.0f, 0.0f});
    CHECK(set_body_vertices(w, crowd.characters[0].body, pose.data(), uint32_t(pose.size())).code ==
          ErrorCode::invalid_argument);
    Vec3 one{};
    CHECK(read_positions(w, crowd.characters[0].skirt, &one, 1).code == ErrorCode::invalid_argument);
    CHECK(set_cloth_body(w, crowd.characters[0].skirt, crowd.characters[1].body).code == ErrorCode::invalid_argument);
    CHECK(run_step_items(w, StepStage::bodies, 0, 2).ok());
    CHECK(run_step_items(w, StepStage::cloths, 0, 4).ok());
    CHECK(run_step_items(w, StepStage::cloths, 4, 4).ok());  // an empty range
    REQUIRE(end_step(w).ok());
    CHECK(world_stats(w).steps == 1);
    CHECK(step(w, crowd.dt_s).ok());
    CHECK(world_stats(w).steps == 2);

    // set_cloth_body: a stale body or cloth is refused; kEveryBody is accepted.
    CHECK(set_cloth_body(w, crowd.characters[0].skirt, BodyId{2}).code == ErrorCode::out_of_range);
    CHECK(set_cloth_body(w, ClothId{4}, crowd.characters[0].body).code == ErrorCode::out_of_range);
    CHECK(set_cloth_body(w, crowd.characters[0].skirt, kEveryBody).ok());
}
