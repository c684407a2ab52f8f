// Stepping never allocates: the global allocation functions are replaced by counting ones, and the
// stepping loop of every seed scene on every SIMD path must leave the count at zero.
//
// Replaced here: every operator new / new[] / delete / delete[] (plain, sized, aligned, nothrow),
// and, except under AddressSanitizer (which owns malloc), malloc / calloc / realloc / free /
// aligned_alloc / memalign / posix_memalign forwarding to glibc's __libc_* entry points. This file is
// its own executable so the replacement cannot disturb the other tests.
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN

// operator delete below hands operator new's memory to free(): that is the point of the replacement.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "common/asset_writer.h"
#include "common/crowd.h"
#include "common/scene_json.h"
#include "common/seed_scenes.h"
#include "common/thread_pool.h"
#include "support/test_support.h"
#include "weft/weft.h"
#include "weft/weft_c.h"
#include "weft/cook.h"
#include "weft/debug.h"

#if defined(__SANITIZE_ADDRESS__)
#define WEFT_TEST_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WEFT_TEST_COUNT_MALLOC 0
#endif
#endif
#if !defined(WEFT_TEST_COUNT_MALLOC) && defined(__GLIBC__)
#define WEFT_TEST_COUNT_MALLOC 1
#endif
#if !defined(WEFT_TEST_COUNT_MALLOC)
#define WEFT_TEST_COUNT_MALLOC 0
#endif

namespace {

// Plain atomics: counting itself must not allocate.
std::atomic<bool> g_counting{false};
std::atomic<uint64_t> g_allocations{0};
std::atomic<uint64_t> g_deallocations{0};

inline void note_allocation() {
    if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
inline void note_deallocation(void* p) {
    if (p != nullptr && g_counting.load(std::memory_order_relaxed))
        g_deallocations.fetch_add(1, std::memory_order_relaxed);
}

// Counts allocations while alive.
struct CountingScope {
    CountingScope() {
        g_allocations = 0;
        g_deallocations = 0;
        g_counting = true;
    }
    ~CountingScope() { g_counting = false; }
    uint64_t allocations() const { return g_allocations.load(); }
    uint64_t deallocations() const { return g_deallocations.load(); }
};

}  // namespace

// --- malloc family (not under ASan) ----------------------------------------------------------------

#if WEFT_TEST_COUNT_MALLOC
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void __libc_free(void*);
void* __libc_memalign(size_t, size_t);

void* malloc(size_t size) {
    note_allocation();
    return __libc_malloc(size);
}
void* calloc(size_t count, size_t size) {
    note_allocation();
    return __libc_calloc(count, size);
}
void* realloc(void* p, size_t size) {
    note_allocation();
    return __libc_realloc(p, size);
}
void free(void* p) {
    note_deallocation(p);
    __libc_free(p);
}
void* memalign(size_t alignment, size_t size) {
    note_allocation();
    return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
    note_allocation();
    return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
    if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) return EINVAL;
    note_allocation();
    void* p = __libc_memalign(alignment, size);
    if (p == nullptr) return ENOMEM;
    *out = p;
    return 0;
}
}  // extern "C"
#endif

// --- operator new / delete, every variant ----------------------------------------------------------

namespace {

// Straight to the underlying allocator, so one operator new counts once.
void* allocate(size_t size) {
    note_allocation();
#if WEFT_TEST_COUNT_MALLOC
    return __libc_malloc(size == 0 ? 1 : size);
#else
    return std::malloc(size == 0 ? 1 : size);
#endif
}
void* allocate_aligned(size_t size, std::align_val_t alignment) {
    note_allocation();
    const size_t a = std::max(static_cast<size_t>(alignment), sizeof(void*));
#if WEFT_TEST_COUNT_MALLOC
    return __libc_memalign(a, size == 0 ? a : size);
#else
    void* p = nullptr;
    if (posix_memalign(&p, a, size == 0 ? a : size) != 0) return nullptr;
    return p;
#endif
}
void release(void* p) {
    note_deallocation(p);
#if WEFT_TEST_COUNT_MALLOC
    __libc_free(p);
#else
    std::free(p);
#endif
}

}  // namespace

