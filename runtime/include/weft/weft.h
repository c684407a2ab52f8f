// Weft: real-time cloth. The one header a game's frame needs: load assets, create a world, add
// cloths, bodies and colliders, step, read positions and normals. Cooking tools add weft/cook.h
// (Weft::cook); profilers, debug views and tests add weft/debug.h; C callers use weft/weft_c.h.
#pragma once

#include "weft/asset_file.h"
#include "weft/asset_view.h"
#include "weft/attachments.h"
#include "weft/body.h"
#include "weft/types.h"
#include "weft/world.h"
