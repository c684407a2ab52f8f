// The C interface (weft/weft_c.h): each call checks its handles, converts its plain C structs to
// world.h's and forwards. Handles are small headers at the start of the caller's blocks, with a
// magic word that weft_destroy_world clears, so a dead handle is refused instead of followed.
#include "weft/weft_c.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>

#include "weft/weft.h"
#include "world_internal.h"  // make_error

using namespace weft;

static_assert(sizeof(WeftVec3) == sizeof(Vec3) && offsetof(WeftVec3, y) == offsetof(Vec3, y) &&
                  offsetof(WeftVec3, z) == offsetof(Vec3, z),
              "WeftVec3 and weft::Vec3 must share a layout: arrays of one are read as the other");
static_assert(sizeof(WeftResult::message) == sizeof(Result::message));
static_assert(uint32_t(WEFT_CORRUPT_ASSET) == uint32_t(ErrorCode::corrupt_asset));
static_assert(uint32_t(WEFT_SIMD_AVX2) == uint32_t(SimdPath::avx2));
static_assert(uint32_t(WEFT_COLLIDER_PLANE) == uint32_t(ColliderShape::plane));

struct WeftAsset {
    uint32_t magic;
    ClothAsset asset;
};

struct WeftWorld {
    uint32_t magic;
    World* world;
};

namespace {

constexpr uint32_t kAssetHandleMagic = 0x41544657u;  // "WFTA"
constexpr uint32_t kWorldHandleMagic = 0x57544657u;  // "WFTW"
// The world's own block starts this far into the caller's, after the handle, on a cache line.
constexpr size_t kWorldHeaderBytes = 64;
static_assert(sizeof(WeftWorld) <= kWorldHeaderBytes);
// The loader's scratch follows the handle in the asset's block.
constexpr size_t kAssetScratchOffset = (sizeof(WeftAsset) + alignof(uint32_t) - 1) / alignof(uint32_t) * alignof(uint32_t);

WeftResult to_c(const Result& r) {
    WeftResult out;
    out.code = WeftErrorCode(r.code);
    std::memcpy(out.message, r.message, sizeof(out.message));
    out.message[sizeof(out.message) - 1] = '\0';
    return out;
}

Vec3 to_cpp(WeftVec3 v) { return {v.x, v.y, v.z}; }
const Vec3* to_cpp(const WeftVec3* v) { return reinterpret_cast<const Vec3*>(v); }
Vec3* to_cpp(WeftVec3* v) { return reinterpret_cast<Vec3*>(v); }

// C ids pack the place (low 16 bits: the world's capacities stay below 2^16) and its generation.
uint32_t to_c_id(uint32_t index, uint32_t generation) { return index | generation << 16; }
ClothId cloth_id(WeftClothId id) { return {id & 0xFFFFu, id >> 16}; }
BodyId body_id(WeftBodyId id) { return id == WEFT_EVERY_BODY ? kEveryBody : BodyId{id & 0xFFFFu, id >> 16}; }
ColliderId collider_id(WeftColliderId id) { return {id & 0xFFFFu, id >> 16}; }

bool is_aligned(const void* p, size_t alignment) { return reinterpret_cast<uintptr_t>(p) % alignment == 0; }

Result live_asset(const WeftAsset* asset) {
    if (asset == nullptr) return make_error(ErrorCode::invalid_argument, "asset is null");
    if (!is_aligned(asset, alignof(WeftAsset)) || asset->magic != kAssetHandleMagic)
        return make_error(ErrorCode::invalid_argument, "asset handle is not a loaded asset");
    return {};
}

Result live_world(const WeftWorld* world) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (!is_aligned(world, alignof(WeftWorld)) || world->magic != kWorldHandleMagic)
        return make_error(ErrorCode::invalid_argument, "world handle is not a live world (destroyed or never created)");
    return {};
}

