// Body attachments and skin constraints: garment particles bound to body triangles (a waistband, a strap) that follow
// the body exactly. weft-bake --body binds a pattern's attachments to the body it dresses the
// garment on and stores them in the asset (ClothAsset::attached_*: particle, body triangle,
// barycentric weights on the triangle's offset hull); those particles are pinned in the asset.
//
//   add_body(world, body, &body_id); add_cloth(world, cloth, &cloth_id);
//   attach_cloth_to_body(world, cloth_id, body_id);   // the same body (its triangles) the asset names
//
// Every substep each attached particle is placed on its triangle of the body's offset hull at its
// weights, the hull moving linearly from the previous step's pose to the one set_body_vertices
// handed this step; nothing is allocated.
#pragma once

#include "weft/body.h"
#include "weft/world.h"

namespace weft {

// Binds the cloth's asset attachments to `body`. Refuses an asset without attachments, a triangle
// index past the body's, or an attached particle that is not pinned; nothing changes on failure.
// Moves the attached particles onto the body at once.
Result attach_cloth_to_body(World* world, ClothId cloth, BodyId body);

// Skin constraints (NvCloth's motion constraints and backstop, Jolt's skinned constraints): each
// bound free particle k stays within a ball around its skinned position and in front of the body's
// surface there. The skinned surface point P is body triangle triangle[k] of the offset hull at
// barycentric weights weight[3k..3k+2] (the hull interpolated from the previous step's pose to
// this one's, as attachments are), N the unit normal interpolated there from the hull's vertex
// normals (this step's pose). After the springs and tethers of every substep:
//   max distance: |x - (P + rest_offset_m N)| <= max_distance_m  (projected onto the ball)
//   backstop:     (x - P) . N >= -backstop_m                     (projected onto the half-space)
// The backstop is a half-space (a plane behind the hull point along N) rather than NvCloth's or
// Jolt's backstop sphere: on the thin limbs of a body a sphere large enough to be flat near the
// surface reaches through the limb (docs/decisions/2026-11-26-body-collision-models.md).
struct SkinConstraints {
    uint32_t count = 0;
    const uint32_t* particle = nullptr;     // [count] caller particles, free (inverse mass > 0), each once
    const uint32_t* triangle = nullptr;     // [count] body triangles
    const float* weight = nullptr;          // [3 * count] barycentric on the triangle, sum 1
    const float* rest_offset_m = nullptr;   // [count] signed distance of the particle along N at rest
    const float* max_distance_m = nullptr;  // [count] >= 0: radius of the ball around P + rest_offset_m N
    const float* backstop_m = nullptr;      // [count] how far behind the hull (along -N) the particle may go
};

// Binds skin constraints to a cloth and a body. The arrays are not copied (like an asset's): they
// must stay valid while the cloth exists. Refuses a triangle past the body's, a particle past the
// cloth's, pinned or bound twice, weights or distances that are not finite, a negative max
// distance; nothing changes on failure. A cloth has at most one binding (a new call replaces it);
// `count` 0 removes it. Nothing is moved at once: the next substep projects.
Result bind_skin_constraints(World* world, ClothId cloth, BodyId body, const SkinConstraints& skin);

}  // namespace weft
