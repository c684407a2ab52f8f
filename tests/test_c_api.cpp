// The C interface (weft/weft_c.h): the seed drape and sphere driven through it step to the same bits
// as through world.h, and bad input (null pointers, small blocks, corrupt files, dead handles) gives
// an error code and a message, never a crash.
#include <cmath>

#include "common/asset_writer.h"
#include "support/test_support.h"
#include "weft/weft_c.h"

using namespace weft;
using namespace weft::test;
using scenes::SeedScene;

namespace {

constexpr uint32_t kGrid = 30;
constexpr uint32_t kSteps = 120;

#define REQUIRE_WEFT_OK(call)                                      \
    do {                                                           \
        const WeftResult r_ = (call);                              \
        INFO(#call, ": ", weft_error_name(r_.code), ": ", r_.message); \
        REQUIRE(r_.code == WEFT_OK);                               \
    } while (0)

// A refused call: the code expected, and a message saying why.
#define CHECK_WEFT_ERROR(call, expected)                           \
    do {                                                           \
        const WeftResult r_ = (call);                              \
        INFO(#call, ": ", weft_error_name(r_.code), ": ", r_.message); \
        CHECK(r_.code == (expected));                              \
        CHECK(std::strlen(r_.message) > 0);                        \
    } while (0)

using Block = std::unique_ptr<void, decltype(&std::free)>;
Block alloc_block(WeftMemoryRequirements need) {
    REQUIRE(need.bytes > 0);
    REQUIRE(need.alignment > 0);
    return {std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment),
            &std::free};
}

// An asset's file bytes (what weft-bake writes), 64-byte aligned.
assets::AlignedBytes file_of(const ClothAsset& asset) {
    std::vector<std::byte> bytes;
    const Result r = assets::write_asset(asset, &bytes);
    INFO(r.message);
    REQUIRE(r.ok());
    return {bytes.data(), bytes.size()};
}

// An asset file loaded, and a world with one cloth of it, all through the C API.
struct CWorld {
    assets::AlignedBytes file;
    Block asset_block{nullptr, &std::free}, world_block{nullptr, &std::free};
    WeftAsset* asset = nullptr;
    WeftWorld* world = nullptr;
    WeftClothId cloth = 0;
    WeftAssetInfo info{};
    ~CWorld() { weft_destroy_world(world); }
};

std::unique_ptr<CWorld> make_c_world(const ClothAsset& asset, WeftSimdPath simd, const std::vector<ColliderDesc>& colliders) {
    auto c = std::make_unique<CWorld>();
    c->file = file_of(asset);
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_asset_memory_requirements(c->file.data(), c->file.size(), &need));
    c->asset_block = alloc_block(need);
    REQUIRE_WEFT_OK(weft_load_asset(c->file.data(), c->file.size(), c->asset_block.get(), need.bytes, &c->asset));
    REQUIRE_WEFT_OK(weft_asset_info(c->asset, &c->info));
    WeftWorldDesc desc = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth(&desc, c->asset));
    desc.max_colliders = uint32_t(colliders.size());
    desc.normals = 1;
    desc.simd = simd;
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&desc, &need));
    c->world_block = alloc_block(need);
    REQUIRE_WEFT_OK(weft_create_world(&desc, c->world_block.get(), need.bytes, &c->world));
    const WeftClothDesc cloth = weft_default_cloth_desc(c->asset);
    REQUIRE_WEFT_OK(weft_add_cloth(c->world, &cloth, &c->cloth));
    for (const ColliderDesc& d : colliders) {
        WeftColliderDesc cd = weft_default_collider_desc();
        cd.shape = WeftColliderShape(d.shape);
        cd.p0 = {d.p0.x, d.p0.y, d.p0.z};
        cd.p1 = {d.p1.x, d.p1.y, d.p1.z};
        cd.radius_m = d.radius_m;
        cd.inflation_m = d.inflation_m;
        cd.friction = d.friction;
        WeftColliderId id = 0;
        REQUIRE_WEFT_OK(weft_add_collider(c->world, &cd, &id));
    }
    return c;
}

std::vector<Vec3> read_c(const CWorld& c) {
    std::vector<Vec3> p(c.info.particle_count);
    REQUIRE_WEFT_OK(weft_read_positions(c.world, c.cloth, reinterpret_cast<WeftVec3*>(p.data()), c.info.particle_count));
    return p;
}

void check_same_bits_as_cpp(SeedScene scene) {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        scenes::SceneOptions o = scene_options(kGrid, path);
        o.normals = true;
        auto cpp = make_scene(scene, o);
        auto c = make_c_world(cpp->asset(), WeftSimdPath(path), scenes::seed_scene(scene, o).colliders);
        REQUIRE(c->info.particle_count == cpp->asset().particle_count);
        for (uint32_t i = 1; i <= kSteps; ++i) {
            REQUIRE(step(cpp->world, cpp->dt_s).ok());
            if (i % 2 == 1) {
                REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
            } else {  // every other step stage by stage, as an engine's job system would run it
                REQUIRE_WEFT_OK(weft_begin_step(c->world, cpp->dt_s));
                for (WeftStepStage stage : {WEFT_STAGE_BODIES, WEFT_STAGE_CLOTHS})
                    REQUIRE_WEFT_OK(weft_run_step_items(c->world, stage, 0, weft_step_stage_items(c->world, stage)));
                REQUIRE_WEFT_OK(weft_end_step(c->world));
            }
            if (i % 20 == 0) {
                CAPTURE(i);
                REQUIRE(same_bits(read_all(*cpp), read_c(*c)));
            }
        }
        const std::vector<Vec3> p = read_c(*c);
        CHECK(all_finite(p));
        CHECK(!same_bits(p, cpp->mesh.positions));  // it moved
        // The step's normals, the same bits through both, unit length on this mesh.
        std::vector<Vec3> n_c(p.size()), n_cpp(p.size());
        REQUIRE_WEFT_OK(weft_read_normals(c->world, c->cloth, reinterpret_cast<WeftVec3*>(n_c.data()), uint32_t(p.size())));
        REQUIRE(read_normals(cpp->world, cpp->cloth, n_cpp.data(), uint32_t(p.size())).ok());
        CHECK(same_bits(n_c, n_cpp));
        for (const Vec3& n : n_c) REQUIRE(std::fabs(std::hypot(n.x, n.y, n.z) - 1.0f) < 1e-5f);
    }
}

}  // namespace

TEST_CASE("C API: the seed drape steps to the same bits as through world.h") { check_same_bits_as_cpp(SeedScene::drape); }
TEST_CASE("C API: the seed sphere (a collider) steps to the same bits as through world.h") {
    check_same_bits_as_cpp(SeedScene::sphere);
}

