// The step as tasks (weft/world.h, StepScheduler and the stage calls): a world of several dressed,
// walking characters gives the same bits however its work items are spread over threads, and the
// stage calls refuse what is out of order. Also the frame budget (set_frame_budget_us) on the crowd.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "asset/xxh64.h"
#include "common/crowd.h"
#include "common/metrics.h"
#include "common/thread_pool.h"
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;

namespace {

constexpr uint32_t kFrames = 40;
constexpr float kCrowdSleepSpeed_m_s = 0.05f;  // a standing character's garments sleep at this speed
constexpr uint32_t kFramesToSleep = 150;       // and within this many frames (2.5 s)

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

// Some characters standing still and their cloths allowed to sleep (ClothDesc::sleep_speed_m_s).
struct Sleep {
    uint32_t standing = 0;
    float speed_m_s = 0.0f;
    uint32_t frames = kFrames;
    uint64_t* sleeping = nullptr;  // out: WorldStats::sleeping_cloths after the last frame
    // The frame budget (set_frame_budget_us), us; 0: never set. Character k's cloths get priority -k.
    float budget_us = 0.0f;
};

// The first character's skirt blown up before one frame (a particle thrown 1 km), the crowd's cloths
// with a recovery policy (ClothDesc::recovery).
struct BlowUp {
    RecoveryPolicy recovery = RecoveryPolicy::none;
    uint32_t frame = 0;              // 0: none
    uint64_t* recoveries = nullptr;  // out: WorldStats::total_recoveries after the last frame
};

void throw_a_particle(const scenes::Crowd& crowd) {
    const ClothId skirt = crowd.characters[0].skirt;
    ClothView view;
    REQUIRE(view_cloth(crowd.world, skirt, &view).ok());
    const ClothAsset& a = *view.asset;
    uint32_t p = a.particle_count / 2;
    while (p + 1 < a.particle_count && !(a.inverse_mass[a.slot_of_particle[p]] > 0.0f)) ++p;
    REQUIRE(set_particle(crowd.world, skirt, p, {1000.0f, 0.0f, 0.0f}, a.inverse_mass[a.slot_of_particle[p]]).ok());
}

// The crowd stepped kFrames frames: by step() (with the pool's scheduler when `threads` > 0), or
// by the stage calls with every item run on its own, last item first.
uint64_t run_crowd(uint32_t characters, Drive drive, uint32_t threads, SimdPath path, const Sleep& sleep = {},
                   const BlowUp& blow_up = {}) {
    std::unique_ptr<tools::ThreadPool> pool;
    scenes::CrowdOptions o = crowd_options(characters);
    o.simd = path;
    o.standing = sleep.standing;
    o.sleep_speed_m_s = sleep.speed_m_s;
    o.recovery = blow_up.recovery;
    if (drive == Drive::step_with_pool) {
        pool = std::make_unique<tools::ThreadPool>(threads);
        o.scheduler = pool->scheduler();
    }
    scenes::Crowd crowd;
    const std::string e = scenes::build_crowd(o, &crowd);
    INFO(e);
    REQUIRE(e.empty());
    if (sleep.budget_us > 0.0f) {
        REQUIRE(set_frame_budget_us(crowd.world, sleep.budget_us).ok());
        for (uint32_t k = 0; k < characters; ++k)
            for (ClothId cloth : {crowd.characters[k].skirt, crowd.characters[k].tee})
                REQUIRE(set_cloth_priority(crowd.world, cloth, -float(k)).ok());
    }
    for (uint32_t frame = 1; frame <= sleep.frames; ++frame) {
        REQUIRE(scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty());
        if (frame == blow_up.frame) throw_a_particle(crowd);
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
    if (sleep.sleeping != nullptr) *sleep.sleeping = world_stats(crowd.world).sleeping_cloths;
    if (blow_up.recoveries != nullptr) *blow_up.recoveries = world_stats(crowd.world).total_recoveries;
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

TEST_CASE("step as tasks: with one of two characters standing and its cloths asleep, the same bits on 1, 2 and 7 threads") {
    for (const SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        uint64_t sleeping = 0;
        Sleep sleep{1, kCrowdSleepSpeed_m_s, kFramesToSleep, &sleeping};
        const uint64_t alone = run_crowd(2, Drive::step_alone, 0, path, sleep);
        CHECK(sleeping == 2);  // the standing character's skirt and tee, not the walker's
        sleep.sleeping = nullptr;
        CHECK(run_crowd(2, Drive::step_with_pool, 1, path, sleep) == alone);
        CHECK(run_crowd(2, Drive::step_with_pool, 2, path, sleep) == alone);
        CHECK(run_crowd(2, Drive::step_with_pool, 7, path, sleep) == alone);
        CHECK(run_crowd(2, Drive::items_backwards, 0, path, sleep) == alone);
        CHECK(run_crowd(2, Drive::step_alone, 0, path, Sleep{1, 0.0f, kFramesToSleep}) != alone);  // sleeping shows
    }
}

TEST_CASE("step as tasks: a skirt blown up and recovered (last good state, dressed pose) gives the same bits on 1, 2 and 7 threads") {
    for (RecoveryPolicy policy : {RecoveryPolicy::last_good_state, RecoveryPolicy::dressed_pose}) {
        CAPTURE(int(policy));
        const SimdPath path = SimdPath::automatic;
        uint64_t recoveries = 0;
        BlowUp blow_up{policy, kFrames / 2, &recoveries};
        const uint64_t alone = run_crowd(2, Drive::step_alone, 0, path, {}, blow_up);
        CHECK(recoveries == 1);  // the skirt, once, in the frame it was thrown
        blow_up.recoveries = nullptr;
        CHECK(run_crowd(2, Drive::step_with_pool, 1, path, {}, blow_up) == alone);
        CHECK(run_crowd(2, Drive::step_with_pool, 2, path, {}, blow_up) == alone);
        CHECK(run_crowd(2, Drive::step_with_pool, 7, path, {}, blow_up) == alone);
        CHECK(run_crowd(2, Drive::items_backwards, 0, path, {}, blow_up) == alone);
    }
    // Without a blow-up a policy changes no bit of the walk.
    CHECK(run_crowd(2, Drive::step_alone, 0, SimdPath::automatic, {}, BlowUp{RecoveryPolicy::last_good_state}) ==
          run_crowd(2, Drive::step_alone, 0, SimdPath::automatic));
}

namespace {

// The crowd's estimated step cost (WorldStats::budget_estimate_us), us: without a budget, or with
// one (1 us: every cloth at the floor).
double crowd_estimate_us(uint32_t characters, float budget_us = 0.0f) {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(characters), &crowd).empty());
    REQUIRE(set_frame_budget_us(crowd.world, budget_us).ok());
    REQUIRE(scenes::animate_crowd(crowd, crowd.dt_s).empty());
    REQUIRE(step(crowd.world, crowd.dt_s).ok());
    return world_stats(crowd.world).budget_estimate_us;
}

}  // namespace

TEST_CASE("frame budget: with one under the estimate, the same bits on 1, 2 and 7 threads, and other bits than without") {
    const float budget_us = float(0.6 * crowd_estimate_us(3));
    for (const SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        Sleep budget;
        budget.budget_us = budget_us;
        const uint64_t alone = run_crowd(3, Drive::step_alone, 0, path, budget);
        CHECK(run_crowd(3, Drive::step_with_pool, 1, path, budget) == alone);
        CHECK(run_crowd(3, Drive::step_with_pool, 2, path, budget) == alone);
        CHECK(run_crowd(3, Drive::step_with_pool, 7, path, budget) == alone);
        CHECK(run_crowd(3, Drive::items_backwards, 0, path, budget) == alone);
        CHECK(run_crowd(3, Drive::step_alone, 0, path) != alone);  // the budget shows
    }
}

TEST_CASE("frame budget: off, or over the estimate, changes no bit") {
    const uint64_t never_set = run_crowd(3, Drive::step_alone, 0, SimdPath::automatic);
    Sleep roomy;  // every cloth fits: nothing is cut
    roomy.budget_us = float(2.0 * crowd_estimate_us(3));
    CHECK(run_crowd(3, Drive::step_alone, 0, SimdPath::automatic, roomy) == never_set);

    // On for some frames, then off: the crowd runs its own splits again (the bits differ by then,
    // so the check is on the splits).
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(2), &crowd).empty());
    const ClothId skirt = crowd.characters[1].skirt;
    SolverSplit own, cut, again;
    REQUIRE(cloth_solver_split(crowd.world, skirt, &own).ok());
    REQUIRE(set_frame_budget_us(crowd.world, 1.0f).ok());  // far under: everything at the floor
    REQUIRE(scenes::animate_crowd(crowd, crowd.dt_s).empty());
    REQUIRE(step(crowd.world, crowd.dt_s).ok());
    REQUIRE(cloth_solver_split(crowd.world, skirt, &cut).ok());
    CHECK(cut.substeps * cut.iterations < own.substeps * own.iterations);
    REQUIRE(set_frame_budget_us(crowd.world, 0.0f).ok());
    REQUIRE(cloth_solver_split(crowd.world, skirt, &again).ok());
    CHECK(again.substeps == own.substeps);
    CHECK(again.iterations == own.iterations);
    REQUIRE(step(crowd.world, crowd.dt_s).ok());
    CHECK(world_stats(crowd.world).budget_cloths_cut == 0);
}