void* operator new(size_t size) {
    if (void* p = allocate(size)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t size) {
    if (void* p = allocate(size)) return p;
    throw std::bad_alloc();
}
void* operator new(size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new[](size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new(size_t size, std::align_val_t alignment) {
    if (void* p = allocate_aligned(size, alignment)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t size, std::align_val_t alignment) {
    if (void* p = allocate_aligned(size, alignment)) return p;
    throw std::bad_alloc();
}
void* operator new(size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return allocate_aligned(size, alignment);
}
void* operator new[](size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
    return allocate_aligned(size, alignment);
}

void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, size_t) noexcept { release(p); }
void operator delete[](void* p, size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }

// --- the tests ----------------------------------------------------------------------------------------

using namespace weft;
using scenes::SeedScene;

namespace {

using test::available_paths;

std::unique_ptr<scenes::SeedWorld> make_scene(SeedScene scene, SimdPath path, bool profile, uint32_t n = 50,
                                              bool contact_tethers = false, bool normals = false) {
    scenes::SceneOptions o;
    o.normals = normals;
    o.n = n;
    o.contact_tethers = contact_tethers;
    o.simd = path;
    o.profile = profile;
    o.sphere_friction = 0.5f;  // friction exercises the collider's second code path
    auto w = std::make_unique<scenes::SeedWorld>();
    const std::string error = scenes::make_seed_world(scene, o, w.get());
    INFO(error);
    REQUIRE(error.empty());
    return w;
}

// Steps `steps` times while counting; returns the allocations seen. Nothing inside the counted loop
// may allocate on the test's side either (no doctest macros: they build strings).
struct LoopResult {
    uint64_t allocations = 0, deallocations = 0;
    uint32_t failed_steps = 0;
};

LoopResult count_stepping(const scenes::SeedWorld& w, uint32_t steps) {
    LoopResult r;
    CountingScope counting;
    for (uint32_t i = 0; i < steps; ++i)
        if (!step(w.world, w.dt_s).ok()) ++r.failed_steps;
    r.allocations = counting.allocations();
    r.deallocations = counting.deallocations();
    return r;
}

void check_no_allocation(SeedScene scene, bool contact_tethers = false) {
    for (SimdPath path : available_paths()) {
        for (bool profile : {false, true}) {
            const std::string label = std::string(scenes::scene_name(scene)) + ", " + simd_path_name(path) +
                                      (profile ? ", profile" : "");
            CAPTURE(label);
            auto w = make_scene(scene, path, profile, 50, contact_tethers);
            REQUIRE(world_simd_path(w->world) == path);
            const LoopResult r = count_stepping(*w, 1000);
            CHECK(r.failed_steps == 0);
            CHECK(r.allocations == 0);
            CHECK(r.deallocations == 0);
            CHECK(world_stats(w->world).steps == 1000);
            if (profile) CHECK(world_stats(w->world).pass_ns[static_cast<int>(Pass::integrate)] > 0);
        }
    }
}

}  // namespace

TEST_CASE("allocation counter sees operator new and, outside ASan, malloc") {
    // The counter must be able to fail: allocations made while counting are seen.
    uint64_t seen = 0;
    {
        CountingScope counting;
        int* volatile p = new int(3);
        delete p;
        auto* volatile a = new (std::align_val_t(64)) double[4];
        ::operator delete[](a, std::align_val_t(64));
        std::vector<float> v(100);
        seen = counting.allocations();
    }
    CHECK(seen == 3);
#if WEFT_TEST_COUNT_MALLOC
    {
        CountingScope counting;
        void* volatile p = std::malloc(10);
        std::free(p);
        seen = counting.allocations();
    }
    CHECK(seen == 1);
#else
    MESSAGE("malloc is not replaced in this build (AddressSanitizer owns it): only operator new is counted");
#endif
}

TEST_CASE("stepping the drape 1000 times allocates nothing") { check_no_allocation(SeedScene::drape); }
TEST_CASE("stepping the flag in wind 1000 times allocates nothing") { check_no_allocation(SeedScene::flag); }
TEST_CASE("stepping the sphere with friction 0.5 1000 times allocates nothing") {
    check_no_allocation(SeedScene::sphere);
}
TEST_CASE("stepping the sphere with contact tethers 1000 times allocates nothing") {
    check_no_allocation(SeedScene::sphere, true);
}

TEST_CASE("stepping four cloths on a thread pool of three allocates nothing, on any thread") {
    // The pool hands the cloths stage to its workers (lib/common/thread_pool.h): the counter is
    // global, so an allocation on a worker counts as one on the stepping thread.
    auto seed = make_scene(SeedScene::sphere, SimdPath::automatic, true, 25);
    const ClothAsset& asset = seed->asset();
    weft::tools::ThreadPool pool(3);
    WorldDesc wd;
    wd.max_cloths = 0;
    for (int k = 0; k < 4; ++k) reserve_cloth(wd, asset);
    wd.max_colliders = 1;
    wd.scheduler = pool.scheduler();
    const MemoryRequirements need = world_memory_requirements(wd);
    std::unique_ptr<unsigned char[], void (*)(void*)> memory{
        static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment)),
        std::free};
    World* world = nullptr;
    REQUIRE(create_world(wd, memory.get(), need.bytes, &world).ok());
    REQUIRE(set_profiling(world, true).ok());
    for (int k = 0; k < 4; ++k) {
        ClothDesc cd;
        cd.asset = &asset;
        cd.translation_m = {3.0f * float(k), 0.0f, 0.0f};
        ClothId id;
        REQUIRE(add_cloth(world, cd, &id).ok());
    }
    ColliderDesc ground;
    ground.shape = ColliderShape::plane;
    ground.p0 = {0.0f, -0.5f, 0.0f};
    ColliderId ground_id;
    REQUIRE(add_collider(world, ground, &ground_id).ok());
    uint64_t allocations = 0, deallocations = 0;
    uint32_t failed = 0;
    {
        CountingScope counting;
        for (int i = 0; i < 300; ++i)
            if (!step(world, seed->dt_s).ok()) ++failed;
        allocations = counting.allocations();
        deallocations = counting.deallocations();
    }
    CHECK(failed == 0);
    CHECK(allocations == 0);
    CHECK(deallocations == 0);
    CHECK(world_stats(world).steps == 300);
    destroy_world(world);
}

#ifdef WEFT_SAMPLE_ASSETS_DIR  // the dressed skirt and tee are baked by weft-bake: built with the tools only
namespace {

// Walking characters in skirt and tee (lib/common/crowd.h).
scenes::CrowdOptions crowd_options(uint32_t characters) {
    scenes::CrowdOptions o;
    o.characters = characters;
    o.skirt_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json";
    o.tee_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/tee-walk.json";
    o.asset_dirs = {WEFT_SAMPLE_ASSETS_DIR};
    return o;
}

}  // namespace

TEST_CASE("1000 despawns and spawns of a dressed character allocate nothing and leave the world's pools as they were") {
    // Two walking characters; the second leaves and comes back every frame: its cloths, limb
    // capsules and body removed, then added, bound and stepped.
    scenes::Crowd crowd;
    const std::string built = scenes::build_crowd(crowd_options(2), &crowd);
    INFO(built);
    REQUIRE(built.empty());
    REQUIRE(step(crowd.world, crowd.dt_s).ok());
    const WorldUsage start = world_usage(crowd.world);
    uint64_t allocations = 0;
    uint32_t failures = 0;
    for (uint32_t cycle = 1; cycle <= 1000; ++cycle) {
        {
            CountingScope counting;
            failures += !scenes::despawn_character(crowd, 1).empty();
            failures += !scenes::spawn_character(crowd, 1).empty();
            allocations += counting.allocations();
        }
        // The game's animation (the mannequin's walk, lib/body) is not Weft's: not counted.
        failures += !scenes::animate_crowd(crowd, float(cycle % 120) * crowd.dt_s).empty();
        CountingScope counting;
        failures += !step(crowd.world, crowd.dt_s).ok();
        allocations += counting.allocations();
    }
    CHECK(failures == 0);
    CHECK(allocations == 0);
    CHECK(world_usage(crowd.world) == start);
    CHECK(world_stats(crowd.world).memory_compactions == 0);  // each comes back to the room it left
    CHECK(step_stage_items(crowd.world, StepStage::cloths) == 4);
}

TEST_CASE("the frame budget allocates nothing: cutting sweeps by priority, priorities changed every frame, refusals") {
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(crowd_options(3), &crowd).empty());
    REQUIRE(step(crowd.world, crowd.dt_s).ok());
    const float budget_us = float(0.6 * world_stats(crowd.world).budget_estimate_us);
    uint64_t allocations = 0, cut = 0;
    uint32_t failures = 0;
    for (uint32_t frame = 1; frame <= 60; ++frame) {
        failures += !scenes::animate_crowd(crowd, float(frame) * crowd.dt_s).empty();  // the game's: not counted
        CountingScope counting;
        failures += !set_frame_budget_us(crowd.world, budget_us).ok();
        for (uint32_t k = 0; k < 3; ++k)  // the nearest character turns round the crowd
            for (ClothId cloth : {crowd.characters[k].skirt, crowd.characters[k].tee})
                failures += !set_cloth_priority(crowd.world, cloth, float((k + frame) % 3)).ok();
        failures += set_cloth_priority(crowd.world, crowd.characters[0].skirt, std::nanf("")).ok();
        failures += set_frame_budget_us(crowd.world, -1.0f).ok();
        failures += !step(crowd.world, crowd.dt_s).ok();
        cut += world_stats(crowd.world).budget_cloths_cut;
        allocations += counting.allocations();
    }
    CHECK(failures == 0);
    CHECK(cut > 0);  // the budget cut
    CHECK(allocations == 0);
}
#endif

