// weft-bench: the seed paper's experiments (section 3) timed on the scalar and the SIMD path.
//
//   weft-bench drape  [--sizes 25,50,75,100,200,400] [--config both|default|plain] [--sweeps 3]
//                     [--iterations I] [--substeps S] [--steps 300] [--warmup 30] [--repeat 1]
//                     [--json] [--json-out FILE] [--no-tethers] [--no-passes] [--paths scalar,avx2]
//   weft-bench flag   [same] [--wind 20]
//   weft-bench sphere [same] [--budgets 3,4,6,10] [--friction 0.5] [--offset 0] [--inflation 0.01]
//   weft-bench passes [same]        every scene, to show which passes each one pays for
//   weft-bench levers [--size 100] [--sweeps 3] [--json]   docs/solver.md's table
//   weft-bench sweep SCENE [--sizes 100] [--wind 10,20,40] [--frames 330] [--budget-ms 0.25,0.5,1]
//                     [--json] [--csv FILE] [--plot FILE.png] [--quick] [--no-peer] ...
//                     run time against error, Weft's budgets and Bullet's (docs/accuracy.md)
//   weft-bench garment [--steps 300] [--json]                          dressed garments on animated bodies
//   weft-bench self [--frames 300] [--json]                             self-collision off and on
//   weft-bench corpus DIR [--body BODY] [--jobs N] [--json]        a folder of patterns, flat and sewn
//   weft-bench baked PATTERN.json ... [--iterations 10] [--repeat 5]   baked vs in-memory, ns per projection
//
// The budget is `--sweeps` spent by the runtime's automatic policy (config "default") or the seed's
// plain method (config "plain"); --iterations / --substeps give an explicit split instead.
// Single-threaded. Pin it for stable figures: taskset -c 1 weft-bench drape.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_run.h"
#include "bench/baked.h"
#include "bench/body.h"
#include "bench/crowd.h"
#include "bench/corpus.h"
#include "bench/garment.h"
#include "bench/self.h"
#include "bench/levers.h"
#include "bench/reference_double.h"
#include "bench/sweep.h"