namespace {

// Each cloth's sweeps this step (substeps x iterations), in cloth order.
std::vector<uint32_t> crowd_sweeps(const scenes::Crowd& crowd) {
    std::vector<uint32_t> sweeps;
    for (const scenes::CrowdCharacter& who : crowd.characters)
        for (ClothId cloth : {who.skirt, who.tee}) {
            SolverSplit split;
            REQUIRE(cloth_solver_split(crowd.world, cloth, &split).ok());
            sweeps.push_back(split.substeps * split.iterations);
        }
    return sweeps;
}

}  // namespace

TEST_CASE("frame budget: the lowest priorities lose sweeps first, the estimate fits, and a change of priority moves the cut") {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(3), &crowd).empty());
    World* w = crowd.world;
    const std::vector<uint32_t> own = crowd_sweeps(crowd);
    // Room for one character at its own sweeps, one at the floor, and one half way between.
    const double full_us = crowd_estimate_us(1), floor_us = crowd_estimate_us(1, 1.0f);
    const float budget_us = float(full_us + 2.0 * floor_us + 0.5 * (full_us - floor_us));
    REQUIRE(set_frame_budget_us(w, budget_us).ok());
    // Character 0 nearest, then 1, then 2 (cloth order: skirt 0, tee 0, skirt 1, ...).
    const auto prioritise = [&](const float (&by_character)[3]) {
        for (uint32_t k = 0; k < 3; ++k)
            for (ClothId cloth : {crowd.characters[k].skirt, crowd.characters[k].tee})
                REQUIRE(set_cloth_priority(w, cloth, by_character[k]).ok());
    };
    prioritise({3.0f, 2.0f, 1.0f});
    for (uint32_t frame = 1; frame <= 5; ++frame) {
        REQUIRE(scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty());
        REQUIRE(step(w, crowd.dt_s).ok());
        const WorldStats stats = world_stats(w);
        CHECK(stats.budget_estimate_us <= double(budget_us));
        CHECK(stats.budget_cloths_cut > 0);
    }
    std::vector<uint32_t> sweeps = crowd_sweeps(crowd);
    CHECK(sweeps[0] == own[0]);  // the nearest character keeps its own sweeps
    CHECK(sweeps[1] == own[1]);
    CHECK(sweeps[4] == kBudgetFloorSweeps);  // the farthest is cut first, to the floor
    CHECK(sweeps[5] == kBudgetFloorSweeps);
    CHECK(sweeps[2] + sweeps[3] < own[2] + own[3]);  // the middle one in part
    CHECK(sweeps[2] + sweeps[3] > 2 * kBudgetFloorSweeps);
    for (uint32_t s : sweeps) CHECK(s >= kBudgetFloorSweeps);  // never below the floor
    uint64_t total = 0;
    for (uint32_t s : sweeps) total += s;
    CHECK(world_stats(w).budget_sweeps == total);

    prioritise({1.0f, 2.0f, 3.0f});  // the camera turned: character 2 is nearest now
    REQUIRE(scenes::animate_crowd(crowd, 6.0f * crowd.dt_s).empty());
    REQUIRE(step(w, crowd.dt_s).ok());
    sweeps = crowd_sweeps(crowd);
    CHECK(sweeps[4] == own[4]);
    CHECK(sweeps[5] == own[5]);
    CHECK(sweeps[0] == kBudgetFloorSweeps);
    CHECK(sweeps[1] == kBudgetFloorSweeps);
    CHECK(world_stats(w).budget_estimate_us <= double(budget_us));

    // A budget no cut can meet: every cloth at the floor, never 0, the estimate over the budget.
    REQUIRE(set_frame_budget_us(w, 1.0f).ok());
    REQUIRE(step(w, crowd.dt_s).ok());
    for (uint32_t s : crowd_sweeps(crowd)) CHECK(s == kBudgetFloorSweeps);
    CHECK(world_stats(w).budget_cloths_cut == 6);
    CHECK(world_stats(w).budget_estimate_us > 1.0);
}

