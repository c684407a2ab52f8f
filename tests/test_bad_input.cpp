// Bad input: every fallible call refuses it with the right ErrorCode and a message, and a refused
// call changes nothing (the next step matches an untouched twin world bit for bit).
#include "support/test_support.h"

#include <functional>
#include <limits>

using namespace weft;
using namespace weft::test;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

void check_refused(const Result& r, ErrorCode expected) {
    INFO("message: ", r.message);
    CHECK(r.code == expected);
    CHECK(r.message[0] != '\0');
    CHECK(std::memchr(r.message, '\0', sizeof(r.message)) != nullptr);  // NUL-terminated
}

// Every float of a cloth's state, in slot order.
std::vector<float> state_of(const World* world, ClothId cloth) {
    const ClothView v = view_of(world, cloth);
    std::vector<float> s;
    for (const float* a : {v.x, v.y, v.z, v.previous_x, v.previous_y, v.previous_z, v.inverse_mass})
        s.insert(s.end(), a, a + v.asset->slot_count);
    s.push_back(v.last_substep_s);
    return s;
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Builds a seed world and its twin, steps both, applies `bad` to the first and checks it was
// refused with `expected` and changed nothing.
void expect_refused(scenes::SeedScene scene, ErrorCode expected,
                    const std::function<Result(scenes::SeedWorld&)>& bad) {
    const scenes::SceneOptions o = scene_options(20);
    auto w = make_scene(scene, o);
    auto twin = make_scene(scene, o);
    step_n(*w, 4);
    step_n(*twin, 4);
    const std::vector<float> before = state_of(w->world, w->cloth);
    REQUIRE(same_floats(before, state_of(twin->world, twin->cloth)));

    check_refused(bad(*w), expected);

    CHECK(same_floats(state_of(w->world, w->cloth), before));
    CHECK(world_stats(w->world).steps == world_stats(twin->world).steps);
    step_n(*w, 2);
    step_n(*twin, 2);
    CHECK(same_bits(read_all(*w), read_all(*twin)));
    CHECK(same_floats(state_of(w->world, w->cloth), state_of(twin->world, twin->cloth)));
}

void expect_refused(ErrorCode expected, const std::function<Result(scenes::SeedWorld&)>& bad) {
    expect_refused(scenes::SeedScene::flag, expected, bad);
}

}  // namespace

// --- step --------------------------------------------------------------------------------------

TEST_CASE("step refuses dt = 0") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) { return step(w.world, 0.0f); });
}
TEST_CASE("step refuses a negative dt") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) { return step(w.world, -0.033f); });
}
TEST_CASE("step refuses dt = -0") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) { return step(w.world, -0.0f); });
}
TEST_CASE("step refuses a NaN dt") {
    expect_refused(ErrorCode::non_finite, [](scenes::SeedWorld& w) { return step(w.world, kNaN); });
}
TEST_CASE("step refuses an infinite dt") {
    expect_refused(ErrorCode::non_finite, [](scenes::SeedWorld& w) { return step(w.world, kInf); });
    expect_refused(ErrorCode::non_finite, [](scenes::SeedWorld& w) { return step(w.world, -kInf); });
}
TEST_CASE("step refuses dt > 1 s") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) { return step(w.world, 1.0001f); });
}
TEST_CASE("step accepts dt = 1 s exactly and a tiny dt") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(10));
    CHECK(step(w->world, 1.0f).ok());
    CHECK(step(w->world, 1e-6f).ok());
    CHECK(all_finite(read_all(*w)));
}
TEST_CASE("step refuses a null world") { check_refused(step(nullptr, 0.033f), ErrorCode::invalid_argument); }

// --- set_particle ------------------------------------------------------------------------------