WorldDesc to_cpp(const WeftWorldDesc& d) {
    WorldDesc w;
    w.max_cloths = d.max_cloths;
    w.max_particles = d.max_particles;
    w.max_constraints = d.max_constraints;
    w.max_coarse_nodes = d.max_coarse_nodes;
    w.max_colliders = d.max_colliders;
    w.max_bodies = d.max_bodies;
    w.max_body_vertices = d.max_body_vertices;
    w.max_body_triangles = d.max_body_triangles;
    w.max_cached_plane_bodies = d.max_cached_plane_bodies;
    w.max_skin_constraints = d.max_skin_constraints;
    w.wind = d.wind != 0;
    w.normals = d.normals != 0;
    w.tangents = d.tangents != 0;
    w.max_triangle_lanes = d.max_triangle_lanes;
    w.render_meshes = d.render_meshes != 0;
    w.max_render_vertices = d.max_render_vertices;
    w.max_last_good_particles = d.max_last_good_particles;
    w.max_self_collision_particles = d.max_self_collision_particles;
    w.max_self_collision_triangles = d.max_self_collision_triangles;
    w.max_layer_particles = d.max_layer_particles;
    w.max_layer_triangles = d.max_layer_triangles;
    w.budget_ns_per_lane = d.budget_ns_per_lane;
    w.budget_ns_per_particle = d.budget_ns_per_particle;
    w.gravity_m_s2 = to_cpp(d.gravity_m_s2);
    w.air_density_kg_m3 = d.air_density_kg_m3;
    w.simd = d.simd <= WEFT_SIMD_AVX2 ? SimdPath(d.simd) : SimdPath(0xFF);  // refused by create_world
    return w;
}

Transform to_cpp(const WeftTransform& t) {
    return {to_cpp(t.translation_m), {t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w}};
}

ColliderDesc to_cpp(const WeftColliderDesc& d) {
    ColliderDesc c;
    c.shape = d.shape <= WEFT_COLLIDER_PLANE ? ColliderShape(d.shape) : ColliderShape(0xFF);  // refused by add_collider
    c.p0 = to_cpp(d.p0);
    c.p1 = to_cpp(d.p1);
    c.radius_m = d.radius_m;
    c.inflation_m = d.inflation_m;
    c.friction = d.friction;
    return c;
}

}  // namespace

extern "C" {

const char* weft_error_name(WeftErrorCode code) {
    switch (code) {
        case WEFT_OK: return "ok";
        case WEFT_INVALID_ARGUMENT: return "invalid_argument";
        case WEFT_NON_FINITE: return "non_finite";
        case WEFT_OUT_OF_RANGE: return "out_of_range";
        case WEFT_CAPACITY_EXCEEDED: return "capacity_exceeded";
        case WEFT_MEMORY_TOO_SMALL: return "memory_too_small";
        case WEFT_UNSUPPORTED: return "unsupported";
        case WEFT_CORRUPT_ASSET: return "corrupt_asset";
        case WEFT_STALE_ID: return "stale_id";
    }
    return "unknown";
}

// --- assets ---------------------------------------------------------------------------------------

WeftResult weft_asset_memory_requirements(const void* file, size_t size, WeftMemoryRequirements* out) {
    if (file == nullptr || out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "file or out is null"));
    AssetFileInfo info;
    if (Result r = read_asset_header(file, size, &info); !r.ok()) return to_c(r);
    out->bytes = kAssetScratchOffset + sizeof(uint32_t) * size_t(info.load_scratch_count);
    out->alignment = alignof(WeftAsset);
    return {};
}

WeftResult weft_load_asset(const void* file, size_t size, void* memory, size_t memory_bytes, WeftAsset** out_asset) {
    if (file == nullptr || memory == nullptr || out_asset == nullptr)
        return to_c(make_error(ErrorCode::invalid_argument, "file, memory or out_asset is null"));
    if (!is_aligned(memory, alignof(WeftAsset)) || memory_bytes < kAssetScratchOffset)
        return to_c(make_error(ErrorCode::memory_too_small, "asset block of %zu bytes at alignment < %zu", memory_bytes,
                               alignof(WeftAsset)));
    // The loader checks the scratch against the file's need (memory_too_small) and every byte.
    uint32_t* scratch = reinterpret_cast<uint32_t*>(static_cast<unsigned char*>(memory) + kAssetScratchOffset);
    const size_t scratch_count = (memory_bytes - kAssetScratchOffset) / sizeof(uint32_t);
    ClothAsset asset;
    const uint32_t scratch_capped = uint32_t(scratch_count > UINT32_MAX ? UINT32_MAX : scratch_count);
    if (Result r = load_asset_in_place(file, size, scratch, scratch_capped, &asset); !r.ok()) return to_c(r);
    WeftAsset* handle = new (memory) WeftAsset{kAssetHandleMagic, asset};
    *out_asset = handle;
    return {};
}