TEST_CASE("frame budget: bad input is refused and changes nothing") {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(2), &crowd).empty());
    World* w = crowd.world;
    const float budget_us = float(0.6 * crowd_estimate_us(2));
    REQUIRE(set_frame_budget_us(w, budget_us).ok());
    REQUIRE(set_cloth_priority(w, crowd.characters[0].skirt, 1.0f).ok());
    REQUIRE(set_cloth_priority(w, crowd.characters[0].tee, 1.0f).ok());
    CHECK(set_frame_budget_us(w, -1.0f).code == ErrorCode::out_of_range);
    CHECK(set_frame_budget_us(w, std::nanf("")).code == ErrorCode::non_finite);
    CHECK(set_frame_budget_us(w, INFINITY).code == ErrorCode::non_finite);
    CHECK(set_frame_budget_us(nullptr, 1.0f).code == ErrorCode::invalid_argument);
    CHECK(set_cloth_priority(w, crowd.characters[1].skirt, std::nanf("")).code == ErrorCode::non_finite);
    CHECK(set_cloth_priority(w, crowd.characters[1].tee, -INFINITY).code == ErrorCode::non_finite);
    CHECK(set_cloth_priority(w, ClothId{100, 0}, 1.0f).code == ErrorCode::out_of_range);
    REQUIRE(begin_step(w, crowd.dt_s).ok());  // nothing changes the world while a step is open
    CHECK(set_frame_budget_us(w, 0.0f).code != ErrorCode::ok);
    CHECK(set_cloth_priority(w, crowd.characters[1].skirt, 9.0f).code != ErrorCode::ok);
    REQUIRE(end_step(w).ok());
    // As before the refusals: the budget is on and character 1 (priority 0) is cut, not character 0.
    REQUIRE(step(w, crowd.dt_s).ok());
    const std::vector<uint32_t> sweeps = crowd_sweeps(crowd);
    CHECK(world_stats(w).budget_cloths_cut > 0);
    CHECK(sweeps[2] + sweeps[3] < sweeps[0] + sweeps[1]);
    // A removed cloth's id is stale.
    const ClothId gone = crowd.characters[1].tee;
    REQUIRE(scenes::despawn_character(crowd, 1).empty());
    CHECK(set_cloth_priority(w, gone, 1.0f).code == ErrorCode::stale_id);
}

