// Numerical stability under abuse (acceptance point 6 of the accuracy issue; results table in
// docs/accuracy.md). Every case runs at least 2 000 steps on a small grid (n = 6 to 24, so the
// suite stays quick under ASan) and asserts finite positions, a bounded extent, no growing
// penetration where there is a collider, and a return to rest where the scene allows one.
// CTest label `stress`. Refused input (NaN, Inf, dt <= 0) is checked to change nothing over a whole
// run; tests/test_bad_input.cpp checks each refusal's error code one call at a time.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>

#include "support/test_support.h"

using namespace weft;
using scenes::SeedScene;

namespace {

constexpr uint32_t kSteps = 2000;

// What a stress case watches while it runs.
struct Outcome {
    bool finite = true;
    double max_extent_m = 0.0;  // largest bounding-box side seen
    // Deepest particle inside a collider's inflated surface after a step, over the first and the
    // second half of the run: "no growing penetration" compares them.
    double penetration_first_half_m = 0.0, penetration_second_half_m = 0.0;
    double final_speed = 0.0;  // mean particle speed after the last step, m/s
    double final_extent_m = 0.0;
};

// Steps `steps` times at dt; `before_step(i)` runs before step i (to move colliders, change wind).
// `colliders` is read after every step for the penetration (it is what the world was last given).
Outcome watch(World* world, ClothId cloth, uint32_t steps, float dt, const std::vector<ColliderDesc>& colliders,
              const std::function<void(uint32_t)>& before_step = {}) {
    Outcome out;
    const metrics::Bounds start = metrics::bounds(test::view_of(world, cloth));
    out.max_extent_m = std::max({double(start.max.x - start.min.x), double(start.max.y - start.min.y),
                                 double(start.max.z - start.min.z)});
    for (uint32_t i = 0; i < steps; ++i) {
        if (before_step) before_step(i);
        const Result r = step(world, dt);
        INFO(r.message);
        REQUIRE(r.ok());
        const ClothView v = test::view_of(world, cloth);
        if (!colliders.empty()) {
            const double depth = metrics::max_penetration_m(v, colliders.data(), uint32_t(colliders.size()));
            double& half = i < steps / 2 ? out.penetration_first_half_m : out.penetration_second_half_m;
            half = std::max(half, depth);
        }
        if (i % 20 != 19 && i + 1 != steps) continue;
        const metrics::Bounds b = metrics::bounds(v);
        out.finite = out.finite && b.finite;
        out.final_extent_m = std::max({double(b.max.x - b.min.x), double(b.max.y - b.min.y), double(b.max.z - b.min.z)});
        out.max_extent_m = std::max(out.max_extent_m, out.final_extent_m);
    }
    out.final_speed = metrics::mean_speed(test::view_of(world, cloth));
    return out;
}

// One line of the results table in docs/accuracy.md.
void report(const std::string& name, const Outcome& o) {
    char line[320];
    std::snprintf(line, sizeof line, "stress | %s | %s | %.3f | %.3f | %.4f / %.4f | %.2e |", name.c_str(),
                  o.finite ? "yes" : "NO", o.max_extent_m, o.final_extent_m, o.penetration_first_half_m * 1e3,
                  o.penetration_second_half_m * 1e3, o.final_speed);
    const std::string text = line;
    MESSAGE(text);
}

std::unique_ptr<scenes::SceneWorld> build(const scenes::Scene& scene) { return test::build_scene_world(scene); }

scenes::Scene default_scene(SeedScene which, uint32_t n, uint32_t sweeps = 3) {
    scenes::SceneOptions o = test::scene_options(n);
    o.wind_m_s = 40.0f;
    o.sphere_friction = 0.5f;
    scenes::apply_config(scenes::Config::default_config, sweeps, o);
    return scenes::seed_scene(which, o);
}

// Moves every free particle to `place(particle, position)`, at rest; pins stay where they are.
void reposition(World* world, ClothId cloth, const std::function<Vec3(uint32_t, Vec3)>& place) {
    const ClothView v = test::view_of(world, cloth);
    const ClothAsset& a = *v.asset;
    std::vector<float> inverse_mass(a.particle_count);
    for (uint32_t p = 0; p < a.particle_count; ++p) inverse_mass[p] = v.inverse_mass[a.slot_of_particle[p]];
    const std::vector<Vec3> now = test::read_all(world, cloth, a.particle_count);
    for (uint32_t p = 0; p < a.particle_count; ++p) {
        if (inverse_mass[p] == 0.0f) continue;
        REQUIRE(set_particle(world, cloth, p, place(p, now[p]), inverse_mass[p]).ok());
    }
}

// The default configuration at the budgets the stiffness work names, on one seed scene.
void check_budgets(SeedScene which, uint32_t n, double extent_limit_m) {
    for (uint32_t sweeps : {1u, 2u, 3u, 100u}) {
        CAPTURE(sweeps);
        const scenes::Scene scene = default_scene(which, n, sweeps);
        auto w = build(scene);
        const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, scene.colliders);
        const std::string name = std::string(scenes::scene_name(which)) + " default, " + std::to_string(sweeps) + " sweeps";
        report(name, o);
        CHECK(o.finite);
        CHECK(o.max_extent_m < extent_limit_m);
        if (which == SeedScene::sphere) CHECK(o.penetration_second_half_m < 1e-4);  // projected out every substep
        if (which != SeedScene::flag) CHECK(o.final_speed < 0.01);               // hangs, or lies, at rest
    }
}

