#include "bench/bench_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace weft::bench {
namespace {

using Clock = std::chrono::steady_clock;

double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double pos = q * double(sorted.size() - 1);
    const size_t lo = size_t(std::floor(pos)), hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - double(lo));
}

std::string make_world(const RunOptions& options, uint32_t n, SimdPath path, bool profile,
                       scenes::SeedWorld* world) {
    scenes::SceneOptions so = options.scene_options;
    so.n = n;
    so.simd = path;
    so.profile = profile;
    return scenes::make_seed_world(options.scene, so, world);
}

std::string step_checked(scenes::SeedWorld& sw) {
    const Result r = step(sw.world, sw.dt_s);
    return r.ok() ? std::string() : std::string("step failed: ") + r.message;
}

}  // namespace

double load_average_1min() {
    double load = -1.0;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &load) != 1) load = -1.0;
        std::fclose(f);
    }
    return load;
}

Summary summarise(std::vector<double> samples) {
    Summary s;
    if (samples.empty()) return s;
    std::sort(samples.begin(), samples.end());
    s.median = quantile(samples, 0.5);
    s.p10 = quantile(samples, 0.1);
    s.p90 = quantile(samples, 0.9);
    s.min = samples.front();
    s.mean = std::accumulate(samples.begin(), samples.end(), 0.0) / double(samples.size());
    return s;
}

namespace {

// One timed run, profile off: warm-up, then per-step times. Fills the asset figures and, when
// `keep_state`, the cloth metrics after the last step.
std::string timed_run(const RunOptions& options, uint32_t n, SimdPath path, bool keep_state, Measurement& m,
                      Summary* out) {
    scenes::SeedWorld sw;
    if (std::string err = make_world(options, n, path, false, &sw); !err.empty()) return err;
    const ClothAsset& a = sw.asset();
    m.particles = a.particle_count;
    m.springs = a.total_constraints();
    m.slots = a.slot_count;
    m.lanes = a.lane_count;
    m.batches = a.batch_count;
    m.colours = a.colour_count;
    m.constraints_on_runs = a.constraints_on_runs;
    m.coarse_nodes = a.coarse_node_count;
    if (Result r = cloth_solver_split(sw.world, sw.cloth, &m.split); !r.ok()) return r.message;

    for (uint32_t i = 0; i < options.warmup; ++i)
        if (std::string err = step_checked(sw); !err.empty()) return err;
    std::vector<double> samples;
    samples.reserve(options.steps);
    for (uint32_t i = 0; i < options.steps; ++i) {
        const auto t0 = Clock::now();
        const Result r = step(sw.world, sw.dt_s);
        const auto t1 = Clock::now();
        if (!r.ok()) return std::string("step failed: ") + r.message;
        samples.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    *out = summarise(std::move(samples));
    if (!keep_state) return {};

    ClothView view;
    if (Result r = view_cloth(sw.world, sw.cloth, &view); !r.ok()) return r.message;
    m.strain = metrics::stretch_strain(view);
    m.rest_speed = metrics::mean_speed(view);
    m.max_tether_excess = metrics::max_tether_excess(view);
    m.bounds = metrics::bounds(view);
    m.finite = m.bounds.finite && std::isfinite(m.strain.max);
    m.final_positions.resize(a.particle_count);
    if (Result r = read_positions(sw.world, sw.cloth, m.final_positions.data(), a.particle_count); !r.ok())
        return r.message;
    return {};
}

// One profiled run: per-step totals and per-pass medians from the deltas of WorldStats::pass_ns.
std::string profiled_run(const RunOptions& options, uint32_t n, SimdPath path, Summary* total,
                         std::array<double, kPassCount>* pass_us, std::array<bool, kPassCount>* present) {
    scenes::SeedWorld sw;
    if (std::string err = make_world(options, n, path, true, &sw); !err.empty()) return err;
    for (uint32_t i = 0; i < options.warmup; ++i)
        if (std::string err = step_checked(sw); !err.empty()) return err;
    std::vector<double> totals;
    std::array<std::vector<double>, kPassCount> passes;
    totals.reserve(options.steps);
    for (auto& p : passes) p.reserve(options.steps);
    WorldStats before = world_stats(sw.world);
    const WorldStats at_start = before;
    for (uint32_t i = 0; i < options.steps; ++i) {
        const auto t0 = Clock::now();
        const Result r = step(sw.world, sw.dt_s);
        const auto t1 = Clock::now();
        if (!r.ok()) return std::string("step failed: ") + r.message;
        totals.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
        const WorldStats after = world_stats(sw.world);
        for (int p = 0; p < kPassCount; ++p) passes[p].push_back(double(after.pass_ns[p] - before.pass_ns[p]) * 1e-3);
        before = after;
    }
    *total = summarise(std::move(totals));
    for (int p = 0; p < kPassCount; ++p) {
        (*pass_us)[p] = summarise(std::move(passes[p])).median;
        (*present)[p] = before.pass_ns[p] > at_start.pass_ns[p];
    }
    return {};
}

}  // namespace

std::string measure(const RunOptions& options, uint32_t n, SimdPath path, Measurement* out) {
    Measurement& m = *out;
    m = Measurement{};
    m.scene = options.scene;
    m.n = n;
    m.path = path;
    m.warmup = options.warmup;
    m.steps = options.steps;
    const uint32_t repeats = options.repeats > 0 ? options.repeats : 1;

    // Run 1, profile off, `repeats` times: the run with the lowest median is kept (other processes
    // only ever add time). The simulation is deterministic, so every repeat ends in the same state.
    for (uint32_t r = 0; r < repeats; ++r) {
        Summary s;
        if (std::string err = timed_run(options, n, path, r == 0, m, &s); !err.empty()) return err;
        m.repeat_medians_us.push_back(s.median);
        if (r == 0 || s.median < m.total_us.median) m.total_us = s;
    }

    // Run 2, profile on: per-pass costs, from the repeat with the lowest profiled median.
    if (options.passes) {
        for (uint32_t r = 0; r < repeats; ++r) {
            Summary total;
            std::array<double, kPassCount> pass_us{};
            std::array<bool, kPassCount> present{};
            if (std::string err = profiled_run(options, n, path, &total, &pass_us, &present); !err.empty()) return err;
            if (r == 0 || total.median < m.total_profiled_us.median) {
                m.total_profiled_us = total;
                m.pass_us = pass_us;
                m.pass_present = present;
            }
        }
        m.passes_measured = true;
    }
    return {};
}

}  // namespace weft::bench