TEST_CASE("set_particle refuses a NaN position") {
    expect_refused(ErrorCode::non_finite,
                   [](scenes::SeedWorld& w) { return set_particle(w.world, w.cloth, 5, {0.0f, kNaN, 0.0f}, 1.0f); });
    expect_refused(ErrorCode::non_finite,
                   [](scenes::SeedWorld& w) { return set_particle(w.world, w.cloth, 5, {kInf, 0.0f, 0.0f}, 1.0f); });
}
TEST_CASE("set_particle refuses a NaN inverse mass") {
    expect_refused(ErrorCode::non_finite,
                   [](scenes::SeedWorld& w) { return set_particle(w.world, w.cloth, 5, {0.0f, 1.0f, 0.0f}, kNaN); });
}
TEST_CASE("set_particle refuses a negative inverse mass") {
    expect_refused(ErrorCode::out_of_range,
                   [](scenes::SeedWorld& w) { return set_particle(w.world, w.cloth, 5, {0.0f, 1.0f, 0.0f}, -1.0f); });
}
TEST_CASE("set_particle refuses an out-of-range particle index") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        return set_particle(w.world, w.cloth, w.asset().particle_count, {0.0f, 1.0f, 0.0f}, 1.0f);
    });
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        return set_particle(w.world, w.cloth, 0xFFFFFFFFu, {0.0f, 1.0f, 0.0f}, 1.0f);
    });
}
TEST_CASE("set_particle moves and pins one particle") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(10));
    const Vec3 target{0.25f, 3.0f, -0.5f};
    REQUIRE(set_particle(w->world, w->cloth, 55, target, 0.0f).ok());
    step_n(*w, 10);
    const std::vector<Vec3> p = read_all(*w);
    CHECK(p[55].x == target.x);
    CHECK(p[55].y == target.y);
    CHECK(p[55].z == target.z);
}

// --- set_wind, set_gravity, set_collider ---------------------------------------------------------

TEST_CASE("set_wind refuses NaN") {
    expect_refused(ErrorCode::non_finite, [](scenes::SeedWorld& w) { return set_wind(w.world, {kNaN, 0.0f, 0.0f}); });
    expect_refused(ErrorCode::non_finite, [](scenes::SeedWorld& w) { return set_wind(w.world, {0.0f, 0.0f, kInf}); });
}
TEST_CASE("set_wind refuses a world without wind") {
    expect_refused(scenes::SeedScene::drape, ErrorCode::invalid_argument,
                   [](scenes::SeedWorld& w) { return set_wind(w.world, {10.0f, 0.0f, 0.0f}); });
}
TEST_CASE("set_gravity refuses NaN") {
    expect_refused(ErrorCode::non_finite,
                   [](scenes::SeedWorld& w) { return set_gravity(w.world, {0.0f, kNaN, 0.0f}); });
}
TEST_CASE("set_collider refuses NaN and unknown colliders") {
    expect_refused(scenes::SeedScene::sphere, ErrorCode::non_finite, [](scenes::SeedWorld& w) {
        ColliderDesc d;
        d.radius_m = kNaN;
        return set_collider(w.world, ColliderId{0}, d);
    });
    expect_refused(scenes::SeedScene::sphere, ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        ColliderDesc d;
        return set_collider(w.world, ColliderId{1}, d);
    });
}

// --- add_cloth ---------------------------------------------------------------------------------

TEST_CASE("add_cloth beyond max_cloths") {
    expect_refused(ErrorCode::capacity_exceeded, [](scenes::SeedWorld& w) {
        ClothDesc d;
        d.asset = &w.asset();
        ClothId id;
        return add_cloth(w.world, d, &id);  // seed worlds hold exactly one cloth
    });
}

namespace {

// A world with room for two cloths by count, sized by `desc`, holding one cloth already; adding a
// second must fail with capacity_exceeded and leave the first cloth exactly as its twin's.
void expect_second_cloth_refused(const WorldDesc& desc, const ClothAsset& asset) {
    OwnedWorld world, twin;
    REQUIRE(make_world(desc, &world).ok());
    REQUIRE(make_world(desc, &twin).ok());
    ClothDesc cd;
    cd.asset = &asset;
    ClothId a, b;
    REQUIRE(add_cloth(world.world, cd, &a).ok());
    REQUIRE(add_cloth(twin.world, cd, &b).ok());
    REQUIRE(step(world.world, 0.033f).ok());
    REQUIRE(step(twin.world, 0.033f).ok());
    const std::vector<float> before = state_of(world.world, a);

    cd.translation_m = {3.0f, 0.0f, 0.0f};
    ClothId second{77};
    check_refused(add_cloth(world.world, cd, &second), ErrorCode::capacity_exceeded);

    CHECK(same_floats(state_of(world.world, a), before));
    std::vector<Vec3> scratch(asset.particle_count);
    CHECK(read_positions(world.world, ClothId{1}, scratch.data(), asset.particle_count).code == ErrorCode::out_of_range);
    REQUIRE(step(world.world, 0.033f).ok());
    REQUIRE(step(twin.world, 0.033f).ok());
    CHECK(same_floats(state_of(world.world, a), state_of(twin.world, b)));
}

}  // namespace

