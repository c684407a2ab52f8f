// Helpers shared by Weft's tests: seed worlds, hand-made worlds, position snapshots.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "common/metrics.h"
#include "common/seed_scenes.h"
#include "weft/weft.h"
#include "weft/cook.h"
#include "weft/debug.h"

namespace weft::test {

// doctest prints these in failure messages.
inline const char* code_name(ErrorCode code) {
    switch (code) {
        case ErrorCode::ok: return "ok";
        case ErrorCode::invalid_argument: return "invalid_argument";
        case ErrorCode::non_finite: return "non_finite";
        case ErrorCode::out_of_range: return "out_of_range";
        case ErrorCode::capacity_exceeded: return "capacity_exceeded";
        case ErrorCode::memory_too_small: return "memory_too_small";
        case ErrorCode::unsupported: return "unsupported";
        case ErrorCode::corrupt_asset: return "corrupt_asset";
        case ErrorCode::stale_id: return "stale_id";
    }
    return "?";
}

// The SIMD paths this build and CPU can run (scalar always).
inline std::vector<SimdPath> available_paths() {
    std::vector<SimdPath> paths{SimdPath::scalar};
    if (simd_path_available(SimdPath::avx2)) paths.push_back(SimdPath::avx2);
    return paths;
}

// Builds `scene` into `w`, failing the test with build_scene's message.
inline void require_scene(const scenes::Scene& scene, scenes::SceneWorld* w, const std::vector<std::string>& asset_dirs = {}) {
    const std::string error = scenes::build_scene(scene, w, asset_dirs);
    INFO(error);
    REQUIRE(error.empty());
}

// The same into a SceneWorld on the heap (the world points into its arrays, so it must not move).
inline std::unique_ptr<scenes::SceneWorld> build_scene_world(const scenes::Scene& scene,
                                                             const std::vector<std::string>& asset_dirs = {}) {
    auto w = std::make_unique<scenes::SceneWorld>();
    require_scene(scene, w.get(), asset_dirs);
    return w;
}

inline scenes::SceneOptions scene_options(uint32_t n, SimdPath path = SimdPath::automatic) {
    scenes::SceneOptions o;
    o.n = n;
    o.simd = path;
    return o;
}

// Builds a seed world; fails the test (REQUIRE) if it cannot. Heap-allocated because SeedWorld
// owns arrays the world points into and must not move once built.
inline std::unique_ptr<scenes::SeedWorld> make_scene(scenes::SeedScene scene, const scenes::SceneOptions& o) {
    auto w = std::make_unique<scenes::SeedWorld>();
    const std::string error = scenes::make_seed_world(scene, o, w.get());
    INFO("scene ", scenes::scene_name(scene), " n ", o.n, ": ", error);
    REQUIRE(error.empty());
    REQUIRE(w->world != nullptr);
    return w;
}

// Distance between two points, m, in double.
inline double distance_m(Vec3 a, Vec3 b) {
    return std::hypot(double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z);
}

inline std::vector<Vec3> read_all(const World* world, ClothId cloth, uint32_t count) {
    std::vector<Vec3> out(count);
    const Result r = read_positions(world, cloth, out.data(), count);
    INFO(r.message);
    REQUIRE(r.ok());
    return out;
}

inline std::vector<Vec3> read_all(const scenes::SeedWorld& w) {
    return read_all(w.world, w.cloth, w.asset().particle_count);
}

inline ClothView view_of(const World* world, ClothId cloth) {
    ClothView v;
    const Result r = view_cloth(world, cloth, &v);
    INFO(r.message);
    REQUIRE(r.ok());
    return v;
}

inline ClothView view_of(const scenes::SeedWorld& w) { return view_of(w.world, w.cloth); }

inline bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

inline bool all_finite(const std::vector<Vec3>& p) {
    for (const Vec3& v : p)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
    return true;
}

inline double max_abs_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0.0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
        worst = std::fmax(worst, std::fabs(double(a[i].x) - b[i].x));
        worst = std::fmax(worst, std::fabs(double(a[i].y) - b[i].y));
        worst = std::fmax(worst, std::fabs(double(a[i].z) - b[i].z));
    }
    return worst;
}

inline void step_n(const scenes::SeedWorld& w, uint32_t steps) {
    for (uint32_t i = 0; i < steps; ++i) {
        const Result r = step(w.world, w.dt_s);
        INFO(r.message);
        REQUIRE(r.ok());
    }
}

// A world built by hand in a block the test owns.
struct OwnedWorld {
    std::unique_ptr<unsigned char[], void (*)(void*)> memory{nullptr, std::free};
    World* world = nullptr;
    size_t bytes = 0;
    OwnedWorld() = default;
    OwnedWorld(const OwnedWorld&) = delete;
    OwnedWorld& operator=(const OwnedWorld&) = delete;
    ~OwnedWorld() { destroy_world(world); }  // a world with bodies holds an Embree device
};