namespace {

using namespace weft;
using weft::scenes::SeedScene;

// The seed paper's table (section 3): grid n -> step time in ms on a Pentium 4 2.4 GHz.
std::optional<double> paper_ms(SeedScene scene, uint32_t n) {
    if (scene != SeedScene::drape) return std::nullopt;
    switch (n) {
        case 25: return 2.0;
        case 50: return 9.4;
        case 75: return 17.3;
        case 100: return 33.4;
        default: return std::nullopt;
    }
}

struct CliOptions {
    std::vector<uint32_t> sizes;
    std::string config = "both";  // "default" (automatic budget policy), "plain" or both, one after the other
    uint32_t sweeps = 3;             // the budget: passes over every constraint per step
    std::vector<uint32_t> budgets;   // several budgets (sweeps) in one run; empty: just `sweeps`
    float friction = 0.5f;           // sphere: Coulomb friction of the sphere
    float offset_m = 0.0f;           // sphere: drop point off the sphere's top, along x
    uint32_t iterations = 0;         // with substeps: an explicit split (0 = the config's)
    uint32_t substeps = 0;
    uint32_t coarse_iterations = 1;  // coarse sweeps per substep, explicit split
    float relaxation = 1.0f;         // spring correction scale, explicit split
    uint32_t steps = 300;
    uint32_t warmup = 30;
    uint32_t repeat = 1;
    bool json = false;
    bool no_tethers = false;
    bool contact_tethers = false;     // ClothDesc::contact_tethers on (the config's otherwise)
    bool no_contact_tethers = false;  // ... off
    bool no_passes = false;
    std::string json_out;  // also append the JSON lines to this file
    std::vector<std::string> paths{"scalar", "avx2"};
    float wind_m_s = 20.0f;
    float inflation_m = 0.01f;
};

void add_common_options(CLI::App* app, CliOptions& o) {
    app->add_option("--sizes", o.sizes, "grid sizes n (n x n particles), comma separated")
        ->delimiter(',')
        ->check(CLI::Range(2u, 4096u))
        ->capture_default_str();
    app->add_option("--config", o.config,
                    "default: the runtime's defaults and automatic budget policy; plain: the seed's method "
                    "(1 substep, no tethers, no coarse level); both: plain, then default")
        ->check(CLI::IsMember({"both", "default", "plain"}))
        ->capture_default_str();
    app->add_option("--sweeps", o.sweeps, "solver budget: passes over every constraint per step")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    app->add_option("--iterations", o.iterations,
                    "constraint sweeps per substep; with --iterations or --substeps the split is explicit "
                    "(sweeps = substeps x iterations) instead of the policy's")
        ->check(CLI::Range(1u, 1000u));
    app->add_option("--substeps", o.substeps, "Verlet substeps per step (explicit split, default 1)")
        ->check(CLI::Range(1u, 64u));
    app->add_option("--coarse-iterations", o.coarse_iterations,
                    "coarse-level sweeps per substep (explicit split, default 1)")
        ->check(CLI::Range(1u, 16u));
    app->add_option("--relaxation", o.relaxation, "scales every spring correction (explicit split, default 1)")
        ->check(CLI::Range(kMinRelaxation, kMaxRelaxation));
    app->add_option("--steps", o.steps, "timed steps (the median is reported)")
        ->check(CLI::Range(1u, 10000000u))
        ->capture_default_str();
    app->add_option("--warmup", o.warmup, "untimed steps before timing")->capture_default_str();
    app->add_option("--repeat", o.repeat, "independent runs per size and path; the lowest median is reported")
        ->check(CLI::Range(1u, 100u))
        ->capture_default_str();
    app->add_option("--paths", o.paths, "SIMD paths to run: scalar, avx2")
        ->delimiter(',')
        ->check(CLI::IsMember({"scalar", "avx2"}))
        ->capture_default_str();
    app->add_flag("--json", o.json, "one JSON object per line (per size x path)");
    app->add_option("--json-out", o.json_out, "also append the JSON lines to this file (with the tables on stdout)");
    app->add_flag("--no-tethers", o.no_tethers, "disable the long-range attachments");
    app->add_flag("--contact-tethers", o.contact_tethers, "tethers to coarse nodes in contact (ClothDesc::contact_tethers)");
    app->add_flag("--no-contact-tethers", o.no_contact_tethers, "no tethers to coarse nodes in contact");
    app->add_flag("--no-passes", o.no_passes, "skip the second, profiled run (no per-pass costs)");
}

bool explicit_split(const CliOptions& o) { return o.iterations > 0 || o.substeps > 0; }

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// Rounds to `digits` decimals so the JSON prints short numbers (nlohmann prints the shortest
// representation that reads back to the same double).
double round_to(double v, int digits) {
    const double scale = std::pow(10.0, digits);
    return std::round(v * scale) / scale;
}

bool bit_identical(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

// Results of one scene at one size: index 0 scalar, 1 avx2 (either may be missing).
struct SizeResult {
    uint32_t n = 0;
    std::optional<bench::Measurement> path[2];
};

nlohmann::ordered_json to_json(const bench::Measurement& m, const CliOptions& o, const bench::Measurement* scalar) {
    nlohmann::ordered_json j;
    const auto paper = paper_ms(m.scene, m.n);
    j["scene"] = scenes::scene_name(m.scene);
    j["n"] = m.n;
    j["particles"] = m.particles;
    j["springs"] = m.springs;
    // The split the runtime actually ran (the automatic policy picks it from the budget).
    j["iterations"] = m.split.iterations;
    j["substeps"] = m.split.substeps;
    j["simd"] = simd_path_name(m.path);
    j["config"] = o.config;
    j["policy"] = explicit_split(o) ? "explicit_split" : "automatic";
    j["sweeps"] = explicit_split(o) ? m.split.substeps * m.split.iterations : o.sweeps;  // the budget asked for
    j["relaxation"] = round_to(m.split.relaxation, 4);
    j["tethers"] = m.split.tethers;
    j["coarse_level"] = m.split.coarse_level;
    j["coarse_iterations"] = m.split.coarse_level ? m.split.coarse_iterations : 0;
    j["coarse_nodes"] = m.coarse_nodes;
    if (m.scene == SeedScene::flag) j["wind_m_s"] = round_to(o.wind_m_s, 3);
    if (m.scene == SeedScene::sphere) {
        const bench::SphereOutcome outcome = bench::sphere_outcome(m, m.n, o.inflation_m);
        j["inflation_m"] = round_to(o.inflation_m, 6);
        j["friction"] = round_to(o.friction, 4);
        j["offset_m"] = round_to(o.offset_m, 4);
        j["middle_y"] = round_to(outcome.middle.y, 4);
        j["middle_gap_m"] = round_to(outcome.middle_gap_m, 5);
        j["stays"] = outcome.stays;
    }
    j["warmup"] = m.warmup;
    j["steps"] = m.steps;
    j["us_per_step"] = round_to(m.total_us.median, 2);
    j["repeats"] = m.repeat_medians_us.size();
    if (m.repeat_medians_us.size() > 1) {
        nlohmann::ordered_json medians = nlohmann::ordered_json::array();
        for (double v : m.repeat_medians_us) medians.push_back(round_to(v, 2));
        j["us_per_step_repeats"] = medians;
    }
    j["us_p10"] = round_to(m.total_us.p10, 2);
    j["us_p90"] = round_to(m.total_us.p90, 2);
    j["us_min"] = round_to(m.total_us.min, 2);
    j["us_mean"] = round_to(m.total_us.mean, 2);
    j["per_particle_ns"] = round_to(m.total_us.median * 1e3 / m.particles, 3);
    j["max_strain"] = round_to(m.strain.max, 6);
    j["mean_strain"] = round_to(m.strain.mean, 6);
    j["rest_speed"] = round_to(m.rest_speed, 6);
    j["max_tether_excess"] = round_to(m.max_tether_excess, 6);
    j["min_y"] = round_to(m.bounds.min.y, 4);
    j["max_y"] = round_to(m.bounds.max.y, 4);
    j["finite"] = m.finite;
    if (paper) {
        j["paper_ms"] = *paper;
        j["speedup_vs_paper"] = round_to(*paper * 1e3 / m.total_us.median, 1);
    } else {
        j["paper_ms"] = nullptr;
        j["speedup_vs_paper"] = nullptr;
    }
    if (scalar && m.path != SimdPath::scalar) {
        j["speedup_vs_scalar"] = round_to(scalar->total_us.median / m.total_us.median, 2);
        j["identical_to_scalar"] = bit_identical(m.final_positions, scalar->final_positions);
    } else {
        j["speedup_vs_scalar"] = m.path == SimdPath::scalar ? nlohmann::ordered_json(1.0) : nullptr;
    }
    j["load_avg_1min"] = round_to(bench::load_average_1min(), 2);
    j["contiguous_fraction"] = round_to(double(m.constraints_on_runs) / double(m.springs), 6);
    j["slots"] = m.slots;
    j["constraint_lanes"] = m.lanes;
    j["batches"] = m.batches;
    j["colours"] = m.colours;
    // One "<pass>_us" field per pass the runtime has (Pass order = the order they run in a step).
    for (int i = 0; i < bench::kPassCount; ++i) {
        const std::string key = std::string(pass_name(Pass(i))) + "_us";
        if (m.passes_measured) {
            j[key] = round_to(m.pass_us[i], 2);
        } else {
            j[key] = nullptr;
        }
    }
    if (m.passes_measured) {
        nlohmann::ordered_json absent = nlohmann::ordered_json::array();
        for (int i = 0; i < bench::kPassCount; ++i)
            if (!m.pass_present[i]) absent.push_back(pass_name(Pass(i)));
        j["absent_passes"] = absent;
        j["us_per_step_profiled"] = round_to(m.total_profiled_us.median, 2);
        j["profile_overhead_pct"] = round_to(100.0 * (m.total_profiled_us.median / m.total_us.median - 1.0), 1);
    }
    return j;
}

void print_header(SeedScene scene, const CliOptions& o, const std::vector<SizeResult>& results) {
    const char* what = scene == SeedScene::drape    ? "2 m square cloth pinned at two corners"
                       : scene == SeedScene::flag   ? "2 m x 1.2 m flag pinned along its pole, wind along +x"
                                                    : "2 m square cloth dropped on a 0.5 m sphere";
    std::printf("weft-bench %s: %s; dt 0.033 s", scenes::scene_name(scene), what);
    if (scene == SeedScene::flag) std::printf(", wind %g m/s", double(o.wind_m_s));
    if (scene == SeedScene::sphere) std::printf(", inflation %g m", double(o.inflation_m));
    // The split as run (the same for every size unless the policy says otherwise).
    const SizeResult& first = results.front();
    const bench::Measurement& m = first.path[0] ? *first.path[0] : *first.path[1];
    // The budget asked for; the automatic policy may run fewer fine sweeps (2 x 1 of 3 on a collider).
    const bool explicit_budget = explicit_split(o) || o.config == "plain";
    std::printf("\nconfig %s, %s budget %u sweep(s): %u substep(s) x %u iteration(s), relaxation %g, tethers %s, "
                "coarse level %s",
                o.config.c_str(), explicit_budget ? "explicit" : "automatic",
                explicit_budget ? m.split.substeps * m.split.iterations : o.sweeps, m.split.substeps, m.split.iterations,
                double(m.split.relaxation), m.split.tethers ? "on" : "off", m.split.coarse_level ? "on" : "off");
    if (m.split.coarse_level) std::printf(" (%u sweep(s) a substep)", m.split.coarse_iterations);
    std::printf("\n");
    std::printf("single thread; %u warm-up steps, median of %u timed steps", o.warmup, o.steps);
    if (o.repeat > 1) std::printf(" (lowest of %u runs)", o.repeat);
    std::printf("; cloth metrics after step %u\n", o.warmup + o.steps);
    // Other processes (on this machine or, in a VM, on the host) only ever add time: say how busy it was.
    if (const double load = bench::load_average_1min(); load >= 0.0) std::printf("1-minute load average at the start: %.2f\n", load);
    std::printf("\n");
}

void print_table(SeedScene scene, const std::vector<SizeResult>& results) {
    std::printf("%5s %9s %8s %8s %10s %10s %7s %8s %8s %10s %11s %7s %8s\n", "n", "particles", "springs",
                "paper ms", "scalar us", "avx2 us", "simd x", "paper/sc", "paper/sd", "max strain",
                "mean strain", "on runs", "ns/part");
    bool mismatch = false;
    for (const SizeResult& r : results) {
        const bench::Measurement* s = r.path[0] ? &*r.path[0] : nullptr;
        const bench::Measurement* v = r.path[1] ? &*r.path[1] : nullptr;
        const bench::Measurement& any = s ? *s : *v;
        const auto paper = paper_ms(scene, r.n);
        const bool same = !(s && v) || bit_identical(s->final_positions, v->final_positions);
        mismatch |= !same;
        const bench::Measurement& best = v ? *v : *s;
        std::printf("%5u %9u %8u %8s %10s %10s %7s %8s %8s %10s%c %10s %6.1f%% %8s\n", r.n, any.particles, any.springs,
                    paper ? fmt("%.1f", *paper).c_str() : "-",
                    s ? fmt("%.1f", s->total_us.median).c_str() : "-",
                    v ? fmt("%.1f", v->total_us.median).c_str() : "-",
                    s && v ? fmt("%.2fx", s->total_us.median / v->total_us.median).c_str() : "-",
                    paper && s ? fmt("%.0fx", *paper * 1e3 / s->total_us.median).c_str() : "-",
                    paper && v ? fmt("%.0fx", *paper * 1e3 / v->total_us.median).c_str() : "-",
                    fmt("%.4f", any.strain.max).c_str(), same ? ' ' : '*', fmt("%.5f", any.strain.mean).c_str(),
                    100.0 * any.constraints_on_runs / any.springs,
                    fmt("%.2f", best.total_us.median * 1e3 / best.particles).c_str());
    }
    std::printf("\nsimd x = scalar / avx2 time; paper/sc, paper/sd = the paper's step time over ours (scalar, avx2);\n"
                "on runs = springs solved as contiguous SIMD runs; ns/part = fastest path per particle per step.\n");
    if (results.size() && results[0].path[0] && results[0].path[1])
        std::printf("avx2 final positions bit-identical to scalar: %s\n",
                    mismatch ? "NO (rows marked *; strain shown is scalar's)" : "yes, every size");
}

void print_passes(const std::vector<std::pair<SeedScene, std::vector<SizeResult>>>& all) {
    std::printf("\nper-pass cost, us/step (median over the timed steps of a profiled run; '-' = pass not in the step)\n");
    std::printf("%-7s %5s %-6s", "scene", "n", "path");
    for (int i = 0; i < bench::kPassCount; ++i) std::printf(" %11s", pass_name(Pass(i)));
    std::printf(" %10s %10s %9s\n", "profiled", "unprofiled", "overhead");
    for (const auto& [scene, results] : all) {
        for (const SizeResult& r : results) {
            for (const auto& m : r.path) {
                if (!m || !m->passes_measured) continue;
                std::printf("%-7s %5u %-6s", scenes::scene_name(scene), m->n, simd_path_name(m->path));
                for (int i = 0; i < bench::kPassCount; ++i)
                    std::printf(" %11s", m->pass_present[i] ? fmt("%.1f", m->pass_us[i]).c_str() : "-");
                std::printf(" %10.1f %10.1f %8.1f%%\n", m->total_profiled_us.median, m->total_us.median,
                            100.0 * (m->total_profiled_us.median / m->total_us.median - 1.0));
            }
        }
    }
}

void print_summary(const std::vector<std::pair<SeedScene, std::vector<SizeResult>>>& all) {
    std::printf("\ncloth state after the last step (scalar run; speed = mean particle speed over the last step)\n");
    std::printf("%-7s %5s %10s %11s %10s %14s %9s %9s %7s\n", "scene", "n", "max strain", "mean strain", "speed m/s",
                "tether excess", "lowest y", "highest y", "finite");
    for (const auto& [scene, results] : all) {
        for (const SizeResult& r : results) {
            const bench::Measurement& m = r.path[0] ? *r.path[0] : *r.path[1];
            std::printf("%-7s %5u %10.4f %11.5f %10.4f %14.4f %9.3f %9.3f %7s\n", scenes::scene_name(scene), r.n,
                        m.strain.max, m.strain.mean, m.rest_speed, m.max_tether_excess, double(m.bounds.min.y),
                        double(m.bounds.max.y), m.finite ? "yes" : "NO");
        }
    }
}

// Runs one scene over every size and path; false on any failure.
bool run_scene(SeedScene scene, const CliOptions& o, std::FILE* json_file, std::vector<SizeResult>* results) {
    bench::RunOptions ro;
    ro.scene = scene;
    scenes::apply_config(o.config == "plain" ? scenes::Config::plain : scenes::Config::default_config, o.sweeps,
                         ro.scene_options);
    if (explicit_split(o)) {
        ro.scene_options.explicit_split = true;
        ro.scene_options.substeps = o.substeps > 0 ? o.substeps : 1;
        ro.scene_options.iterations = o.iterations > 0 ? o.iterations : 3;
        ro.scene_options.sweeps = ro.scene_options.substeps * ro.scene_options.iterations;
        ro.scene_options.coarse_iterations = o.coarse_iterations;
        ro.scene_options.relaxation = o.relaxation;
    }
    if (o.no_tethers) ro.scene_options.tethers = false;
    if (o.contact_tethers) ro.scene_options.contact_tethers = true;
    if (o.no_contact_tethers) ro.scene_options.contact_tethers = false;
    ro.scene_options.wind_m_s = o.wind_m_s;
    ro.scene_options.sphere_inflation_m = o.inflation_m;
    ro.scene_options.sphere_friction = o.friction;
    ro.scene_options.sphere_offset_m = o.offset_m;
    ro.warmup = o.warmup;
    ro.steps = o.steps;
    ro.passes = !o.no_passes;
    ro.repeats = o.repeat;

    bool want[2] = {false, false};
    for (const std::string& p : o.paths) want[p == "avx2" ? 1 : 0] = true;
    if (want[1] && !simd_path_available(SimdPath::avx2)) {
        std::fprintf(stderr, "weft-bench: the avx2 path is not available in this build or on this CPU; skipping it\n");
        want[1] = false;
    }
    bool ok = true;
    for (uint32_t n : o.sizes) {
        SizeResult r;
        r.n = n;
        for (int i = 0; i < 2; ++i) {
            if (!want[i]) continue;
            bench::Measurement m;
            const SimdPath path = i == 0 ? SimdPath::scalar : SimdPath::avx2;
            if (std::string err = bench::measure(ro, n, path, &m); !err.empty()) {
                std::fprintf(stderr, "weft-bench: %s n=%u %s: %s\n", scenes::scene_name(scene), n,
                             simd_path_name(path), err.c_str());
                ok = false;
                continue;
            }
            if (!m.finite) {
                std::fprintf(stderr, "weft-bench: %s n=%u %s: non-finite particle positions\n",
                             scenes::scene_name(scene), n, simd_path_name(path));
                ok = false;
            }
            r.path[i] = std::move(m);
            if (o.json || json_file) {
                const bench::Measurement* scalar = r.path[0] ? &*r.path[0] : nullptr;
                const std::string line = to_json(*r.path[i], o, scalar).dump();
                if (o.json) {
                    std::printf("%s\n", line.c_str());
                    std::fflush(stdout);
                }
                if (json_file) std::fprintf(json_file, "%s\n", line.c_str());
            }
        }
        if (r.path[0] || r.path[1]) results->push_back(std::move(r));
    }
    return ok;
}

// The sphere's verdict per configuration and budget (issue: stays on the sphere at what cost).
void print_sphere_rows(const std::vector<std::pair<CliOptions, std::vector<SizeResult>>>& runs) {
    std::printf("\nsphere: friction %g, offset %g m; stays = at rest, nothing below y = -1 m, middle particle within 2 cm\n"
                "outside the inflated sphere; ratio = time over plain's at 3 sweeps, same size and path\n",
                double(runs.front().first.friction), double(runs.front().first.offset_m));
    std::printf("%-8s %6s %5s %6s %-6s %9s %6s %9s %8s %9s %9s %9s %6s\n", "config", "sweeps", "n", "split", "path",
                "us/step", "ratio", "middle_y", "min_y", "mean str%", "max str%", "rest m/s", "stays");
    for (const auto& [co, results] : runs) {
        for (const SizeResult& r : results) {
            for (int i = 0; i < 2; ++i) {
                if (!r.path[i]) continue;
                const bench::Measurement& m = *r.path[i];
                double plain3 = 0.0;  // plain at 3 sweeps, same n and path, if it ran
                for (const auto& [po, presults] : runs)
                    if (po.config == "plain" && po.sweeps == 3)
                        for (const SizeResult& pr : presults)
                            if (pr.n == r.n && pr.path[i]) plain3 = pr.path[i]->total_us.median;
                const bench::SphereOutcome s = bench::sphere_outcome(m, r.n, co.inflation_m);
                char split[16];
                std::snprintf(split, sizeof split, "%ux%u", m.split.substeps, m.split.iterations);
                std::printf("%-8s %6u %5u %6s %-6s %9.1f %6s %9.3f %8.2f %9.3f %9.2f %9.4f %6s\n", co.config.c_str(),
                            co.sweeps, r.n, split, simd_path_name(m.path), m.total_us.median,
                            plain3 > 0.0 ? fmt("%.2f", m.total_us.median / plain3).c_str() : "-", double(s.middle.y),
                            double(m.bounds.min.y), 100.0 * m.strain.mean, 100.0 * m.strain.max, m.rest_speed,
                            s.stays ? "yes" : "no");
            }
        }
    }
}

int run(const std::vector<SeedScene>& scenes_to_run, const CliOptions& o, bool full_tables) {
    bool ok = true;
    std::FILE* json_file = nullptr;
    if (!o.json_out.empty()) {
        json_file = std::fopen(o.json_out.c_str(), "a");
        if (!json_file) {
            std::fprintf(stderr, "weft-bench: cannot open %s for writing\n", o.json_out.c_str());
            return 1;
        }
    }
    // Every configuration asked for, at every budget asked for.
    std::vector<std::string> configs = o.config == "both" ? std::vector<std::string>{"plain", "default"}
                                                          : std::vector<std::string>{o.config};
    std::vector<uint32_t> budgets = o.budgets.empty() ? std::vector<uint32_t>{o.sweeps} : o.budgets;
    for (SeedScene scene : scenes_to_run) {
        std::vector<std::pair<CliOptions, std::vector<SizeResult>>> runs;
        for (const std::string& config : configs) {
            for (uint32_t sweeps : budgets) {
                CliOptions co = o;
                co.config = config;
                co.sweeps = sweeps;
                std::vector<SizeResult> results;
                ok &= run_scene(scene, co, json_file, &results);
                if (!o.json && full_tables && !results.empty()) {
                    print_header(scene, co, results);
                    print_table(scene, results);
                }
                runs.emplace_back(co, std::move(results));
            }
        }
        if (!o.json) {
            std::vector<std::pair<SeedScene, std::vector<SizeResult>>> all;
            for (const auto& [co, results] : runs) all.emplace_back(scene, results);
            if (!full_tables)
                std::printf("weft-bench passes: which passes %s pays for; %u sweep(s)%s, median of %u steps after %u\n",
                            scenes::scene_name(scene), o.sweeps, explicit_split(o) ? " (explicit split)" : "", o.steps,
                            o.warmup);
            if (!o.no_passes) print_passes(all);
            print_summary(all);
            if (scene == SeedScene::sphere && full_tables) print_sphere_rows(runs);
        }
    }
    if (json_file && std::fclose(json_file) != 0) ok = false;
    return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-bench: the seed paper's cloth experiments, timed on the scalar and AVX2 paths"};
    app.require_subcommand(1, 1);

    CliOptions drape_o, flag_o, sphere_o, passes_o;
    drape_o.sizes = {25, 50, 75, 100, 200, 400};
    flag_o.sizes = {25, 50, 100};
    sphere_o.sizes = {100};
    sphere_o.budgets = {3, 4, 6, 10};
    sphere_o.paths = {"avx2"};
    passes_o.sizes = {50};

    CLI::App* drape = app.add_subcommand("drape", "the paper's timing experiment: a square cloth pinned at two corners");
    add_common_options(drape, drape_o);
    CLI::App* flag = app.add_subcommand("flag", "a flag pinned along its pole, in wind (adds the wind pass)");
    add_common_options(flag, flag_o);
    flag->add_option("--wind", flag_o.wind_m_s, "wind speed, m/s (the paper: 10, 20, 40)")->capture_default_str();
    CLI::App* sphere = app.add_subcommand("sphere", "a cloth dropped on a sphere (adds the collide pass)");
    add_common_options(sphere, sphere_o);
    sphere->add_option("--inflation", sphere_o.inflation_m, "collision skin added to the 0.5 m radius, m")
        ->capture_default_str();
    sphere->add_option("--friction", sphere_o.friction, "Coulomb friction of the sphere")->capture_default_str();
    sphere->add_option("--offset", sphere_o.offset_m, "drop point off the sphere's top along x, m")->capture_default_str();
    sphere->add_option("--budgets", sphere_o.budgets, "sweeps per step to run, comma separated")
        ->delimiter(',')
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    uint32_t levers_size = 100, levers_sweeps = 3, levers_steps = 300;
    bool levers_json = false;
    CLI::App* levers = app.add_subcommand("levers", "docs/solver.md: every lever at equal budget, drape and sphere");
    levers->add_option("--size", levers_size, "grid size n")->check(CLI::Range(2u, 4096u))->capture_default_str();
    levers->add_option("--sweeps", levers_sweeps, "the budget")->check(CLI::Range(1u, 1000u))->capture_default_str();
    levers->add_option("--steps", levers_steps, "timed steps after 30 warm-up steps")->capture_default_str();
    levers->add_flag("--json", levers_json, "one JSON object per lever and scene");
    CLI::App* passes = app.add_subcommand("passes", "per-pass costs of drape, flag and sphere side by side");
    add_common_options(passes, passes_o);

    bench::SweepOptions sweep_o;
    std::string sweep_scene = "drape";
    bool sweep_quick = false, sweep_no_peer = false, sweep_csv_off = false;
    CLI::App* sweep = app.add_subcommand(
        "sweep", "run time against error: a grid of budgets against a converged reference, Bullet beside (docs/accuracy.md)");
    sweep->add_option("scene", sweep_scene, "drape, flag, sphere or garment (the skirt on the walking mannequin)")
        ->check(CLI::IsMember({"drape", "flag", "sphere", "garment"}))
        ->required();
    sweep->add_option("--sizes", sweep_o.sizes, "grid sizes n, comma separated")
        ->delimiter(',')
        ->check(CLI::Range(2u, 4096u))
        ->capture_default_str();
    sweep->add_option("--wind", sweep_o.winds_m_s, "flag: wind speeds, m/s, comma separated (the paper: 10, 20, 40)")
        ->delimiter(',')
        ->check(CLI::Range(0.0f, 500.0f))
        ->capture_default_str();
    sweep->add_option("--frames", sweep_o.sampling.frames, "steps per run (dt 0.033 s; the garment: 1/60 s)")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    sweep->add_option("--sample-every", sweep_o.sampling.sample_every, "frames between sampled frames")
        ->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    sweep->add_option("--iterations", sweep_o.iterations, "Weft: iterations per substep to sweep")
        ->delimiter(',')
        ->check(CLI::Range(0u, 1000u))
        ->capture_default_str();
    sweep->add_option("--substeps", sweep_o.substeps, "Weft: substeps per step to sweep")
        ->delimiter(',')
        ->check(CLI::Range(1u, 64u))
        ->capture_default_str();
    sweep->add_option("--peer-iterations", sweep_o.peer_iterations, "Bullet: position iterations to sweep")
        ->delimiter(',')
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    sweep->add_option("--paths", sweep_o.paths, "Weft's SIMD paths: scalar, avx2")
        ->delimiter(',')
        ->check(CLI::IsMember({"scalar", "avx2"}))
        ->capture_default_str();
    sweep->add_option("--reference-cap", sweep_o.reference.max_substeps,
                      "most substeps per step the reference doubles to (1 iteration each)")
        ->check(CLI::Range(1u, 64u))
        ->capture_default_str();
    sweep->add_option("--tolerance", sweep_o.reference.tolerance, "the reference is converged when a doubling moves it less")
        ->capture_default_str();
    std::vector<float> sweep_compliance;
    sweep->add_option("--compliance", sweep_compliance,
                      "the fabric: XPBD compliance of stretch, shear and bend springs, m/N (three values)")
        ->delimiter(',')
        ->expected(3)
        ->check(CLI::Range(0.0f, 1e6f));
    sweep->add_option("--friction", sweep_o.friction, "sphere: Coulomb friction")->capture_default_str();
    sweep->add_option("--repeat", sweep_o.repeat, "timing runs per configuration (median of their medians)")
        ->check(CLI::Range(1u, 100u))
        ->capture_default_str();
    sweep->add_option("--budget-ms", sweep_o.budgets_ms, "name the least-error configuration within these ms per step")
        ->delimiter(',')
        ->check(CLI::PositiveNumber);
    sweep->add_flag("--json", sweep_o.json, "one JSON object per configuration");
    sweep->add_option("--csv", sweep_o.csv_path, "CSV output (default sweep-SCENE.csv)");
    sweep->add_flag("--no-csv", sweep_csv_off, "write no CSV");
    sweep->add_option("--plot", sweep_o.plot_path, "PNG plot via gnuplot (one per size / wind when several)");
    sweep->add_flag("--no-peer", sweep_no_peer, "leave Bullet out");
    sweep->add_option("--peer-voxel", sweep_o.peer_voxel_m, "Bullet: its sparse distance field's voxel, m")
        ->check(CLI::Range(0.001f, 10.0f))
        ->capture_default_str();
    bool sweep_peer_no_body = false;
    sweep->add_flag("--peer-no-body", sweep_peer_no_body, "garment: Bullet without the body collider (its cloth's own cost)");
    sweep->add_flag("--quick", sweep_quick, "a tiny grid (tests): 2 x 2 configurations, one Bullet budget, reference capped at 4 substeps");
    CLI::App* baked = bench::add_baked_subcommand(app);

    uint32_t garment_steps = 300;
    bool garment_json = false;
    CLI::App* garment = app.add_subcommand("garment", "the dressed garments (skirt, tee, shared dress) on their animated bodies");
    garment->add_option("--steps", garment_steps, "steps measured per scene (after the body's ramp)")->capture_default_str()
        ->check(CLI::Range(1u, 100000u));
    garment->add_flag("--json", garment_json, "one JSON object per scene and model");
    std::vector<std::string> garment_models = {"exact", "cached_planes", "skin_constraints", "skin_constraints+limb_capsules"};
    garment->add_option("--collision", garment_models, "body collision models, each a row (exact, cached_planes, skin_constraints; "
                        "+limb_capsules adds the mannequin's limb capsules: the scene's, or the thighs')")
        ->delimiter(',')->capture_default_str();
    std::string garment_simd = "automatic";
    garment->add_option("--simd", garment_simd, "the SIMD path every scene runs on")
        ->check(CLI::IsMember({"automatic", "scalar", "avx2"}))->capture_default_str();
    bench::SelfBenchOptions self_o;
    CLI::App* self = app.add_subcommand("self", "self-collision off and on: the drape, a heap on the ground, the skirt walking and bending and sitting");
    self->add_option("--frames", self_o.frames, "frames measured per scene (the skirt's after the walk's 1 s ramp)")
        ->check(CLI::Range(1u, 100000u))->capture_default_str();
    self->add_flag("--json", self_o.json, "one JSON object per scene and setting");
    self->add_option("--thickness", self_o.thickness_m, "m: the self-collision thickness (ClothDesc::self_thickness_m)")
        ->check(CLI::Range(double(kMinSelfThickness_m), double(kMaxSelfThickness_m)))->capture_default_str();
    self->add_option("--friction", self_o.friction, "the friction between the cloth's layers (ClothDesc::self_friction)")
        ->check(CLI::Range(0.0, 10.0))->capture_default_str();
    bench::CrowdBenchOptions crowd_o;
    CLI::App* crowd = app.add_subcommand("crowd", "walking mannequins in skirt and tee, each its own body, on 1, 2, ... threads");
    crowd->add_option("--characters", crowd_o.characters, "mannequins (two garments each)")->check(CLI::Range(1u, 1024u))
        ->capture_default_str();
    crowd->add_option("--threads", crowd_o.threads, "thread counts, each its own crowd (the first is the speedup's baseline)")
        ->delimiter(',')->check(CLI::Range(1u, 256u))->capture_default_str();
    crowd->add_option("--frames", crowd_o.frames, "frames measured after the walk's 1 s ramp")->check(CLI::Range(1u, 100000u))
        ->capture_default_str();
    crowd->add_option("--standing", crowd_o.standing, "of the characters, how many stand still in the dressed pose")
        ->check(CLI::Range(0u, 1024u))->capture_default_str();
    crowd->add_option("--sleep-speed", crowd_o.sleep_speed_m_s,
                      "m/s: a cloth whose particles all stay slower sleeps (ClothDesc::sleep_speed_m_s; 0: never)")
        ->check(CLI::Range(0.0f, 10.0f))->capture_default_str();
    crowd->add_option("--budget-us", crowd_o.budget_us,
                      "us: also step each crowd under this frame budget (set_frame_budget_us), priority by "
                      "nearness to a camera in front; 0: off")
        ->check(CLI::Range(0.0f, 1.0e7f))->capture_default_str();
    crowd->add_flag("--json", crowd_o.json, "one JSON object per thread count");
    bench::CorpusOptions corpus_o;
    CLI::App* corpus = app.add_subcommand("corpus", "a folder of sewing patterns baked flat and sewn, one JSON line per garment and a summary");
    corpus->add_option("dir", corpus_o.dir, "folder of patterns (GarmentCode *_specification.json or Weft *.json)")->required();
    corpus->add_option("--body", corpus_o.body, "sew onto this body (OBJ, glTF or 'mannequin'); none: flat bakes only");
    corpus->add_option("--blend-to", corpus_o.blend_to, "with --body: run each garment that stays on while the body blends to this pose (same faces)");
    corpus->add_option("--moving-s", corpus_o.moving_s, "seconds the blend takes")->check(CLI::Range(0.1f, 60.0f))->capture_default_str();
    corpus->add_flag("--self-collision", corpus_o.self_collision, "with --blend-to: the moving run with self-collision on");
    corpus->add_option("--jobs", corpus_o.jobs, "garments baked at once (0: one per core)")->capture_default_str();
    corpus->add_option("--sweeps", corpus_o.sweeps, "the sewing and drape budget (weft-bake --sweeps)")
        ->check(CLI::Range(1u, 1000u))->capture_default_str();
    corpus->add_option("--timeout", corpus_o.timeout_s, "seconds one garment may take")->check(CLI::PositiveNumber)->capture_default_str();
    corpus->add_option("--filter", corpus_o.filter, "only the files whose name contains one of these (comma-separated)");
    corpus->add_flag("--json", corpus_o.json, "one JSON object per garment, then the summary (\"summary\": true)");
    bench::BodyBenchOptions body_o;
    CLI::App* body = app.add_subcommand("body", "body collision pass on the shared mean_all body, A-pose <-> T-pose");
    body->add_option("--frames", body_o.frames, "frames measured")->capture_default_str();
    body->add_option("--points", body_o.points, "particles near the torso, hips and upper arms")->capture_default_str();
    body->add_option("--thickness", body_o.thickness_m, "offset hull thickness, m")->capture_default_str();
    body->add_option("--fall", body_o.fall_m_s2, "gravity on the points, m/s^2 (> 5.4: every point moves past 5 mm a step, so every point casts a ray)")->capture_default_str();
    body->add_flag("--random-order", body_o.random_order, "points in random order (no neighbours next to each other)");
    body->add_flag("--scalar", body_o.scalar, "the scalar path instead of AVX2");
    body->add_flag("--json", body_o.json, "one JSON object");
    body->add_option("--simplify", body_o.simplify, "Weft's world: the body's triangles simplified to this share (meshoptimizer), 0: full")
        ->capture_default_str();

    bench::ReferenceStudyOptions reference_o;
    CLI::App* reference = app.add_subcommand(
        "reference", "drape: the double-precision plain solver against the float runtime, substeps doubled (docs/accuracy.md)");
    std::string reference_scene = "drape";
    float reference_offset_m = 1e-6f;
    reference->add_option("scene", reference_scene, "drape (double solver beside the float runtime) or sphere (float only)")
        ->check(CLI::IsMember({"drape", "sphere"}))
        ->capture_default_str();
    reference->add_option("--offset", reference_offset_m, "sphere: m off-centre for the sensitivity column")
        ->capture_default_str();
    reference->add_option("--sizes", reference_o.sizes, "grid sizes n")->delimiter(',')->check(CLI::Range(2u, 4096u))
        ->capture_default_str();
    reference->add_option("--frames", reference_o.sampling.frames, "steps per run (dt 0.033 s)")
        ->check(CLI::Range(1u, 100000u))->capture_default_str();
    reference->add_option("--sample-every", reference_o.sampling.sample_every, "frames between sampled frames")
        ->check(CLI::Range(1u, 100000u))->capture_default_str();
    reference->add_option("--cap", reference_o.cap, "most substeps per step for the double solver")
        ->check(CLI::Range(1u, 1u << 20))->capture_default_str();
    reference->add_option("--perturb", reference_o.perturb_m, "m: the start moved this much for the sensitivity column")
        ->capture_default_str();
    std::vector<float> reference_compliance;
    reference->add_option("--compliance", reference_compliance, "stretch, shear, bend compliance, m/N (default hard)")
        ->delimiter(',')->expected(3)->check(CLI::Range(0.0f, 1e6f));
    reference->add_flag("--json", reference_o.json, "one JSON object per split");

    CLI11_PARSE(app, argc, argv);
    if (reference->parsed()) {
        for (size_t k = 0; k < reference_compliance.size() && k < 3; ++k)
            reference_o.compliance_m_per_n[k] = reference_compliance[k];
        return reference_scene == "sphere" ? bench::run_sphere_sensitivity(reference_o, reference_offset_m)
                                           : bench::run_reference_study(reference_o);
    }
    if (body->parsed()) return bench::run_body(body_o);
    if (corpus->parsed()) return bench::run_corpus(corpus_o);
    if (garment->parsed()) {
        std::vector<bench::GarmentModel> models(garment_models.size());
        for (size_t m = 0; m < models.size(); ++m)
            if (!bench::garment_model_from_name(garment_models[m], &models[m]))
                return std::fprintf(stderr, "weft-bench garment: unknown --collision '%s'\n", garment_models[m].c_str()), 2;
        const SimdPath simd = garment_simd == "scalar" ? SimdPath::scalar
                              : garment_simd == "avx2" ? SimdPath::avx2
                                                       : SimdPath::automatic;
        return bench::run_garment(garment_steps, garment_json, models, simd);
    }
    if (crowd->parsed()) return bench::run_crowd(crowd_o);
    if (self->parsed()) return bench::run_self(self_o);

    if (baked->parsed()) return bench::run_baked();
    if (drape->parsed()) return run({SeedScene::drape}, drape_o, true);
    if (flag->parsed()) return run({SeedScene::flag}, flag_o, true);
    if (sphere->parsed()) return run({SeedScene::sphere}, sphere_o, true);
    if (sweep->parsed()) {
        sweep_o.scene = sweep_scene == "flag" ? SeedScene::flag : sweep_scene == "sphere" ? SeedScene::sphere : SeedScene::drape;
        sweep_o.garment = sweep_scene == "garment";
        if (sweep_quick) {  // the quick grid, except what was given explicitly
            bench::SweepOptions quick = sweep_o;
            bench::make_quick(quick);
            if (sweep->count("--iterations") == 0) sweep_o.iterations = quick.iterations;
            if (sweep->count("--substeps") == 0) sweep_o.substeps = quick.substeps;
            if (sweep->count("--peer-iterations") == 0) sweep_o.peer_iterations = quick.peer_iterations;
            if (sweep->count("--reference-cap") == 0) sweep_o.reference.max_substeps = quick.reference.max_substeps;
            sweep_o.long_range = quick.long_range;
        }
        for (size_t k = 0; k < sweep_compliance.size() && k < 3; ++k) sweep_o.compliance_m_per_n[k] = sweep_compliance[k];
        sweep_o.peer = !sweep_no_peer;
        sweep_o.peer_body = !sweep_peer_no_body;
        if (sweep_o.csv_path.empty() && !sweep_csv_off) sweep_o.csv_path = "sweep-" + sweep_scene + ".csv";
        if (sweep_csv_off) sweep_o.csv_path.clear();
        return bench::run_sweep(sweep_o);
    }
    if (levers->parsed()) return bench::run_levers(levers_size, levers_sweeps, levers_steps, levers_json);
    return run({SeedScene::drape, SeedScene::flag, SeedScene::sphere}, passes_o, false);
}