TEST_CASE("C API: normals of a flat square point along its winding's normal, area-weighted") {
    auto cpp = make_scene(SeedScene::drape, scene_options(4));  // flat in x-z at y = 2 m
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, {});
    const std::vector<Vec3> p = read_c(*c);
    std::vector<Vec3> n(p.size());
    REQUIRE_WEFT_OK(weft_read_normals(c->world, c->cloth, reinterpret_cast<WeftVec3*>(n.data()), uint32_t(p.size())));
    std::vector<uint32_t> triangles(3 * size_t(c->info.triangle_count));
    REQUIRE_WEFT_OK(weft_asset_triangles(c->asset, triangles.data(), uint32_t(triangles.size())));
    REQUIRE(triangles.size() == cpp->mesh.triangles.size());
    for (uint32_t v : triangles) REQUIRE(v < c->info.particle_count);  // caller order
    std::vector<Vec3> start(p.size());  // the start pose: where the cloth is before its first step
    REQUIRE_WEFT_OK(weft_asset_start_positions(c->asset, reinterpret_cast<WeftVec3*>(start.data()), uint32_t(start.size())));
    CHECK(same_bits(start, p));
    for (const Vec3& v : n) {
        CHECK(std::fabs(v.x) < 1e-6f);
        CHECK(std::fabs(std::fabs(v.y) - 1.0f) < 1e-6f);
        CHECK(v.y * n[0].y > 0.0f);  // one side for all
        CHECK(std::fabs(v.z) < 1e-6f);
    }
}

TEST_CASE("C API: tangents and a render mesh read the same bits as through world.h") {
    const CookedCloth cooked = uv_grid_with_render_mesh(12);
    const ClothAsset& a = cooked.asset();

    // C: the file loaded, a world with tangents and render meshes.
    const assets::AlignedBytes file = file_of(a);
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_asset_memory_requirements(file.data(), file.size(), &need));
    Block asset_block = alloc_block(need);
    WeftAsset* asset = nullptr;
    REQUIRE_WEFT_OK(weft_load_asset(file.data(), file.size(), asset_block.get(), need.bytes, &asset));
    WeftAssetInfo info{};
    REQUIRE_WEFT_OK(weft_asset_info(asset, &info));
    CHECK(info.render_vertex_count == a.render.vertex_count);
    CHECK(info.render_triangle_count == a.render.triangle_count);
    std::vector<uint32_t> indices(3 * size_t(info.render_triangle_count));
    std::vector<float> render_uv(2 * size_t(info.render_vertex_count));
    REQUIRE_WEFT_OK(weft_asset_render_mesh(asset, indices.data(), uint32_t(indices.size()), render_uv.data(), uint32_t(render_uv.size())));
    CHECK(std::memcmp(indices.data(), a.render.triangles, indices.size() * sizeof(uint32_t)) == 0);
    CHECK(std::memcmp(render_uv.data(), a.render.uv, render_uv.size() * sizeof(float)) == 0);
    CHECK_WEFT_ERROR(weft_asset_render_mesh(asset, indices.data(), 3, nullptr, 0), WEFT_OUT_OF_RANGE);
    WeftWorldDesc desc = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth(&desc, asset));
    desc.tangents = 1;
    desc.render_meshes = 1;
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&desc, &need));
    Block world_block = alloc_block(need);
    WeftWorld* world = nullptr;
    REQUIRE_WEFT_OK(weft_create_world(&desc, world_block.get(), need.bytes, &world));
    const WeftClothDesc cloth_desc = weft_default_cloth_desc(asset);
    WeftClothId cloth = 0;
    REQUIRE_WEFT_OK(weft_add_cloth(world, &cloth_desc, &cloth));

    // C++: the cooked asset, the same features.
    WorldDesc cpp_desc;
    cpp_desc.max_cloths = 0;
    reserve_cloth(cpp_desc, a);
    cpp_desc.tangents = cpp_desc.render_meshes = true;
    OwnedWorld cpp;
    REQUIRE(make_world(cpp_desc, &cpp).ok());
    ClothDesc cd;
    cd.asset = &a;
    ClothId id;
    REQUIRE(add_cloth(cpp.world, cd, &id).ok());
    for (int frame = 0; frame < 30; ++frame) {
        REQUIRE_WEFT_OK(weft_step(world, 1.0f / 60.0f));
        REQUIRE(step(cpp.world, 1.0f / 60.0f).ok());
    }
    std::vector<WeftVec4> t_c(info.particle_count);
    std::vector<Vec4> t_cpp(info.particle_count);
    REQUIRE_WEFT_OK(weft_read_tangents(world, cloth, t_c.data(), info.particle_count));
    REQUIRE(read_tangents(cpp.world, id, t_cpp.data(), info.particle_count).ok());
    CHECK(std::memcmp(t_c.data(), t_cpp.data(), t_c.size() * sizeof(Vec4)) == 0);
    std::vector<Vec3> x_c(info.render_vertex_count), n_c(x_c.size()), x_cpp(x_c.size()), n_cpp(x_c.size());
    REQUIRE_WEFT_OK(weft_read_render_mesh(world, cloth, reinterpret_cast<WeftVec3*>(x_c.data()), reinterpret_cast<WeftVec3*>(n_c.data()),
                                          info.render_vertex_count));
    REQUIRE(read_render_mesh(cpp.world, id, x_cpp.data(), n_cpp.data(), info.render_vertex_count).ok());
    CHECK(same_bits(x_c, x_cpp));
    CHECK(same_bits(n_c, n_cpp));
    CHECK_WEFT_ERROR(weft_read_render_mesh(world, cloth, reinterpret_cast<WeftVec3*>(x_c.data()), nullptr, 1), WEFT_OUT_OF_RANGE);
    weft_destroy_world(world);
}