// Explicit splits across what the API accepts (substeps 1..64, relaxation kMinRelaxation to
// kMaxRelaxation, the coarse level with 1 or 3 sweeps a substep up to kMaxCoarseSubsteps, else
// tethers), on one seed scene at n = 16 for 600 steps (20 s): finite, bounded, and, where the scene
// lets it rest, no jitter: no motion back and forth faster than 5 cm/s over the last 10 frames
// (with damping 1/s, oscillation left after 20 s is energy the solver adds). Creeping (the plain
// method's drape stretches on; tethers stop it) or sliding off the sphere (many substeps without
// the coarse level's tension do; so does the converged model on small cloths,
// tests/test_irregular.cpp) is not jitter.
void check_accepted_splits(SeedScene which, double extent_limit_m) {
    for (uint32_t substeps : {1u, 2u, 3u, kMaxCoarseSubsteps, 64u})
        for (uint32_t iterations : {1u, 4u})
            for (float relaxation : {kMinRelaxation, 0.8f, kMaxRelaxation})
                for (uint32_t coarse_iterations : {0u, 1u, 3u}) {  // 0: no coarse level, tethers
                    if (coarse_iterations > 0 && substeps > kMaxCoarseSubsteps) continue;  // refused
                    scenes::SceneOptions o = test::scene_options(16);
                    o.wind_m_s = 40.0f;
                    o.sphere_friction = 0.5f;
                    o.explicit_split = true;
                    o.substeps = substeps;
                    o.iterations = iterations;
                    o.sweeps = substeps * iterations;
                    o.relaxation = relaxation;
                    o.coarse_level = coarse_iterations > 0 ? CoarseLevel::on : CoarseLevel::off;
                    o.coarse_iterations = std::max(coarse_iterations, 1u);
                    o.tethers = coarse_iterations == 0;
                    const scenes::Scene scene = scenes::seed_scene(which, o);
                    auto w = build(scene);
                    const ClothId cloth = w->cloths[0].id;
                    const Outcome out = watch(w->world, cloth, 590, w->dt_s, scene.colliders);
                    // Then 10 frames, whole frames apart (with many substeps the last substep's
                    // velocity counts motions of micrometres back and forth): the particles' mean
                    // path and mean net displacement.
                    const uint32_t count = test::view_of(w->world, cloth).asset->particle_count;
                    const std::vector<Vec3> start = test::read_all(w->world, cloth, count);
                    std::vector<Vec3> last = start;
                    double path_m = 0.0;
                    for (int frame = 0; frame < 10; ++frame) {
                        REQUIRE(step(w->world, w->dt_s).ok());
                        const std::vector<Vec3> now = test::read_all(w->world, cloth, count);
                        for (uint32_t p = 0; p < count; ++p) path_m += test::distance_m(now[p], last[p]) / count;
                        last = now;
                    }
                    double net_m = 0.0;
                    for (uint32_t p = 0; p < count; ++p) net_m += test::distance_m(last[p], start[p]) / count;
                    const double speed = path_m / (10.0 * w->dt_s);
                    CAPTURE(std::string(scenes::scene_name(which)));
                    CAPTURE(substeps);
                    CAPTURE(iterations);
                    CAPTURE(relaxation);
                    CAPTURE(coarse_iterations);
                    CHECK(out.finite);
                    CHECK(out.max_extent_m < extent_limit_m);
                    CAPTURE(speed);
                    CAPTURE(net_m);
                    // Jitter: moving faster than 5 cm/s along a path more than twice as long as
                    // where it got to (back and forth). Creeping or sliding off is not jitter.
                    if (which != SeedScene::flag) CHECK_FALSE((speed > 0.05 && path_m > 2.0 * net_m));  // it flaps
                }
}

}  // namespace

