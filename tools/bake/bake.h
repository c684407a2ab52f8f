// The whole bake, pattern text to asset bytes, one call per stage:
//   parse_pattern (pattern.h: Weft JSON or GarmentCode) -> mesh_garment (garment.h: seed 4.1,
//   CGAL) -> cook_cloth (runtime: springs, slots, runs, colours, tethers, coarse level) ->
//   write_asset (tools/common/asset_writer.h: docs/asset-format.md) -> load_asset_copy (the
//   runtime's validating loader reads the bytes back: what it refuses is never written).
// weft-bake is the command line around it; tests call it directly.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "garment.h"
#include "pattern.h"
#include "weft/weft.h"

namespace weft::bake {

struct BakeOptions {
    ParseOptions parse;
    MeshOptions mesh;
    CookOptions cook;
};

struct Baked {
    Pattern pattern;
    MeshedGarment garment;
    CookedCloth cooked;
    std::vector<std::byte> bytes;  // the asset file
};

Status bake_pattern(std::string_view pattern_json, const BakeOptions& options, Baked* out);

}  // namespace weft::bake