TEST_CASE("a frame's calls allocate nothing: set_wind, set_collider, step, read_positions, read_normals, view_cloth") {
    for (SeedScene scene : {SeedScene::flag, SeedScene::sphere}) {
        const std::string scene_name = scenes::scene_name(scene);
        CAPTURE(scene_name);
        auto w = make_scene(scene, SimdPath::automatic, true, 25, false, true);
        std::vector<Vec3> positions(w->asset().particle_count), normals(positions.size());
        ColliderDesc sphere;
        sphere.radius_m = 0.5f;
        sphere.inflation_m = 0.01f;
        sphere.friction = 0.5f;
        uint32_t failures = 0;
        uint64_t allocations = 0;
        {
            CountingScope counting;
            for (uint32_t i = 0; i < 300; ++i) {
                const float t = float(i) * w->dt_s;
                if (scene == SeedScene::flag) {
                    failures += !set_wind(w->world, {20.0f + 5.0f * std::sin(t), 0.0f, 2.0f}).ok();
                } else {
                    sphere.p0 = {0.1f * std::sin(t), 0.0f, 0.0f};
                    failures += !set_collider(w->world, ColliderId{0}, sphere).ok();
                }
                failures += !set_gravity(w->world, {0.0f, -9.81f, 0.0f}).ok();
                failures += !step(w->world, w->dt_s).ok();
                failures += !read_positions(w->world, w->cloth, positions.data(), uint32_t(positions.size())).ok();
                failures += !read_normals(w->world, w->cloth, normals.data(), uint32_t(normals.size())).ok();
                ClothView view;
                failures += !view_cloth(w->world, w->cloth, &view).ok();
                const WorldStats stats = world_stats(w->world);
                failures += stats.steps != i + 1;
                // Refused calls allocate nothing either (the message is formatted in place).
                failures += step(w->world, -1.0f).ok();
                failures += read_positions(w->world, ClothId{5}, positions.data(), 1).ok();
            }
            allocations = counting.allocations();
        }
        CHECK(failures == 0);
        CHECK(allocations == 0);
    }
}

