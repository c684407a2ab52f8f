// Health and recovery (ClothDesc::recovery, cloth_health; docs/architecture.md, "Health and
// recovery"): a blow-up forced on the drape (a particle thrown 1 km with and without the tethers, a
// NaN written through the debug view, every particle given 1 000 m/s) is reported by the step that sees it, and each recovery policy
// puts the cloth back at the end of that same step. Policy none reports and changes nothing.
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "common/seed_scenes.h"
#include "support/test_support.h"
#include "weft/asset_view.h"
#include "weft/debug.h"

using namespace weft;
using namespace weft::test;

namespace {

constexpr uint32_t kSettleFrames = 60;  // 2 s at the seed's dt: the drape has swung and is healthy

// The seed drape (n x n, pinned along its top edge) with the given recovery policy.
std::unique_ptr<scenes::SceneWorld> drape(RecoveryPolicy recovery, uint32_t n = 16, SimdPath path = SimdPath::automatic) {
    scenes::Scene scene = scenes::seed_scene(scenes::SeedScene::drape, scene_options(n, path));
    scene.cloths[0].desc.recovery = recovery;
    return test::build_scene_world(scene);
}

ClothHealth health_of(const scenes::SceneWorld& w) {
    ClothHealth h;
    REQUIRE(cloth_health(w.world, w.cloths[0].id, &h).ok());
    return h;
}

std::vector<Vec3> positions(const scenes::SceneWorld& w) {
    return read_all(w.world, w.cloths[0].id, w.cloths[0].asset->particle_count);
}

void step_frames(const scenes::SceneWorld& w, uint32_t frames) {
    for (uint32_t i = 0; i < frames; ++i) REQUIRE(step(w.world, w.dt_s).ok());
}

// A movable particle (caller order) of the drape: the middle of its bottom row.
uint32_t movable_particle(const scenes::SceneWorld& w) {
    const ClothAsset& a = *w.cloths[0].asset;
    for (uint32_t p = a.particle_count / 2; p < a.particle_count; ++p)
        if (a.inverse_mass[a.slot_of_particle[p]] > 0.0f) return p;
    FAIL("no movable particle");
    return 0;
}

// The three forced blow-ups, each made between steps.
enum class BlowUp { thrown_1_km, thrown_1_km_untethered, nan_written, every_particle_1000_m_s };
constexpr BlowUp kBlowUps[] = {BlowUp::thrown_1_km, BlowUp::thrown_1_km_untethered, BlowUp::nan_written,
                               BlowUp::every_particle_1000_m_s};
const char* name(BlowUp b) {
    switch (b) {
        case BlowUp::thrown_1_km: return "a particle thrown 1 km";
        case BlowUp::thrown_1_km_untethered: return "a particle thrown 1 km, no tethers";
        case BlowUp::nan_written: return "a NaN written";
        case BlowUp::every_particle_1000_m_s: return "every particle at 1 000 m/s";
    }
    return "";
}
// The tethers pull a thrown particle back within the step: what shows is its energy. Without them
// the springs' 3 sweeps leave it far away: the box is overstretched.
uint32_t expected_problem(BlowUp b) {
    switch (b) {
        case BlowUp::thrown_1_km: return kEnergySpike;
        case BlowUp::thrown_1_km_untethered: return kOverstretched;
        case BlowUp::nan_written: return kNonFinite;
        case BlowUp::every_particle_1000_m_s: return kEnergySpike;
    }
    return 0;
}

void blow_up(const scenes::SceneWorld& w, BlowUp how) {
    const ClothId id = w.cloths[0].id;
    const ClothAsset& a = *w.cloths[0].asset;
    const uint32_t p = movable_particle(w);
    if (how == BlowUp::thrown_1_km || how == BlowUp::thrown_1_km_untethered) {
        if (how == BlowUp::thrown_1_km_untethered) {
            ClothDesc d = w.cloths[0].desc;
            d.asset = &a;
            d.tethers = false;
            REQUIRE(set_cloth_settings(w.world, id, d).ok());
        }
        REQUIRE(set_particle(w.world, id, p, {1000.0f, 0.0f, 0.0f}, a.inverse_mass[a.slot_of_particle[p]]).ok());
        return;
    }
    // The API refuses NaN and infinite input, so the debug view's arrays are written directly (what
    // a bug in the solver or memory trodden on by the game would do).
    ClothView v = view_of(w.world, id);
    if (how == BlowUp::nan_written) {
        const_cast<float*>(v.x)[a.slot_of_particle[p]] = NAN;
        return;
    }
    const float back_m = 1000.0f * v.last_substep_s;  // previous positions 1 000 m/s behind
    for (uint32_t s = 0; s < a.slot_count; ++s)
        if (v.inverse_mass[s] > 0.0f) const_cast<float*>(v.previous_x)[s] = v.x[s] - back_m;
}

}  // namespace

