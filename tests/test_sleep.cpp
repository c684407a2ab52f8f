// Sleeping cloths (ClothDesc::sleep_speed_m_s; docs/architecture.md, "Sleeping cloths"): a cloth at
// rest stops stepping, its positions stay the same bits, and anything that may move it wakes it.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "common/seed_scenes.h"
#include "support/test_support.h"
#include "weft/debug.h"

using namespace weft;
using namespace weft::test;

namespace {

constexpr float kSleepSpeed_m_s = 0.02f;
constexpr uint32_t kMaxFramesToSleep = 600;  // 20 s at the seed's dt

// A seed scene (n x n) with every cloth's sleep speed set; the sphere with friction 1 (at 0.5 the
// cloth's hanging edge keeps creeping at 0.07-0.16 m/s for 20 s and more), and a
// second sphere far from the cloth (index 1) that a test may move without touching it.
std::unique_ptr<scenes::SceneWorld> seed_world(scenes::SeedScene which, float sleep_speed_m_s, uint32_t n = 16) {
    scenes::SceneOptions o = scene_options(n);
    o.sphere_friction = 1.0f;
    scenes::Scene scene = scenes::seed_scene(which, o);
    scene.cloths[0].desc.sleep_speed_m_s = sleep_speed_m_s;
    if (which == scenes::SeedScene::sphere) {
        ColliderDesc far;
        far.p0 = {10.0f, 0.0f, 0.0f};
        far.radius_m = 0.5f;
        scene.colliders.push_back(far);
    }
    return test::build_scene_world(scene);
}

bool sleeping(const scenes::SceneWorld& w) {
    bool asleep = false;
    REQUIRE(cloth_is_sleeping(w.world, w.cloths[0].id, &asleep).ok());
    return asleep;
}

std::vector<Vec3> positions(const scenes::SceneWorld& w) {
    return read_all(w.world, w.cloths[0].id, w.cloths[0].asset->particle_count);
}

// Steps until the cloth sleeps; returns the frames it took (kMaxFramesToSleep + 1: it never did).
uint32_t step_until_asleep(const scenes::SceneWorld& w) {
    for (uint32_t frame = 1; frame <= kMaxFramesToSleep; ++frame) {
        REQUIRE(step(w.world, w.dt_s).ok());
        if (sleeping(w)) return frame;
    }
    return kMaxFramesToSleep + 1;
}

// The sphere's cloth asleep on it.
std::unique_ptr<scenes::SceneWorld> asleep_on_sphere() {
    auto w = seed_world(scenes::SeedScene::sphere, kSleepSpeed_m_s);
    REQUIRE(step_until_asleep(*w) <= kMaxFramesToSleep);
    return w;
}

}  // namespace

TEST_CASE("sleep: a cloth draped on a sphere falls asleep in bounded time and stays the same bits while asleep") {
    auto w = seed_world(scenes::SeedScene::sphere, kSleepSpeed_m_s);
    const uint32_t frames = step_until_asleep(*w);
    MESSAGE("asleep after ", frames, " frames");
    CHECK(frames > kCalmStepsBeforeSleep);  // it fell first: not calm from the start
    REQUIRE(frames <= kMaxFramesToSleep);
    CHECK(world_stats(w->world).sleeping_cloths == 1);
    const std::vector<Vec3> at_rest = positions(*w);
    for (int frame = 0; frame < 60; ++frame) {
        REQUIRE(step(w->world, w->dt_s).ok());
        CHECK(world_stats(w->world).run_projections == 0);  // its step ran nothing
    }
    CHECK(sleeping(*w));
    CHECK(same_bits(positions(*w), at_rest));
}