TEST_SUITE("stress") {
    TEST_CASE("stress: the default drape at 1 2 3 and 100 sweeps stays finite and bounded and comes to rest") {
        check_budgets(SeedScene::drape, 24, 3.0);  // a 2 m cloth: no side may grow past 3 m
    }
    TEST_CASE("stress: the default flag in 40 m/s wind at 1 2 3 and 100 sweeps stays finite and bounded") {
        check_budgets(SeedScene::flag, 24, 6.0);  // 2 m x 1.2 m, flapping hard
    }
    TEST_CASE("stress: the default sphere drop at 1 2 3 and 100 sweeps stays finite and bounded and outside and comes to rest") {
        check_budgets(SeedScene::sphere, 24, 3.0);
    }

    // One case a scene, so ctest runs them side by side (each is minutes under ASan).
    TEST_CASE("stress: every accepted explicit split on the drape stays finite and bounded and never jitters") {
        check_accepted_splits(SeedScene::drape, 4.0);
    }

    TEST_CASE("stress: every accepted explicit split on the flag stays finite and bounded and never jitters") {
        check_accepted_splits(SeedScene::flag, 4.0);
    }

    TEST_CASE("stress: every accepted explicit split on the sphere stays finite and bounded and never jitters") {
        check_accepted_splits(SeedScene::sphere, 4.0);
    }

    TEST_CASE("stress: dt ten times the seed dt (0.33 s) on the drape and the sphere") {
        for (SeedScene which : {SeedScene::drape, SeedScene::sphere}) {
            CAPTURE(scenes::scene_name(which));
            const scenes::Scene scene = default_scene(which, 24);
            auto w = build(scene);
            const Outcome o = watch(w->world, w->cloths[0].id, kSteps, 0.33f, scene.colliders);
            report(which == SeedScene::drape ? "drape, dt 0.33 s" : "sphere, dt 0.33 s (slides off, falls)", o);
            CHECK(o.finite);
            CHECK(o.max_extent_m < 3.0);
            CHECK(o.penetration_second_half_m <= o.penetration_first_half_m + 1e-4);
            // The drape hangs at rest. The sphere's cloth slides off at this dt and falls at the
            // damping's terminal speed (g / 1 s^-1 = 9.8 m/s), with nothing below to stop it: see the
            // skipped case below.
            if (which == SeedScene::drape) CHECK(o.final_speed < 0.01);
        }
    }

    // Found by this suite, not fixed here (the runtime is others' work): at dt 0.33 s the default
    // policy (2 substeps x 1 iteration, coarse level, friction 0.5) lets the cloth slide off the
    // sphere, which holds it at dt 0.033 s. Remove the skip when the runtime keeps it on.
    TEST_CASE("stress: at dt 0.33 s the cloth stays on the sphere and comes to rest" * doctest::skip()) {
        const scenes::Scene scene = default_scene(SeedScene::sphere, 24);
        auto w = build(scene);
        const Outcome o = watch(w->world, w->cloths[0].id, kSteps, 0.33f, scene.colliders);
        CHECK(o.final_speed < 0.01);
        const metrics::Bounds b = metrics::bounds(test::view_of(w->world, w->cloths[0].id));
        CHECK(b.min.y > -1.0f);
    }

    TEST_CASE("stress: the flag in 200 m/s wind") {
        scenes::SceneOptions so = test::scene_options(24);
        so.wind_m_s = 200.0f;
        const scenes::Scene scene = scenes::seed_scene(SeedScene::flag, so);
        auto w = build(scene);
        const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, scene.colliders);
        report("flag, wind 200 m/s", o);
        CHECK(o.finite);
        CHECK(world_stats(w->world).unhealthy_cloths == 0);  // cloth_health: the gale ends healthy
        CHECK(o.max_extent_m < 6.0);  // held by its pole and tethers; no rest in a gale
    }

    // Found by `weft-bench sweep flag --wind 40` (docs/accuracy.md): the seed's plain method (no
    // tethers) at 1 iteration per step tore, its stretched triangles caught ever more wind and after
    // 2 000 steps particles were 188 km away. The wind now acts on at most a triangle's rest area
    // (ClothAsset::wind_rest_area): the torn flag stays within a few metres of its pole.
    TEST_CASE("stress: the plain method at 1 iteration stays bounded in 40 m/s wind at n = 50") {
        scenes::SceneOptions so = test::scene_options(50);
        so.wind_m_s = 40.0f;
        scenes::apply_config(scenes::Config::plain, 1, so);
        const scenes::Scene scene = scenes::seed_scene(SeedScene::flag, so);
        auto w = build(scene);
        const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, scene.colliders);
        CHECK(o.finite);
        // Torn at 1 correction a step it stretches (max strain about 13 after 2 000 steps, 15 after
        // 8 000) but stays within about 8 m of its 2 m pole: bounded, where it used to run away.
        CHECK(o.max_extent_m < 12.0);
    }

    TEST_CASE("stress: the drape started stretched x5 or crumpled to a point or randomised") {
        // Pins stay at their places; every free particle is moved, at rest, then the cloth is let go.
        struct Start {
            const char* name;
            std::function<Vec3(uint32_t, Vec3)> place;
            double extent_limit_m;
        };
        std::mt19937 rng(20240611u);
        std::uniform_real_distribution<float> offset(-0.5f, 0.5f);
        const Vec3 centre{0.0f, 2.0f, -1.0f};  // midway between the pinned corners
        const std::vector<Start> starts{
            {"drape, start stretched x5",
             [&](uint32_t, Vec3 p) {
                 return Vec3{centre.x + 5.0f * (p.x - centre.x), p.y, centre.z + 5.0f * (p.z - centre.z)};
             },
             10.5},  // the start itself spans 10 m
            {"drape, start crumpled to a point", [&](uint32_t, Vec3) { return Vec3{0.0f, 1.5f, 0.0f}; }, 3.0},
            {"drape, start randomised +-0.5 m",
             [&](uint32_t, Vec3 p) { return Vec3{p.x + offset(rng), p.y + offset(rng), p.z + offset(rng)}; }, 3.5},
        };
        for (const Start& s : starts) {
            CAPTURE(s.name);
            const scenes::Scene scene = default_scene(SeedScene::drape, 24);
            auto w = build(scene);
            reposition(w->world, w->cloths[0].id, s.place);
            const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, scene.colliders);
            report(s.name, o);
            CHECK(o.finite);
            CHECK(o.max_extent_m < s.extent_limit_m);
            CHECK(o.final_extent_m < 3.0);  // back to a 2 m cloth's size
            CHECK(o.final_speed < 0.01);
        }
    }

    TEST_CASE("stress: zero-area triangles and duplicate vertices") {
        // A 16 x 16 grid whose row 8 sits exactly on row 7: duplicate vertices, zero-area triangles
        // and zero-length springs between the two rows. Pinned at the two corners of row 0.
        scenes::GridMesh g = scenes::make_grid(16, 2.0f, 2.0f, false, 2.0f);
        for (uint32_t c = 0; c < g.n; ++c) g.positions[g.index(8, c)] = g.positions[g.index(7, c)];
        g.masses[g.index(0, 0)] = g.masses[g.index(0, g.n - 1)] = 0.0f;
        const CookedCloth cooked = test::cook(g.desc());
        test::OwnedWorld owned;
        REQUIRE(test::make_world(test::world_for({&cooked.asset()}), &owned).ok());
        ClothDesc cd;
        cd.asset = &cooked.asset();
        ClothId cloth;
        REQUIRE(add_cloth(owned.world, cd, &cloth).ok());
        const Outcome o = watch(owned.world, cloth, kSteps, 0.033f, {});
        report("drape with zero-area triangles and duplicate vertices", o);
        CHECK(o.finite);
        CHECK(o.max_extent_m < 3.0);
        CHECK(o.final_speed < 0.01);
    }

    TEST_CASE("stress: everything pinned stays exactly put and nothing pinned falls without stretching") {
        scenes::Scene all = default_scene(SeedScene::drape, 24);
        for (int32_t r = 0; r < 24; ++r) all.cloths[0].grid->pin_rows.push_back(r);
        auto pinned = build(all);
        const ClothId id = pinned->cloths[0].id;
        const std::vector<Vec3> start = test::read_all(pinned->world, id, 24 * 24);
        const Outcome o = watch(pinned->world, id, kSteps, pinned->dt_s, {});
        report("drape, every particle pinned", o);
        CHECK(o.finite);
        CHECK(test::same_bits(test::read_all(pinned->world, id, 24 * 24), start));

        scenes::Scene none = default_scene(SeedScene::drape, 24);
        none.cloths[0].grid->pins.clear();
        auto free = build(none);
        const Outcome f = watch(free->world, free->cloths[0].id, kSteps, free->dt_s, {});
        report("drape, nothing pinned (free fall)", f);
        CHECK(f.finite);
        // A falling cloth keeps its size (y spans the fall only within the cloth: it stays flat).
        CHECK(f.max_extent_m < 2.01);
    }

    TEST_CASE("stress: a mass ratio of 1e6 across every spring") {
        // Checkerboard: every spring joins a particle to one a million times heavier.
        const scenes::Scene scene = default_scene(SeedScene::drape, 24);
        auto w = build(scene);
        const ClothId id = w->cloths[0].id;
        const ClothView v = test::view_of(w->world, id);
        for (uint32_t p = 0; p < v.asset->particle_count; ++p) {
            const float inverse_mass = v.inverse_mass[v.asset->slot_of_particle[p]];
            if (inverse_mass == 0.0f || ((p / 24 + p % 24) & 1) == 0) continue;
            REQUIRE(set_particle(w->world, id, p, metrics::particle_position(v, p), inverse_mass * 1e-6f).ok());
        }
        const Outcome o = watch(w->world, id, kSteps, w->dt_s, {});
        report("drape, mass ratio 1e6 across every spring", o);
        CHECK(o.finite);
        CHECK(o.max_extent_m < 3.0);
        CHECK(o.final_speed < 0.01);
    }

    TEST_CASE("stress: a collider teleported 10 m in one frame and one sweeping through the cloth at 50 m/s") {
        // The drape hangs as a curtain below its pinned edge (z = -1 m, x in [-1, 1], y in [0, 2]).
        ColliderDesc sphere;
        sphere.radius_m = 0.5f;
        sphere.inflation_m = 0.01f;
        sphere.friction = 0.5f;
        sphere.p0 = {0.0f, -9.0f, -1.0f};
        {
            scenes::Scene scene = default_scene(SeedScene::drape, 24);
            scene.colliders = {sphere};
            auto w = build(scene);
            std::vector<ColliderDesc> now = scene.colliders;
            // Into the hanging curtain at step 300, out again at step 1000 (10 m each time).
            const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, now, [&](uint32_t i) {
                if (i != 300 && i != 1000) return;
                now[0].p0.y += i == 300 ? 10.0f : -10.0f;
                REQUIRE(set_collider(w->world, w->colliders[0], now[0]).ok());
            });
            report("drape, sphere teleported 10 m into it and out", o);
            CHECK(o.finite);
            CHECK(world_stats(w->world).unhealthy_cloths == 0);
            CHECK(o.max_extent_m < 3.0);
            CHECK(o.penetration_second_half_m <= o.penetration_first_half_m + 1e-4);
            CHECK(o.penetration_first_half_m < 1e-3);
            CHECK(o.final_speed < 0.01);
        }
        {
            scenes::Scene scene = default_scene(SeedScene::drape, 24);
            sphere.p0 = {-5.0f, 1.2f, -1.0f};
            scene.colliders = {sphere};
            auto w = build(scene);
            std::vector<ColliderDesc> now = scene.colliders;
            // Back and forth along x between -5 and 5 m at 50 m/s (1.65 m a frame) until step 1500,
            // then parked far away so the cloth can settle.
            const float stride = 50.0f * w->dt_s;
            float direction = 1.0f;
            const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, now, [&](uint32_t i) {
                if (i >= 1500) {
                    now[0].p0 = {0.0f, -20.0f, -1.0f};
                } else {
                    if (std::fabs(now[0].p0.x + direction * stride) > 5.0f) direction = -direction;
                    now[0].p0.x += direction * stride;
                }
                REQUIRE(set_collider(w->world, w->colliders[0], now[0]).ok());
            });
            report("drape, sphere sweeping through at 50 m/s", o);
            CHECK(o.finite);
            CHECK(world_stats(w->world).unhealthy_cloths == 0);
            CHECK(o.max_extent_m < 3.0);
            CHECK(o.penetration_second_half_m <= o.penetration_first_half_m + 1e-4);
            CHECK(o.final_speed < 0.01);
        }
    }

    TEST_CASE("stress: iterations 0 and 1 000 per substep") {
        for (uint32_t iterations : {0u, 1000u}) {
            CAPTURE(iterations);
            // 1 000 iterations on a 6 x 6 grid: 2 000 steps of it take about 25 s under ASan.
            scenes::SceneOptions so = test::scene_options(iterations == 0 ? 24 : 6);
            so.explicit_split = true;
            so.substeps = 1;
            so.iterations = iterations;
            so.sweeps = std::max(1u, iterations);
            const scenes::Scene scene = scenes::seed_scene(SeedScene::drape, so);
            auto w = build(scene);
            const Outcome o = watch(w->world, w->cloths[0].id, kSteps, w->dt_s, {});
            report(iterations == 0 ? "drape, 0 iterations (tethers only)" : "drape n=6, 1000 iterations", o);
            CHECK(o.finite);
            CHECK(o.max_extent_m < 3.0);  // with no spring sweep the tethers alone bound the cloth
            CHECK(o.final_speed < 0.01);
        }
    }

    TEST_CASE("stress: NaN and Inf in every user input and dt <= 0 are refused over a whole run and change nothing") {
        // Two flag worlds (wind, and a sphere added so set_collider has something to refuse): one is
        // handed a bad value before every step, the other nothing. They must end bit-identical.
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        scenes::Scene scene = default_scene(SeedScene::flag, 16);
        ColliderDesc sphere;
        sphere.p0 = {1.0f, 2.0f, 0.5f};
        scene.colliders = {sphere};
        auto w = build(scene), twin = build(scene);
        const ClothId id = w->cloths[0].id;
        const ClothDesc settings = scene.cloths[0].desc;
        std::vector<std::function<Result(float)>> inputs{
            [&](float bad) { return step(w->world, bad); },
            [&](float bad) { return set_wind(w->world, {bad, 0.0f, 0.0f}); },
            [&](float bad) { return set_wind(w->world, {0.0f, 0.0f, bad}); },
            [&](float bad) { return set_gravity(w->world, {0.0f, bad, 0.0f}); },
            [&](float bad) { return set_particle(w->world, id, 7, {bad, 1.0f, 0.0f}, 1.0f); },
            [&](float bad) { return set_particle(w->world, id, 7, {0.0f, 1.0f, 0.0f}, bad); },
        };
        // Every float of a collider and of the cloth settings.
        for (int field = 0; field < 9; ++field)
            inputs.push_back([&, field](float bad) {
                ColliderDesc d = sphere;
                float* f[9] = {&d.p0.x, &d.p0.y, &d.p0.z, &d.p1.x, &d.p1.y, &d.p1.z, &d.radius_m, &d.inflation_m, &d.friction};
                *f[field] = bad;
                return set_collider(w->world, w->colliders[0], d);
            });
        for (int field = 0; field < 11; ++field)
            inputs.push_back([&, field](float bad) {
                ClothDesc d = settings;
                d.asset = w->cloths[0].asset;
                float* f[11] = {&d.translation_m.x, &d.relaxation, &d.compliance_m_per_n[0], &d.compliance_m_per_n[1],
                                &d.compliance_m_per_n[2], &d.damping_per_s, &d.tether_slack, &d.drag_coefficient,
                                &d.lift_coefficient, &d.translation_m.y, &d.translation_m.z};
                *f[field] = bad;
                return set_cloth_settings(w->world, id, d);
            });
        const std::vector<float> bad_values{nan, inf, -inf};
        uint32_t refused = 0;
        for (uint32_t i = 0; i < kSteps; ++i) {
            const auto& input = inputs[i % inputs.size()];
            const float bad = bad_values[(i / inputs.size()) % bad_values.size()];
            const Result r = input(bad);
            CHECK_FALSE(r.ok());
            refused += r.ok() ? 0 : 1;
            if (i % inputs.size() == 0) {  // dt 0 and negative as well
                CHECK(step(w->world, 0.0f).code == ErrorCode::out_of_range);
                CHECK(step(w->world, -0.033f).code == ErrorCode::out_of_range);
            }
            REQUIRE(step(w->world, w->dt_s).ok());
            REQUIRE(step(twin->world, twin->dt_s).ok());
        }
        const bool same =
            test::same_bits(test::read_all(w->world, id, 256), test::read_all(twin->world, twin->cloths[0].id, 256));
        const std::string line = "stress | every NaN / Inf input and dt <= 0 | refused " + std::to_string(refused) +
                                 " of " + std::to_string(kSteps) + " bad calls over 2000 steps | bit-identical to the " +
                                 "untouched twin: " + (same ? "yes" : "NO") + " |";
        MESSAGE(line);
        CHECK(refused == kSteps);
        CHECK(same);
    }
}