TEST_CASE("add_cloth beyond max_particles") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(12));
    const ClothAsset& asset = w->asset();
    WorldDesc d = world_for({&asset, &asset});
    d.max_particles -= 1;  // one slot short of two cloths
    expect_second_cloth_refused(d, asset);
}

TEST_CASE("add_cloth beyond max_constraints") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(12));
    const ClothAsset& asset = w->asset();
    WorldDesc d = world_for({&asset, &asset});
    d.max_constraints -= 1;  // one lane short of two cloths
    expect_second_cloth_refused(d, asset);
}

TEST_CASE("add_cloth beyond max_coarse_nodes") {
    auto w = make_scene(scenes::SeedScene::sphere, scene_options(25));
    const ClothAsset& asset = w->asset();
    REQUIRE(asset.coarse_node_count > 0);
    WorldDesc d = world_for({&asset, &asset});
    d.max_coarse_nodes -= 1;  // one node short of two cloths
    expect_second_cloth_refused(d, asset);
}

TEST_CASE("add_cloth and set_cloth_settings refuse bad settings: substeps 0, relaxation 2.5, negative compliance") {
    struct Case {
        const char* name;
        std::function<void(ClothDesc&)> spoil;
        ErrorCode expected;
    };
    const std::vector<Case> cases{
        {"sweeps 0", [](ClothDesc& d) { d.sweeps = 0; }, ErrorCode::out_of_range},
        {"sweeps 1001", [](ClothDesc& d) { d.sweeps = 1001; }, ErrorCode::out_of_range},
        {"unknown policy", [](ClothDesc& d) { d.policy = static_cast<BudgetPolicy>(7); }, ErrorCode::invalid_argument},
        {"substeps 0", [](ClothDesc& d) { d.substeps = 0; }, ErrorCode::out_of_range},
        {"explicit substeps 0", [](ClothDesc& d) { d.policy = BudgetPolicy::explicit_split; d.substeps = 0; },
         ErrorCode::out_of_range},
        {"iterations 1001", [](ClothDesc& d) { d.policy = BudgetPolicy::explicit_split; d.iterations = 1001; },
         ErrorCode::out_of_range},
        {"substeps 65", [](ClothDesc& d) { d.substeps = 65; }, ErrorCode::out_of_range},
        {"relaxation 2.5", [](ClothDesc& d) { d.relaxation = 2.5f; }, ErrorCode::out_of_range},
        {"coarse iterations 0", [](ClothDesc& d) { d.coarse_iterations = 0; }, ErrorCode::out_of_range},
        {"coarse iterations 17", [](ClothDesc& d) { d.coarse_iterations = 17; }, ErrorCode::out_of_range},
        {"relaxation 0", [](ClothDesc& d) { d.relaxation = 0.0f; }, ErrorCode::out_of_range},
        {"relaxation 1.3 (over-relaxation jitters)", [](ClothDesc& d) { d.relaxation = 1.3f; }, ErrorCode::out_of_range},
        {"relaxation 0.4", [](ClothDesc& d) { d.relaxation = 0.4f; }, ErrorCode::out_of_range},
        {"coarse level with 16 substeps", [](ClothDesc& d) {
             d.policy = BudgetPolicy::explicit_split;
             d.substeps = 16;
             d.coarse_level = CoarseLevel::on;
         }, ErrorCode::out_of_range},
        {"relaxation NaN", [](ClothDesc& d) { d.relaxation = kNaN; }, ErrorCode::non_finite},
        {"negative stretch compliance", [](ClothDesc& d) { d.compliance_m_per_n[0] = -1e-6f; }, ErrorCode::out_of_range},
        {"negative bend compliance", [](ClothDesc& d) { d.compliance_m_per_n[2] = -1.0f; }, ErrorCode::out_of_range},
        {"NaN compliance", [](ClothDesc& d) { d.compliance_m_per_n[1] = kNaN; }, ErrorCode::non_finite},
        {"negative damping", [](ClothDesc& d) { d.damping_per_s = -0.1f; }, ErrorCode::out_of_range},
        {"NaN translation", [](ClothDesc& d) { d.translation_m.x = kNaN; }, ErrorCode::non_finite},
        {"negative tether slack", [](ClothDesc& d) { d.tether_slack = -0.1f; }, ErrorCode::out_of_range},
        {"negative drag", [](ClothDesc& d) { d.drag_coefficient = -0.1f; }, ErrorCode::out_of_range},
        {"no asset", [](ClothDesc& d) { d.asset = nullptr; }, ErrorCode::invalid_argument},
    };
    auto w = make_scene(scenes::SeedScene::drape, scene_options(10));
    const ClothAsset& asset = w->asset();
    for (const Case& c : cases) {
        CAPTURE(c.name);
        // add_cloth into an empty world with room for the cloth: refused, and the world stays empty.
        OwnedWorld world;
        REQUIRE(make_world(world_for({&asset}), &world).ok());
        ClothDesc d;
        d.asset = &asset;
        c.spoil(d);
        ClothId id;
        check_refused(add_cloth(world.world, d, &id), c.expected);
        std::vector<Vec3> scratch(asset.particle_count);
        CHECK(read_positions(world.world, ClothId{0}, scratch.data(), asset.particle_count).code ==
              ErrorCode::out_of_range);
        d = ClothDesc();
        d.asset = &asset;
        CHECK(add_cloth(world.world, d, &id).ok());  // nothing was used up

        // set_cloth_settings on a running cloth: refused, nothing changes.
        expect_refused(scenes::SeedScene::drape, c.expected, [&](scenes::SeedWorld& sw) {
            ClothDesc s;
            s.asset = &sw.asset();
            c.spoil(s);
            return set_cloth_settings(sw.world, sw.cloth, s);
        });
    }
}

