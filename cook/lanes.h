// Distance constraints into lanes and batches (cook.cpp, steps 3 and 4): shared by the fine springs
// and the coarse level's constraints, so both are laid out, coloured and solved the same way.
#pragma once

#include <vector>

#include "weft/cook.h"

namespace weft {

struct Spring {
    uint32_t a, b;  // slots, a < b once ordered
    ConstraintKind kind;
    float rest;
};

// Where cook_lanes writes: one set of lane arrays and its batches.
struct LaneArrays {
    std::vector<float>& rest_length;
    std::vector<float>& lane_weight;
    std::vector<uint32_t>& index_a;
    std::vector<uint32_t>& index_b;
    std::vector<ConstraintBatch>& batches;
};

// Cuts `springs` (slots a < b, over `slot_count` slots) into runs (same kind and offset b - a,
// consecutive a, gaps bridged by padding lanes), colours runs and leftover springs into
// particle-disjoint colours and appends their lanes and batches to `out`. Returns the colour count;
// `on_runs` receives how many springs sit on runs.
uint32_t cook_lanes(std::vector<Spring> springs, uint32_t slot_count, const CookOptions& options, LaneArrays out,
                    uint32_t* on_runs);

// The highest slot (exclusive) any lane of these batches reads, padding included.
uint32_t slots_touched(const std::vector<ConstraintBatch>& batches, uint32_t slot_count);

}  // namespace weft