TEST_CASE("sleeping cloths allocate nothing: falling asleep, sleeping steps, waking by a collider and wake_cloth") {
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        scenes::SceneOptions o;
        o.n = 16;
        o.simd = path;
        o.sphere_friction = 1.0f;  // at rest in about 260 frames (test_sleep.cpp)
        scenes::Scene scene = scenes::seed_scene(SeedScene::sphere, o);
        scene.cloths[0].desc.sleep_speed_m_s = 0.02f;
        scenes::SceneWorld w;
        REQUIRE(scenes::build_scene(scene, &w).empty());
        ColliderDesc sphere = scene.colliders[0];
        uint32_t failures = 0;
        uint64_t allocations = 0, slept = 0;
        bool asleep = false;
        {
            CountingScope counting;
            for (uint32_t i = 0; i < 800; ++i) {
                if (i == 700) {  // asleep by now: woken by its sphere, then once more by the call
                    sphere.p0.y += 0.01f;
                    failures += !set_collider(w.world, w.colliders[0], sphere).ok();
                    failures += !wake_cloth(w.world, w.cloths[0].id).ok();
                }
                failures += !step(w.world, w.dt_s).ok();
                failures += !cloth_is_sleeping(w.world, w.cloths[0].id, &asleep).ok();
                slept += asleep;
            }
            allocations = counting.allocations();
        }
        CHECK(failures == 0);
        CHECK(slept > 0);  // it slept
        CHECK(allocations == 0);
    }
}