TEST_CASE("set_cloth_settings refuses a different asset") {
    auto other = make_scene(scenes::SeedScene::drape, scene_options(20));
    expect_refused(scenes::SeedScene::drape, ErrorCode::invalid_argument, [&](scenes::SeedWorld& w) {
        ClothDesc d;
        d.asset = &other->asset();
        return set_cloth_settings(w.world, w.cloth, d);
    });
}

TEST_CASE("add_cloth refuses null arguments") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(10));
    ClothDesc d;
    d.asset = &w->asset();
    ClothId id;
    check_refused(add_cloth(nullptr, d, &id), ErrorCode::invalid_argument);
    check_refused(add_cloth(w->world, d, nullptr), ErrorCode::invalid_argument);
}

// --- add_collider ------------------------------------------------------------------------------

TEST_CASE("add_collider beyond capacity") {
    // The sphere scene holds exactly one collider, the drape none.
    expect_refused(scenes::SeedScene::sphere, ErrorCode::capacity_exceeded, [](scenes::SeedWorld& w) {
        ColliderDesc d;
        d.p0 = {2.0f, 0.0f, 0.0f};
        ColliderId id;
        return add_collider(w.world, d, &id);
    });
    expect_refused(scenes::SeedScene::drape, ErrorCode::capacity_exceeded, [](scenes::SeedWorld& w) {
        ColliderDesc d;
        ColliderId id;
        return add_collider(w.world, d, &id);
    });
}

