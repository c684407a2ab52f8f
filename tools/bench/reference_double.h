// A double-precision scalar solver of the seed's plain method (explicit split, relaxation 1, no
// tethers, no coarse level, hard or compliant springs at one iteration per substep) for the drape,
// which has no collider and no wind: the runtime's step (runtime/src/step.cpp) term for term - Verlet
// with exp(-d h) damping and the half h^2 first substep (integrate/verlet.h), then every spring in
// the asset's batch order (constraints/distance.h, exact projection) - with positions, velocities
// and rest lengths in double. It lives in tools/bench only (never in runtime/): it answers what
// limits the float references' convergence (docs/accuracy.md), and gives the drape a reference
// beyond the runtime's 64 substeps per step.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/accuracy.h"

namespace weft::bench {

// Runs the drape of `physics` (its n, damping and compliance) at `substeps` x 1 for `sampling`.
// `perturb_m` moves every free particle's start by up to that much along x, y and z (a fixed
// pseudo-random pattern): how far a run's trajectory depends on its rounding.
std::string run_drape_double(const scenes::SceneOptions& physics, uint32_t substeps, const Sampling& sampling,
                             Trajectory* out, double perturb_m = 0.0);

}  // namespace weft::bench

namespace weft::bench {

// weft-bench reference drape [--sizes 25] [--frames 330] [--cap 4096]: for substeps doubled from
// 1 at 1 iteration, the double solver's change between doublings, and the float runtime's distance
// from the double solver at the same split (up to the runtime's 64): float rounding shows in the
// second, the order of convergence in the first; and the double run against itself with the start
// moved by `perturb_m` (sensitivity to rounding-sized changes). Trajectory errors, as the sweep's.
struct ReferenceStudyOptions {
    std::vector<uint32_t> sizes{25};
    Sampling sampling;
    uint32_t cap = 4096;
    float compliance_m_per_n[3] = {0.0f, 0.0f, 0.0f};  // stretch, shear, bend (default hard, as the sweep)
    double perturb_m = 1e-9;  // the sensitivity column: the double run with its start moved this much
    bool json = false;
};
int run_reference_study(const ReferenceStudyOptions& options);

// weft-bench reference sphere: the float runtime only (no double solver of the collision here), for
// substeps doubled from 1 to 64: the change between doublings, and the run against itself dropped
// `offset_m` off-centre (sensitivity to a rounding-sized change of the start).
int run_sphere_sensitivity(const ReferenceStudyOptions& options, float offset_m);

}  // namespace weft::bench
