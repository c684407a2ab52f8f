// The whole bake, pattern text to asset bytes, one call per stage:
//   parse_pattern (pattern.h: Weft JSON or GarmentCode) -> mesh_garment (garment.h: seed 4.1,
//   CGAL) -> cook_cloth (runtime: springs, slots, runs, colours, tethers, coarse level) ->
//   write_asset (lib/common/asset_writer.h: docs/asset-format.md) -> load_asset_copy (the
//   runtime's validating loader reads the bytes back: what it refuses is never written).
// weft-bake is the command line around it; tests call it directly.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "bake/garment.h"
#include "bake/pattern.h"
#include "bake/sew.h"
#include "weft/weft.h"
#include "weft/cook.h"

namespace weft::bake {

struct BakeOptions {
    ParseOptions parse;
    MeshOptions mesh;
    CookOptions cook;
    // Cook the garment with each of kRunChoices' (min_run_lanes, max_run_gap) as well as `cook`'s
    // own, and keep the best by cook_score (padding budget, then run_cost_ns); false: `cook` as given.
    bool choose_runs = true;
    // Called before each stage with its name and number (weft-bake's progress bar); may be empty.
    std::function<void(const char* stage, uint32_t index, uint32_t count)> on_stage;
    // Sew the garment onto this body and store the dressed pose (sew.h); null: the flat bake.
    const SewBody* body = nullptr;
    SewOptions sew;
    // A render mesh bound to the cooked cloth (bind_render_mesh), authored in the space of the
    // asset's start pose (the flat layout, or the dressed pose with `body`); null: none, unless
    // render_subdivide >= 0 makes one from the cloth's own triangles (subdivide_cloth_mesh).
    const RenderMeshSource* render_mesh = nullptr;
    int render_subdivide = -1;
    // Layered garments (weft-bake --over): patterns (their JSON text) worn under this one, innermost
    // first. Each is baked on `body` as weft-bake bakes it alone (each over those before it, with
    // these options but no render mesh), and this garment is sewn and draped over them
    // (SewOptions::worn_over). Needs `body`.
    std::vector<std::string> over_patterns;
};

// Run shapes the baker tries (BakeOptions::choose_runs): {min_run_lanes, max_run_gap}.
inline constexpr uint32_t kRunChoices[][2] = {{16, 4}, {8, 2}, {8, 4}, {8, 6}, {8, 12}};

// The constraint pass's estimated cost per sweep, ns (weft/cook.h: kRunLaneNs, kIndexedLaneNs).
double run_cost_ns(const ClothAsset& asset);

// The padding budget: a trial that pads more than this share of its constraint pass's lanes, or of
// all its batched lanes (lane_padding), loses to any trial within it, whatever their costs. On the
// tee the cheapest trial pads its constraint pass 12.2%; the cheapest within 10% costs 4% more.
inline constexpr double kMaxPaddingRatio = 0.10;

// How the baker ranks its trials: within the padding budget first, then by run_cost_ns.
struct CookScore {
    bool over_padding_budget = false;
    double cost_ns = 0.0;
    bool operator<(const CookScore& o) const {
        return over_padding_budget != o.over_padding_budget ? !over_padding_budget : cost_ns < o.cost_ns;
    }
};
CookScore cook_score(const ClothAsset& asset);

// cook_cloth(mesh, cook), and with `choose_runs` also each of kRunChoices' run shapes: the best by
// cook_score is kept (the first on ties), its options in *chosen (optional).
Result cook_garment(const ClothMeshDesc& mesh, const CookOptions& cook, bool choose_runs, CookedCloth* out,
                    CookOptions* chosen = nullptr);

// cook_garment over each lattice packing of `g` (MeshedGarment::lattice, then lattice_alternatives,
// each with its plane stride) in `mesh`: the best by cook_score is kept (the first on ties);
// *winner is 0 for g.lattice, k + 1 for alternative k. bake_pattern's cook step.
Result cook_packings(const ClothMeshDesc& mesh, const MeshedGarment& g, const CookOptions& cook, bool choose_runs,
                     CookedCloth* out, CookOptions* chosen, size_t* winner);

// A waistline ("lower_interface") is bound to the body only when no part of the garment is placed
// more than this above it: bound under the pencil dress's bodice, it held the dress at the waist as
// well as at the shoulders and stretched its straps 109% (60% hanging from the shoulders alone).
inline constexpr float kWaistHeldBelow_m = 0.10f;

struct Baked {
    Pattern pattern;
    MeshedGarment garment;
    CookedCloth cooked;
    SewnGarment sewn;              // with BakeOptions::body: the sewn, dressed garment
    SewReport sew_report;
    CookOptions cook_options;      // what `cooked` was cooked with (BakeOptions::choose_runs)
    double render_bind_error_m = 0.0;  // with a render mesh: the largest vertex - reconstruction at rest
    std::vector<std::byte> bytes;  // the asset file
};

Status bake_pattern(std::string_view pattern_json, const BakeOptions& options, Baked* out);

// A folder's patterns, sorted by file name: every *_specification.json when there is one
// (GarmentCode keeps other JSON beside its specifications), else every *.json. An empty list and
// *error set when the folder cannot be read.
std::vector<std::string> pattern_files(const std::string& folder, std::string* error);
// A pattern's asset name: its file name without "_specification.json" (GarmentCode) or ".json".
std::string asset_name(const std::string& pattern_path);

}  // namespace weft::bake