TEST_CASE("C API: null pointers, small blocks and bad descriptions are refused with a message") {
    auto cpp = make_scene(SeedScene::drape, scene_options(8));
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, {});
    WeftMemoryRequirements need{};
    CHECK_WEFT_ERROR(weft_asset_memory_requirements(nullptr, 100, &need), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_asset_memory_requirements(c->file.data(), c->file.size(), nullptr), WEFT_INVALID_ARGUMENT);
    REQUIRE_WEFT_OK(weft_asset_memory_requirements(c->file.data(), c->file.size(), &need));
    Block block = alloc_block(need);
    WeftAsset* asset = nullptr;
    CHECK_WEFT_ERROR(weft_load_asset(c->file.data(), c->file.size(), block.get(), need.bytes - 4, &asset),
                     WEFT_MEMORY_TOO_SMALL);
    CHECK_WEFT_ERROR(weft_load_asset(c->file.data(), c->file.size(), block.get(), 8, &asset), WEFT_MEMORY_TOO_SMALL);
    CHECK_WEFT_ERROR(weft_load_asset(c->file.data(), c->file.size(), nullptr, need.bytes, &asset), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_load_asset(c->file.data(), c->file.size(), block.get(), need.bytes, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK(asset == nullptr);
    WeftAssetInfo info{};
    CHECK_WEFT_ERROR(weft_asset_info(nullptr, &info), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_asset_info(c->asset, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_asset_triangles(c->asset, nullptr, 3), WEFT_INVALID_ARGUMENT);
    uint32_t three[3];
    CHECK_WEFT_ERROR(weft_asset_triangles(c->asset, three, 3), WEFT_OUT_OF_RANGE);
    WeftVec3 one[1];
    CHECK_WEFT_ERROR(weft_asset_start_positions(nullptr, one, 1), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_asset_start_positions(c->asset, nullptr, c->info.particle_count), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_asset_start_positions(c->asset, one, 1), WEFT_OUT_OF_RANGE);

    // The world: a description without a cloth, null pointers, a block one byte short or misaligned.
    WeftWorldDesc desc = weft_default_world_desc();
    CHECK_WEFT_ERROR(weft_world_memory_requirements(&desc, &need), WEFT_INVALID_ARGUMENT);  // max_cloths 0
    CHECK_WEFT_ERROR(weft_world_memory_requirements(nullptr, &need), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_reserve_cloth(&desc, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_reserve_cloth(nullptr, c->asset), WEFT_INVALID_ARGUMENT);
    REQUIRE_WEFT_OK(weft_reserve_cloth(&desc, c->asset));
    desc.simd = WeftSimdPath(7);
    CHECK_WEFT_ERROR(weft_world_memory_requirements(&desc, &need), WEFT_UNSUPPORTED);
    desc.simd = WeftSimdPath(256);
    CHECK_WEFT_ERROR(weft_world_memory_requirements(&desc, &need), WEFT_UNSUPPORTED);
    desc.simd = WEFT_SIMD_AUTOMATIC;
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&desc, &need));
    Block world_block = alloc_block({need.bytes + need.alignment, need.alignment});
    WeftWorld* world = nullptr;
    CHECK_WEFT_ERROR(weft_create_world(&desc, world_block.get(), need.bytes - 1, &world), WEFT_MEMORY_TOO_SMALL);
    CHECK_WEFT_ERROR(weft_create_world(&desc, world_block.get(), 16, &world), WEFT_MEMORY_TOO_SMALL);
    CHECK_WEFT_ERROR(weft_create_world(&desc, static_cast<char*>(world_block.get()) + 1, need.bytes, &world),
                     WEFT_MEMORY_TOO_SMALL);
    CHECK_WEFT_ERROR(weft_create_world(nullptr, world_block.get(), need.bytes, &world), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_create_world(&desc, world_block.get(), need.bytes, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK(world == nullptr);

    // Calls on a live world with bad arguments.
    WeftClothDesc cloth = weft_default_cloth_desc(c->asset);
    WeftClothId cloth_id = 0;
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, nullptr, &cloth_id), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &cloth, &cloth_id), WEFT_CAPACITY_EXCEEDED);  // room for one
    cloth.asset = nullptr;
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &cloth, &cloth_id), WEFT_INVALID_ARGUMENT);
    WeftColliderDesc collider = weft_default_collider_desc();
    WeftColliderId collider_id = 0;
    CHECK_WEFT_ERROR(weft_add_collider(c->world, &collider, &collider_id), WEFT_CAPACITY_EXCEEDED);
    CHECK_WEFT_ERROR(weft_add_collider(c->world, nullptr, &collider_id), WEFT_INVALID_ARGUMENT);
    collider.shape = WeftColliderShape(256);  // any value a C caller may pass names nothing here
    CHECK_WEFT_ERROR(weft_add_collider(c->world, &collider, &collider_id), WEFT_INVALID_ARGUMENT);
    WeftBodyDesc body = weft_default_body_desc();
    WeftBodyId body_id = 0;
    CHECK(weft_add_body(c->world, &body, &body_id).code != WEFT_OK);  // no mesh, no room
    CHECK_WEFT_ERROR(weft_add_body(c->world, nullptr, &body_id), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_wind(c->world, {1.0f, 0.0f, 0.0f}), WEFT_INVALID_ARGUMENT);  // no wind feature
    CHECK_WEFT_ERROR(weft_set_gravity(c->world, {0.0f, NAN, 0.0f}), WEFT_NON_FINITE);
    CHECK(weft_step(c->world, 0.0f).code != WEFT_OK);
    CHECK(weft_step(c->world, NAN).code != WEFT_OK);
    std::vector<WeftVec3> positions(c->info.particle_count), normals(c->info.particle_count);
    CHECK_WEFT_ERROR(weft_read_positions(c->world, c->cloth, nullptr, c->info.particle_count), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_read_positions(c->world, c->cloth, positions.data(), 1), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_read_normals(c->world, c->cloth, nullptr, c->info.particle_count), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_read_normals(c->world, c->cloth, normals.data(), 2), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_read_normals(c->world, 9, normals.data(), c->info.particle_count), WEFT_OUT_OF_RANGE);
    CHECK(std::strcmp(weft_error_name(WEFT_CORRUPT_ASSET), "corrupt_asset") == 0);
    CHECK(std::strcmp(weft_error_name(WeftErrorCode(99)), "unknown") == 0);

    // Every refusal left the world as it was: it still steps to the C++ API's bits.
    for (uint32_t i = 0; i < 10; ++i) {
        REQUIRE(step(cpp->world, cpp->dt_s).ok());
        REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
    }
    CHECK(same_bits(read_all(*cpp), read_c(*c)));
}

