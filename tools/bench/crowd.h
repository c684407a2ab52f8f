// weft-bench crowd: many walking mannequins in skirt and tee, stepped on 1, 2, ... threads through
// the built-in thread pool (issue 23, point 2).
#pragma once

#include <cstdint>
#include <vector>

namespace weft::bench {

struct CrowdBenchOptions {
    uint32_t characters = 32;
    std::vector<uint32_t> threads = {1, 2};
    uint32_t frames = 120;  // measured, after the walk's 1 s ramp
    uint32_t standing = 0;        // characters that stand still in the dressed pose
    float sleep_speed_m_s = 0.0f;  // the cloths' ClothDesc::sleep_speed_m_s (0: never sleep)
    bool json = false;
};

// Dresses the sample skirt and tee on the mannequin (weft-bake --body), builds one crowd per thread
// count and steps them in turn, frame by frame; prints each one's median and 99th percentile step
// time and checks that every thread count gives the same bits.
int run_crowd(const CrowdBenchOptions& options);

}  // namespace weft::bench
