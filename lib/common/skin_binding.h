// Skin constraints for a scene's cloth dressed on its body (weft/attachments.h). An asset baked by
// weft-bake --body carries its binding (ClothAsset::skin), which bind_asset_skin_constraints binds;
// for an asset baked without one, bind_skin cooks it from the world just built (the cloth in its
// dressed start pose on the body's rest pose) with cook_skin_binding, the baker's own function.
#pragma once

#include <string>

#include "weft/attachments.h"
#include "weft/weft.h"
#include "weft/cook.h"

namespace weft::scenes {

// Cooks the binding of every free particle of `cloth` to `body` as they are now into `out` (which
// must outlive the cloth: the world points into it) and binds it. Empty on success, else why not.
std::string bind_skin(World* world, ClothId cloth, BodyId body, const SkinBindingOptions& options, SkinBinding* out);

}  // namespace weft::scenes