TEST_CASE("sleep: a standing character's cloths sleep through the same pose and wake when its body moves") {
    scenes::CrowdOptions o = crowd_options(1);
    o.standing = 1;
    o.sleep_speed_m_s = kCrowdSleepSpeed_m_s;
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(o, &crowd).empty());
    const auto asleep = [&] {
        bool skirt = false, tee = false;
        REQUIRE(cloth_is_sleeping(crowd.world, crowd.characters[0].skirt, &skirt).ok());
        REQUIRE(cloth_is_sleeping(crowd.world, crowd.characters[0].tee, &tee).ok());
        return uint32_t(skirt) + uint32_t(tee);
    };
    for (uint32_t frame = 1; frame <= kFramesToSleep; ++frame) {
        REQUIRE(scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty());  // the same pose
        REQUIRE(step(crowd.world, crowd.dt_s).ok());
    }
    REQUIRE(asleep() == 2);
    crowd.characters[0].standing = false;  // it starts to walk: a pose that differs
    REQUIRE(scenes::animate_crowd(crowd, 0.8f).empty());
    CHECK(asleep() == 0);
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

namespace {

struct CharacterFigures {
    double max_strain = 0.0, deepest_m = 0.0;  // over both garments and the frames after the ramp
};

void measure(scenes::Crowd& crowd, CharacterFigures* f) {
    const scenes::CrowdCharacter& who = crowd.characters[0];
    for (ClothId cloth : {who.skirt, who.tee}) {
        ClothView view;
        REQUIRE(view_cloth(crowd.world, cloth, &view).ok());
        REQUIRE(metrics::bounds(view).finite);
        f->max_strain = std::max(f->max_strain, metrics::stretch_strain(view).max);
        f->deepest_m = std::max(f->deepest_m, metrics::max_body_penetration_m(crowd.world, who.body, view));
    }
}

Quat turn_about_y(float radians) { return {0.0f, std::sin(0.5f * radians), 0.0f, std::cos(0.5f * radians)}; }

// One character walking for `frames` frames; `root_at(t)` moves its root (null: in place).
CharacterFigures walk_one(float inertia, uint32_t frames, Transform (*root_at)(float)) {
    scenes::CrowdOptions o = crowd_options(1);
    o.inertia = inertia;
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(o, &crowd).empty());
    CharacterFigures f;
    const uint32_t ramp = uint32_t(1.0f / crowd.dt_s + 0.5f);
    for (uint32_t frame = 1; frame <= frames; ++frame) {
        const float t = float(frame) * crowd.dt_s;
        if (root_at != nullptr) crowd.characters[0].root = root_at(t);
        REQUIRE(scenes::animate_crowd(crowd, t).empty());
        REQUIRE(step(crowd.world, crowd.dt_s).ok());
        if (frame > ramp) measure(crowd, &f);
    }
    return f;
}

// After the walk's 1 s ramp: from standing to 10 m/s along +x in 0.5 s, turning 180 degrees about
// the vertical between 1.3 and 1.5 s (so it runs back along -x), then on at 10 m/s.
Transform sprint_and_turn(float t) {
    const float a = 20.0f;  // m/s^2: 10 m/s after 0.5 s
    float heading = 0.0f;
    if (t > 1.3f) heading = 3.14159265f * std::min(1.0f, (t - 1.3f) / 0.2f);
    // Distance along the path, integrated in closed form; the path's direction turns with the heading.
    Vec3 at{};
    const float dt = 1.0f / 600.0f;  // fine steps of the path (the same for every call: deterministic)
    for (float s = 1.0f; s < t; s += dt) {
        const float speed = s < 1.5f ? a * (s - 1.0f) : 10.0f;
        const float h = s > 1.3f ? 3.14159265f * std::min(1.0f, (s - 1.3f) / 0.2f) : 0.0f;
        at.x += speed * std::cos(h) * dt;
        at.z -= speed * std::sin(h) * dt;
    }
    return {at, turn_about_y(heading)};
}