TEST_CASE("C API: corrupt, truncated and misaligned asset files are refused, the handle left alone") {
    auto cpp = make_scene(SeedScene::drape, scene_options(8));
    const assets::AlignedBytes good = file_of(cpp->asset());
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_asset_memory_requirements(good.data(), good.size(), &need));
    Block block = alloc_block(need);
    WeftAsset* asset = nullptr;

    assets::AlignedBytes flipped(good.data(), good.size());
    flipped.data()[good.size() / 2] ^= std::byte{0x5a};
    CHECK_WEFT_ERROR(weft_asset_memory_requirements(flipped.data(), flipped.size(), &need), WEFT_CORRUPT_ASSET);
    CHECK_WEFT_ERROR(weft_load_asset(flipped.data(), flipped.size(), block.get(), need.bytes, &asset), WEFT_CORRUPT_ASSET);
    CHECK_WEFT_ERROR(weft_load_asset(good.data(), good.size() / 2, block.get(), need.bytes, &asset), WEFT_CORRUPT_ASSET);
    CHECK_WEFT_ERROR(weft_load_asset(good.data(), 7, block.get(), need.bytes, &asset), WEFT_CORRUPT_ASSET);
    std::vector<std::byte> shifted_bytes(good.size() + 64);
    std::byte* shifted = shifted_bytes.data() + (64 - reinterpret_cast<uintptr_t>(shifted_bytes.data()) % 64) % 64 + 4;
    std::memcpy(shifted, good.data(), good.size());
    CHECK(weft_load_asset(shifted, good.size(), block.get(), need.bytes, &asset).code != WEFT_OK);
    CHECK(asset == nullptr);
    // A block that never held a loaded asset is not one.
    std::memset(block.get(), 0, need.bytes);
    WeftAssetInfo info{};
    CHECK_WEFT_ERROR(weft_asset_info(static_cast<const WeftAsset*>(block.get()), &info), WEFT_INVALID_ARGUMENT);
    WeftWorldDesc desc = weft_default_world_desc();
    CHECK_WEFT_ERROR(weft_reserve_cloth(&desc, static_cast<const WeftAsset*>(block.get())), WEFT_INVALID_ARGUMENT);
    // The good file still loads into the same block.
    REQUIRE_WEFT_OK(weft_load_asset(good.data(), good.size(), block.get(), need.bytes, &asset));
    REQUIRE_WEFT_OK(weft_asset_info(asset, &info));
    CHECK(info.particle_count == cpp->asset().particle_count);
}

TEST_CASE("C API: stale ids and a destroyed world give an error, not a crash") {
    auto cpp = make_scene(SeedScene::sphere, scene_options(8));
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, scenes::seed_scene(SeedScene::sphere, scene_options(8)).colliders);
    std::vector<WeftVec3> positions(c->info.particle_count);
    const WeftColliderDesc collider = weft_default_collider_desc();
    WeftBodyDesc body = weft_default_body_desc();
    CHECK_WEFT_ERROR(weft_read_positions(c->world, 1, positions.data(), c->info.particle_count), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_read_positions(c->world, 0xFFFFFFFFu, positions.data(), c->info.particle_count), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_set_collider(c->world, 1, &collider), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_set_collider(c->world, 0, nullptr), WEFT_INVALID_ARGUMENT);
    REQUIRE_WEFT_OK(weft_set_collider(c->world, 0, &collider));
    CHECK(weft_set_body_vertices(c->world, 0, body.positions, 3).code != WEFT_OK);  // no body 0
    CHECK(weft_attach_cloth_to_body(c->world, 0, 0).code != WEFT_OK);
    CHECK_WEFT_ERROR(weft_set_cloth_body(c->world, 0, 0), WEFT_OUT_OF_RANGE);  // no body 0
    CHECK_WEFT_ERROR(weft_run_step_items(c->world, WEFT_STAGE_CLOTHS, 0, 1), WEFT_INVALID_ARGUMENT);  // no step open
    CHECK_WEFT_ERROR(weft_end_step(c->world), WEFT_INVALID_ARGUMENT);
    CHECK(weft_step_stage_items(c->world, WEFT_STAGE_CLOTHS) == 1);
    CHECK(weft_step_stage_items(nullptr, WEFT_STAGE_CLOTHS) == 0);

    // Removed: the ids go stale; the next add takes the place under a new generation.
    REQUIRE_WEFT_OK(weft_remove_collider(c->world, 0));
    CHECK_WEFT_ERROR(weft_set_collider(c->world, 0, &collider), WEFT_STALE_ID);
    REQUIRE_WEFT_OK(weft_remove_cloth(c->world, 0));
    CHECK_WEFT_ERROR(weft_read_positions(c->world, 0, positions.data(), c->info.particle_count), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_remove_cloth(c->world, 0), WEFT_STALE_ID);
    CHECK(std::string(weft_error_name(WEFT_STALE_ID)) == "stale_id");
    const WeftClothDesc again = weft_default_cloth_desc(c->asset);
    WeftClothId again_id = 0;
    REQUIRE_WEFT_OK(weft_add_cloth(c->world, &again, &again_id));
    CHECK((again_id & 0xFFFFu) == 0);
    CHECK(again_id != 0);
    REQUIRE_WEFT_OK(weft_read_positions(c->world, again_id, positions.data(), c->info.particle_count));
    REQUIRE_WEFT_OK(weft_step(c->world, 0.01f));
    CHECK_WEFT_ERROR(weft_remove_body(c->world, 0), WEFT_OUT_OF_RANGE);  // the world has no bodies

    // Destroyed: every call refuses the handle; destroying again does nothing.
    WeftWorld* world = c->world;
    weft_destroy_world(world);
    c->world = nullptr;
    CHECK_WEFT_ERROR(weft_step(world, 0.01f), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_begin_step(world, 0.01f), WEFT_INVALID_ARGUMENT);
    CHECK(weft_step_stage_items(world, WEFT_STAGE_CLOTHS) == 0);
    CHECK_WEFT_ERROR(weft_read_positions(world, 0, positions.data(), c->info.particle_count), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_collider(world, 0, &collider), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_wind(world, {0.0f, 0.0f, 0.0f}), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_gravity(world, {0.0f, -9.81f, 0.0f}), WEFT_INVALID_ARGUMENT);
    const WeftClothDesc cloth = weft_default_cloth_desc(c->asset);
    WeftClothId cloth_id = 0;
    CHECK_WEFT_ERROR(weft_add_cloth(world, &cloth, &cloth_id), WEFT_INVALID_ARGUMENT);
    WeftColliderId collider_id = 0;
    CHECK_WEFT_ERROR(weft_add_collider(world, &collider, &collider_id), WEFT_INVALID_ARGUMENT);
    WeftBodyId body_id = 0;
    CHECK_WEFT_ERROR(weft_add_body(world, &body, &body_id), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_body_vertices(world, 0, nullptr, 0), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_attach_cloth_to_body(world, 0, 0), WEFT_INVALID_ARGUMENT);
    weft_destroy_world(world);
    weft_destroy_world(nullptr);
    CHECK_WEFT_ERROR(weft_step(nullptr, 0.01f), WEFT_INVALID_ARGUMENT);
}

