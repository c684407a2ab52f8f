// Determinism (two independent worlds, same answer bit for bit) and scalar vs AVX2 parity.
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;
using scenes::SeedScene;

namespace {

constexpr uint32_t kGrid = 50;

void check_determinism(SeedScene scene) {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        auto a = make_scene(scene, scene_options(kGrid, path));
        auto b = make_scene(scene, scene_options(kGrid, path));
        CHECK(world_simd_path(a->world) == path);
        for (uint32_t i = 0; i < 300; ++i) {
            REQUIRE(step(a->world, a->dt_s).ok());
            REQUIRE(step(b->world, b->dt_s).ok());
        }
        const std::vector<Vec3> pa = read_all(*a), pb = read_all(*b);
        CHECK(all_finite(pa));
        CHECK(same_bits(pa, pb));
        // The cloth did move (a trivially identical pair of frozen worlds proves nothing).
        CHECK(!same_bits(pa, a->mesh.positions));
    }
}

// Scalar and AVX2 after 100 steps: bit-identical by design (same operations, same order, no
// implicit FMA contraction); at the very least within 1e-5 of the 2 m cloth size.
void check_parity(SeedScene scene, uint32_t steps) {
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("AVX2 is not available in this build or CPU: scalar vs SIMD parity not tested");
        return;
    }
    auto scalar = make_scene(scene, scene_options(kGrid, SimdPath::scalar));
    auto avx2 = make_scene(scene, scene_options(kGrid, SimdPath::avx2));
    REQUIRE(world_simd_path(scalar->world) == SimdPath::scalar);
    REQUIRE(world_simd_path(avx2->world) == SimdPath::avx2);
    uint32_t first_difference = 0;
    for (uint32_t i = 1; i <= steps; ++i) {
        REQUIRE(step(scalar->world, scalar->dt_s).ok());
        REQUIRE(step(avx2->world, avx2->dt_s).ok());
        if (first_difference == 0 && !same_bits(read_all(*scalar), read_all(*avx2))) first_difference = i;
    }
    const std::vector<Vec3> ps = read_all(*scalar), pv = read_all(*avx2);
    REQUIRE(all_finite(ps));
    REQUIRE(all_finite(pv));
    const double cloth_size_m = 2.0;
    const double difference = max_abs_difference(ps, pv);
    INFO("max |scalar - avx2| = ", difference, " m; first differing step: ", first_difference);
    CHECK(difference <= 1e-5 * cloth_size_m);
    CHECK(same_bits(ps, pv));
}

}  // namespace

TEST_CASE("determinism: drape, 300 steps, bit-identical") { check_determinism(SeedScene::drape); }
TEST_CASE("determinism: flag, 300 steps, bit-identical") { check_determinism(SeedScene::flag); }
TEST_CASE("determinism: sphere, 300 steps, bit-identical") { check_determinism(SeedScene::sphere); }

namespace {

// Two sphere worlds with friction 0.5, dropped `offset_m` off-centre: bit-identical after 300 steps.
void check_sphere_determinism(float offset_m, bool contact_tethers) {
    scenes::SceneOptions o = scene_options(kGrid);
    o.sphere_friction = 0.5f;
    o.sphere_offset_m = offset_m;
    o.contact_tethers = contact_tethers;
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        o.simd = path;
        auto a = make_scene(SeedScene::sphere, o);
        auto b = make_scene(SeedScene::sphere, o);
        step_n(*a, 300);
        step_n(*b, 300);
        CHECK(same_bits(read_all(*a), read_all(*b)));
    }
}

}  // namespace

TEST_CASE("determinism: sphere with friction 0.5 and an off-centre drop") { check_sphere_determinism(0.3f, false); }
TEST_CASE("determinism: contact tethers on the sphere, 300 steps") { check_sphere_determinism(0.25f, true); }

TEST_CASE("scalar vs avx2: drape after 100 steps") { check_parity(SeedScene::drape, 100); }
TEST_CASE("scalar vs avx2: flag after 100 steps") { check_parity(SeedScene::flag, 100); }
TEST_CASE("scalar vs avx2: sphere after 100 steps") { check_parity(SeedScene::sphere, 100); }