namespace {

// A drape world with one free collider slot; adding `desc` must fail with `expected`.
void expect_collider_refused(const ColliderDesc& desc, ErrorCode expected) {
    auto scene = make_scene(scenes::SeedScene::drape, scene_options(12));
    const ClothAsset& asset = scene->asset();
    OwnedWorld world, twin;
    REQUIRE(make_world(world_for({&asset}, 1), &world).ok());
    REQUIRE(make_world(world_for({&asset}, 1), &twin).ok());
    ClothDesc cd;
    cd.asset = &asset;
    ClothId a, b;
    REQUIRE(add_cloth(world.world, cd, &a).ok());
    REQUIRE(add_cloth(twin.world, cd, &b).ok());
    ColliderId id{99};
    check_refused(add_collider(world.world, desc, &id), expected);
    // No collider was added: set_collider on index 0 fails, and stepping matches the twin.
    check_refused(set_collider(world.world, ColliderId{0}, ColliderDesc{}), ErrorCode::out_of_range);
    for (int i = 0; i < 30; ++i) {
        REQUIRE(step(world.world, 0.033f).ok());
        REQUIRE(step(twin.world, 0.033f).ok());
    }
    CHECK(same_floats(state_of(world.world, a), state_of(twin.world, b)));
    // The slot is still free.
    ColliderDesc fine;
    fine.p0 = {0.0f, -10.0f, 0.0f};
    CHECK(add_collider(world.world, fine, &id).ok());
    CHECK(id.index == 0);
}

}  // namespace

TEST_CASE("add_collider refuses a NaN radius") {
    ColliderDesc d;
    d.p0 = {0.0f, 1.9f, 0.0f};  // would touch the cloth
    d.radius_m = kNaN;
    expect_collider_refused(d, ErrorCode::non_finite);
}
TEST_CASE("add_collider refuses a negative inflation") {
    ColliderDesc d;
    d.p0 = {0.0f, 1.9f, 0.0f};
    d.inflation_m = -0.01f;
    expect_collider_refused(d, ErrorCode::out_of_range);
}
TEST_CASE("add_collider refuses a negative radius, a negative friction and a NaN position") {
    ColliderDesc d;
    d.p0 = {0.0f, 1.9f, 0.0f};
    d.radius_m = -0.5f;
    expect_collider_refused(d, ErrorCode::out_of_range);
    d.radius_m = 0.5f;
    d.friction = -1.0f;
    expect_collider_refused(d, ErrorCode::out_of_range);
    d.friction = 0.0f;
    d.p1.z = kNaN;
    d.shape = ColliderShape::capsule;
    expect_collider_refused(d, ErrorCode::non_finite);
}
TEST_CASE("add_collider refuses a plane whose normal is not unit length") {
    ColliderDesc d;
    d.shape = ColliderShape::plane;
    d.p0 = {0.0f, 0.0f, 0.0f};
    d.p1 = {0.0f, 2.0f, 0.0f};
    expect_collider_refused(d, ErrorCode::invalid_argument);
}

// --- create_world ------------------------------------------------------------------------------

TEST_CASE("create_world refuses a block that is too small or null") {
    WorldDesc desc;
    desc.max_cloths = 2;
    desc.max_particles = 4096;
    desc.max_constraints = 20000;
    desc.max_colliders = 3;
    desc.wind = true;
    const MemoryRequirements need = world_memory_requirements(desc);
    REQUIRE(need.bytes > 0);
    REQUIRE(need.alignment > 0);
    std::unique_ptr<unsigned char[], void (*)(void*)> block{
        static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes / need.alignment + 1) * need.alignment)),
        std::free};
    World* world = reinterpret_cast<World*>(uintptr_t(1));
    check_refused(create_world(desc, block.get(), need.bytes - 1, &world), ErrorCode::memory_too_small);
    CHECK(world == nullptr);
    world = reinterpret_cast<World*>(uintptr_t(1));
    check_refused(create_world(desc, block.get(), 0, &world), ErrorCode::memory_too_small);
    CHECK(world == nullptr);
    world = reinterpret_cast<World*>(uintptr_t(1));
    check_refused(create_world(desc, nullptr, need.bytes, &world), ErrorCode::invalid_argument);
    CHECK(world == nullptr);
    check_refused(create_world(desc, block.get(), need.bytes, nullptr), ErrorCode::invalid_argument);
    // The exact size works.
    CHECK(create_world(desc, block.get(), need.bytes, &world).ok());
    CHECK(world != nullptr);
}

