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

struct SkinConstraints;  // weft/cloth_asset.h (a cooking tool fills one: weft/cook.h)

// Binds the cloth's asset attachments to `body`. Refuses an asset without attachments, a triangle
// index past the body's, or an attached particle that is not pinned; nothing changes on failure.
// Moves the attached particles onto the body at once.
Result attach_cloth_to_body(World* world, ClothId cloth, BodyId body);

// Skin constraints (weft/cloth_asset.h: SkinConstraints documents the projection) keep free
// particles near their skinned position on the body and in front of its surface, with no search.
//
//   attach_cloth_to_body(world, cloth_id, body_id);          // if the asset has attachments
//   bind_asset_skin_constraints(world, cloth_id, body_id);   // the skin constraints weft-bake baked
//
// Binds the cloth's asset skin constraints (ClothAsset::skin) to `body`, the body (its triangles)
// the garment was dressed on. Refuses an asset without them, a triangle past the body's, a
// particle pinned since; nothing changes on failure. Nothing is moved at once.
Result bind_asset_skin_constraints(World* world, ClothId cloth, BodyId body);

// Binds skin constraints to a cloth and a body. The arrays are copied, in slot order, into the room
// WorldDesc::max_skin_constraints reserved (capacity_exceeded when it is used up); the caller may
// free them after the call. Refuses a triangle past the body's, a particle past the
// cloth's, pinned or bound twice, weights or distances that are not finite, a negative max
// distance; nothing changes on failure. A cloth has at most one binding (a new call replaces it);
// `count` 0 removes it. Nothing is moved at once: the next substep projects.
Result bind_skin_constraints(World* world, ClothId cloth, BodyId body, const SkinConstraints& skin);

// Puts a dressed cloth back at its dressed pose on its body as the body is now (a respawn, a cut to
// another animation): every particle its skin constraints bind at its skinned position (the point
// at its weights on the offset hull, moved out by its rest offset), its attached particles on their
// triangles, the rest at the asset's start pose; at rest. Pose the body first (teleport_body for a
// jump). Refuses a cloth with neither skin constraints nor attachments: nothing says where on the
// body it goes (reset_cloth, teleport_cloth).
Result reset_to_pose(World* world, ClothId cloth);

}  // namespace weft