TEST_CASE("a step that recovers a blown-up cloth allocates nothing, under each recovery policy") {
    for (RecoveryPolicy policy : {RecoveryPolicy::last_good_state, RecoveryPolicy::rest_pose, RecoveryPolicy::dressed_pose}) {
        CAPTURE(int(policy));
        scenes::SceneOptions o;
        o.n = 16;
        scenes::Scene scene = scenes::seed_scene(scenes::SeedScene::drape, o);
        scene.cloths[0].desc.recovery = policy;
        scenes::SceneWorld w;
        REQUIRE(scenes::build_scene(scene, &w).empty());
        const ClothAsset& a = *w.cloths[0].asset;
        uint32_t thrown = a.particle_count - 1;  // a movable particle: the bottom row's last
        while (thrown > 0 && !(a.inverse_mass[a.slot_of_particle[thrown]] > 0.0f)) --thrown;
        uint32_t failures = 0;
        uint64_t allocations = 0;
        {
            CountingScope counting;
            for (uint32_t i = 0; i < 100; ++i) {
                if (i == 60)  // 1 km away: overstretched, recovered at the end of this step
                    failures += !set_particle(w.world, w.cloths[0].id, thrown, {1000.0f, 0.0f, 0.0f},
                                              a.inverse_mass[a.slot_of_particle[thrown]]).ok();
                failures += !step(w.world, w.dt_s).ok();
            }
            allocations = counting.allocations();
        }
        CHECK(failures == 0);
        CHECK(world_stats(w.world).total_recoveries == 1);
        CHECK(allocations == 0);
    }
}

TEST_CASE("a frame with tangents and a render mesh allocates nothing: step, read_normals, read_tangents, read_render_mesh") {
    const CookedCloth cooked = test::uv_grid_with_render_mesh(24);
    const uint32_t render_vertices = cooked.asset().render.vertex_count;
    for (SimdPath path : available_paths()) {
        WorldDesc desc;
        desc.max_cloths = 0;
        reserve_cloth(desc, cooked.asset());
        desc.max_colliders = 1;
        desc.tangents = true;
        desc.render_meshes = true;
        desc.simd = path;
        const MemoryRequirements need = world_memory_requirements(desc);
        std::unique_ptr<void, decltype(&std::free)> block(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment), std::free);
        World* world = nullptr;
        REQUIRE(create_world(desc, block.get(), need.bytes, &world).ok());
        ClothDesc cloth_desc;
        cloth_desc.asset = &cooked.asset();
        ClothId cloth;
        REQUIRE(add_cloth(world, cloth_desc, &cloth).ok());
        ColliderDesc sphere;
        sphere.p0 = {0.1f, 0.5f, 0.05f};
        sphere.radius_m = 0.3f;
        ColliderId collider;
        REQUIRE(add_collider(world, sphere, &collider).ok());
        std::vector<Vec3> normals(cooked.asset().particle_count);
        std::vector<Vec4> tangents(cooked.asset().particle_count);
        std::vector<Vec3> render_x(render_vertices), render_n(render_vertices);
        uint32_t failures = 0;
        uint64_t allocations = 0;
        {
            CountingScope counting;
            for (uint32_t i = 0; i < 300; ++i) {
                failures += !step(world, 1.0f / 60.0f).ok();
                failures += !read_normals(world, cloth, normals.data(), cooked.asset().particle_count).ok();
                failures += !read_tangents(world, cloth, tangents.data(), cooked.asset().particle_count).ok();
                failures += !read_render_mesh(world, cloth, render_x.data(), render_n.data(), render_vertices).ok();
            }
            allocations = counting.allocations();
        }
        destroy_world(world);
        CHECK(failures == 0);
        CHECK(allocations == 0);
    }
}

TEST_CASE("reset_cloth and set_cloth_settings between frames allocate nothing") {
    auto w = make_scene(SeedScene::drape, SimdPath::automatic, false, 25);
    ClothDesc settings;
    settings.asset = &w->asset();
    uint32_t failures = 0;
    uint64_t allocations = 0;
    {
        CountingScope counting;
        for (uint32_t i = 0; i < 100; ++i) {
            settings.sweeps = 1 + i % 5;
            settings.policy = i % 2 == 0 ? BudgetPolicy::automatic : BudgetPolicy::explicit_split;
            settings.iterations = 1 + i % 5;
            settings.substeps = 1 + i % 3;
            settings.coarse_level = i % 4 < 2 ? CoarseLevel::on : CoarseLevel::off;
            failures += !set_cloth_settings(w->world, w->cloth, settings).ok();
            failures += !step(w->world, w->dt_s).ok();
            if (i % 25 == 24) failures += !reset_cloth(w->world, w->cloth).ok();
            failures += !set_particle(w->world, w->cloth, 3, {0.0f, 2.0f, 0.0f}, 1.0f).ok();
        }
        allocations = counting.allocations();
    }
    CHECK(failures == 0);
    CHECK(allocations == 0);
}

