// weft-bench garment: the dressed garments on their animated bodies (issue 13, point 8).
#pragma once

#include <cstdint>

namespace weft::bench {

// Bakes the sample skirt and tee onto the mannequin (and the shared pencil dress onto mean_all when
// ../shared/data is there), runs their scene files and prints per-pass costs per step, the plain
// Embree point-query baseline measured in the same run, and the deepest penetration.
int run_garment(uint32_t steps, bool as_json);

}  // namespace weft::bench
