// Invariants every step keeps, on every path and budget policy: inverse masses are never changed by
// stepping, pinned and padding slots never move, and a cloth's neighbours in the world's block are
// never touched (a kernel that runs past the end of a cloth's arrays breaks one of these).
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;
using scenes::SeedScene;

namespace {

struct Variant {
    const char* name;
    SeedScene scene;
    uint32_t n;
    bool explicit_coarse;  // explicit split with the coarse level (pinned cloths use it only then)
};

const Variant kVariants[] = {
    {"drape 25", SeedScene::drape, 25, false},   {"drape 50", SeedScene::drape, 50, false},
    {"flag 25", SeedScene::flag, 25, false},     {"flag 50", SeedScene::flag, 50, false},
    {"sphere 25", SeedScene::sphere, 25, false}, {"sphere 50", SeedScene::sphere, 50, false},
    {"sphere 24", SeedScene::sphere, 24, false}, {"sphere 32", SeedScene::sphere, 32, false},
    {"drape 50, explicit 2x2 with coarse level", SeedScene::drape, 50, true},
};

std::unique_ptr<scenes::SeedWorld> make_variant(const Variant& v, SimdPath path) {
    scenes::SceneOptions o = scene_options(v.n, path);
    if (v.explicit_coarse) {
        o.explicit_split = true;
        o.substeps = 2;
        o.iterations = 2;
        o.coarse_level = CoarseLevel::on;
    }
    return make_scene(v.scene, o);
}

}  // namespace

TEST_CASE("stepping never changes inverse masses, and pinned and padding slots never move") {
    for (const Variant& variant : kVariants) {
        for (SimdPath path : available_paths()) {
            const std::string label = std::string(variant.name) + ", " + simd_path_name(path);
            CAPTURE(label);
            auto w = make_variant(variant, path);
            const ClothAsset& a = w->asset();
            step_n(*w, 40);
            const ClothView v = view_of(*w);
            uint32_t changed_mass = 0, moved = 0, first_bad = kNoParticle;
            for (uint32_t s = 0; s < a.slot_count; ++s) {
                if (std::memcmp(&v.inverse_mass[s], &a.inverse_mass[s], sizeof(float)) != 0) {
                    ++changed_mass;
                    if (first_bad == kNoParticle) first_bad = s;
                }
                if (a.inverse_mass[s] != 0.0f) continue;
                if (v.x[s] != a.start_x[s] || v.y[s] != a.start_y[s] || v.z[s] != a.start_z[s]) {
                    ++moved;
                    if (first_bad == kNoParticle) first_bad = s;
                }
            }
            INFO("slots ", a.slot_count, "; first bad slot ", first_bad);
            CHECK(changed_mass == 0);
            CHECK(moved == 0);
            CHECK(metrics::bounds(v).finite);
        }
    }
}