TEST_CASE("C API: a cloth with a sleep speed falls asleep on the sphere, wakes on weft_wake_cloth, refuses bad input") {
    const scenes::SceneOptions o = scene_options(8);
    auto cpp = make_scene(SeedScene::sphere, o);
    std::vector<ColliderDesc> colliders = scenes::seed_scene(SeedScene::sphere, o).colliders;
    colliders[0].friction = 1.0f;  // at rest in bounds (test_sleep.cpp)
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, colliders);
    WeftClothDesc desc = weft_default_cloth_desc(c->asset);
    CHECK(desc.sleep_speed_m_s == 0.0f);  // never sleeps by default
    desc.sleep_speed_m_s = -1.0f;
    WeftClothId sleeper = 0;
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &desc, &sleeper), WEFT_OUT_OF_RANGE);
    REQUIRE_WEFT_OK(weft_remove_cloth(c->world, c->cloth));  // room for the sleeper
    desc.sleep_speed_m_s = 0.02f;
    REQUIRE_WEFT_OK(weft_add_cloth(c->world, &desc, &sleeper));
    int asleep = 1;
    REQUIRE_WEFT_OK(weft_cloth_is_sleeping(c->world, sleeper, &asleep));
    CHECK(asleep == 0);
    for (uint32_t frame = 0; frame < 600 && asleep == 0; ++frame) {
        REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
        REQUIRE_WEFT_OK(weft_cloth_is_sleeping(c->world, sleeper, &asleep));
    }
    CHECK(asleep == 1);
    REQUIRE_WEFT_OK(weft_wake_cloth(c->world, sleeper));
    REQUIRE_WEFT_OK(weft_cloth_is_sleeping(c->world, sleeper, &asleep));
    CHECK(asleep == 0);
    CHECK_WEFT_ERROR(weft_cloth_is_sleeping(c->world, sleeper, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_cloth_is_sleeping(c->world, c->cloth, &asleep), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_wake_cloth(c->world, c->cloth), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_wake_cloth(nullptr, sleeper), WEFT_INVALID_ARGUMENT);
}

TEST_CASE("C API: a cloth with a recovery policy is reported and recovered after a forced blow-up, and bad policies are refused") {
    const scenes::SceneOptions o = scene_options(8);
    auto cpp = make_scene(SeedScene::sphere, o);
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, scenes::seed_scene(SeedScene::sphere, o).colliders);
    WeftClothDesc desc = weft_default_cloth_desc(c->asset);
    CHECK(desc.recovery == WEFT_RECOVER_NONE);  // report only by default
    REQUIRE_WEFT_OK(weft_remove_cloth(c->world, c->cloth));  // room for the recovering cloth
    WeftClothId cloth = 0;
    desc.recovery = WeftRecoveryPolicy(9);
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &desc, &cloth), WEFT_INVALID_ARGUMENT);
    desc.recovery = WEFT_RECOVER_LAST_GOOD;  // the world has no room for its copy
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &desc, &cloth), WEFT_CAPACITY_EXCEEDED);
    desc.recovery = WEFT_RECOVER_REST_POSE;
    REQUIRE_WEFT_OK(weft_add_cloth(c->world, &desc, &cloth));
    for (uint32_t frame = 0; frame < 30; ++frame) REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
    WeftClothHealth health{};
    REQUIRE_WEFT_OK(weft_cloth_health(c->world, cloth, &health));
    CHECK(health.problems == 0);
    // The blow-up: gravity of 1 000 m/s^2 sideways (a whole cloth at tens of m/s in a frame or two).
    REQUIRE_WEFT_OK(weft_set_gravity(c->world, {1000.0f, 0.0f, 0.0f}));
    uint32_t frames = 0;
    for (; frames < 3 && health.recovered == 0; ++frames) {
        REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
        REQUIRE_WEFT_OK(weft_cloth_health(c->world, cloth, &health));
    }
    CHECK(health.recovered == 1);
    CHECK((health.problems & WEFT_HEALTH_ENERGY_SPIKE) != 0);
    CHECK(health.recoveries == 1);
    WeftWorldHealth world_health{};
    REQUIRE_WEFT_OK(weft_world_health(c->world, &world_health));
    CHECK(world_health.unhealthy_cloths == 1);
    CHECK(world_health.recovered_cloths == 1);
    CHECK(world_health.total_recoveries == 1);
    REQUIRE_WEFT_OK(weft_set_gravity(c->world, {0.0f, -9.81f, 0.0f}));
    REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
    REQUIRE_WEFT_OK(weft_cloth_health(c->world, cloth, &health));
    CHECK(health.problems == 0);
    CHECK(health.recovered == 0);
    CHECK_WEFT_ERROR(weft_cloth_health(c->world, cloth, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_cloth_health(c->world, c->cloth, &health), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_world_health(nullptr, &world_health), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_world_health(c->world, nullptr), WEFT_INVALID_ARGUMENT);

    // weft_reserve_cloth_recovering sizes a world for the last good copy.
    WeftWorldDesc wd = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth_recovering(&wd, c->asset, WEFT_RECOVER_LAST_GOOD));
    CHECK(wd.max_last_good_particles > 0);
    CHECK_WEFT_ERROR(weft_reserve_cloth_recovering(&wd, c->asset, WeftRecoveryPolicy(9)), WEFT_INVALID_ARGUMENT);
}