// --- bodies --------------------------------------------------------------------------------------

#include "body/body_mesh.h"

namespace {

// Counts, separately, the allocations made inside rtcCommitScene (Embree's) and outside (Weft's
// and the test's), through the world's commit hook.
std::atomic<bool> g_inside_commit{false};
std::atomic<uint64_t> g_commits{0};
void commit_hook(void*, bool entering) {
    if (entering) {
        g_inside_commit = true;
        g_commits.fetch_add(1);
        g_allocations = 0;  // the commit's own count starts here; the caller saved the rest
    } else {
        g_inside_commit = false;
    }
}

}  // namespace

TEST_CASE("a world without bodies creates no Embree device: create_world allocates nothing") {
    WorldDesc desc;
    desc.max_particles = 64;
    const MemoryRequirements need = world_memory_requirements(desc);
    std::vector<unsigned char> block(need.bytes + need.alignment);
    void* memory = block.data() + (need.alignment - reinterpret_cast<uintptr_t>(block.data()) % need.alignment);
    World* world = nullptr;
    uint64_t allocations = 0;
    {
        CountingScope counting;
        REQUIRE(create_world(desc, memory, need.bytes, &world).ok());
        destroy_world(world);
        allocations = counting.allocations();
    }
    CHECK(allocations == 0);
}