WeftResult weft_asset_info(const WeftAsset* asset, WeftAssetInfo* out) {
    if (Result r = live_asset(asset); !r.ok()) return to_c(r);
    if (out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "out is null"));
    const AssetView v = view_asset(asset->asset);
    out->particle_count = v.particle_count;
    out->triangle_count = v.triangle_count;
    out->uv = v.uv;
    out->sewn_point_count = v.sewn_point_count;
    out->sewn_particle = v.sewn_particle;
    out->sewn_uv_first = v.sewn_uv_first;
    out->sewn_uv = v.sewn_uv;
    out->has_fabric = v.has_fabric ? 1 : 0;
    out->damping_per_s = v.fabric.damping_per_s;
    for (int k = 0; k < 3; ++k) out->compliance_m_per_n[k] = v.fabric.compliance_m_per_n[k];
    out->attachment_count = v.attachment_count;
    out->skin_constraint_count = v.skin_constraint_count;
    out->render_vertex_count = v.render_vertex_count;
    out->render_triangle_count = v.render_triangle_count;
    return {};
}

WeftResult weft_asset_render_mesh(const WeftAsset* asset, uint32_t* out_indices, uint32_t index_count, float* out_uv,
                                  uint32_t uv_count) {
    if (Result r = live_asset(asset); !r.ok()) return to_c(r);
    const AssetView v = view_asset(asset->asset);
    if (out_indices != nullptr && uint64_t(index_count) != 3 * uint64_t(v.render_triangle_count))
        return to_c(make_error(ErrorCode::out_of_range, "index_count %u, render mesh has %u triangles (3 indices each)",
                               index_count, v.render_triangle_count));
    if (out_uv != nullptr && uint64_t(uv_count) != 2 * uint64_t(v.render_vertex_count))
        return to_c(make_error(ErrorCode::out_of_range, "uv_count %u, render mesh has %u vertices (2 floats each)", uv_count,
                               v.render_vertex_count));
    if (out_indices != nullptr)
        for (uint32_t k = 0; k < index_count; ++k) out_indices[k] = v.render_triangles[k];
    if (out_uv != nullptr)
        for (uint32_t k = 0; k < uv_count; ++k) out_uv[k] = v.render_uv[k];
    return {};
}

WeftResult weft_asset_triangles(const WeftAsset* asset, uint32_t* out_indices, uint32_t index_count) {
    if (Result r = live_asset(asset); !r.ok()) return to_c(r);
    return to_c(read_triangles(asset->asset, out_indices, index_count));
}

WeftResult weft_asset_start_positions(const WeftAsset* asset, WeftVec3* out, uint32_t count) {
    if (Result r = live_asset(asset); !r.ok()) return to_c(r);
    return to_c(read_start_positions(asset->asset, to_cpp(out), count));
}

// --- the world --------------------------------------------------------------------------------------

WeftWorldDesc weft_default_world_desc(void) {
    const WorldDesc d;
    WeftWorldDesc w{};
    w.max_cloths = 0;  // weft_reserve_cloth counts the cloths
    w.wind = d.wind ? 1 : 0;
    w.normals = d.normals ? 1 : 0;
    w.tangents = d.tangents ? 1 : 0;
    w.render_meshes = d.render_meshes ? 1 : 0;
    w.gravity_m_s2 = {d.gravity_m_s2.x, d.gravity_m_s2.y, d.gravity_m_s2.z};
    w.air_density_kg_m3 = d.air_density_kg_m3;
    w.simd = WeftSimdPath(d.simd);
    w.budget_ns_per_lane = d.budget_ns_per_lane;
    w.budget_ns_per_particle = d.budget_ns_per_particle;
    return w;
}