TEST_CASE("C API: a frame budget cuts a cloth's sweeps to fit, reports what it did, refuses bad input") {
    const scenes::SceneOptions o = scene_options(8);
    auto cpp = make_scene(SeedScene::sphere, o);
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, scenes::seed_scene(SeedScene::sphere, o).colliders);
    WeftClothDesc desc = weft_default_cloth_desc(c->asset);
    desc.sweeps = 10;  // held by the sphere: 3 substeps x 3 iterations, cut to as few as 2 x 1
    REQUIRE_WEFT_OK(weft_remove_cloth(c->world, c->cloth));
    WeftClothId cloth = 0;
    REQUIRE_WEFT_OK(weft_add_cloth(c->world, &desc, &cloth));
    REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));  // off by default
    WeftFrameBudgetStats own{};
    REQUIRE_WEFT_OK(weft_frame_budget_stats(c->world, &own));
    CHECK(own.estimate_us > 0.0);
    CHECK(own.cloths_cut == 0);
    CHECK(own.sweeps == 9);
    const float budget_us = float(0.5 * own.estimate_us);
    REQUIRE_WEFT_OK(weft_set_frame_budget_us(c->world, budget_us));
    REQUIRE_WEFT_OK(weft_set_cloth_priority(c->world, cloth, 1.0f));
    REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
    WeftFrameBudgetStats cut{};
    REQUIRE_WEFT_OK(weft_frame_budget_stats(c->world, &cut));
    CHECK(cut.cloths_cut == 1);
    CHECK(cut.sweeps < own.sweeps);
    CHECK(cut.sweeps >= 2);
    CHECK(cut.estimate_us <= double(budget_us));

    CHECK_WEFT_ERROR(weft_set_frame_budget_us(c->world, -5.0f), WEFT_OUT_OF_RANGE);
    CHECK_WEFT_ERROR(weft_set_frame_budget_us(c->world, std::nanf("")), WEFT_NON_FINITE);
    CHECK_WEFT_ERROR(weft_set_frame_budget_us(nullptr, 1.0f), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_set_cloth_priority(c->world, cloth, std::nanf("")), WEFT_NON_FINITE);
    CHECK_WEFT_ERROR(weft_set_cloth_priority(c->world, c->cloth, 1.0f), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_frame_budget_stats(c->world, nullptr), WEFT_INVALID_ARGUMENT);
    REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));  // the refusals changed nothing: still cut
    REQUIRE_WEFT_OK(weft_frame_budget_stats(c->world, &cut));
    CHECK(cut.cloths_cut == 1);
    // The cost model is the game's to set: twice the cost per lane and per particle, twice the estimate.
    WeftWorldDesc dear = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth(&dear, c->asset));
    dear.budget_ns_per_lane *= 2.0f, dear.budget_ns_per_particle *= 2.0f;
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&dear, &need));
    Block block = alloc_block(need);
    WeftWorld* world = nullptr;
    REQUIRE_WEFT_OK(weft_create_world(&dear, block.get(), need.bytes, &world));
    REQUIRE_WEFT_OK(weft_add_cloth(world, &desc, &cloth));
    REQUIRE_WEFT_OK(weft_step(world, cpp->dt_s));
    WeftFrameBudgetStats doubled{};
    REQUIRE_WEFT_OK(weft_frame_budget_stats(world, &doubled));
    CHECK(doubled.estimate_us == doctest::Approx(2.0 * own.estimate_us).epsilon(1e-6));
    weft_destroy_world(world);
    dear.budget_ns_per_lane = -1.0f;
    CHECK_WEFT_ERROR(weft_create_world(&dear, block.get(), need.bytes, &world), WEFT_OUT_OF_RANGE);

    REQUIRE_WEFT_OK(weft_set_frame_budget_us(c->world, 0.0f));  // off: its own sweeps again
    REQUIRE_WEFT_OK(weft_step(c->world, cpp->dt_s));
    REQUIRE_WEFT_OK(weft_frame_budget_stats(c->world, &cut));
    CHECK(cut.cloths_cut == 0);
    CHECK(cut.sweeps == own.sweeps);
}

TEST_CASE("C API: self-collision is reserved by weft_reserve_cloth_desc, chosen at weft_add_cloth, and checked") {
    const scenes::SceneOptions o = scene_options(16);
    auto cpp = make_scene(SeedScene::sphere, o);
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, scenes::seed_scene(SeedScene::sphere, o).colliders);
    WeftClothDesc desc = weft_default_cloth_desc(c->asset);
    CHECK(desc.self_collision == 0);  // off by default, with world.h's thickness and friction
    CHECK(desc.self_thickness_m == ClothDesc{}.self_thickness_m);
    desc.self_collision = 1;
    WeftClothId cloth = 0;
    CHECK_WEFT_ERROR(weft_add_cloth(c->world, &desc, &cloth), WEFT_CAPACITY_EXCEEDED);  // no room reserved
    WeftWorldDesc wd = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth_desc(&wd, &desc));
    CHECK(wd.max_self_collision_particles == cpp->asset().slot_count);
    CHECK(wd.max_self_collision_triangles == cpp->asset().triangle_count);
    CHECK_WEFT_ERROR(weft_reserve_cloth_desc(&wd, nullptr), WEFT_INVALID_ARGUMENT);
    wd.max_colliders = 1;
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&wd, &need));
    Block block = alloc_block(need);
    WeftWorld* world = nullptr;
    REQUIRE_WEFT_OK(weft_create_world(&wd, block.get(), need.bytes, &world));
    desc.self_thickness_m = std::nanf("");
    CHECK_WEFT_ERROR(weft_add_cloth(world, &desc, &cloth), WEFT_NON_FINITE);
    desc.self_thickness_m = 0.004f;
    REQUIRE_WEFT_OK(weft_add_cloth(world, &desc, &cloth));
    const ColliderDesc s = scenes::seed_scene(SeedScene::sphere, o).colliders[0];
    WeftColliderDesc sphere = weft_default_collider_desc();
    sphere.p0 = {s.p0.x, s.p0.y, s.p0.z};
    sphere.radius_m = s.radius_m;
    sphere.inflation_m = s.inflation_m;
    WeftColliderId collider = 0;
    REQUIRE_WEFT_OK(weft_add_collider(world, &sphere, &collider));
    for (int f = 0; f < 100; ++f) REQUIRE_WEFT_OK(weft_step(world, cpp->dt_s));
    std::vector<WeftVec3> x(c->info.particle_count);
    REQUIRE_WEFT_OK(weft_read_positions(world, cloth, x.data(), uint32_t(x.size())));
    for (const WeftVec3& p : x) CHECK((std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)));
    weft_destroy_world(world);
}