// Weft's own hierarchy (the default): no commit and no allocation at all, still or moving. The
// plain reference pass (add_reference_body) refits Embree's BVH: one commit per moving
// step, at most one transient allocation inside it.
TEST_CASE("stepping with a body allocates nothing, Embree's reference pass at most once per moving body's commit") {
    const body::BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 4);
    const scenes::GridMesh grid = scenes::make_grid(30, 0.8f, 0.8f, false, 0.35f);
    CookedCloth cooked;
    REQUIRE(cook_cloth(grid.desc(), {}, &cooked).ok());
    for (SimdPath path : available_paths())
    for (int pass = 0; pass < 4; ++pass) {  // the exact pass, cached planes, Embree's reference pass, skin constraints
        const bool reference = pass == 2;
        CAPTURE(simd_path_name(path));
        CAPTURE(pass);
        WorldDesc desc;
        desc.max_cloths = 0;
        reserve_cloth(desc, cooked.asset());
        desc.max_bodies = 1;
        desc.max_cached_plane_bodies = pass == 1 ? 1 : 0;
        desc.max_body_vertices = uint32_t(sphere.positions.size());
        desc.max_body_triangles = uint32_t(sphere.triangles.size() / 3);
        desc.max_skin_constraints = pass == 3 ? cooked.asset().particle_count : 0;  // bound twice: the second reuses
        desc.simd = path;
        const MemoryRequirements need = world_memory_requirements(desc);
        std::unique_ptr<unsigned char[], void (*)(void*)> block(
            static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) /
                                                                               need.alignment * need.alignment)),
            std::free);
        World* world = nullptr;
        REQUIRE(create_world(desc, block.get(), need.bytes, &world).ok());
        ClothDesc cd;
        cd.asset = &cooked.asset();
        if (pass == 1) {  // later substeps: the planes and the exact search of the particles that left them
            cd.policy = BudgetPolicy::explicit_split;
            cd.substeps = 3;
            cd.iterations = 1;
        }
        ClothId cloth;
        REQUIRE(add_cloth(world, cd, &cloth).ok());
        BodyDesc bd;
        bd.positions = sphere.positions.data();
        bd.vertex_count = uint32_t(sphere.positions.size());
        bd.triangles = sphere.triangles.data();
        bd.triangle_count = uint32_t(sphere.triangles.size() / 3);
        bd.collision = pass == 1   ? BodyCollision::cached_planes
                       : pass == 3 ? BodyCollision::skin_constraints
                                   : BodyCollision::exact;
        BodyId body;
        REQUIRE((reference ? add_reference_body(world, bd, &body) : add_body(world, bd, &body)).ok());
        SkinBinding skin;  // pass 3: every particle bound to the sphere
        if (pass == 3) REQUIRE(scenes::bind_skin(world, cloth, body, SkinBindingOptions{}, &skin).empty());
        if (pass == 3) {  // binding arrays already made (an asset's: bind_asset_skin_constraints) allocates nothing
            uint64_t allocations = 0;
            bool bound = false;
            {
                CountingScope counting;
                bound = bind_skin_constraints(world, cloth, body, skin.constraints()).ok();
                allocations = counting.allocations();
            }
            CHECK(bound);
            CHECK(allocations == 0);
        }
        REQUIRE(set_embree_commit_hook(world, commit_hook, nullptr).ok());
        const WorldStats created = world_stats(world);
        CHECK((created.embree_bytes > 0) == reference);  // Embree's BVH, built at add_body for the reference pass only

        std::vector<Vec3> moved = sphere.positions;
        uint32_t failures = 0;
        uint64_t weft_allocations = 0, embree_allocations = 0, worst_commit = 0, commits = 0;
        for (int phase = 0; phase < 2; ++phase) {  // 0: still body, 1: moving body
            g_commits = 0;
            CountingScope counting;
            for (int i = 0; i < 200; ++i) {
                if (phase == 1) {
                    for (size_t v = 0; v < moved.size(); ++v)
                        moved[v].x = sphere.positions[v].x + 0.001f * float(i % 50);
                    failures += !set_body_vertices(world, body, moved.data(), uint32_t(moved.size())).ok();
                }
                // Everything before the commit is Weft's; the hook restarts the count at the commit.
                const uint64_t before = g_allocations.load();
                const uint64_t commits_before = g_commits.load();
                failures += !step(world, 1.0f / 30.0f).ok();
                if (g_commits.load() != commits_before) {
                    // g_allocations now counts only what happened since the commit began (Embree's
                    // commit, then the rest of this step, which the still phase proves is nothing).
                    const uint64_t in_commit = g_allocations.load();
                    embree_allocations += in_commit;
                    worst_commit = in_commit > worst_commit ? in_commit : worst_commit;
                    weft_allocations += before;
                } else {
                    weft_allocations += g_allocations.load();
                }
                g_allocations = 0;
            }
            commits += g_commits.load();
            if (phase == 0) {
                CHECK(g_commits.load() == 0);  // a still body needs no commit
                CHECK(weft_allocations == 0);
                CHECK(embree_allocations == 0);
            }
        }
        const WorldStats after = world_stats(world);
        MESSAGE(std::string(simd_path_name(path)), std::string(reference ? " reference pass" : pass == 1 ? " cached planes" : pass == 3 ? " skin constraints" : " own hierarchy"), ": ", commits, " commits while moving; heap allocations inside them ",
                embree_allocations, " (at most ", worst_commit, " per commit), outside them ", weft_allocations,
                "; Embree's memory monitor: ", after.embree_allocations - created.embree_allocations,
                " growths, ", after.embree_bytes - created.embree_bytes, " bytes held since creation");
        CHECK(failures == 0);
        CHECK(commits == (reference ? 200u : 0u));
        CHECK(weft_allocations == 0);
        CHECK(worst_commit <= 1);
        CHECK(after.embree_bytes == created.embree_bytes);  // a refit holds no new memory
        destroy_world(world);
    }
}