WeftResult weft_reserve_cloth(WeftWorldDesc* desc, const WeftAsset* asset) {
    if (desc == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc is null"));
    if (Result r = live_asset(asset); !r.ok()) return to_c(r);
    WorldDesc w = to_cpp(*desc);
    reserve_cloth(w, asset->asset);
    desc->max_cloths = w.max_cloths;
    desc->max_particles = w.max_particles;
    desc->max_constraints = w.max_constraints;
    desc->max_coarse_nodes = w.max_coarse_nodes;
    desc->max_triangle_lanes = w.max_triangle_lanes;
    desc->max_render_vertices = w.max_render_vertices;
    desc->max_skin_constraints = w.max_skin_constraints;
    return {};
}

WeftResult weft_reserve_cloth_recovering(WeftWorldDesc* desc, const WeftAsset* asset, WeftRecoveryPolicy recovery) {
    if (desc == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc is null"));
    if (uint32_t(recovery) > WEFT_RECOVER_DRESSED_POSE)
        return to_c(make_error(ErrorCode::invalid_argument, "unknown recovery policy %u", unsigned(recovery)));
    if (WeftResult r = weft_reserve_cloth(desc, asset); r.code != WEFT_OK) return r;
    if (recovery == WEFT_RECOVER_LAST_GOOD) desc->max_last_good_particles += asset->asset.slot_count;
    return {};
}

WeftResult weft_reserve_cloth_desc(WeftWorldDesc* desc, const WeftClothDesc* cloth) {
    if (desc == nullptr || cloth == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc or cloth is null"));
    if (WeftResult r = weft_reserve_cloth_recovering(desc, cloth->asset, cloth->recovery); r.code != WEFT_OK) return r;
    if (cloth->self_collision != 0) {
        desc->max_self_collision_particles += cloth->asset->asset.slot_count;
        desc->max_self_collision_triangles += cloth->asset->asset.triangle_count;
    }
    return {};
}

WeftResult weft_reserve_layer(WeftWorldDesc* desc, const WeftAsset* outer, const WeftAsset* largest_inner) {
    if (desc == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc is null"));
    if (Result r = live_asset(outer); !r.ok()) return to_c(r);
    if (Result r = live_asset(largest_inner); !r.ok()) return to_c(r);
    desc->max_layer_particles += outer->asset.slot_count + largest_inner->asset.slot_count;
    desc->max_layer_triangles += outer->asset.triangle_count;
    return {};
}

WeftResult weft_world_memory_requirements(const WeftWorldDesc* desc, WeftMemoryRequirements* out) {
    if (desc == nullptr || out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc or out is null"));
    const MemoryRequirements need = world_memory_requirements(to_cpp(*desc));
    if (need.bytes == 0) {  // the description is refused: say why, as create_world would
        World* unused = nullptr;
        Result r = create_world(to_cpp(*desc), nullptr, 0, &unused);
        if (r.ok()) r = make_error(ErrorCode::invalid_argument, "bad world description");
        return to_c(r);
    }
    out->bytes = kWorldHeaderBytes + need.bytes;
    out->alignment = need.alignment > alignof(WeftWorld) ? need.alignment : alignof(WeftWorld);
    return {};
}

WeftResult weft_create_world(const WeftWorldDesc* desc, void* memory, size_t bytes, WeftWorld** out_world) {
    if (desc == nullptr || memory == nullptr || out_world == nullptr)
        return to_c(make_error(ErrorCode::invalid_argument, "desc, memory or out_world is null"));
    if (!is_aligned(memory, alignof(WeftWorld)) || bytes < kWorldHeaderBytes)
        return to_c(make_error(ErrorCode::memory_too_small, "world block of %zu bytes is too small or misaligned", bytes));
    unsigned char* block = static_cast<unsigned char*>(memory);
    World* world = nullptr;
    if (Result r = create_world(to_cpp(*desc), block + kWorldHeaderBytes, bytes - kWorldHeaderBytes, &world); !r.ok())
        return to_c(r);
    *out_world = new (memory) WeftWorld{kWorldHandleMagic, world};
    return {};
}

void weft_destroy_world(WeftWorld* world) {
    if (!live_world(world).ok()) return;
    destroy_world(world->world);
    world->magic = 0;
    world->world = nullptr;
}

WeftClothDesc weft_default_cloth_desc(const WeftAsset* asset) {
    const ClothDesc d;
    WeftClothDesc c{};
    c.asset = asset;
    c.sweeps = d.sweeps;
    for (uint32_t k = 0; k < 3; ++k) c.compliance_m_per_n[k] = d.compliance_m_per_n[k];
    c.damping_per_s = d.damping_per_s;
    c.drag_coefficient = d.drag_coefficient;
    c.lift_coefficient = d.lift_coefficient;
    c.sleep_speed_m_s = d.sleep_speed_m_s;
    c.recovery = WeftRecoveryPolicy(d.recovery);
    c.self_collision = d.self_collision ? 1 : 0;
    c.self_thickness_m = d.self_thickness_m;
    c.self_friction = d.self_friction;
    c.worn_over_count = 0;
    c.layer_thickness_m = d.layer_thickness_m;
    c.layer_friction = d.layer_friction;
    c.linear_inertia = d.linear_inertia;
    c.angular_inertia = d.angular_inertia;
    c.max_inertial_speed_m_s = d.max_inertial_speed_m_s;
    c.jump_speed_m_s = d.jump_speed_m_s;
    c.jump_turn_rad_s = d.jump_turn_rad_s;
    c.max_step_growth = d.max_step_growth;
    c.max_step_s = d.max_step_s;
    if (live_asset(asset).ok() && asset->asset.has_fabric) {  // the fabric the pattern named (as weft-sim)
        const Fabric& f = asset->asset.fabric;
        for (uint32_t k = 0; k < 3; ++k) c.compliance_m_per_n[k] = f.compliance_m_per_n[k];
        c.damping_per_s = f.damping_per_s;
    }
    return c;
}

WeftResult weft_add_cloth(WeftWorld* world, const WeftClothDesc* desc, WeftClothId* out_cloth) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (desc == nullptr || out_cloth == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc or out_cloth is null"));
    if (Result r = live_asset(desc->asset); !r.ok()) return to_c(r);
    ClothDesc c;
    c.asset = &desc->asset->asset;
    c.translation_m = to_cpp(desc->translation_m);
    c.sweeps = desc->sweeps;
    for (uint32_t k = 0; k < 3; ++k) c.compliance_m_per_n[k] = desc->compliance_m_per_n[k];
    c.damping_per_s = desc->damping_per_s;
    c.drag_coefficient = desc->drag_coefficient;
    c.lift_coefficient = desc->lift_coefficient;
    c.sleep_speed_m_s = desc->sleep_speed_m_s;
    c.recovery = uint32_t(desc->recovery) <= WEFT_RECOVER_DRESSED_POSE ? RecoveryPolicy(desc->recovery)
                                                                    : RecoveryPolicy(0xFF);  // refused by add_cloth
    c.self_collision = desc->self_collision != 0;
    c.self_thickness_m = desc->self_thickness_m;
    c.self_friction = desc->self_friction;
    c.worn_over_count = desc->worn_over_count;  // above kMaxWornOver: refused by add_cloth
    for (uint32_t k = 0; k < kMaxWornOver && k < desc->worn_over_count; ++k) c.worn_over[k] = cloth_id(desc->worn_over[k]);
    c.layer_thickness_m = desc->layer_thickness_m;
    c.layer_friction = desc->layer_friction;
    c.linear_inertia = desc->linear_inertia;
    c.angular_inertia = desc->angular_inertia;
    c.max_inertial_speed_m_s = desc->max_inertial_speed_m_s;
    c.jump_speed_m_s = desc->jump_speed_m_s;
    c.jump_turn_rad_s = desc->jump_turn_rad_s;
    c.max_step_growth = desc->max_step_growth;
    c.max_step_s = desc->max_step_s;
    ClothId id;
    if (Result r = add_cloth(world->world, c, &id); !r.ok()) return to_c(r);
    *out_cloth = to_c_id(id.index, id.generation);
    return {};
}

// --- bodies and colliders ------------------------------------------------------------------------------

WeftBodyDesc weft_default_body_desc(void) {
    const BodyDesc d;
    WeftBodyDesc b{};
    b.thickness_m = d.thickness_m;
    b.margin_m = d.margin_m;
    b.friction = d.friction;
    b.collision = WeftBodyCollision(d.collision);
    return b;
}

WeftResult weft_add_body(WeftWorld* world, const WeftBodyDesc* desc, WeftBodyId* out_body) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (desc == nullptr || out_body == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc or out_body is null"));
    BodyDesc b;
    b.positions = to_cpp(desc->positions);
    b.vertex_count = desc->vertex_count;
    b.triangles = desc->triangles;
    b.triangle_count = desc->triangle_count;
    b.thickness_m = desc->thickness_m;
    b.margin_m = desc->margin_m;
    b.friction = desc->friction;
    b.collision = uint32_t(desc->collision) <= WEFT_BODY_SKIN_CONSTRAINTS ? BodyCollision(desc->collision)
                                                                        : BodyCollision(0xFF);  // refused by add_body
    BodyId id;
    if (Result r = add_body(world->world, b, &id); !r.ok()) return to_c(r);
    *out_body = to_c_id(id.index, id.generation);
    return {};
}

WeftResult weft_teleport_body(WeftWorld* world, WeftBodyId body, const WeftVec3* positions, uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(teleport_body(world->world, body_id(body), to_cpp(positions), count));
}

WeftResult weft_bind_asset_skin_constraints(WeftWorld* world, WeftClothId cloth, WeftBodyId body) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(bind_asset_skin_constraints(world->world, cloth_id(cloth), body_id(body)));
}

WeftResult weft_set_body_vertices(WeftWorld* world, WeftBodyId body, const WeftVec3* positions, uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_body_vertices(world->world, body_id(body), to_cpp(positions), count));
}

WeftResult weft_attach_cloth_to_body(WeftWorld* world, WeftClothId cloth, WeftBodyId body) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(attach_cloth_to_body(world->world, cloth_id(cloth), body_id(body)));
}

WeftColliderDesc weft_default_collider_desc(void) {
    const ColliderDesc d;
    WeftColliderDesc c{};
    c.shape = WeftColliderShape(d.shape);
    c.p0 = {d.p0.x, d.p0.y, d.p0.z};
    c.p1 = {d.p1.x, d.p1.y, d.p1.z};
    c.radius_m = d.radius_m;
    c.inflation_m = d.inflation_m;
    c.friction = d.friction;
    return c;
}

WeftResult weft_add_collider(WeftWorld* world, const WeftColliderDesc* desc, WeftColliderId* out_collider) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (desc == nullptr || out_collider == nullptr)
        return to_c(make_error(ErrorCode::invalid_argument, "desc or out_collider is null"));
    ColliderId id;
    if (Result r = add_collider(world->world, to_cpp(*desc), &id); !r.ok()) return to_c(r);
    *out_collider = to_c_id(id.index, id.generation);
    return {};
}

WeftResult weft_teleport_collider(WeftWorld* world, WeftColliderId collider, const WeftColliderDesc* desc) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (desc == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc is null"));
    return to_c(teleport_collider(world->world, collider_id(collider), to_cpp(*desc)));
}

// --- character motion -----------------------------------------------------------------------------------

WeftResult weft_set_cloth_root(WeftWorld* world, WeftClothId cloth, const WeftTransform* root) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (root == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "root is null"));
    return to_c(set_cloth_root(world->world, cloth_id(cloth), to_cpp(*root)));
}