TEST_CASE("health: a settled drape is healthy, with its kinetic energy reported") {
    auto w = drape(RecoveryPolicy::none);
    step_frames(*w, kSettleFrames);
    const ClothHealth h = health_of(*w);
    CHECK(h.problems == 0);
    CHECK(!h.recovered);
    CHECK(h.recoveries == 0);
    CHECK(std::isfinite(h.energy_J_per_kg));
    CHECK(h.energy_J_per_kg >= 0.0f);
    CHECK(world_stats(w->world).unhealthy_cloths == 0);
}

TEST_CASE("health: a forced blow-up is reported, and with policy none the cloth is left as it is") {
    for (BlowUp how : kBlowUps) {
        CAPTURE(std::string(name(how)));
        auto w = drape(RecoveryPolicy::none);
        step_frames(*w, kSettleFrames);
        blow_up(*w, how);
        REQUIRE(step(w->world, w->dt_s).ok());
        const ClothHealth h = health_of(*w);
        MESSAGE(std::string(name(how)), ": problems ", h.problems, ", energy ", h.energy_J_per_kg, " J/kg after the step");
        CHECK((h.problems & expected_problem(how)) != 0);
        CHECK(!h.recovered);
        const WorldStats stats = world_stats(w->world);
        CHECK(stats.unhealthy_cloths == 1);
        CHECK(stats.recovered_cloths == 0);
        CHECK(stats.total_recoveries == 0);
    }
}

TEST_CASE("health: each recovery policy puts a blown-up drape back within one frame") {
    for (RecoveryPolicy policy :
         {RecoveryPolicy::last_good_state, RecoveryPolicy::rest_pose, RecoveryPolicy::dressed_pose}) {
        for (BlowUp how : kBlowUps) {
            CAPTURE(int(policy));
            CAPTURE(std::string(name(how)));
            auto w = drape(policy);
            step_frames(*w, kSettleFrames);
            const std::vector<Vec3> settled = positions(*w);
            blow_up(*w, how);
            REQUIRE(step(w->world, w->dt_s).ok());  // the frame that sees it recovers it
            const ClothHealth h = health_of(*w);
            CHECK((h.problems & expected_problem(how)) != 0);
            CHECK(h.recovered);
            CHECK(h.recoveries == 1);
            const WorldStats stats = world_stats(w->world);
            CHECK(stats.unhealthy_cloths == 1);
            CHECK(stats.recovered_cloths == 1);
            CHECK(stats.total_recoveries == 1);
            const std::vector<Vec3> after = positions(*w);
            CHECK(all_finite(after));
            if (policy == RecoveryPolicy::last_good_state) {
                // A copy of a healthy step at most kLastGoodRefreshSteps old: near where it settled.
                CHECK(max_abs_difference(after, settled) < 0.5);
            } else {  // the drape has no body binding: the dressed pose falls back to the rest pose
                std::vector<Vec3> start(w->cloths[0].asset->particle_count);
                REQUIRE(read_start_positions(*w->cloths[0].asset, start.data(), uint32_t(start.size())).ok());
                CHECK(same_bits(after, start));
            }
            REQUIRE(step(w->world, w->dt_s).ok());  // and it goes on healthy
            CHECK(health_of(*w).problems == 0);
            CHECK(!health_of(*w).recovered);
            CHECK(world_stats(w->world).recovered_cloths == 0);
            CHECK(world_stats(w->world).total_recoveries == 1);
        }
    }
}

TEST_CASE("health: a recovery policy changes no bit while the cloth stays healthy") {
    auto none = drape(RecoveryPolicy::none);
    for (RecoveryPolicy policy :
         {RecoveryPolicy::last_good_state, RecoveryPolicy::rest_pose, RecoveryPolicy::dressed_pose}) {
        auto w = drape(policy);
        step_frames(*w, 200);
        CHECK(world_stats(w->world).total_recoveries == 0);
        if (policy == RecoveryPolicy::last_good_state) step_frames(*none, 200);
        CHECK(same_bits(positions(*w), positions(*none)));
    }
}