// The sprint at `inertia` against the still walk: max strain within `strain_factor` of it, the
// deepest particle within `depth_factor` of it (and never held to less than 2 mm).
void check_sprint_within_still_walk(float inertia, double strain_factor, double depth_factor) {
    const CharacterFigures still = walk_one(1.0f, 150, nullptr);
    const CharacterFigures sprint = walk_one(inertia, 150, sprint_and_turn);
    CAPTURE(still.max_strain);
    CAPTURE(still.deepest_m);
    CAPTURE(sprint.max_strain);
    CAPTURE(sprint.deepest_m);
    CHECK(sprint.max_strain <= strain_factor * still.max_strain);
    CHECK(sprint.deepest_m <= std::max(0.002, depth_factor * still.deepest_m));
}

}  // namespace

TEST_CASE("character motion: carried fully (inertia 0), sprinting to 10 m/s and turning 180 degrees in 0.2 s changes nothing of the walk") {
    // The carry moves the garments with the root substep by substep, as the body's hull and its
    // skinned points move: the walk reads as the still one to within its noise.
    check_sprint_within_still_walk(0.0f, 1.05, 1.1);
}

// Known to fail (issue 23, point 3): at inertia 0.5 the sample skirt and tee reach 465% max strain
// (the skirt's hem flung out after the turn) and 4.2 mm below the hull (the skirt at the back of
// the knee, between the thigh and shin capsules, while it accelerates; the still walk: 75%,
// 1.3 mm): docs/decisions/2026-12-07-hung-garments-swing.md; traced before in
// docs/decisions/2026-12-07-jumps-and-hitches.md, "The sprint".
// should_fail: it reports when it holds.
TEST_CASE("character motion: sprinting to 10 m/s and turning 180 degrees in 0.2 s at inertia 0.5 stays within the still walk's strain and penetration (known to fail)" *
          doctest::should_fail()) {
    check_sprint_within_still_walk(0.5f, 1.1, 1.0);
}

namespace {

// Two copies of the same one-character walk, stepped side by side for `frames` + 1 frames. Before
// the last step, `last_frame(twin, t)` poses the second copy in place of its walk's animation (and
// may act on it: a teleport, a reset).
template <class LastFrame>
void walk_twins(scenes::Crowd* first, scenes::Crowd* twin, uint32_t frames, LastFrame&& last_frame) {
    REQUIRE(scenes::build_crowd(crowd_options(1), first).empty());
    REQUIRE(scenes::build_crowd(crowd_options(1), twin).empty());
    for (uint32_t frame = 1; frame <= frames + 1; ++frame) {
        const float t = float(frame) * first->dt_s;
        REQUIRE(scenes::animate_crowd(*first, t).empty());
        if (frame <= frames)
            REQUIRE(scenes::animate_crowd(*twin, t).empty());
        else
            last_frame(*twin, t);
        REQUIRE(step(first->world, first->dt_s).ok());
        REQUIRE(step(twin->world, twin->dt_s).ok());
    }
}

}  // namespace

TEST_CASE("character motion: a 10 m teleport leaves no stretch and no penetration after one frame") {
    // Two copies of the same walk; one character jumps 10 m and turns 90 degrees before frame 91.
    // After that frame its garments are no more stretched than the copy's that stayed, and no
    // deeper in its body.
    scenes::Crowd stays, jumps;
    const uint32_t frames = 90;
    walk_twins(&stays, &jumps, frames, [](scenes::Crowd& twin, float t) {
        REQUIRE(scenes::teleport_character(twin, 0, {{10.0f, 0.0f, 0.0f}, turn_about_y(1.5707963f)}, t).empty());
    });
    CharacterFigures stayed, jumped;
    measure(stays, &stayed);
    measure(jumps, &jumped);
    CAPTURE(stayed.max_strain);
    CAPTURE(jumped.max_strain);
    CAPTURE(jumped.deepest_m);
    CHECK(jumped.max_strain <= stayed.max_strain * 1.05 + 0.01);
    CHECK(jumped.deepest_m <= std::max(0.002, stayed.deepest_m));
    // And it really went: the skirt's particles are about 10 m away.
    ClothView view;
    REQUIRE(view_cloth(jumps.world, jumps.characters[0].skirt, &view).ok());
    CHECK(metrics::bounds(view).min.x > 9.0f);

    // A respawn drops the garments' velocity: they start from rest where they land.
    REQUIRE(scenes::teleport_character(jumps, 0, {{-10.0f, 0.0f, 0.0f}, {}}, float(frames + 2) * stays.dt_s, true).empty());
    REQUIRE(view_cloth(jumps.world, jumps.characters[0].skirt, &view).ok());
    CHECK(metrics::bounds(view).max.x < -9.0f);
    double fastest = 0.0;
    for (uint32_t s = 0; s < view.asset->slot_count; ++s)
        fastest = std::max({fastest, double(std::fabs(view.x[s] - view.previous_x[s])), double(std::fabs(view.y[s] - view.previous_y[s])),
                            double(std::fabs(view.z[s] - view.previous_z[s]))});
    CHECK(fastest == 0.0);
    REQUIRE(step(jumps.world, jumps.dt_s).ok());
    CharacterFigures respawned;
    measure(jumps, &respawned);
    CHECK(respawned.deepest_m <= 0.002);
}

