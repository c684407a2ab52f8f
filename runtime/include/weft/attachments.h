// Body attachments: garment particles bound to body triangles (a waistband, a strap) that follow
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

}  // namespace weft