// Layered garments through C: a sheet worn over another (the seed sphere's sheet, 2 mm above it, so
// within the layer thickness as they fall)
// steps to the bits world.h gives, its layer stage run item by item; the room is reserve_layer's.
TEST_CASE("C API: a cloth worn over another steps to the same bits as through world.h, and is checked") {
    const scenes::SceneOptions o = scene_options(16);
    auto cpp = make_scene(SeedScene::sphere, o);
    auto c = make_c_world(cpp->asset(), WEFT_SIMD_AUTOMATIC, {});
    const ClothAsset& asset = cpp->asset();
    WeftWorldDesc wd = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth(&wd, c->asset));
    REQUIRE_WEFT_OK(weft_reserve_cloth(&wd, c->asset));
    REQUIRE_WEFT_OK(weft_reserve_layer(&wd, c->asset, c->asset));
    CHECK(wd.max_layer_particles == 2 * asset.slot_count);
    CHECK(wd.max_layer_triangles == asset.triangle_count);
    CHECK_WEFT_ERROR(weft_reserve_layer(&wd, nullptr, c->asset), WEFT_INVALID_ARGUMENT);
    WeftMemoryRequirements need{};
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&wd, &need));
    Block block = alloc_block(need);
    WeftWorld* world = nullptr;
    REQUIRE_WEFT_OK(weft_create_world(&wd, block.get(), need.bytes, &world));
    WeftClothDesc inner = weft_default_cloth_desc(c->asset);
    CHECK(inner.worn_over_count == 0);
    CHECK(inner.layer_thickness_m == ClothDesc{}.layer_thickness_m);
    WeftClothId inner_id = 0, outer_id = 0;
    REQUIRE_WEFT_OK(weft_add_cloth(world, &inner, &inner_id));
    WeftClothDesc outer = inner;
    outer.translation_m = {0.0f, 0.002f, 0.0f};
    outer.worn_over[0] = inner_id + (1u << 16);  // another generation: stale
    outer.worn_over_count = 1;
    CHECK_WEFT_ERROR(weft_add_cloth(world, &outer, &outer_id), WEFT_STALE_ID);
    outer.worn_over[0] = inner_id;
    REQUIRE_WEFT_OK(weft_add_cloth(world, &outer, &outer_id));
    CHECK(weft_step_stage_items(world, WEFT_STAGE_SECOND_LAYER) == 2);
    CHECK_WEFT_ERROR(weft_remove_cloth(world, inner_id), WEFT_INVALID_ARGUMENT);  // worn under outer

    // The same through world.h.
    WorldDesc cd;
    cd.max_cloths = 0;
    reserve_cloth(cd, asset);
    reserve_cloth(cd, asset);
    reserve_layer(cd, asset, asset);
    test::OwnedWorld w;
    REQUIRE(test::make_world(cd, &w).ok());
    ClothDesc ci;
    ci.asset = &asset;
    ClothId ii{}, oi{};
    REQUIRE(add_cloth(w.world, ci, &ii).ok());
    ClothDesc co = ci;
    co.translation_m = {0.0f, 0.002f, 0.0f};
    co.worn_over[0] = ii;
    co.worn_over_count = 1;
    REQUIRE(add_cloth(w.world, co, &oi).ok());
    uint64_t contacts = 0;
    for (int f = 0; f < 30; ++f) {
        REQUIRE(step(w.world, cpp->dt_s).ok());
        contacts += world_stats(w.world).layer_contacts;
        REQUIRE_WEFT_OK(weft_begin_step(world, cpp->dt_s));
        for (WeftStepStage stage : {WEFT_STAGE_BODIES, WEFT_STAGE_CLOTHS, WEFT_STAGE_SECOND_LAYER, WEFT_STAGE_THIRD_LAYER})
            for (uint32_t i = 0; i < weft_step_stage_items(world, stage); ++i) REQUIRE_WEFT_OK(weft_run_step_items(world, stage, i, i + 1));
        REQUIRE_WEFT_OK(weft_end_step(world));
    }
    std::vector<Vec3> x(c->info.particle_count);
    REQUIRE_WEFT_OK(weft_read_positions(world, outer_id, reinterpret_cast<WeftVec3*>(x.data()), uint32_t(x.size())));
    CHECK(same_bits(x, read_all(w.world, oi, asset.particle_count)));
    CHECK(contacts > 0);
    weft_destroy_world(world);
}

#ifdef WEFT_SAMPLE_ASSETS_DIR
#include "common/crowd.h"

namespace {

Quat turn_about_y(float radians) { return {0.0f, std::sin(0.5f * radians), 0.0f, std::cos(0.5f * radians)}; }
WeftTransform to_c(const Transform& t) {
    return {{t.translation_m.x, t.translation_m.y, t.translation_m.z}, {t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w}};
}

}  // namespace

