// Validation of an asset's arrays (validate.cpp): what load_asset_in_place and add_cloth check
// before any pass reads them. No Embree, no world: the loader and cooking tools include it too.
#pragma once

#include <cstdint>

#include "weft/cloth_asset.h"

namespace weft {

// validate_asset with the caller's scratch (scratch_count words) instead of an allocation.
Result validate_asset_with_scratch(const ClothAsset& asset, uint32_t* scratch, uint32_t scratch_count);

}  // namespace weft