inline Result make_world(const WorldDesc& desc, OwnedWorld* out) {
    const MemoryRequirements need = world_memory_requirements(desc);
    REQUIRE(need.bytes > 0);
    REQUIRE(need.alignment > 0);
    out->bytes = need.bytes;
    const size_t rounded = (need.bytes + need.alignment - 1) / need.alignment * need.alignment;
    out->memory = {static_cast<unsigned char*>(std::aligned_alloc(need.alignment, rounded)), std::free};
    REQUIRE(out->memory != nullptr);
    return create_world(desc, out->memory.get(), need.bytes, &out->world);
}

// A world sized for exactly these assets (one cloth each), `colliders` colliders.
inline WorldDesc world_for(const std::vector<const ClothAsset*>& assets, uint32_t colliders = 0,
                           SimdPath path = SimdPath::automatic) {
    WorldDesc d;
    d.max_cloths = 0;
    for (const ClothAsset* a : assets) reserve_cloth(d, *a);
    d.max_colliders = colliders;
    d.simd = path;
    return d;
}

// Cooks a mesh; fails the test if it cannot.
// The triangles of a rows x cols grid of particles numbered row by row from `first`, two a quad
// (a, c, b), (b, c, d) with a the quad's first corner, c the one below it.
inline void grid_triangles(uint32_t rows, uint32_t cols, uint32_t first, std::vector<uint32_t>* triangles) {
    for (uint32_t i = 0; i + 1 < rows; ++i)
        for (uint32_t j = 0; j + 1 < cols; ++j) {
            const uint32_t a = first + i * cols + j, b = a + 1, c = a + cols, d = c + 1;
            triangles->insert(triangles->end(), {a, c, b, b, c, d});
        }
}

inline CookedCloth cook(const ClothMeshDesc& mesh, const CookOptions& options = {}) {
    CookedCloth cooked;
    const Result r = cook_cloth(mesh, options, &cooked);
    INFO(r.message);
    REQUIRE(r.ok());
    return cooked;
}

// A flat n x n grid cloth 1 m wide with uv (x, z) metres, cooked, with a render mesh: its own
// triangles cut into four `levels` times (the render output's allocation and C API tests).
inline CookedCloth uv_grid_with_render_mesh(uint32_t n, uint32_t levels = 1) {
    const scenes::GridMesh grid = scenes::make_grid(n, 1.0f, 1.0f, false, 1.0f);
    std::vector<float> uv;
    for (const Vec3& x : grid.positions) uv.insert(uv.end(), {x.x, x.z});
    ClothMeshDesc mesh = grid.desc();
    mesh.uv = uv.data();
    CookedCloth cooked = cook(mesh);
    RenderMeshSource fine;
    REQUIRE(subdivide_cloth_mesh(cooked.asset(), levels, &fine).ok());
    REQUIRE(bind_render_mesh(fine.desc(), &cooked).ok());
    return cooked;
}

// One cooked cloth in a world the test owns (the render output's tests).
struct OneClothWorld {
    CookedCloth cooked;
    OwnedWorld owned;
    ClothId cloth;
};

// Creates `out`'s world from `desc` (world_for the cooked asset, plus the features under test) with
// the cloth at its start pose and, with `sphere`, an off-centre ball under it that the cloth slides
// and folds on. `out.cooked` must be filled first.
inline void make_one_cloth_world(WorldDesc desc, bool sphere, OneClothWorld& out) {
    desc.max_colliders = std::max(desc.max_colliders, sphere ? 1u : 0u);
    REQUIRE(make_world(desc, &out.owned).ok());
    ClothDesc cloth;
    cloth.asset = &out.cooked.asset();
    REQUIRE(add_cloth(out.owned.world, cloth, &out.cloth).ok());
    if (sphere) {
        ColliderDesc c;
        c.shape = ColliderShape::sphere;
        c.p0 = {0.1f, 0.5f, 0.05f};
        c.radius_m = 0.3f;
        c.inflation_m = 0.01f;
        ColliderId id;
        REQUIRE(add_collider(out.owned.world, c, &id).ok());
    }
}

// Unconnected particles (no triangles, no springs), 10 g each, in caller order.
struct Points {
    std::vector<Vec3> positions;
    std::vector<float> masses;
    CookedCloth cooked;
    explicit Points(std::vector<Vec3> p) : positions(std::move(p)), masses(positions.size(), 0.01f) {
        ClothMeshDesc d;
        d.particle_count = uint32_t(positions.size());
        d.positions = positions.data();
        d.masses = masses.data();
        cooked = cook(d);
    }
};

}  // namespace weft::test

namespace weft {
// doctest stringifies enums as numbers; this overload (found by argument-dependent lookup) names them.
inline doctest::String toString(ErrorCode code) { return test::code_name(code); }
}  // namespace weft