TEST_CASE("create_world works in a block that starts off a cache line") {
    // The requirement includes a cache line of slack so the block may start anywhere.
    auto scene = make_scene(scenes::SeedScene::flag, scene_options(16));
    const ClothAsset& asset = scene->asset();
    WorldDesc desc = world_for({&asset});
    desc.wind = true;
    const MemoryRequirements need = world_memory_requirements(desc);
    // One world at offset 4 bytes past a cache line, its twin in an aligned block.
    std::vector<unsigned char> raw(need.bytes + 2 * need.alignment, 0xCD);
    unsigned char* start = raw.data() + (need.alignment - reinterpret_cast<uintptr_t>(raw.data()) % need.alignment) + 4;
    World* world = nullptr;
    REQUIRE(create_world(desc, start, need.bytes, &world).ok());
    OwnedWorld twin;
    REQUIRE(make_world(desc, &twin).ok());
    ClothDesc cd;
    cd.asset = &asset;
    ClothId id, twin_id;
    REQUIRE(add_cloth(world, cd, &id).ok());
    REQUIRE(add_cloth(twin.world, cd, &twin_id).ok());
    for (World* w : {world, twin.world}) {
        REQUIRE(set_wind(w, {20.0f, 0.0f, 3.0f}).ok());
        for (int i = 0; i < 20; ++i) REQUIRE(step(w, 0.033f).ok());
    }
    // Same answer as the aligned world (the block's address does not change the physics).
    const std::vector<Vec3> p = read_all(world, id, asset.particle_count);
    CHECK(all_finite(p));
    CHECK(same_bits(p, read_all(twin.world, twin_id, asset.particle_count)));
    // Nothing written past the block.
    for (size_t i = size_t(start - raw.data()) + need.bytes; i < raw.size(); ++i) REQUIRE(raw[i] == 0xCD);
}

TEST_CASE("create_world refuses bad descriptions") {
    WorldDesc desc;
    desc.max_particles = 64;
    desc.max_constraints = 64;
    desc.max_cloths = 0;
    CHECK(world_memory_requirements(desc).bytes == 0);
    std::vector<unsigned char> raw(1 << 16);
    World* world = nullptr;
    check_refused(create_world(desc, raw.data(), raw.size(), &world), ErrorCode::invalid_argument);
    desc.max_cloths = 1;
    desc.gravity_m_s2.y = kNaN;
    check_refused(create_world(desc, raw.data(), raw.size(), &world), ErrorCode::non_finite);
    desc.gravity_m_s2.y = -9.81f;
    desc.air_density_kg_m3 = -1.0f;
    check_refused(create_world(desc, raw.data(), raw.size(), &world), ErrorCode::out_of_range);
    desc.air_density_kg_m3 = 1.2f;
    if (!simd_path_available(SimdPath::avx2)) {
        desc.simd = SimdPath::avx2;
        check_refused(create_world(desc, raw.data(), raw.size(), &world), ErrorCode::unsupported);
    }
}

// --- cook_cloth --------------------------------------------------------------------------------

namespace {

void expect_cook_refused(const std::function<void(scenes::GridMesh&, ClothMeshDesc&)>& spoil, ErrorCode expected) {
    scenes::GridMesh grid = scenes::make_grid(6, 1.0f, 1.0f, false, 1.0f);
    ClothMeshDesc desc = grid.desc();
    spoil(grid, desc);
    // `out` holds a previous result; a refused cook must leave it alone.
    CookedCloth out = cook(scenes::make_grid(4, 1.0f, 1.0f, false, 1.0f).desc());
    const uint32_t lanes = out.asset().lane_count;
    check_refused(cook_cloth(desc, CookOptions{}, &out), expected);
    CHECK(out.asset().particle_count == 16);
    CHECK(out.asset().lane_count == lanes);
    CHECK(validate_asset(out.asset()).ok());
}

}  // namespace