TEST_CASE("health: the flag in 200 m/s wind ends healthy, and the wind switched on at once recovers nothing") {
    scenes::SceneOptions o = scene_options(16);
    o.wind_m_s = 200.0f;
    scenes::Scene scene = scenes::seed_scene(scenes::SeedScene::flag, o);
    scene.cloths[0].desc.recovery = RecoveryPolicy::rest_pose;
    scenes::SceneWorld w;
    REQUIRE(scenes::build_scene(scene, &w).empty());
    step_frames(w, 300);
    CHECK(health_of(w).problems == 0);
    CHECK(health_of(w).recoveries == 0);  // a gale is not a spike: its energy became the baseline
    MESSAGE("energy in 200 m/s wind: ", health_of(w).energy_J_per_kg, " J/kg");
    CHECK(all_finite(positions(w)));
}

TEST_CASE("health: the recovery policy is checked, and last_good_state needs its room and is chosen at add_cloth") {
    auto w = drape(RecoveryPolicy::none);
    ClothDesc d = w->cloths[0].desc;
    d.asset = w->cloths[0].asset;
    ClothHealth h;
    CHECK(cloth_health(w->world, w->cloths[0].id, nullptr).code == ErrorCode::invalid_argument);
    CHECK(cloth_health(nullptr, w->cloths[0].id, &h).code == ErrorCode::invalid_argument);
    d.recovery = RecoveryPolicy(7);
    CHECK(set_cloth_settings(w->world, w->cloths[0].id, d).code == ErrorCode::invalid_argument);
    d.recovery = RecoveryPolicy::last_good_state;  // no copy was carved for it
    CHECK(set_cloth_settings(w->world, w->cloths[0].id, d).code == ErrorCode::invalid_argument);
    d.recovery = RecoveryPolicy::rest_pose;  // the others may change at any time
    CHECK(set_cloth_settings(w->world, w->cloths[0].id, d).ok());

    // A world not sized for the copy refuses the cloth and stays as it was.
    WorldDesc wd;
    wd.max_cloths = 0;
    reserve_cloth(wd, *d.asset);
    OwnedWorld small;
    REQUIRE(make_world(wd, &small).ok());
    d.recovery = RecoveryPolicy::last_good_state;
    ClothId id;
    CHECK(add_cloth(small.world, d, &id).code == ErrorCode::capacity_exceeded);
    CHECK(world_usage(small.world).cloths == 0);
}

TEST_CASE("health: the scalar and AVX2 paths report the same energy bits, so both recover the same cloths") {
    if (!simd_path_available(SimdPath::avx2)) return;
    // 21 x 21 = 441 particles: slots in every lane, and a blow-up of every particle at 1 000 m/s
    // read by both paths, recovered by both to the same bits.
    auto scalar = drape(RecoveryPolicy::rest_pose, 21, SimdPath::scalar);
    auto avx2 = drape(RecoveryPolicy::rest_pose, 21, SimdPath::avx2);
    for (uint32_t frame = 0; frame < kSettleFrames; ++frame) {
        step_frames(*scalar, 1);
        step_frames(*avx2, 1);
        const ClothHealth a = health_of(*scalar), b = health_of(*avx2);
        REQUIRE(std::memcmp(&a.energy_J_per_kg, &b.energy_J_per_kg, sizeof(float)) == 0);
        REQUIRE(a.problems == b.problems);
    }
    blow_up(*scalar, BlowUp::every_particle_1000_m_s);
    blow_up(*avx2, BlowUp::every_particle_1000_m_s);
    step_frames(*scalar, 1);
    step_frames(*avx2, 1);
    const ClothHealth a = health_of(*scalar), b = health_of(*avx2);
    CHECK(a.recovered);
    CHECK(b.recovered);
    CHECK(std::memcmp(&a.energy_J_per_kg, &b.energy_J_per_kg, sizeof(float)) == 0);
    const std::vector<Vec3> ps = positions(*scalar), pa = positions(*avx2);
    REQUIRE(ps.size() == pa.size());
    CHECK(std::memcmp(ps.data(), pa.data(), ps.size() * sizeof(Vec3)) == 0);
}