WeftResult weft_teleport_cloth(WeftWorld* world, WeftClothId cloth, const WeftTransform* root, int drop_velocity) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (root == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "root is null"));
    return to_c(teleport_cloth(world->world, cloth_id(cloth), to_cpp(*root), drop_velocity != 0));
}

WeftResult weft_reset_to_pose(WeftWorld* world, WeftClothId cloth) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(reset_to_pose(world->world, cloth_id(cloth)));
}

WeftResult weft_set_collider(WeftWorld* world, WeftColliderId collider, const WeftColliderDesc* desc) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (desc == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "desc is null"));
    return to_c(set_collider(world->world, collider_id(collider), to_cpp(*desc)));
}

// --- every frame ----------------------------------------------------------------------------------------

WeftResult weft_set_wind(WeftWorld* world, WeftVec3 velocity_m_s) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_wind(world->world, to_cpp(velocity_m_s)));
}

WeftResult weft_set_gravity(WeftWorld* world, WeftVec3 gravity_m_s2) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_gravity(world->world, to_cpp(gravity_m_s2)));
}

WeftResult weft_step(WeftWorld* world, float dt_s) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(step(world->world, dt_s));
}

WeftResult weft_begin_step(WeftWorld* world, float dt_s) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(begin_step(world->world, dt_s));
}

