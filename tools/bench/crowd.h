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
    // The frame budget (set_frame_budget_us), priority by nearness to a camera in front of the
    // crowd; > 0: each thread count also runs the crowd with it, to compare. 0: off.
    float budget_us = 0.0f;
    bool json = false;
};

// Dresses the sample skirt and tee on the mannequin (weft-bake --body), builds one crowd per thread
// count and steps them in turn, frame by frame; prints each one's median and 99th percentile step
// time and checks that every thread count gives the same bits. With a budget, each thread count
// also steps a budgeted crowd in the same turn, and the budget's rows give the time saved and each
// instance's strain (lib/common/metrics.h) with the budget against without it.
int run_crowd(const CrowdBenchOptions& options);

}  // namespace weft::bench