// A game binding Weft from C dresses a character as world.h does: the baked skirt bound to the
// walking mannequin by its attachments and skin constraints (WEFT_BODY_SKIN_CONSTRAINTS), carried
// by a moving, turning root at inertia 0.5, teleported, turned past the jump speed and reset to its
// dressed pose. Every frame's calls are the same through both; the positions are the same bits.
TEST_CASE("C API: a dressed skirt on a walking, moving, teleported character steps to the same bits as through world.h") {
    scenes::CrowdOptions o;  // the sample skirt, its scene and the mannequin's walk, as the crowd builds them
    o.characters = 1;
    o.skirt_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json";
    o.tee_scene = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/tee-walk.json";
    o.asset_dirs = {WEFT_SAMPLE_ASSETS_DIR};
    scenes::Crowd crowd;
    REQUIRE(scenes::build_crowd(o, &crowd).empty());
    const scenes::SceneBody& mannequin = *crowd.skirt.body;
    const ClothAsset& asset = *crowd.skirt.cloths[0].asset;
    REQUIRE(asset.skin.count > 0);
    const uint32_t vertices = uint32_t(mannequin.rest.size()), triangles = uint32_t(mannequin.triangles.size() / 3);

    // Through world.h.
    WorldDesc wd;
    reserve_cloth(wd, asset);
    wd.max_bodies = 1;
    wd.max_body_vertices = vertices;
    wd.max_body_triangles = triangles;
    const MemoryRequirements need = world_memory_requirements(wd);
    Block cpp_block = alloc_block({need.bytes, need.alignment});
    World* cpp = nullptr;
    REQUIRE(create_world(wd, cpp_block.get(), (need.bytes + need.alignment - 1) / need.alignment * need.alignment, &cpp).ok());
    BodyDesc bd;
    bd.positions = mannequin.rest.data();
    bd.vertex_count = vertices;
    bd.triangles = mannequin.triangles.data();
    bd.triangle_count = triangles;
    bd.thickness_m = mannequin.spec.thickness_m;
    bd.margin_m = mannequin.spec.margin_m;
    bd.friction = mannequin.spec.friction;
    bd.collision = BodyCollision::skin_constraints;
    BodyId body;
    REQUIRE(add_body(cpp, bd, &body).ok());
    ClothDesc cd;
    cd.asset = &asset;
    cd.sweeps = crowd.skirt.cloths[0].desc.sweeps;
    cd.linear_inertia = cd.angular_inertia = 0.5f;
    ClothId cloth;
    REQUIRE(add_cloth(cpp, cd, &cloth).ok());
    REQUIRE(attach_cloth_to_body(cpp, cloth, body).ok());
    REQUIRE(bind_asset_skin_constraints(cpp, cloth, body).ok());

    // Through weft_c.h.
    CWorld c;
    c.file = file_of(asset);
    WeftMemoryRequirements c_need{};
    REQUIRE_WEFT_OK(weft_asset_memory_requirements(c.file.data(), c.file.size(), &c_need));
    c.asset_block = alloc_block(c_need);
    REQUIRE_WEFT_OK(weft_load_asset(c.file.data(), c.file.size(), c.asset_block.get(), c_need.bytes, &c.asset));
    REQUIRE_WEFT_OK(weft_asset_info(c.asset, &c.info));
    WeftWorldDesc cwd = weft_default_world_desc();
    REQUIRE_WEFT_OK(weft_reserve_cloth(&cwd, c.asset));
    CHECK(cwd.max_skin_constraints == wd.max_skin_constraints);
    cwd.max_bodies = 1;
    cwd.max_body_vertices = vertices;
    cwd.max_body_triangles = triangles;
    REQUIRE_WEFT_OK(weft_world_memory_requirements(&cwd, &c_need));
    c.world_block = alloc_block(c_need);
    REQUIRE_WEFT_OK(weft_create_world(&cwd, c.world_block.get(), c_need.bytes, &c.world));
    WeftBodyDesc cbd = weft_default_body_desc();
    CHECK(cbd.collision == WEFT_BODY_EXACT);
    cbd.positions = reinterpret_cast<const WeftVec3*>(mannequin.rest.data());
    cbd.vertex_count = vertices;
    cbd.triangles = mannequin.triangles.data();
    cbd.triangle_count = triangles;
    cbd.thickness_m = bd.thickness_m;
    cbd.margin_m = bd.margin_m;
    cbd.friction = bd.friction;
    cbd.collision = WeftBodyCollision(7);
    WeftBodyId c_body = 0;
    CHECK_WEFT_ERROR(weft_add_body(c.world, &cbd, &c_body), WEFT_INVALID_ARGUMENT);  // no such model
    cbd.collision = WEFT_BODY_SKIN_CONSTRAINTS;
    REQUIRE_WEFT_OK(weft_add_body(c.world, &cbd, &c_body));
    WeftClothDesc ccd = weft_default_cloth_desc(c.asset);
    CHECK(ccd.jump_turn_rad_s == cd.jump_turn_rad_s);
    CHECK(ccd.max_step_growth == cd.max_step_growth);
    ccd.sweeps = cd.sweeps;
    ccd.linear_inertia = ccd.angular_inertia = 0.5f;
    REQUIRE_WEFT_OK(weft_add_cloth(c.world, &ccd, &c.cloth));
    REQUIRE_WEFT_OK(weft_attach_cloth_to_body(c.world, c.cloth, c_body));
    REQUIRE_WEFT_OK(weft_bind_asset_skin_constraints(c.world, c.cloth, c_body));

    // The root walks forward and turns; frame 20 is a 2 m teleport (announced), frame 35 a 1 rad
    // turn in one frame (unannounced: a jump), frame 50 a reset to the dressed pose.
    scenes::CrowdCharacter& who = crowd.characters[0];
    const float dt = crowd.dt_s;
    float extra_x = 0.0f, extra_turn = 0.0f;
    for (uint32_t frame = 1; frame <= 60; ++frame) {
        const float t = float(frame) * dt;
        if (frame == 20) extra_x = 2.0f;
        if (frame == 35) extra_turn = 1.0f;
        who.root = {{0.8f * t + extra_x, 0.0f, 0.0f}, turn_about_y(0.4f * t + extra_turn)};
        REQUIRE(scenes::animate_crowd(crowd, t).empty());  // poses crowd.pose at who's root
        const Transform root{{who.root.translation_m.x + who.offset_m.x, who.offset_m.y, who.offset_m.z}, who.root.rotation};
        const WeftTransform c_root = to_c(root);
        const WeftVec3* c_pose = reinterpret_cast<const WeftVec3*>(crowd.pose.data());
        if (frame == 20) {
            REQUIRE(teleport_body(cpp, body, crowd.pose.data(), vertices).ok());
            REQUIRE(teleport_cloth(cpp, cloth, root, true).ok());
            REQUIRE_WEFT_OK(weft_teleport_body(c.world, c_body, c_pose, vertices));
            REQUIRE_WEFT_OK(weft_teleport_cloth(c.world, c.cloth, &c_root, 1));
        } else {
            REQUIRE(set_body_vertices(cpp, body, crowd.pose.data(), vertices).ok());
            REQUIRE(set_cloth_root(cpp, cloth, root).ok());
            REQUIRE_WEFT_OK(weft_set_body_vertices(c.world, c_body, c_pose, vertices));
            REQUIRE_WEFT_OK(weft_set_cloth_root(c.world, c.cloth, &c_root));
        }
        if (frame == 50) {
            REQUIRE(reset_to_pose(cpp, cloth).ok());
            REQUIRE_WEFT_OK(weft_reset_to_pose(c.world, c.cloth));
        }
        REQUIRE(step(cpp, dt).ok());
        REQUIRE_WEFT_OK(weft_step(c.world, dt));
        if (frame % 10 == 0) {
            CAPTURE(frame);
            std::vector<Vec3> a(asset.particle_count);
            REQUIRE(read_positions(cpp, cloth, a.data(), asset.particle_count).ok());
            const std::vector<Vec3> b = read_c(c);
            REQUIRE(same_bits(a, b));
            CHECK(all_finite(b));
        }
    }
    // It went with the root: 2 m and more along x.
    const std::vector<Vec3> p = read_c(c);
    float lowest_x = p[0].x;
    for (const Vec3& q : p) lowest_x = std::min(lowest_x, q.x);
    CHECK(lowest_x > who.offset_m.x + 2.0f);

    // Refused, nothing changed: a root or a pose that is not finite, null roots, a stale cloth.
    WeftTransform bad{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f, 1.0f}};
    bad.translation_m.x = NAN;
    CHECK_WEFT_ERROR(weft_set_cloth_root(c.world, c.cloth, &bad), WEFT_NON_FINITE);
    CHECK_WEFT_ERROR(weft_teleport_cloth(c.world, c.cloth, &bad, 0), WEFT_NON_FINITE);
    CHECK_WEFT_ERROR(weft_set_cloth_root(c.world, c.cloth, nullptr), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_teleport_cloth(c.world, c.cloth, nullptr, 1), WEFT_INVALID_ARGUMENT);
    CHECK_WEFT_ERROR(weft_teleport_collider(c.world, 0, nullptr), WEFT_INVALID_ARGUMENT);
    std::vector<Vec3> poisoned = crowd.pose;
    poisoned[7].y = NAN;
    CHECK_WEFT_ERROR(weft_teleport_body(c.world, c_body, reinterpret_cast<const WeftVec3*>(poisoned.data()), vertices),
                     WEFT_NON_FINITE);
    CHECK(same_bits(read_c(c), p));
    REQUIRE_WEFT_OK(weft_remove_cloth(c.world, c.cloth));
    const WeftTransform c_identity{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f, 1.0f}};
    CHECK_WEFT_ERROR(weft_set_cloth_root(c.world, c.cloth, &c_identity), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_reset_to_pose(c.world, c.cloth), WEFT_STALE_ID);
    CHECK_WEFT_ERROR(weft_bind_asset_skin_constraints(c.world, c.cloth, c_body), WEFT_STALE_ID);
    destroy_world(cpp);
}
#endif
