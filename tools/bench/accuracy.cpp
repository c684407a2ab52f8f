#include "bench/accuracy.h"

#include <time.h>

#include <chrono>
#include <cmath>
#include <limits>
#include "weft/debug.h"

namespace weft::bench {

using Clock = std::chrono::steady_clock;

namespace {

double thread_cpu_us() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e6 + double(t.tv_nsec) * 1e-3;
}

double wall_us() { return std::chrono::duration<double, std::micro>(Clock::now().time_since_epoch()).count(); }

}  // namespace

void StepClock::start() {
    wall_start_us_ = wall_us();
    cpu_start_us_ = thread_cpu_us();
}

void StepClock::stop(std::vector<double>* cpu_us, std::vector<double>* wall) const {
    const double cpu_end = thread_cpu_us();
    const double wall_end = wall_us();
    cpu_us->push_back(cpu_end - cpu_start_us_);
    wall->push_back(wall_end - wall_start_us_);
}

std::string run_trajectory(scenes::SeedScene scene, const scenes::SceneOptions& options, const Sampling& sampling,
                           Trajectory* out) {
    *out = Trajectory{};
    scenes::SeedWorld sw;
    if (std::string err = scenes::make_seed_world(scene, options, &sw); !err.empty()) return err;
    const std::vector<ColliderDesc> colliders = scenes::seed_scene(scene, options).colliders;
    const uint32_t count = sw.asset().particle_count;
    out->start.resize(count);
    if (Result r = read_positions(sw.world, sw.cloth, out->start.data(), count); !r.ok()) return r.message;
    out->step_us.reserve(sampling.frames);
    out->step_wall_us.reserve(sampling.frames);
    StepClock clock;
    for (uint32_t frame = 1; frame <= sampling.frames; ++frame) {
        clock.start();
        const Result r = step(sw.world, sw.dt_s);
        clock.stop(&out->step_us, &out->step_wall_us);
        if (!r.ok()) return std::string("step failed: ") + r.message;
        if (!sampling.sampled(frame)) continue;
        std::vector<Vec3> positions(count);
        if (Result rr = read_positions(sw.world, sw.cloth, positions.data(), count); !rr.ok()) return rr.message;
        for (const Vec3& p : positions) out->finite = out->finite && std::isfinite(p.x + p.y + p.z);
        if (!colliders.empty()) {
            ClothView view;
            if (Result rv = view_cloth(sw.world, sw.cloth, &view); !rv.ok()) return rv.message;
            out->max_penetration_m = std::max(
                out->max_penetration_m, metrics::max_penetration_m(view, colliders.data(), uint32_t(colliders.size())));
        }
        out->frames.push_back(std::move(positions));
    }
    return {};
}

scenes::SceneOptions plain_split(const scenes::SceneOptions& physics, uint32_t substeps, uint32_t iterations) {
    scenes::SceneOptions o = physics;
    scenes::apply_config(scenes::Config::plain, substeps * iterations, o);
    o.substeps = substeps;
    o.iterations = iterations;
    return o;
}

std::string compute_reference(scenes::SeedScene scene, const scenes::SceneOptions& physics, const Sampling& sampling,
                              const ReferenceOptions& options, Reference* out) {
    return compute_reference(
        [&](uint32_t substeps, uint32_t iterations, Trajectory* run) {
            return run_trajectory(scene, plain_split(physics, substeps, iterations), sampling, run);
        },
        options, out);
}

std::string compute_reference(const RunPlain& run_plain, const ReferenceOptions& options, Reference* out) {
    *out = Reference{};
    Trajectory previous;
    const uint32_t iterations = 1;
    uint32_t substeps = 1;
    for (;;) {
        Trajectory run;
        const auto t0 = Clock::now();
        if (std::string err = run_plain(substeps, iterations, &run); !err.empty()) return err;
        ReferenceStep step;
        step.substeps = substeps;
        step.iterations = iterations;
        step.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        if (out->diagonal_m == 0.0) out->diagonal_m = metrics::diagonal_m(run.start);
        step.change = previous.frames.empty() ? std::numeric_limits<double>::infinity()
                                              : metrics::trajectory_error(run.frames, previous.frames, out->diagonal_m);
        out->steps.push_back(step);
        out->substeps = substeps;
        out->iterations = iterations;
        out->change = step.change;
        out->converged = step.change < options.tolerance;
        previous = std::move(run);
        if (out->converged || substeps * 2 > options.max_substeps) break;
        substeps *= 2;
    }
    out->trajectory = std::move(previous);
    return {};
}

std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& error) {
    std::vector<bool> front(time.size(), false);
    for (size_t i = 0; i < time.size(); ++i) {
        if (!std::isfinite(error[i])) continue;
        bool beaten = false;
        for (size_t j = 0; j < time.size() && !beaten; ++j) {
            if (j == i || !std::isfinite(error[j])) continue;
            const bool no_worse = time[j] <= time[i] && error[j] <= error[i];
            const bool better = time[j] < time[i] || error[j] < error[i];
            beaten = no_worse && better;
        }
        front[i] = !beaten;
    }
    return front;
}

}  // namespace weft::bench