uint32_t weft_step_stage_items(const WeftWorld* world, WeftStepStage stage) {
    if (!live_world(world).ok()) return 0;
    return step_stage_items(world->world, static_cast<StepStage>(stage));
}

WeftResult weft_run_step_items(WeftWorld* world, WeftStepStage stage, uint32_t begin, uint32_t end) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(run_step_items(world->world, static_cast<StepStage>(stage), begin, end));
}

WeftResult weft_end_step(WeftWorld* world) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(end_step(world->world));
}

WeftResult weft_set_cloth_body(WeftWorld* world, WeftClothId cloth, WeftBodyId body) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_cloth_body(world->world, cloth_id(cloth), body_id(body)));
}

WeftResult weft_remove_cloth(WeftWorld* world, WeftClothId cloth) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(remove_cloth(world->world, cloth_id(cloth)));
}

WeftResult weft_remove_body(WeftWorld* world, WeftBodyId body) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(remove_body(world->world, body_id(body)));
}

WeftResult weft_remove_collider(WeftWorld* world, WeftColliderId collider) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(remove_collider(world->world, collider_id(collider)));
}

WeftResult weft_read_positions(const WeftWorld* world, WeftClothId cloth, WeftVec3* out, uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(read_positions(world->world, cloth_id(cloth), to_cpp(out), count));
}

