// Body attachments (weft/attachments.h): binding a cloth's asset attachments to a body.
#include "weft/attachments.h"

#include "constraints/attachments.h"
#include "world_internal.h"

namespace weft {

Result attach_cloth_to_body(World* world, ClothId cloth, BodyId body) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (cloth.index >= world->cloth_count)
        return make_error(ErrorCode::out_of_range, "cloth %u of %u", cloth.index, world->cloth_count);
    if (body.index >= world->body_count)
        return make_error(ErrorCode::out_of_range, "body %u of %u", body.index, world->body_count);
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

}  // namespace weft
