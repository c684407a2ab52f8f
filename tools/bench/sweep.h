// weft-bench sweep: run time against error over a grid of budgets (acceptance point 3).
//
// For every size (and, for the flag, every wind speed) the sweep computes the converged reference
// (accuracy.h), runs every configuration of the grid (iterations x substeps x tethers on/off; on the
// sphere, which has no pins and so no tethers, the coarse level on/off instead) on the chosen SIMD
// paths, and the Bullet peer at its position-iteration budgets, all measured with the same metrics
// against the same reference. It prints ms per step against each error, marks each solver's Pareto
// front, writes a CSV and optionally a gnuplot PNG, and with --budget-ms names the configuration with
// the least trajectory error that fits each budget.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bench/accuracy.h"

namespace weft::bench {

struct SweepOptions {
    scenes::SeedScene scene = scenes::SeedScene::drape;
    // The dressed garment instead (garment_sweep.h: the skirt on the walking mannequin, dt 1/60 s,
    // the fabric's own compliance and damping); `scene` and `sizes` are then unused.
    bool garment = false;
    std::vector<uint32_t> sizes{100};
    std::vector<float> winds_m_s{20.0f};  // flag only
    Sampling sampling;
    std::vector<uint32_t> iterations{1, 2, 3, 4, 8, 16, 32};
    std::vector<uint32_t> substeps{1, 2, 4};
    std::vector<bool> long_range{false, true};  // tethers (pinned scenes) or coarse level (sphere)
    std::vector<std::string> paths{"avx2"};
    bool peer = true;  // Bullet, when this build has it (drape, sphere and garment)
    bool peer_body = true;  // garment: Bullet collides with the body (off: its cloth alone, for its cost)
    float peer_voxel_m = 0.25f;  // Bullet's btSparseSdf voxel (its default 0.25 m), all scenes
    std::vector<uint32_t> peer_iterations{1, 2, 4, 8, 16, 32};
    ReferenceOptions reference;
    float friction = 0.5f;  // sphere
    // The fabric's XPBD compliance per spring kind (stretch, shear, bend), m/N: the model every
    // configuration and the reference run. Default: hard, the seed's model and Weft's default.
    float compliance_m_per_n[3] = {0.0f, 0.0f, 0.0f};
    uint32_t repeat = 1;    // timing runs per configuration; the median of their medians is reported
    std::vector<double> budgets_ms;  // --budget-ms
    bool json = false;
    std::string csv_path;   // empty: no CSV
    std::string plot_path;  // empty: no plot
};

// The --quick grid for tests: 2 x 2 configurations, one Bullet budget, a reference capped at 4 substeps.
void make_quick(SweepOptions& options);

// Runs the sweep; returns the process exit code.
int run_sweep(const SweepOptions& options);

}  // namespace weft::bench
