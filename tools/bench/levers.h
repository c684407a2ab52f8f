// The levers of docs/solver.md: every way of spending a fixed budget, measured at equal budget on
// the hanging drape and on the cloth dropped on a sphere, against the seed's plain method.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_run.h"

namespace weft::bench {

// The figure 8 scene's verdict (docs/solver.md): after the run the cloth is at rest (mean speed
// < 1 cm/s), nothing has fallen below y = -1 m, and the particle nearest the cloth's centre lies on
// the sphere: within 2 cm outside the inflated radius (on top when dropped centred, on the side when
// dropped off-centre).
struct SphereOutcome {
    Vec3 middle{};
    double middle_gap_m = 0.0;  // distance of the middle particle outside the inflated sphere
    bool stays = false;
};
SphereOutcome sphere_outcome(const Measurement& m, uint32_t n, float inflation_m);

struct Lever {
    std::string name;         // as in the docs table
    scenes::SceneOptions options;  // n, simd and profile are set by the runner
};
// The levers at `sweeps` sweeps per step.
std::vector<Lever> levers(uint32_t sweeps);

// Prints the table (or JSON lines) for the drape and the sphere at size n; returns an exit code.
int run_levers(uint32_t n, uint32_t sweeps, uint32_t steps, bool json);

}  // namespace weft::bench
