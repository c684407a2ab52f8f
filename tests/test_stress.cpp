// Stability of the default configuration (docs/solver.md) at every budget the stiffness work names:
// 1, 2, 3 and 100 sweeps per step, on the drape, the flag at 40 m/s and the sphere, 2 000 steps each.
// Every case asserts finite positions and a bounded extent (no blow-up), the sphere no growing
// penetration, and a return to rest where the scene has one. CTest label `stress`.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "metrics.h"
#include "seed_scenes.h"

using namespace weft;
using scenes::SeedScene;

namespace {

constexpr uint32_t kSteps = 2000;

struct Outcome {
    bool finite = true;
    double max_extent_m = 0.0;       // largest bounding-box side seen
    double max_penetration_m = 0.0;  // sphere only: deepest particle inside the inflated radius
    double final_speed = 0.0;
};

Outcome run(SeedScene scene, uint32_t sweeps, uint32_t n) {
    scenes::SceneOptions o;
    o.n = n;
    o.wind_m_s = 40.0f;
    o.sphere_friction = 0.5f;
    scenes::apply_config(scenes::Config::default_config, sweeps, o);
    scenes::SeedWorld w;
    const std::string err = scenes::make_seed_world(scene, o, &w);
    REQUIRE(err.empty());
    Outcome out;
    for (uint32_t i = 0; i < kSteps; ++i) {
        REQUIRE(step(w.world, w.dt_s).ok());
        if (i % 20 != 19) continue;
        ClothView v;
        REQUIRE(view_cloth(w.world, w.cloth, &v).ok());
        const metrics::Bounds b = metrics::bounds(v);
        out.finite = out.finite && b.finite;
        out.max_extent_m = std::max({out.max_extent_m, double(b.max.x - b.min.x), double(b.max.y - b.min.y),
                                     double(b.max.z - b.min.z)});
        if (scene == SeedScene::sphere) {
            for (uint32_t s = 0; s < v.asset->slot_count; ++s) {
                if (v.asset->particle_of_slot[s] == kNoParticle) continue;
                const double r = std::sqrt(double(v.x[s]) * v.x[s] + double(v.y[s]) * v.y[s] + double(v.z[s]) * v.z[s]);
                out.max_penetration_m = std::max(out.max_penetration_m, 0.51 - r);
            }
        }
    }
    ClothView v;
    REQUIRE(view_cloth(w.world, w.cloth, &v).ok());
    out.final_speed = metrics::mean_speed(v);
    return out;
}

void check_scene(SeedScene scene, uint32_t n, double extent_limit_m) {
    for (uint32_t sweeps : {1u, 2u, 3u, 100u}) {
        CAPTURE(sweeps);
        const Outcome o = run(scene, sweeps, n);
        MESSAGE(std::string(scenes::scene_name(scene)), " n=", n, ", ", sweeps, " sweeps, ", kSteps, " steps: extent ",
                o.max_extent_m, " m, penetration ", o.max_penetration_m, " m, final mean speed ", o.final_speed, " m/s");
        CHECK(o.finite);
        CHECK(o.max_extent_m < extent_limit_m);
        if (scene == SeedScene::sphere) CHECK(o.max_penetration_m < 1e-4);  // projected out every substep
        if (scene != SeedScene::flag) CHECK(o.final_speed < 0.01);          // hangs, or lies, at rest
    }
}

}  // namespace

TEST_SUITE("stress") {
    TEST_CASE("stress: the default drape at 1, 2, 3 and 100 sweeps stays finite, bounded and comes to rest") {
        check_scene(SeedScene::drape, 24, 3.0);  // a 2 m cloth: no side may grow past 3 m
    }
    TEST_CASE("stress: the default flag in 40 m/s wind at 1, 2, 3 and 100 sweeps stays finite and bounded") {
        check_scene(SeedScene::flag, 24, 6.0);  // 2 m x 1.2 m, flapping hard
    }
    TEST_CASE("stress: the default sphere drop at 1, 2, 3 and 100 sweeps: finite, bounded, never inside, at rest") {
        check_scene(SeedScene::sphere, 24, 3.0);
    }
}