// A root that turns faster than ClothDesc::jump_turn_rad_s between two frames is a jump: the step
// carries the garments and takes the body's motion as teleport_character (teleport_cloth,
// teleport_body, teleport_collider) would, to the bit.
TEST_CASE("character motion: a root turned past the jump speed in one frame is stepped as a teleport of the character") {
    scenes::Crowd announced, unannounced;
    for (scenes::Crowd* c : {&announced, &unannounced}) REQUIRE(scenes::build_crowd(crowd_options(1), c).empty());
    const float dt = announced.dt_s;
    const ClothDesc& settings = announced.skirt.cloths[0].desc;
    REQUIRE(1.0f > settings.jump_turn_rad_s * dt);  // 1 rad in a frame is past it
    uint32_t frame = 1;
    for (; frame <= 40; ++frame)
        for (scenes::Crowd* c : {&announced, &unannounced}) {
            REQUIRE(scenes::animate_crowd(*c, float(frame) * dt).empty());
            REQUIRE(step(c->world, dt).ok());
        }
    const Transform turned{{0.0f, 0.0f, 0.0f}, turn_about_y(1.0f)};
    REQUIRE(scenes::teleport_character(announced, 0, turned, float(frame) * dt).empty());
    unannounced.characters[0].root = turned;
    REQUIRE(scenes::animate_crowd(unannounced, float(frame) * dt).empty());
    for (scenes::Crowd* c : {&announced, &unannounced}) REQUIRE(step(c->world, dt).ok());
    CHECK(hash_crowd(announced) == hash_crowd(unannounced));
    for (++frame; frame <= 60; ++frame)
        for (scenes::Crowd* c : {&announced, &unannounced}) {
            REQUIRE(scenes::animate_crowd(*c, float(frame) * dt).empty());
            REQUIRE(step(c->world, dt).ok());
        }
    CHECK(hash_crowd(announced) == hash_crowd(unannounced));
}

TEST_CASE("character motion: reset_to_pose puts a walking character's garments back on its body as it is now, at rest") {
    // Two copies of the same walk. Before frame 91 one character's garments are thrown 3 m off its
    // body (teleport_cloth alone) and then reset_to_pose: at rest on the body as posed for frame
    // 91, and after that frame no deeper in the body than 2 mm and no more stretched than the
    // copy's that walked on (within 10% + 1 percentage point: the dressed pose on a striding body is
    // not the walk's own).
    scenes::Crowd walks, resets;
    walk_twins(&walks, &resets, 90, [](scenes::Crowd& twin, float t) {
        REQUIRE(scenes::animate_crowd(twin, t).empty());
        const scenes::CrowdCharacter& who = twin.characters[0];
        for (ClothId cloth : {who.skirt, who.tee}) {
            REQUIRE(teleport_cloth(twin.world, cloth, {{3.0f, 0.0f, 0.0f}, {}}).ok());
            REQUIRE(reset_to_pose(twin.world, cloth).ok());
            ClothView view;
            REQUIRE(view_cloth(twin.world, cloth, &view).ok());
            double fastest = 0.0, farthest_x = 0.0;
            for (uint32_t s = 0; s < view.asset->slot_count; ++s) {
                if (view.asset->particle_of_slot[s] == kNoParticle) continue;
                fastest = std::max({fastest, double(std::fabs(view.x[s] - view.previous_x[s])),
                                    double(std::fabs(view.y[s] - view.previous_y[s])),
                                    double(std::fabs(view.z[s] - view.previous_z[s]))});
                farthest_x = std::max(farthest_x, double(std::fabs(view.x[s])));
            }
            CHECK(fastest == 0.0);
            CHECK(farthest_x < 1.0);  // back on the body at the origin
        }
    });
    CharacterFigures walked, reset;
    measure(walks, &walked);
    measure(resets, &reset);
    CAPTURE(walked.max_strain);
    CAPTURE(walked.deepest_m);
    CAPTURE(reset.max_strain);
    CAPTURE(reset.deepest_m);
    CHECK(reset.deepest_m <= 0.002);
    CHECK(reset.max_strain <= walked.max_strain * 1.1 + 0.01);

    // A cloth with neither skin constraints nor attachments has no pose on a body.
    auto seed = make_scene(scenes::SeedScene::drape, scene_options(8));
    CHECK(reset_to_pose(seed->world, seed->cloth).code == ErrorCode::invalid_argument);
    CHECK(reset_to_pose(resets.world, ClothId{9, 0}).code == ErrorCode::out_of_range);
}