TEST_CASE("stepping one cloth leaves a second cloth in the same block untouched") {
    // Two cloths in one world; the second is parked with every particle pinned by set_particle, so
    // nothing of its state may change while the first one is stepped.
    for (const Variant& variant : kVariants) {
        for (SimdPath path : available_paths()) {
            const std::string label = std::string(variant.name) + ", " + simd_path_name(path);
            CAPTURE(label);
            auto scene = make_variant(variant, path);  // for its asset and settings
            const ClothAsset& a = scene->asset();
            WorldDesc d = world_for({&a, &a}, variant.scene == SeedScene::sphere ? 1 : 0, path);
            d.wind = variant.scene == SeedScene::flag;
            OwnedWorld world;
            REQUIRE(make_world(d, &world).ok());
            ClothDesc cd;
            cd.asset = &a;
            if (variant.explicit_coarse) {
                cd.policy = BudgetPolicy::explicit_split;
                cd.substeps = 2;
                cd.iterations = 2;
                cd.coarse_level = CoarseLevel::on;
            }
            ClothId first, second;
            REQUIRE(add_cloth(world.world, cd, &first).ok());
            cd.translation_m = {10.0f, 0.0f, 0.0f};
            REQUIRE(add_cloth(world.world, cd, &second).ok());
            for (uint32_t p = 0; p < a.particle_count; ++p) {
                const uint32_t s = a.slot_of_particle[p];
                REQUIRE(set_particle(world.world, second, p, {a.start_x[s] + 10.0f, a.start_y[s], a.start_z[s]}, 0.0f).ok());
            }
            if (variant.scene == SeedScene::sphere) {
                ColliderDesc sphere;
                sphere.radius_m = 0.5f;
                sphere.inflation_m = 0.01f;
                ColliderId id;
                REQUIRE(add_collider(world.world, sphere, &id).ok());
            }
            if (d.wind) REQUIRE(set_wind(world.world, {20.0f, 0.0f, 0.0f}).ok());
            const ClothView parked = view_of(world.world, second);
            std::vector<float> before;
            for (const float* arr : {parked.x, parked.y, parked.z, parked.previous_x, parked.previous_y,
                                     parked.previous_z, parked.inverse_mass})
                before.insert(before.end(), arr, arr + a.slot_count);
            for (int i = 0; i < 40; ++i) REQUIRE(step(world.world, 0.033f).ok());
            const ClothView after = view_of(world.world, second);
            std::vector<float> now;
            for (const float* arr : {after.x, after.y, after.z, after.inverse_mass})
                now.insert(now.end(), arr, arr + a.slot_count);
            std::vector<float> expected;
            expected.insert(expected.end(), before.begin(), before.begin() + 3 * a.slot_count);
            expected.insert(expected.end(), before.begin() + 6 * a.slot_count, before.end());
            CHECK(std::memcmp(now.data(), expected.data(), now.size() * sizeof(float)) == 0);
            // The first cloth moved (gravity), and is finite.
            CHECK(metrics::bounds(view_of(world.world, first)).finite);
        }
    }
}

TEST_CASE("the budget policy: pinned cloths iterate with tethers, collider-held cloths substep") {
    auto drape = make_scene(SeedScene::drape, scene_options(25));
    SolverSplit split;
    REQUIRE(cloth_solver_split(drape->world, drape->cloth, &split).ok());
    CHECK(split.substeps == 1);
    CHECK(split.iterations == 3);
    CHECK(split.tethers);
    auto sphere = make_scene(SeedScene::sphere, scene_options(25));
    REQUIRE(cloth_solver_split(sphere->world, sphere->cloth, &split).ok());
    // 2 substeps x 1 iteration with 3 coarse sweeps each: the budget's cost, not more (docs/solver.md).
    CHECK(split.substeps == 2);
    CHECK(split.iterations == 1);
    CHECK(split.coarse_level);
    CHECK(split.coarse_iterations == 3);
    CHECK_FALSE(split.tethers);
    // An explicit split is taken as given.
    scenes::SceneOptions o = scene_options(25);
    o.explicit_split = true;
    o.substeps = 2;
    o.iterations = 5;
    auto explicit_drape = make_scene(SeedScene::drape, o);
    REQUIRE(cloth_solver_split(explicit_drape->world, explicit_drape->cloth, &split).ok());
    CHECK(split.substeps == 2);
    CHECK(split.iterations == 5);
    // Its coarse level, unless named, follows the policy: off where the tethers hold the cloth (the
    // pinned drape), on where only colliders do (the sphere); named, it is taken as given.
    CHECK_FALSE(split.coarse_level);
    auto explicit_sphere = make_scene(SeedScene::sphere, o);
    REQUIRE(cloth_solver_split(explicit_sphere->world, explicit_sphere->cloth, &split).ok());
    CHECK(split.coarse_level);
    o.coarse_level = CoarseLevel::on;
    auto coarse_drape = make_scene(SeedScene::drape, o);
    REQUIRE(cloth_solver_split(coarse_drape->world, coarse_drape->cloth, &split).ok());
    CHECK(split.coarse_level);
    o.coarse_level = CoarseLevel::off;
    auto fine_sphere = make_scene(SeedScene::sphere, o);
    REQUIRE(cloth_solver_split(fine_sphere->world, fine_sphere->cloth, &split).ok());
    CHECK_FALSE(split.coarse_level);
    CHECK(cloth_solver_split(drape->world, ClothId{3}, &split).code == ErrorCode::out_of_range);
    CHECK(cloth_solver_split(drape->world, drape->cloth, nullptr).code == ErrorCode::invalid_argument);
}
