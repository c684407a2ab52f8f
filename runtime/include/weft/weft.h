// Weft: real-time cloth. Include this one header for the whole public API.
#pragma once

#include "weft/asset_file.h"
#include "weft/attachments.h"
#include "weft/body.h"
#include "weft/cloth_asset.h"
#include "weft/types.h"
#include "weft/world.h"