TEST_CASE("character motion: bad roots and inertia are refused, a still root changes nothing") {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(1), &crowd).empty());
    const ClothId skirt = crowd.characters[0].skirt;
    CHECK(set_cloth_root(crowd.world, skirt, {{0, 0, 0}, {0, 0, 0, 2}}).code == ErrorCode::out_of_range);
    CHECK(set_cloth_root(crowd.world, skirt, {{NAN, 0, 0}, {}}).code == ErrorCode::non_finite);
    CHECK(teleport_cloth(crowd.world, ClothId{9}, {}).code == ErrorCode::out_of_range);
    ClothDesc d = crowd.skirt.cloths[0].desc;
    d.linear_inertia = 1.5f;
    CHECK(set_cloth_settings(crowd.world, skirt, d).code == ErrorCode::out_of_range);
    d.linear_inertia = 0.5f;
    d.max_inertial_speed_m_s = -1.0f;
    CHECK(set_cloth_settings(crowd.world, skirt, d).code == ErrorCode::out_of_range);
    d.max_inertial_speed_m_s = 1000.0f;
    d.jump_turn_rad_s = NAN;
    CHECK(set_cloth_settings(crowd.world, skirt, d).code == ErrorCode::out_of_range);
    d.jump_turn_rad_s = 30.0f;
    d.max_step_s = 2.0f;
    CHECK(set_cloth_settings(crowd.world, skirt, d).code == ErrorCode::out_of_range);
    d.max_step_s = 1.0f / 30.0f;
    d.max_step_growth = 0.5f;  // 0 (off) or at least 1
    CHECK(set_cloth_settings(crowd.world, skirt, d).code == ErrorCode::out_of_range);
}

