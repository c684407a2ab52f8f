// Where a baked garment's constraint lanes go: on runs or not, and why; where its padding lanes
// come from. A diagnostic for the baker's layout work (docs/pattern-format.md), printed by
// `weft-bake PATTERN -o OUT --runs`.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "bake/garment.h"
#include "weft/cloth_asset.h"
#include "weft/cook.h"

namespace weft::bake {

struct RunReport {
    // Real constraints by kind: on runs, and off runs by cause.
    //   off_lattice: an end has no lattice node (a strip particle that found no free node)
    //   odd_family:  both ends on the lattice, but (di, dj) is none of the grid's families for that
    //                kind (strip springs of another shape)
    //   short_run:   a grid family, but its sequence of slots is shorter than min_run_lanes (or broken
    //                by a gap longer than max_run_gap)
    struct Kind {
        uint64_t on_runs = 0, off_lattice = 0, odd_family = 0, short_run = 0;
    };
    Kind kinds[kConstraintKindCount];
    // Lanes of the constraint runs: real, padding inside a run (gaps), padding at the end (round up).
    uint64_t run_lanes = 0, gap_lanes = 0, tail_lanes = 0, indexed_lanes = 0;
    uint64_t runs = 0;
    // Padding lanes inside runs by gap size, where the lanes on both sides belong to one panel or not.
    std::map<uint32_t, uint64_t> gaps_inside_panels, gaps_between_panels;
    std::map<std::string, uint64_t> odd_families;    // "kind(di,dj)" -> constraints
    std::map<uint32_t, uint64_t> short_run_lengths;  // length of the maximal sequence -> constraints
    uint64_t coarse_lanes = 0, coarse_padding_lanes = 0;
    // Wind: triangles on runs / gathered or one at a time, and the runs' padding lanes.
    uint64_t wind_run_triangles = 0, wind_single_triangles = 0, wind_padding_lanes = 0, wind_lanes = 0;
    uint64_t tether_lanes = 0, tether_padding_lanes = 0;
    uint64_t lattice_box = 0;  // slots of the four parity planes
    bool lattice_used = false;
};

RunReport run_report(const MeshedGarment& garment, const ClothAsset& asset, const CookOptions& options);
std::string format_run_report(const RunReport& report);

}  // namespace weft::bake
