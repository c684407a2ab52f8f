// weft-bench's measurement: one seed scene, one size, one SIMD path.
//
// Two runs of the same scene (each `repeats` times), each `warmup` untimed steps followed by
// `steps` timed ones:
//   1. totals: profiling off, one steady_clock read per step; the reported step time is the
//      median over the timed steps. The cloth metrics are read after this run's last step.
//   2. passes: set_profiling on (the runtime reads the clock around every pass); the per-pass
//      figures are medians of the per-step deltas of WorldStats::pass_ns. The total of this run is
//      kept too, so the profiling overhead is visible next to the unprofiled total.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/metrics.h"
#include "common/seed_scenes.h"
#include "weft/debug.h"

namespace weft::bench {

inline constexpr int kPassCount = static_cast<int>(Pass::count);

struct RunOptions {
    scenes::SeedScene scene = scenes::SeedScene::drape;
    scenes::SceneOptions scene_options;  // n and simd are set per measurement
    uint32_t warmup = 30;
    uint32_t steps = 300;
    bool passes = true;  // the second, profiled run
    uint32_t repeats = 1;  // independent runs of each kind; the one with the lowest median is kept
};

// Robust summary of a sample of per-step times, microseconds.
struct Summary {
    double median = 0.0, p10 = 0.0, p90 = 0.0, min = 0.0, mean = 0.0;
};
Summary summarise(std::vector<double> samples_us);

struct Measurement {
    scenes::SeedScene scene{};
    uint32_t n = 0;
    SimdPath path = SimdPath::scalar;
    uint32_t warmup = 0, steps = 0;

    // The asset.
    uint32_t particles = 0, springs = 0, slots = 0, lanes = 0, batches = 0, colours = 0;
    uint32_t constraints_on_runs = 0;
    uint32_t coarse_nodes = 0;
    SolverSplit split;  // how the runtime spends the budget (after the policy)

    Summary total_us;           // run 1, profile off (the repeat with the lowest median)
    std::vector<double> repeat_medians_us;  // the median of every repeat of run 1
    Summary total_profiled_us;  // run 2, profile on (zero when passes were not measured)
    std::array<double, kPassCount> pass_us{};     // median per-step cost of each pass (run 2)
    std::array<bool, kPassCount> pass_present{};  // the pass ran at all (accumulated > 0 ns)
    bool passes_measured = false;

    metrics::Strain strain;
    double rest_speed = 0.0;
    double max_tether_excess = 0.0;
    metrics::Bounds bounds;  // of the real particles, metres
    bool finite = true;
    std::vector<Vec3> final_positions;  // caller order, after run 1 (for the bit-identity check)
};

// The 1-minute load average (Linux), or a negative value when unknown. Other processes on the
// machine inflate the timings; the bench reports how busy it was instead of hiding it.
double load_average_1min();

// Returns the failure message (empty on success).
std::string measure(const RunOptions& options, uint32_t n, SimdPath path, Measurement* out);

}  // namespace weft::bench