namespace {

// The slowest-settling garment's mean speed (m/s) and whether every particle of both garments is
// finite and within 1.5 m of the character's root across and 0-2 m above it.
struct GarmentState {
    double mean_speed_m_s = 0.0, max_strain = 0.0;
    bool finite_and_bounded = true;
};
GarmentState garment_state(scenes::Crowd& crowd) {
    const scenes::CrowdCharacter& who = crowd.characters[0];
    GarmentState g;
    for (ClothId cloth : {who.skirt, who.tee}) {
        ClothView view;
        REQUIRE(view_cloth(crowd.world, cloth, &view).ok());
        const metrics::Bounds b = metrics::bounds(view);
        const Vec3 root{who.offset_m.x + who.root.translation_m.x, who.offset_m.y + who.root.translation_m.y,
                        who.offset_m.z + who.root.translation_m.z};
        g.finite_and_bounded = g.finite_and_bounded && b.finite && b.min.x > root.x - 1.5f && b.max.x < root.x + 1.5f &&
                               b.min.z > root.z - 1.5f && b.max.z < root.z + 1.5f && b.min.y > root.y - 0.05f &&
                               b.max.y < root.y + 2.0f;
        g.mean_speed_m_s = std::max(g.mean_speed_m_s, metrics::mean_speed(view));
        g.max_strain = std::max(g.max_strain, metrics::stretch_strain(view).max);
    }
    return g;
}

// `frames` frames of the character standing still in its rest pose (the walk's pose at t = 0) at
// its root; the state after them, and whether every frame was finite and bounded.
GarmentState stand(scenes::Crowd& crowd, uint32_t frames) {
    bool bounded = true;
    for (uint32_t frame = 0; frame < frames; ++frame) {
        REQUIRE(scenes::animate_crowd(crowd, 0.0f).empty());
        REQUIRE(step(crowd.world, crowd.dt_s).ok());
        bounded = bounded && garment_state(crowd).finite_and_bounded;
    }
    GarmentState g = garment_state(crowd);
    g.finite_and_bounded = g.finite_and_bounded && bounded;
    return g;
}


// Issue 23 point 6. The sample skirt and tee on the mannequin standing still (world space, inertia
// 1: the worst case); after each abuse the character stands: every particle stays finite and within
// reach of the body throughout, the garments end no more stretched than they started (within 10% +
// 1 percentage point) and at rest (mean speed under 5 mm/s) 2 s after each: refused vertices, a
// 100 m teleport, the spin (a root turning past ClothDesc::jump_turn_rad_s carries the garments
// whole) and the hitch (a step more than ClothDesc::max_step_growth times the last is stepped as
// long as the last).
void abuse_a_dressed_character() {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(1), &crowd).empty());
    scenes::CrowdCharacter& who = crowd.characters[0];
    const GarmentState start = stand(crowd, 30);
    REQUIRE(start.finite_and_bounded);
    CAPTURE(start.max_strain);
    auto check_recovered = [&](const std::string& what, float settle_s) {
        const GarmentState after = stand(crowd, uint32_t(settle_s / crowd.dt_s + 0.5f));
        INFO(what);
        CAPTURE(after.mean_speed_m_s);
        CAPTURE(after.max_strain);
        CHECK(after.finite_and_bounded);
        CHECK(after.mean_speed_m_s < 0.005);
        CHECK(after.max_strain <= 1.1 * start.max_strain + 0.01);
        CHECK(world_stats(crowd.world).unhealthy_cloths == 0);  // cloth_health: every garment healthy
    };

    // 1. Body vertices with NaN or 1e30: refused, and nothing changes (the cloths' and the body's
    // arrays keep every bit).
    {
        ClothView skirt;
        REQUIRE(view_cloth(crowd.world, who.skirt, &skirt).ok());
        BodyView body;
        REQUIRE(view_body(crowd.world, who.body, &body).ok());
        const std::vector<float> x_before(skirt.x, skirt.x + skirt.asset->slot_count);
        const std::vector<float> hull_before(body.hull, body.hull + 4 * size_t(body.vertex_count));
        std::vector<Vec3> bad = crowd.pose;
        REQUIRE(bad.size() == body.vertex_count);
        for (float poison : {NAN, 1e30f, -INFINITY}) {
            bad[bad.size() / 2].y = poison;
            CHECK(set_body_vertices(crowd.world, who.body, bad.data(), uint32_t(bad.size())).code != ErrorCode::ok);
            CHECK(teleport_body(crowd.world, who.body, bad.data(), uint32_t(bad.size())).code != ErrorCode::ok);
        }
        CHECK(std::equal(x_before.begin(), x_before.end(), skirt.x));
        CHECK(std::equal(hull_before.begin(), hull_before.end(), body.hull));
        check_recovered("after refused vertices", 2.0f);
    }

    // 2. The body teleported 100 m (a respawn the cloths are told of: teleport_character).
    REQUIRE(scenes::teleport_character(crowd, 0, {{100.0f, 0.0f, 0.0f}, {}}, 0.0f).empty());
    check_recovered("after a 100 m teleport", 2.0f);

    // 3. Spinning at 10 revolutions a second about the vertical for half a second, then still.
    {
        bool bounded = true;
        const uint32_t half_second = uint32_t(0.5f / crowd.dt_s + 0.5f);
        for (uint32_t frame = 1; frame <= half_second; ++frame) {
            who.root.rotation = turn_about_y(2.0f * 3.14159265f * 10.0f * float(frame) * crowd.dt_s);
            REQUIRE(scenes::animate_crowd(crowd, 0.0f).empty());
            REQUIRE(step(crowd.world, crowd.dt_s).ok());
            bounded = bounded && garment_state(crowd).finite_and_bounded;
        }
        CHECK(bounded);
        check_recovered("after spinning at 10 revolutions a second", 2.0f);
    }

    // 4. One frame of 0.25 s (a hitch).
    REQUIRE(scenes::animate_crowd(crowd, 0.0f).empty());
    REQUIRE(step(crowd.world, 0.25f).ok());
    CHECK(garment_state(crowd).finite_and_bounded);
    check_recovered("after a 0.25 s frame", 2.0f);

    // 5. A cloth removed while the frame's tasks run: refused until the step ends, then removed;
    // the other garment steps on.
    REQUIRE(scenes::animate_crowd(crowd, 0.0f).empty());
    REQUIRE(begin_step(crowd.world, crowd.dt_s).ok());
    CHECK(remove_cloth(crowd.world, who.skirt).code == ErrorCode::invalid_argument);
    for (StepStage stage : {StepStage::bodies, StepStage::cloths})
        REQUIRE(run_step_items(crowd.world, stage, 0, step_stage_items(crowd.world, stage)).ok());
    CHECK(remove_cloth(crowd.world, who.skirt).code == ErrorCode::invalid_argument);
    REQUIRE(end_step(crowd.world).ok());
    CHECK(remove_cloth(crowd.world, who.skirt).ok());
    for (uint32_t frame = 0; frame < 30; ++frame) REQUIRE(step(crowd.world, crowd.dt_s).ok());  // the body stands
    ClothView tee;
    REQUIRE(view_cloth(crowd.world, who.tee, &tee).ok());
    CHECK(metrics::bounds(tee).finite);
    CHECK(metrics::mean_speed(tee) < 0.005);
}

}  // namespace

TEST_CASE("stress: a dressed character abused as a game does (bad vertices, a 100 m teleport, 10 revolutions a second, a 0.25 s frame, a removal mid-frame) stays finite and bounded and is back at rest within 2 s of each") {
    abuse_a_dressed_character();
}