WeftResult weft_read_normals(const WeftWorld* world, WeftClothId cloth, WeftVec3* out, uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(read_normals(world->world, cloth_id(cloth), to_cpp(out), count));
}

WeftResult weft_read_render_mesh(const WeftWorld* world, WeftClothId cloth, WeftVec3* positions, WeftVec3* normals,
                                 uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(read_render_mesh(world->world, cloth_id(cloth), to_cpp(positions), to_cpp(normals), count));
}

WeftResult weft_read_tangents(const WeftWorld* world, WeftClothId cloth, WeftVec4* out, uint32_t count) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    static_assert(sizeof(WeftVec4) == sizeof(Vec4) && alignof(WeftVec4) == alignof(Vec4));
    return to_c(read_tangents(world->world, cloth_id(cloth), reinterpret_cast<Vec4*>(out), count));
}

WeftResult weft_cloth_is_sleeping(const WeftWorld* world, WeftClothId cloth, int* out_sleeping) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (out_sleeping == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "out_sleeping is null"));
    bool sleeping = false;
    if (Result r = cloth_is_sleeping(world->world, cloth_id(cloth), &sleeping); !r.ok()) return to_c(r);
    *out_sleeping = sleeping ? 1 : 0;
    return {};
}

WeftResult weft_wake_cloth(WeftWorld* world, WeftClothId cloth) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(wake_cloth(world->world, cloth_id(cloth)));
}

WeftResult weft_cloth_health(const WeftWorld* world, WeftClothId cloth, WeftClothHealth* out) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "out is null"));
    ClothHealth h;
    if (Result r = cloth_health(world->world, cloth_id(cloth), &h); !r.ok()) return to_c(r);
    *out = {h.problems, h.recovered ? 1 : 0, h.energy_J_per_kg, h.recoveries};
    return {};
}

WeftResult weft_world_health(const WeftWorld* world, WeftWorldHealth* out) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "out is null"));
    const WorldStats stats = world_stats(world->world);
    *out = {stats.unhealthy_cloths, stats.recovered_cloths, stats.total_recoveries};
    return {};
}

WeftResult weft_set_frame_budget_us(WeftWorld* world, float budget_us) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_frame_budget_us(world->world, budget_us));
}

WeftResult weft_set_cloth_priority(WeftWorld* world, WeftClothId cloth, float priority) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    return to_c(set_cloth_priority(world->world, cloth_id(cloth), priority));
}

WeftResult weft_frame_budget_stats(const WeftWorld* world, WeftFrameBudgetStats* out) {
    if (Result r = live_world(world); !r.ok()) return to_c(r);
    if (out == nullptr) return to_c(make_error(ErrorCode::invalid_argument, "out is null"));
    const WorldStats stats = world_stats(world->world);
    *out = {stats.budget_estimate_us, stats.budget_cloths_cut, stats.budget_sweeps};
    return {};
}

}  // extern "C"
