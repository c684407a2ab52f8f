// Run time against error (docs/accuracy.md): a scene's trajectory sampled every few frames, the
// converged reference it is compared with, and the Pareto front of time against error.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/metrics.h"
#include "common/seed_scenes.h"

namespace weft::bench {

// Which frames a trajectory keeps: every `sample_every`-th of `frames`, and always the last one.
struct Sampling {
    uint32_t frames = 330;  // steps of dt 0.033 s (10.9 s: the drape and the sphere come to rest)
    uint32_t sample_every = 10;
    bool sampled(uint32_t frame) const {  // frame = steps taken, 1..frames
        return frame == frames || (sample_every > 0 && frame % sample_every == 0);
    }
};

// Times one step two ways: the CPU time of the calling thread, which does not count the time slices
// other processes take on a shared machine (a step that outlasts a scheduler slice is otherwise
// inflated several times over: measured 10 ms wall for a 2.5 ms step at load 7 on 2 cores), and the
// wall time. Both solvers are single-threaded, so CPU time is their cost.
class StepClock {
public:
    void start();
    void stop(std::vector<double>* cpu_us, std::vector<double>* wall_us) const;

private:
    double cpu_start_us_ = 0.0, wall_start_us_ = 0.0;
};

// One run of a scene: the sampled positions (caller order) and the time of every step.
struct Trajectory {
    std::vector<Vec3> start;         // positions before the first step
    metrics::Frames frames;          // after each sampled step
    std::vector<double> step_us;     // CPU time of the stepping thread per step() call, microseconds
    std::vector<double> step_wall_us;  // wall time of the same
    double max_penetration_m = 0.0;  // deepest inside a collider over the sampled frames
    bool finite = true;
};

// Runs a seed scene for `sampling.frames` steps; returns the failure message (empty on success).
std::string run_trajectory(scenes::SeedScene scene, const scenes::SceneOptions& options, const Sampling& sampling,
                           Trajectory* out);

// The converged reference (acceptance point 2): the same model (the seed's plain method: explicit
// split, relaxation 1, no tethers, no coarse level; same physics) with its substeps doubled from 1,
// at 1 iteration per substep, until the trajectory moves by less than `tolerance` (trajectory error
// between two doublings) or the cap is reached. Measured on the drape (docs/accuracy.md):
//   - iterations are not doubled: the runtime does not accumulate the XPBD multiplier across
//     iterations (constraints/distance.h), so with compliant springs more iterations make them
//     stiffer, a different model; with hard springs more iterations drive the grid towards its
//     locked limit (every spring rigid: a rigid plate), and the change between doublings grows
//     again (n = 25: 0.0025 at 64 x 2, 0.010 at 64 x 64). With 1 iteration per substep the
//     sequence converges at first order (the change halves with each doubling).
//   - the cap is the runtime's 64 substeps per step: splitting a frame into shorter steps does not
//     refine further, because float positions then lose gravity's g h^2 to rounding (at 512
//     substeps per 0.033 s the 2 m high drape does not fall at all).
//   - past the cap nothing converges either: a double-precision solver of the same model
//     (reference_double.h) stops at the same change, because from about 64 substeps on the run
//     amplifies a 1e-9 m change of its start to 1e-3 of the diagonal (docs/accuracy.md).
// The 1e-4 tolerance is therefore not reached at the cap; the last change is reported with every
// result and bounds the reference's own error (first-order convergence: about equal to it).
struct ReferenceOptions {
    uint32_t max_substeps = 64;
    double tolerance = 1e-4;
};
struct ReferenceStep {
    uint32_t substeps = 0, iterations = 0;
    double change = 0.0;  // trajectory error against the previous doubling (infinite for the first)
    double seconds = 0.0;  // wall time of the run
};
struct Reference {
    Trajectory trajectory;  // of the last run
    uint32_t substeps = 0, iterations = 0;  // its budget (substeps per frame)
    bool converged = false;
    double change = 0.0;  // the last doubling's change
    double diagonal_m = 0.0;  // of the start pose: the errors' length scale
    std::vector<ReferenceStep> steps;
};
std::string compute_reference(scenes::SeedScene scene, const scenes::SceneOptions& physics, const Sampling& sampling,
                              const ReferenceOptions& options, Reference* out);
// The same for any scene: `run_plain(substeps, iterations, out)` runs it with the plain method at
// that split (the garment: garment_sweep.h).
using RunPlain = std::function<std::string(uint32_t substeps, uint32_t iterations, Trajectory* out)>;
std::string compute_reference(const RunPlain& run_plain, const ReferenceOptions& options, Reference* out);

// The seed's plain method at an explicit split, keeping every physical setting of `physics`.
scenes::SceneOptions plain_split(const scenes::SceneOptions& physics, uint32_t substeps, uint32_t iterations);

// Marks the points no other point beats in both time and error (lower is better in both).
std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& error);

}  // namespace weft::bench
