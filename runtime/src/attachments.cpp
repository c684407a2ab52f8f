// Body attachments (weft/attachments.h): binding a cloth's asset attachments to a body.
#include "weft/attachments.h"

#include <algorithm>
#include <cmath>

#include "constraints/attachments.h"
#include "constraints/skin.h"
#include "asset/garment_checks.h"
#include "world_internal.h"

namespace weft {
namespace {

Result find_cloth_and_body(const World* world, ClothId cloth, BodyId body) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    return find_body(world, body);
}

// SkinState's arrays, `padded` lanes each, one after another from `block`.
void carve_skin_state(uint8_t* block, uint32_t padded, SkinState& s) {
    auto next = [&, i = 0u]() mutable { return reinterpret_cast<uint32_t*>(block) + size_t(padded) * i++; };
    auto next_float = [&] { return reinterpret_cast<float*>(next()); };
    s.slot = next();
    for (int i = 0; i < 3; ++i) s.corner[i] = next(), s.weight[i] = next_float();
    s.rest_offset_m = next_float();
    s.max_distance_m = next_float();
    s.backstop_m = next_float();
    for (int i = 0; i < 3; ++i)
        s.previous_point[i] = next_float(), s.point[i] = next_float(), s.normal[i] = next_float();
}

// Room for `bytes` of skin constraints in the world's skin pool: the first gap between the cloths'
// blocks that fits, after compacting them when none does (memory/regions.h).
bool reserve_skin_memory(World& world, size_t bytes, Region* out) {
    Region* live = world.regions;  // max_cloths entries at least
    uint32_t n = 0;
    for (uint32_t i = 0; i < world.cloth_slots; ++i)
        if (world.cloths[i].slot.live && world.cloths[i].skin_memory.end > 0)
            live[n++] = {world.cloths[i].skin_memory.begin, world.cloths[i].skin_memory.end, i};
    sort_regions(live, n);
    uint8_t* const base = world.skin_pool.base;
    size_t at = first_fit(base, live, n, 0, world.skin_pool.capacity, bytes);
    if (at == SIZE_MAX) {
        // Not even after compacting: fail before moving anything (the caller's old block, left out
        // of `live`, is still in use if the binding fails).
        if (first_fit(base, nullptr, 0, compacted_end(base, live, n, 0), world.skin_pool.capacity, bytes) == SIZE_MAX)
            return false;
        world.stats.memory_compactions += 1;
        compact_regions(base, live, n, 0, [&](const Region& r, ptrdiff_t) {
            ClothInstance& c = world.cloths[r.owner];
            c.skin_memory = {r.begin, r.end};
            carve_skin_state(base + r.begin, c.skin_capacity, c.skin_state);
        });
        sort_regions(live, n);
        at = first_fit(base, live, n, 0, world.skin_pool.capacity, bytes);
        if (at == SIZE_MAX) return false;
    }
    *out = {at, at + bytes};
    return true;
}

}  // namespace