TEST_CASE("sleep: a collider moved into the cloth's box wakes it and it moves, one moved far from it does not") {
    auto w = asleep_on_sphere();
    const std::vector<Vec3> at_rest = positions(*w);
    ColliderDesc far;
    far.p0 = {10.0f, 1.0f, 0.0f};  // moved, still far from the cloth
    far.radius_m = 0.5f;
    REQUIRE(set_collider(w->world, w->colliders[1], far).ok());
    CHECK(sleeping(*w));
    ColliderDesc sphere;
    sphere.p0 = {0.0f, 0.1f, 0.0f};  // up by 10 cm, into the cloth
    sphere.radius_m = 0.5f;
    sphere.inflation_m = 0.01f;
    sphere.friction = 1.0f;
    REQUIRE(set_collider(w->world, w->colliders[0], sphere).ok());
    CHECK_FALSE(sleeping(*w));
    REQUIRE(step(w->world, w->dt_s).ok());
    CHECK(world_stats(w->world).sleeping_cloths == 0);
    CHECK(max_abs_difference(positions(*w), at_rest) > 0.01);
}

TEST_CASE("sleep: adding or removing a collider that meets the cloth's box wakes it, one far from it does not") {
    auto w = asleep_on_sphere();
    const std::vector<Vec3> at_rest = positions(*w);
    REQUIRE(remove_collider(w->world, w->colliders[1]).ok());  // far away
    CHECK(sleeping(*w));
    ColliderDesc small;
    small.radius_m = 0.05f;
    small.p0 = {0.0f, 2.0f, 0.0f};  // well above the draped cloth
    ColliderId added;
    REQUIRE(add_collider(w->world, small, &added).ok());
    CHECK(sleeping(*w));
    REQUIRE(remove_collider(w->world, added).ok());
    CHECK(sleeping(*w));
    small.p0 = {0.0f, 0.53f, 0.0f};  // into the cloth on the sphere's top (0.51 m)
    REQUIRE(add_collider(w->world, small, &added).ok());
    CHECK_FALSE(sleeping(*w));
    for (uint32_t i = 0; i < kCalmStepsBeforeSleep + 5 && !sleeping(*w); ++i) REQUIRE(step(w->world, w->dt_s).ok());
    REQUIRE(sleeping(*w));
    REQUIRE(remove_collider(w->world, w->colliders[0]).ok());  // the sphere it lies on
    CHECK_FALSE(sleeping(*w));
    REQUIRE(step(w->world, w->dt_s).ok());
    REQUIRE(step(w->world, w->dt_s).ok());
    CHECK(max_abs_difference(positions(*w), at_rest) > 0.001);  // it falls
}

TEST_CASE("sleep: a gravity that changes wakes the cloth, the same value does not") {
    auto w = asleep_on_sphere();
    REQUIRE(set_gravity(w->world, {0.0f, -9.81f, 0.0f}).ok());  // the same
    CHECK(sleeping(*w));
    REQUIRE(set_gravity(w->world, {0.0f, -9.0f, 0.0f}).ok());
    CHECK_FALSE(sleeping(*w));
}

TEST_CASE("sleep: wake_cloth and every call that moves the cloth wake it, at rest") {
    auto w = asleep_on_sphere();
    const ClothId cloth = w->cloths[0].id;
    REQUIRE(wake_cloth(w->world, cloth).ok());
    CHECK_FALSE(sleeping(*w));
    const ClothView v = view_of(w->world, cloth);  // it wakes with zero velocity: previous = current
    bool at_rest = true;
    for (uint32_t s = 0; s < w->cloths[0].asset->slot_count; ++s)
        at_rest = at_rest && v.previous_x[s] == v.x[s] && v.previous_y[s] == v.y[s] && v.previous_z[s] == v.z[s];
    CHECK(at_rest);
    // Asleep again after its calm steps; each of these wakes it.
    const auto asleep_again = [&] {
        for (uint32_t i = 0; i < kCalmStepsBeforeSleep + 5 && !sleeping(*w); ++i) REQUIRE(step(w->world, w->dt_s).ok());
        REQUIRE(sleeping(*w));
    };
    asleep_again();
    REQUIRE(set_cloth_settings(w->world, cloth, w->cloths[0].desc).ok());
    CHECK_FALSE(sleeping(*w));
    asleep_again();
    const float inverse_mass = v.inverse_mass[w->cloths[0].asset->slot_of_particle[0]];
    REQUIRE(set_particle(w->world, cloth, 0, positions(*w)[0], inverse_mass).ok());
    CHECK_FALSE(sleeping(*w));
    asleep_again();
    REQUIRE(reset_cloth(w->world, cloth).ok());
    CHECK_FALSE(sleeping(*w));
    const Transform root{};
    REQUIRE(set_cloth_root(w->world, cloth, root).ok());  // the first root only says where it is
    REQUIRE(step_until_asleep(*w) <= kMaxFramesToSleep);   // it fell from the start pose again
    REQUIRE(set_cloth_root(w->world, cloth, root).ok());  // the same root
    CHECK(sleeping(*w));
    Transform moved{};
    moved.translation_m = {0.0f, 0.0f, 0.01f};
    REQUIRE(set_cloth_root(w->world, cloth, moved).ok());
    CHECK_FALSE(sleeping(*w));
    asleep_again();
    REQUIRE(teleport_cloth(w->world, cloth, moved).ok());
    CHECK_FALSE(sleeping(*w));
}

