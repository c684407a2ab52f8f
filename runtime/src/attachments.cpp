// Body attachments (weft/attachments.h): binding a cloth's asset attachments to a body.
#include "weft/attachments.h"

#include <algorithm>
#include <cmath>

#include "constraints/attachments.h"
#include "asset/garment_checks.h"
#include "world_internal.h"

namespace weft {
namespace {

Result find_cloth_and_body(const World* world, ClothId cloth, BodyId body) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (cloth.index >= world->cloth_count)
        return make_error(ErrorCode::out_of_range, "cloth %u of %u", cloth.index, world->cloth_count);
    if (body.index >= world->body_count)
        return make_error(ErrorCode::out_of_range, "body %u of %u", body.index, world->body_count);
    return {};
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
        auto* block = static_cast<uint32_t*>(world->skin_pool.allocate(kSkinArrays * sizeof(float) * size_t(padded)));
        if (block == nullptr)
            return make_error(ErrorCode::capacity_exceeded,
                              "%u skin constraints do not fit in what WorldDesc::max_skin_constraints left",
                              skin.count);
        SkinState& s = c.skin_state;
        auto next = [&, i = 0u]() mutable { return block + size_t(padded) * i++; };
        auto next_float = [&] { return reinterpret_cast<float*>(next()); };
        s.slot = next();
        for (int i = 0; i < 3; ++i) s.corner[i] = next(), s.weight[i] = next_float();
        s.rest_offset_m = next_float();
        s.max_distance_m = next_float();
        s.backstop_m = next_float();
        for (int i = 0; i < 3; ++i)
            s.previous_point[i] = next_float(), s.point[i] = next_float(), s.normal[i] = next_float();
        c.skin_capacity = padded;
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
    c.skin_body = body.index;
    c.skin_points_current = false;  // the first step gathers P on both hulls
    return {};
}

}  // namespace weft