Result attach_cloth_to_body(World* world, ClothId cloth, BodyId body) {
    if (Result r = find_cloth_and_body(world, cloth, body); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    const BodyState& b = world->bodies[body.index];
    const ClothAsset& a = *c.asset;
    if (a.attachment_count == 0) return make_error(ErrorCode::invalid_argument, "the cloth's asset has no attachments");
    for (uint32_t k = 0; k < a.attachment_count; ++k) {
        if (a.attached_triangle[k] >= b.triangle_count)
            return make_error(ErrorCode::out_of_range, "attachment %u names body triangle %u of %u", k,
                              a.attached_triangle[k], b.triangle_count);
        if (c.particles.inverse_mass[a.slot_of_particle[a.attached_particle[k]]] != 0.0f)
            return make_error(ErrorCode::invalid_argument, "attached particle %u is not pinned", a.attached_particle[k]);
    }
    wake(c);
    c.attached_body = body.index;
    follow_attachments(b, a, c.particles, 1.0f);
    for (uint32_t k = 0; k < a.attachment_count; ++k) {
        const uint32_t s = a.slot_of_particle[a.attached_particle[k]];
        c.particles.previous_x[s] = c.particles.x[s];
        c.particles.previous_y[s] = c.particles.y[s];
        c.particles.previous_z[s] = c.particles.z[s];
    }
    return {};
}

Result bind_asset_skin_constraints(World* world, ClothId cloth, BodyId body) {
    if (Result r = find_cloth_and_body(world, cloth, body); !r.ok()) return r;
    const SkinConstraints& skin = world->cloths[cloth.index].asset->skin;
    if (skin.count == 0) return make_error(ErrorCode::invalid_argument, "the cloth's asset has no skin constraints");
    return bind_skin_constraints(world, cloth, body, skin);
}

Result bind_skin_constraints(World* world, ClothId cloth, BodyId body, const SkinConstraints& skin) {
    if (Result r = find_cloth_and_body(world, cloth, body); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (skin.count == 0) {
        wake(c);
        c.skin_body = ~0u;
        return {};
    }
    const BodyState& b = world->bodies[body.index];
    const ClothAsset& a = *c.asset;
    if (Result r = check_skin_constraints(skin, a.particle_count, a.slot_of_particle, c.particles.inverse_mass,
                                          world->validation_scratch);  // [max_particles] >= particle_count
        !r.ok())
        return r;
    for (uint32_t k = 0; k < skin.count; ++k)
        if (skin.triangle[k] >= b.triangle_count)
            return make_error(ErrorCode::out_of_range, "skin constraint %u names body triangle %u of %u", k,
                              skin.triangle[k], b.triangle_count);
    // The cloth's SkinState: reused when the binding fits, else carved anew from the world's pool.
    const uint32_t padded = (skin.count + kSimdWidth - 1) / kSimdWidth * kSimdWidth;
    if (padded > c.skin_capacity) {
        const Region old = c.skin_memory;
        c.skin_memory = {};  // the old room is free for the search
        Region room;
        if (!reserve_skin_memory(*world, kSkinArrays * sizeof(float) * size_t(padded), &room)) {
            c.skin_memory = old;
            return make_error(ErrorCode::capacity_exceeded,
                              "%u skin constraints do not fit in what WorldDesc::max_skin_constraints left",
                              skin.count);
        }
        c.skin_memory = room;
        c.skin_capacity = padded;
        carve_skin_state(world->skin_pool.base + room.begin, padded, c.skin_state);
    }
    // Slot order (each particle is bound once, so the order changes no result): the substep
    // pass's loads and stores then walk the particle arrays forwards. The permutation is sorted in
    // corner[0], which each constraint's own entry overwrites last.
    SkinState& s = c.skin_state;
    s.count = skin.count;
    uint32_t* const order = s.corner[0];
    for (uint32_t k = 0; k < skin.count; ++k) order[k] = k;
    std::sort(order, order + skin.count, [&](uint32_t u, uint32_t v) {
        return a.slot_of_particle[skin.particle[u]] < a.slot_of_particle[skin.particle[v]];
    });
    for (uint32_t k = skin.count; k < padded; ++k) order[k] = order[skin.count - 1];
    const uint32_t* const body_triangles = b.triangles;
    for (uint32_t k = 0; k < padded; ++k) {
        const uint32_t j = order[k];
        s.slot[k] = a.slot_of_particle[skin.particle[j]];
        s.rest_offset_m[k] = skin.rest_offset_m[j];
        s.max_distance_m[k] = skin.max_distance_m[j];
        s.backstop_m[k] = skin.backstop_m[j];
        for (int i = 2; i >= 0; --i) {  // corner[0] last: it holds j
            s.weight[i][k] = skin.weight[3 * j + i];
            s.corner[i][k] = body_triangles[3 * skin.triangle[j] + i];
        }
    }
    wake(c);
    c.skin_body = body.index;
    c.skin_points_current = false;  // the first step gathers P on both hulls
    return {};
}

Result reset_to_pose(World* world, ClothId cloth) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (c.skin_body == ~0u && c.attached_body == ~0u)
        return make_error(ErrorCode::invalid_argument,
                          "cloth %u has no skin constraints or attachments: nothing says where on a body it goes",
                          cloth.index);
    wake(c);
    forget_last_good(c);
    place_on_body(*world, c);
    return {};
}

void place_on_body(const World& world, ClothInstance& c) {
    place_at_start(*world.kernels, c);
    const Particles& p = c.particles;
    if (c.skin_body != ~0u) {  // S = P + rest offset * N on the hull as it is now (constraints/skin.h)
        const BodyState& body = world.bodies[c.skin_body];
        const SkinState& s = c.skin_state;
        world.kernels->skin_frames(s, SkinFrameArgs{body.hull, body.hull, body.normals});
        for (uint32_t k = 0; k < s.count; ++k) {
            const uint32_t slot = s.slot[k];
            p.x[slot] = p.previous_x[slot] = std::fma(s.rest_offset_m[k], s.normal[0][k], s.point[0][k]);
            p.y[slot] = p.previous_y[slot] = std::fma(s.rest_offset_m[k], s.normal[1][k], s.point[1][k]);
            p.z[slot] = p.previous_z[slot] = std::fma(s.rest_offset_m[k], s.normal[2][k], s.point[2][k]);
        }
        c.skin_points_current = true;  // P at this hull: the next step moves it from here
    }
    if (c.attached_body != ~0u) {
        follow_attachments(world.bodies[c.attached_body], *c.asset, p, 1.0f);
        for (uint32_t k = 0; k < c.asset->attachment_count; ++k) {
            const uint32_t s = c.asset->slot_of_particle[c.asset->attached_particle[k]];
            p.previous_x[s] = p.x[s], p.previous_y[s] = p.y[s], p.previous_z[s] = p.z[s];
        }
    }
    if (p.normal_x != nullptr) world.kernels->vertex_normals(p, *c.asset);
    c.previous_root = c.root;  // carried from the root it stands at now
}

}  // namespace weft
