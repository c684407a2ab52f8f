// Pay for what you use: a pass a scene does not need is not in its step at all, so its profiled time
// is exactly zero; passes it does use are timed.
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;
using scenes::SeedScene;

namespace {

uint64_t pass_ns(const World* world, Pass pass) { return world_stats(world).pass_ns[static_cast<int>(pass)]; }

scenes::SceneOptions profiled(uint32_t n, bool tethers = true) {
    scenes::SceneOptions o = scene_options(n);
    o.profile = true;
    o.tethers = tethers;
    return o;
}

}  // namespace

TEST_CASE("profile: the drape pays nothing for wind or collisions") {
    auto w = make_scene(SeedScene::drape, profiled(50));
    step_n(*w, 30);
    const WorldStats stats = world_stats(w->world);
    CHECK(stats.steps == 30);
    CHECK(pass_ns(w->world, Pass::wind) == 0);
    CHECK(pass_ns(w->world, Pass::collide) == 0);
    CHECK(pass_ns(w->world, Pass::coarse) == 0);  // held by pins: the budget goes to iterations
    CHECK(pass_ns(w->world, Pass::integrate) > 0);
    CHECK(pass_ns(w->world, Pass::constraints) > 0);
    CHECK(pass_ns(w->world, Pass::tethers) > 0);
}

TEST_CASE("profile: tethers off means no tether pass") {
    auto w = make_scene(SeedScene::drape, profiled(50, false));
    step_n(*w, 30);
    CHECK(pass_ns(w->world, Pass::tethers) == 0);
    CHECK(pass_ns(w->world, Pass::wind) == 0);
    CHECK(pass_ns(w->world, Pass::collide) == 0);
    CHECK(pass_ns(w->world, Pass::constraints) > 0);
}

TEST_CASE("profile: the flag pays for wind, not for collisions") {
    auto w = make_scene(SeedScene::flag, profiled(50));
    step_n(*w, 30);
    CHECK(pass_ns(w->world, Pass::wind) > 0);
    CHECK(pass_ns(w->world, Pass::collide) == 0);
    CHECK(pass_ns(w->world, Pass::integrate) > 0);
}

TEST_CASE("profile: without the coarse level there is no coarse pass") {
    scenes::SceneOptions o = profiled(30);
    o.explicit_split = true;
    o.substeps = 3;
    o.iterations = 1;
    o.coarse_level = CoarseLevel::off;
    auto w = make_scene(SeedScene::sphere, o);
    step_n(*w, 20);
    CHECK(pass_ns(w->world, Pass::coarse) == 0);
    CHECK(pass_ns(w->world, Pass::constraints) > 0);
}

TEST_CASE("profile: the sphere pays for collisions, not for wind or tethers (nothing is pinned)") {
    auto w = make_scene(SeedScene::sphere, profiled(50));
    step_n(*w, 30);
    CHECK(pass_ns(w->world, Pass::collide) > 0);
    CHECK(pass_ns(w->world, Pass::coarse) > 0);  // held by a collider: the coarse level carries tension
    CHECK(pass_ns(w->world, Pass::wind) == 0);
    CHECK(w->asset().tether_batch_count == 0);
    CHECK(pass_ns(w->world, Pass::tethers) == 0);
}

TEST_CASE("profile off: no pass is timed, and profiling does not change the physics") {
    auto plain = make_scene(SeedScene::flag, scene_options(30));
    auto timed = make_scene(SeedScene::flag, profiled(30));
    step_n(*plain, 40);
    step_n(*timed, 40);
    for (int p = 0; p < static_cast<int>(Pass::count); ++p) CHECK(world_stats(plain->world).pass_ns[p] == 0);
    CHECK(same_bits(read_all(*plain), read_all(*timed)));
    CHECK(world_stats(plain->world).steps == 40);
}

TEST_CASE("pass names") {
    CHECK(std::string(pass_name(Pass::wind)) == "wind");
    CHECK(std::string(pass_name(Pass::integrate)) == "integrate");
    CHECK(std::string(pass_name(Pass::coarse)) == "coarse");
    CHECK(std::string(pass_name(Pass::constraints)) == "constraints");
    CHECK(std::string(pass_name(Pass::tethers)) == "tethers");
    CHECK(std::string(pass_name(Pass::collide)) == "collide");
    CHECK(std::string(pass_name(Pass::body)) == "body");
    CHECK(std::string(pass_name(Pass::normals)) == "normals");
    CHECK(std::string(pass_name(Pass::render_mesh)) == "render_mesh");
    CHECK(std::string(pass_name(Pass::health)) == "health");
    CHECK(std::string(simd_path_name(SimdPath::scalar)) == "scalar");
    CHECK(std::string(simd_path_name(SimdPath::avx2)) == "avx2");
    CHECK(simd_path_available(SimdPath::scalar));
    CHECK(simd_path_available(SimdPath::automatic));
}

TEST_CASE("automatic picks avx2 when it is available") {
    auto w = make_scene(SeedScene::drape, scene_options(10));
    CHECK(world_simd_path(w->world) == (simd_path_available(SimdPath::avx2) ? SimdPath::avx2 : SimdPath::scalar));
}
