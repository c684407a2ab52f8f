// Body attachments (weft/attachments.h): binding a cloth's asset attachments to a body.
#include "weft/attachments.h"

#include <cmath>
#include <cstring>

#include "constraints/attachments.h"
#include "world_internal.h"

namespace weft {
namespace {

Result find_cloth_and_body(const World* world, ClothId cloth, BodyId body) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
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

Result bind_skin_constraints(World* world, ClothId cloth, BodyId body, const SkinConstraints& skin) {
    if (Result r = find_cloth_and_body(world, cloth, body); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (skin.count == 0) {
        c.skin = {};
        c.skin_body = ~0u;
        return {};
    }
    const BodyState& b = world->bodies[body.index];
    const ClothAsset& a = *c.asset;
    if (skin.particle == nullptr || skin.triangle == nullptr || skin.weight == nullptr || skin.rest_offset_m == nullptr ||
        skin.max_distance_m == nullptr || skin.backstop_m == nullptr)
        return make_error(ErrorCode::invalid_argument, "a skin constraint array is null");
    if (skin.count > a.particle_count)
        return make_error(ErrorCode::out_of_range, "%u skin constraints for %u particles", skin.count, a.particle_count);
    // Each particle at most once (two lanes of one SIMD group writing one particle would make the
    // paths differ): marked in the world's validation scratch, [max_particles] >= particle_count.
    uint32_t* seen = world->validation_scratch;
    std::memset(seen, 0, sizeof(uint32_t) * a.particle_count);
    for (uint32_t k = 0; k < skin.count; ++k) {
        const uint32_t particle = skin.particle[k];
        if (particle >= a.particle_count)
            return make_error(ErrorCode::out_of_range, "skin constraint %u names particle %u of %u", k, particle,
                              a.particle_count);
        if (seen[particle]++ != 0)
            return make_error(ErrorCode::invalid_argument, "particle %u has two skin constraints", particle);
        if (c.particles.inverse_mass[a.slot_of_particle[particle]] == 0.0f)
            return make_error(ErrorCode::invalid_argument, "skin constraint %u: particle %u is pinned", k, particle);
        if (skin.triangle[k] >= b.triangle_count)
            return make_error(ErrorCode::out_of_range, "skin constraint %u names body triangle %u of %u", k,
                              skin.triangle[k], b.triangle_count);
        const float* w = skin.weight + 3 * k;
        if (!std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]) ||
            std::fabs(w[0] + w[1] + w[2] - 1.0f) > 1e-3f)
            return make_error(ErrorCode::invalid_argument, "skin constraint %u: weights not finite or not summing to 1", k);
        if (!std::isfinite(skin.rest_offset_m[k]) || !std::isfinite(skin.max_distance_m[k]) ||
            !std::isfinite(skin.backstop_m[k]))
            return make_error(ErrorCode::non_finite, "skin constraint %u: a distance is not finite", k);
        if (skin.max_distance_m[k] < 0.0f)
            return make_error(ErrorCode::out_of_range, "skin constraint %u: max distance %g m < 0", k,
                              double(skin.max_distance_m[k]));
    }
    c.skin = skin;
    c.skin_body = body.index;
    return {};
}

}  // namespace weft