// The C interface (weft/weft_c.h) forwards to world.h and adds no allocation of its own: loading an
// asset file, creating the world, the frame loop (refusals included) and destroying it.
TEST_CASE("the C API allocates nothing: load, create, a frame loop with normals, destroy") {
    auto w = make_scene(SeedScene::sphere, SimdPath::automatic, false, 25);
    std::vector<std::byte> file_bytes;
    REQUIRE(assets::write_asset(w->asset(), &file_bytes).ok());
    const assets::AlignedBytes file(file_bytes.data(), file_bytes.size());
    WeftMemoryRequirements asset_need{}, world_need{};
    REQUIRE(weft_asset_memory_requirements(file.data(), file.size(), &asset_need).code == WEFT_OK);
    std::vector<std::max_align_t> asset_block(asset_need.bytes / sizeof(std::max_align_t) + 1);
    const uint32_t count = w->asset().particle_count;
    std::vector<WeftVec3> positions(count), normals(count);
    WeftAsset* asset = nullptr;
    WeftWorldDesc desc = weft_default_world_desc();
    uint32_t failures = 0;
    uint64_t allocations = 0;
    {
        CountingScope counting;
        failures += weft_load_asset(file.data(), file.size(), asset_block.data(), asset_need.bytes, &asset).code != WEFT_OK;
        failures += weft_reserve_cloth(&desc, asset).code != WEFT_OK;
        desc.max_colliders = 1;
        desc.normals = 1;
        failures += weft_world_memory_requirements(&desc, &world_need).code != WEFT_OK;
        allocations += counting.allocations();
    }
    REQUIRE(failures == 0);
    std::vector<unsigned char> block(world_need.bytes + world_need.alignment);
    void* memory = block.data() + (world_need.alignment - reinterpret_cast<uintptr_t>(block.data()) % world_need.alignment);
    {
        CountingScope counting;
        WeftWorld* world = nullptr;
        failures += weft_create_world(&desc, memory, world_need.bytes, &world).code != WEFT_OK;
        const WeftClothDesc cloth_desc = weft_default_cloth_desc(asset);
        WeftClothId cloth = 0;
        failures += weft_add_cloth(world, &cloth_desc, &cloth).code != WEFT_OK;
        WeftColliderDesc sphere = weft_default_collider_desc();
        sphere.inflation_m = 0.01f;
        sphere.friction = 0.5f;
        WeftColliderId collider = 0;
        failures += weft_add_collider(world, &sphere, &collider).code != WEFT_OK;
        for (uint32_t i = 0; i < 100; ++i) {
            sphere.p0.x = 0.1f * std::sin(float(i) * w->dt_s);
            failures += weft_set_collider(world, collider, &sphere).code != WEFT_OK;
            failures += weft_step(world, w->dt_s).code != WEFT_OK;
            failures += weft_read_positions(world, cloth, positions.data(), count).code != WEFT_OK;
            failures += weft_read_normals(world, cloth, normals.data(), count).code != WEFT_OK;
            failures += weft_step(world, -1.0f).code == WEFT_OK;  // refusals format their message in place
            failures += weft_read_positions(world, 7, positions.data(), count).code == WEFT_OK;
        }
        weft_destroy_world(world);
        failures += weft_step(world, w->dt_s).code == WEFT_OK;  // a dead handle
        allocations += counting.allocations();
    }
    CHECK(failures == 0);
    CHECK(allocations == 0);
}

TEST_CASE("self-collision allocates nothing: the sphere's cloth folding onto itself round the sphere") {
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        scenes::SceneOptions o;
        o.n = 24;
        o.simd = path;
        scenes::Scene scene = scenes::seed_scene(SeedScene::sphere, o);
        scene.cloths[0].desc.self_collision = true;
        scenes::SceneWorld w;
        REQUIRE(scenes::build_scene(scene, &w).empty());
        uint32_t failures = 0;
        uint64_t allocations = 0, contacts = 0;
        {
            CountingScope counting;
            for (uint32_t i = 0; i < 200; ++i) {
                failures += !step(w.world, w.dt_s).ok();
                contacts += world_stats(w.world).self_contacts;
            }
            allocations = counting.allocations();
        }
        CHECK(failures == 0);
        CHECK(contacts > 0);  // it did touch itself
        CHECK(allocations == 0);
    }
}

#ifdef WEFT_SAMPLE_ASSETS_DIR
// Layered garments (ClothDesc::worn_over): the overshirt worn over the tee on the walking mannequin;
// the body is posed outside the counted steps (the scene's animation is the game's).
TEST_CASE("stepping an overshirt worn over a tee on the walking mannequin allocates nothing") {
    scenes::Scene scene;
    REQUIRE(scenes::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/layers-walk.json", &scene).empty());
    scenes::SceneWorld w;
    REQUIRE(scenes::build_scene(scene, &w, {WEFT_SAMPLE_ASSETS_DIR}).empty());
    uint32_t failures = 0;
    uint64_t allocations = 0, contacts = 0;
    for (uint32_t f = 1; f <= 30; ++f) {
        REQUIRE(scenes::animate_body(w, float(f) * scene.dt_s).empty());
        CountingScope counting;
        failures += !step(w.world, scene.dt_s).ok();
        contacts += world_stats(w.world).layer_contacts;
        allocations += counting.allocations();
    }
    CHECK(failures == 0);
    CHECK(contacts > 0);  // the layers touched
    CHECK(allocations == 0);
}
#endif