TEST_CASE("cook_cloth refuses a NaN position") {
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.positions[7].y = kNaN; }, ErrorCode::non_finite);
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.positions[0].z = -kInf; }, ErrorCode::non_finite);
}
TEST_CASE("cook_cloth refuses a NaN rest position") {
    expect_cook_refused(
        [](scenes::GridMesh& g, ClothMeshDesc& d) {
            static std::vector<Vec3> rest;
            rest = g.positions;
            rest[3].x = kNaN;
            d.rest_positions = rest.data();
        },
        ErrorCode::non_finite);
}
TEST_CASE("cook_cloth refuses a negative or NaN mass") {
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.masses[5] = -0.01f; }, ErrorCode::out_of_range);
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.masses[5] = kNaN; }, ErrorCode::non_finite);
}
TEST_CASE("cook_cloth refuses a triangle index out of range") {
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.triangles[10] = uint32_t(g.positions.size()); },
                        ErrorCode::out_of_range);
}
TEST_CASE("cook_cloth refuses a triangle that repeats a vertex") {
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.triangles[4] = g.triangles[3]; },
                        ErrorCode::invalid_argument);
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc&) { g.triangles[5] = g.triangles[3]; },
                        ErrorCode::invalid_argument);
}
TEST_CASE("cook_cloth refuses both or neither of masses and inverse_masses") {
    expect_cook_refused([](scenes::GridMesh& g, ClothMeshDesc& d) { d.inverse_masses = g.masses.data(); },
                        ErrorCode::invalid_argument);
    expect_cook_refused([](scenes::GridMesh&, ClothMeshDesc& d) { d.masses = nullptr; }, ErrorCode::invalid_argument);
}
TEST_CASE("cook_cloth refuses a mesh without particles or with null triangles") {
    expect_cook_refused([](scenes::GridMesh&, ClothMeshDesc& d) { d.particle_count = 0; }, ErrorCode::invalid_argument);
    expect_cook_refused([](scenes::GridMesh&, ClothMeshDesc& d) { d.triangles = nullptr; }, ErrorCode::invalid_argument);
    CHECK(cook_cloth(scenes::make_grid(4, 1.0f, 1.0f, false, 1.0f).desc(), CookOptions{}, nullptr).code ==
          ErrorCode::invalid_argument);
}

// --- read_positions and cloth ids ----------------------------------------------------------------

TEST_CASE("read_positions refuses a wrong count and a null buffer") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(10));
    const uint32_t n = w->asset().particle_count;
    std::vector<Vec3> out(n + 1, Vec3{7.0f, 7.0f, 7.0f});
    check_refused(read_positions(w->world, w->cloth, out.data(), n - 1), ErrorCode::out_of_range);
    check_refused(read_positions(w->world, w->cloth, out.data(), n + 1), ErrorCode::out_of_range);
    check_refused(read_positions(w->world, w->cloth, out.data(), w->asset().slot_count), ErrorCode::out_of_range);
    check_refused(read_positions(w->world, w->cloth, nullptr, n), ErrorCode::invalid_argument);
    for (const Vec3& v : out) CHECK(v.x == 7.0f);  // nothing written on refusal
}

TEST_CASE("an invalid cloth id is refused everywhere") {
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        std::vector<Vec3> out(w.asset().particle_count);
        return read_positions(w.world, ClothId{1}, out.data(), uint32_t(out.size()));
    });
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        return set_particle(w.world, ClothId{1}, 0, {0.0f, 0.0f, 0.0f}, 1.0f);
    });
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) { return reset_cloth(w.world, ClothId{1}); });
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        ClothDesc d;
        d.asset = &w.asset();
        return set_cloth_settings(w.world, ClothId{0xFFFFFFFFu}, d);
    });
    expect_refused(ErrorCode::out_of_range, [](scenes::SeedWorld& w) {
        ClothView v;
        return view_cloth(w.world, ClothId{2}, &v);
    });
}

TEST_CASE("reset_cloth puts the cloth back at its start pose, at rest") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(12));
    const std::vector<Vec3> start = read_all(*w);
    step_n(*w, 20);
    REQUIRE(!same_bits(read_all(*w), start));
    REQUIRE(reset_cloth(w->world, w->cloth).ok());
    CHECK(same_bits(read_all(*w), start));
    // And from there it replays the same motion as a fresh world.
    auto fresh = make_scene(scenes::SeedScene::drape, scene_options(12));
    step_n(*w, 15);
    step_n(*fresh, 15);
    CHECK(same_bits(read_all(*w), read_all(*fresh)));
}