namespace {

// The sphere with friction on both paths: bit-identical after `steps` steps.
void check_sphere_parity(uint32_t n, float offset_m, uint32_t steps, bool contact_tethers = false) {
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("AVX2 is not available in this build or CPU: scalar vs SIMD parity not tested");
        return;
    }
    CAPTURE(n);
    scenes::SceneOptions o = scene_options(n);
    o.sphere_friction = 0.5f;
    o.sphere_offset_m = offset_m;
    o.contact_tethers = contact_tethers;
    o.simd = SimdPath::scalar;
    auto scalar = make_scene(SeedScene::sphere, o);
    o.simd = SimdPath::avx2;
    auto avx2 = make_scene(SeedScene::sphere, o);
    REQUIRE(scalar->asset().coarse_lattice_cols > 0);
    step_n(*scalar, steps);
    step_n(*avx2, steps);
    const std::vector<Vec3> ps = read_all(*scalar), pv = read_all(*avx2);
    INFO("max |scalar - avx2| = ", max_abs_difference(ps, pv), " m");
    CHECK(all_finite(pv));
    CHECK(!same_bits(pv, avx2->mesh.positions));
    CHECK(max_abs_difference(ps, pv) <= 2e-5);
    CHECK(same_bits(ps, pv));
}

}  // namespace

TEST_CASE("scalar vs avx2: sphere with friction 0.5 after 100 steps") { check_sphere_parity(kGrid, 0.3f, 100); }

TEST_CASE("scalar vs avx2: contact tethers on the sphere") {
    // Anchored nodes on both paths: the per-step anchors are scalar code, the ball projection runs
    // on the coarse solve's lane groups (gathers on AVX2).
    check_sphere_parity(kGrid, 0.3f, 100, true);
    check_sphere_parity(37, 0.1f, 60, true);
}

TEST_CASE("scalar vs avx2: three coarse sweeps a substep on the sphere") {
    // ClothDesc::coarse_iterations (docs/solver.md: 2 substeps x 1 iteration with 3 coarse sweeps
    // stays on the sphere at about plain's cost). Both paths agree bit for bit, and the extra
    // sweeps change the result (the knob reaches the solve).
    if (!simd_path_available(SimdPath::avx2)) return;
    scenes::SceneOptions o = scene_options(kGrid);
    o.sphere_friction = 0.5f;
    o.sphere_offset_m = 0.25f;
    o.explicit_split = true;
    o.substeps = 2;
    o.iterations = 1;
    o.sweeps = 2;
    o.relaxation = 0.8f;
    o.coarse_iterations = 3;
    o.simd = SimdPath::scalar;
    auto scalar = make_scene(SeedScene::sphere, o);
    o.simd = SimdPath::avx2;
    auto avx2 = make_scene(SeedScene::sphere, o);
    o.coarse_iterations = 1;
    auto one_sweep = make_scene(SeedScene::sphere, o);
    SolverSplit split;
    REQUIRE(cloth_solver_split(avx2->world, avx2->cloth, &split).ok());
    CHECK(split.coarse_level);
    CHECK(split.coarse_iterations == 3);
    step_n(*scalar, 60);
    step_n(*avx2, 60);
    step_n(*one_sweep, 60);
    const std::vector<Vec3> ps = read_all(*scalar), pv = read_all(*avx2), p1 = read_all(*one_sweep);
    CHECK(all_finite(pv));
    CHECK(same_bits(ps, pv));
    CHECK(max_abs_difference(pv, p1) > 1e-4);
}

TEST_CASE("scalar vs avx2: the coarse lattice's row tails and narrow rows on the sphere") {
    // n = 37: plane rows of 19 columns (two lane groups and one overlapping tail group); n = 12: rows
    // of 6 columns, narrower than a lane group (one lane at a time on both paths). The default
    // policy (coarse level, 2 substeps) and friction, so the lattice interpolation (gather_near),
    // the integration's row tails and the friction response all run.
    check_sphere_parity(37, 0.1f, 60);
    check_sphere_parity(12, 0.1f, 60);
}