TEST_CASE("sleep: a pinned flag in wind never sleeps") {
    auto w = seed_world(scenes::SeedScene::flag, kSleepSpeed_m_s);
    CHECK(step_until_asleep(*w) == kMaxFramesToSleep + 1);
}

TEST_CASE("sleep: with sleep_speed 0 (the default) no cloth ever sleeps") {
    CHECK(ClothDesc{}.sleep_speed_m_s == 0.0f);
    auto w = seed_world(scenes::SeedScene::sphere, 0.0f);
    CHECK(step_until_asleep(*w) == kMaxFramesToSleep + 1);
    CHECK(world_stats(w->world).sleeping_cloths == 0);
}

TEST_CASE("sleep: a stale or invalid id, or a null output, is refused") {
    auto w = seed_world(scenes::SeedScene::sphere, kSleepSpeed_m_s);
    const ClothId cloth = w->cloths[0].id;
    bool asleep = true;
    CHECK(cloth_is_sleeping(w->world, ClothId{7, 0}, &asleep).code == ErrorCode::out_of_range);
    CHECK(wake_cloth(w->world, ClothId{7, 0}).code == ErrorCode::out_of_range);
    CHECK(cloth_is_sleeping(w->world, cloth, nullptr).code == ErrorCode::invalid_argument);
    CHECK(cloth_is_sleeping(nullptr, cloth, &asleep).code == ErrorCode::invalid_argument);
    CHECK(wake_cloth(nullptr, cloth).code == ErrorCode::invalid_argument);
    REQUIRE(cloth_is_sleeping(w->world, cloth, &asleep).ok());
    CHECK_FALSE(asleep);
    REQUIRE(remove_cloth(w->world, cloth).ok());
    CHECK(cloth_is_sleeping(w->world, cloth, &asleep).code == ErrorCode::stale_id);
    CHECK(wake_cloth(w->world, cloth).code == ErrorCode::stale_id);
}

TEST_CASE("sleep: a NaN, infinite or negative sleep speed is refused by add_cloth and set_cloth_settings") {
    auto w = seed_world(scenes::SeedScene::sphere, 0.0f);
    const ClothId cloth = w->cloths[0].id;
    for (float bad : {std::nanf(""), INFINITY, -0.01f}) {
        CAPTURE(bad);
        ClothDesc desc = w->cloths[0].desc;
        desc.sleep_speed_m_s = bad;
        const Result set = set_cloth_settings(w->world, cloth, desc);
        CHECK(set.code == (std::isfinite(bad) ? ErrorCode::out_of_range : ErrorCode::non_finite));
        CHECK(std::string(set.message).find("sleep_speed_m_s") != std::string::npos);
        ClothId added;
        const Result add = add_cloth(w->world, desc, &added);
        CHECK_FALSE(add.ok());
        CHECK(std::string(add.message).find("sleep_speed_m_s") != std::string::npos);
    }
    ClothDesc fine = w->cloths[0].desc;
    fine.sleep_speed_m_s = kSleepSpeed_m_s;
    CHECK(set_cloth_settings(w->world, cloth, fine).ok());
}
