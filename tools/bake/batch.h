// weft-bake's batches: a folder of patterns or a manifest (docs/pattern-format.md, "Baking many
// patterns") read into one entry per asset, each with the options it bakes with.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "weft/weft.h"

namespace weft::bake {

// One asset to bake and how: weft-bake's per-pattern options.
struct BatchEntry {
    std::string name;     // the asset: OUT_DIR/<name>.weft
    std::string pattern;  // the pattern file
    std::string body;     // OBJ / glTF / "mannequin" to sew onto; empty: the flat bake
    double target_edge_m = 0.0;  // 0: the pattern's, else 0.02
    uint32_t simd_width = kSimdWidth;
    uint32_t sweeps = 8;
    std::array<double, 3> offset_m{};  // added to every panel's placement (GarmentCode v1)
    std::string manifest;  // the manifest that names it (a depfile dependency); empty for a folder
    std::string render_mesh;   // OBJ / glTF render mesh in the start pose's space (one pattern only)
    int render_subdivide = -1;  // >= 0: the cloth's triangles subdivided that often as the render mesh
    // Patterns worn under it, innermost first (BakeOptions::over_patterns): dressed first on the same
    // body, this one sewn over them. Needs a body.
    std::vector<std::string> over;
};

// Whether `text` is a manifest: a JSON object whose "format" is "weft-bake-manifest".
bool is_manifest(std::string_view text);

// Every pattern in `folder` (pattern_files), each with `defaults`' options and its asset_name.
std::string read_folder(const std::string& folder, const BatchEntry& defaults, std::vector<BatchEntry>* out);

// The manifest's entries: paths relative to the manifest's folder; the manifest's "defaults", then
// each entry's own keys, over `defaults` (the command line's options). Refuses unknown keys, values
// out of range and two assets of one name, naming the entry.
std::string read_manifest(const std::string& path, std::string_view text, const BatchEntry& defaults,
                          std::vector<BatchEntry>* out);

}  // namespace weft::bake