TEST_CASE("a particle pinned and released by set_particle on the coarse lattice, both paths") {
    // While no slot of the lattice planes is pinned, the integration skips the per-lane pinned
    // check (ClothInstance::held_plane_slots); set_particle must switch it back on and off.
    std::vector<Vec3> finals[2];
    const SimdPath paths[2] = {SimdPath::scalar, SimdPath::avx2};
    for (int i = 0; i < 2; ++i) {
        if (!simd_path_available(paths[i])) continue;
        CAPTURE(i);
        scenes::SceneOptions o = scene_options(40, paths[i]);
        o.sphere_friction = 0.5f;
        auto w = make_scene(SeedScene::sphere, o);
        REQUIRE(w->asset().coarse_lattice_cols > 0);
        step_n(*w, 5);
        const uint32_t corner = 0;
        const Vec3 held = read_all(*w)[corner];
        REQUIRE(set_particle(w->world, w->cloth, corner, held, 0.0f).ok());
        step_n(*w, 20);
        const Vec3 after = read_all(*w)[corner];
        CHECK(after.x == held.x);
        CHECK(after.y == held.y);
        CHECK(after.z == held.z);
        REQUIRE(set_particle(w->world, w->cloth, corner, held, 1.0f).ok());
        step_n(*w, 5);
        CHECK(read_all(*w)[corner].y < held.y);  // released: it falls again
        finals[i] = read_all(*w);
    }
    if (!finals[0].empty() && !finals[1].empty()) CHECK(same_bits(finals[0], finals[1]));
}

TEST_CASE("scalar vs avx2: substeps, compliance and relaxation") {
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("AVX2 is not available in this build or CPU: scalar vs SIMD parity not tested");
        return;
    }
    // Non-default solver settings go through the same kernels: still bit-identical.
    std::unique_ptr<scenes::SeedWorld> worlds[2];
    const SimdPath paths[2] = {SimdPath::scalar, SimdPath::avx2};
    for (int i = 0; i < 2; ++i) {
        scenes::SceneOptions o = scene_options(30, paths[i]);
        o.explicit_split = true;
        o.substeps = 3;
        o.iterations = 2;
        o.relaxation = 0.7f;
        worlds[i] = make_scene(SeedScene::flag, o);
        ClothDesc d;
        d.asset = &worlds[i]->asset();
        d.policy = BudgetPolicy::explicit_split;
        d.coarse_level = CoarseLevel::on;
        d.substeps = 3;
        d.iterations = 2;
        d.relaxation = 0.7f;
        d.compliance_m_per_n[2] = 1e-4f;
        d.damping_per_s = 0.5f;
        d.tether_slack = 0.05f;
        REQUIRE(set_cloth_settings(worlds[i]->world, worlds[i]->cloth, d).ok());
        step_n(*worlds[i], 60);
    }
    const std::vector<Vec3> ps = read_all(*worlds[0]), pv = read_all(*worlds[1]);
    INFO("max |scalar - avx2| = ", max_abs_difference(ps, pv), " m");
    CHECK(max_abs_difference(ps, pv) <= 2e-5);
    CHECK(same_bits(ps, pv));
}

TEST_CASE("scalar vs avx2: pinned drape with an explicit split and the coarse level") {
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("AVX2 is not available in this build or CPU: scalar vs SIMD parity not tested");
        return;
    }
    for (uint32_t n : {25u, 50u}) {
        CAPTURE(n);
        std::unique_ptr<scenes::SeedWorld> worlds[2];
        const SimdPath paths[2] = {SimdPath::scalar, SimdPath::avx2};
        for (int i = 0; i < 2; ++i) {
            scenes::SceneOptions o = scene_options(n, paths[i]);
            o.explicit_split = true;
            o.substeps = 2;
            o.iterations = 2;
            o.coarse_level = CoarseLevel::on;
            worlds[i] = make_scene(SeedScene::drape, o);
            step_n(*worlds[i], 100);
        }
        const std::vector<Vec3> ps = read_all(*worlds[0]), pv = read_all(*worlds[1]);
        INFO("max |scalar - avx2| = ", max_abs_difference(ps, pv), " m");
        CHECK(max_abs_difference(ps, pv) <= 2e-5);
        CHECK(same_bits(ps, pv));
    }
}
