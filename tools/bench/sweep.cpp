#include "bench/sweep.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "bench/bench_run.h"
#include "bench/garment_sweep.h"
#include "bench/peer_bullet.h"
#include "common/progress.h"

namespace weft::bench {
namespace {

using scenes::SeedScene;

// One point of the sweep: a configuration of one solver and what it measured.
struct Row {
    std::string solver = "weft";  // or "bullet"
    uint32_t n = 0;
    float wind_m_s = 0.0f;       // flag only
    std::string simd;            // weft: the path; bullet: "-"
    uint32_t substeps = 1, iterations = 0;
    bool tethers = false, coarse_level = false;
    float relaxation = 1.0f;
    double us_per_step = 0.0;    // CPU time: median over the steps (median over repeats of that)
    double wall_us_per_step = 0.0;  // the same in wall time
    double trajectory_error = 0.0;
    std::optional<double> rest_error;  // scenes that come to rest
    metrics::Strain strain;      // at the last frame
    double max_penetration_m = 0.0;
    bool finite = true;
    bool pareto = false;
    std::vector<double> best_within_ms;  // the --budget-ms budgets this row is the best fit for
};

// The group of rows compared with one reference.
struct Group {
    uint32_t n = 0;
    float wind_m_s = 0.0f;
    Reference reference;
    metrics::Strain reference_strain;  // at its last frame: how stretched the reference itself is
    std::vector<Row> rows;
};

// The flag flaps and the garment walks; the drape and the sphere come to rest.
bool comes_to_rest(const SweepOptions& o) { return !o.garment && o.scene != SeedScene::flag; }

const char* scene_label(const SweepOptions& o) { return o.garment ? "garment" : scenes::scene_name(o.scene); }

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    return summarise(std::move(v)).median;
}

std::string split_name(const Row& r) {
    char buf[64];
    if (r.solver == "bullet") {
        std::snprintf(buf, sizeof buf, "piter %u", r.iterations);
    } else {
        std::snprintf(buf, sizeof buf, "%ux%u%s%s", r.substeps, r.iterations, r.tethers ? " +tethers" : "",
                      r.coarse_level ? " +coarse" : "");
    }
    return buf;
}

// Fills a row's errors from its trajectory, against the group's reference.
struct Timing {
    std::vector<double> cpu_us, wall_us;  // one median per repeat
};

void score(const Trajectory& t, const Reference& ref, const ClothAsset& asset, bool rest, const Timing& timing,
           Row* row) {
    row->us_per_step = median(timing.cpu_us);
    row->wall_us_per_step = median(timing.wall_us);
    row->trajectory_error = metrics::trajectory_error(t.frames, ref.trajectory.frames, ref.diagonal_m);
    if (rest) row->rest_error = metrics::rest_state_error(t.frames, ref.trajectory.frames, ref.diagonal_m);
    if (!t.frames.empty()) row->strain = metrics::stretch_strain(asset, t.frames.back());
    row->max_penetration_m = t.max_penetration_m;
    row->finite = t.finite;
}

scenes::SceneOptions physics_of(const SweepOptions& o, uint32_t n, float wind_m_s) {
    scenes::SceneOptions p;
    p.n = n;
    p.wind_m_s = wind_m_s;
    p.sphere_friction = o.friction;
    p.stretch_compliance_m_per_n = o.compliance_m_per_n[0];
    p.shear_compliance_m_per_n = o.compliance_m_per_n[1];
    p.bend_compliance_m_per_n = o.compliance_m_per_n[2];
    return p;
}

// The configuration grid of one group (the Weft rows, not yet measured).
std::vector<std::pair<Row, scenes::SceneOptions>> weft_grid(const SweepOptions& o, const scenes::SceneOptions& physics) {
    std::vector<std::pair<Row, scenes::SceneOptions>> grid;
    for (const std::string& path : o.paths) {
        for (bool long_range : o.long_range) {
            for (uint32_t substeps : o.substeps) {
                for (uint32_t iterations : o.iterations) {
                    scenes::SceneOptions so = plain_split(physics, substeps, iterations);
                    so.simd = path == "scalar" ? SimdPath::scalar : SimdPath::avx2;
                    if (o.scene == SeedScene::sphere) {
                        // No pins, so no tethers: the long-range lever is the coarse level, run as
                        // the automatic policy runs it (under-relaxed 0.8, docs/solver.md).
                        so.coarse_level = long_range ? CoarseLevel::on : CoarseLevel::off;
                        so.relaxation = long_range ? 0.8f : 1.0f;
                    } else {
                        so.tethers = long_range;
                    }
                    Row r;
                    r.simd = path;
                    r.substeps = substeps;
                    r.iterations = iterations;
                    r.tethers = so.tethers && o.scene != SeedScene::sphere;
                    r.coarse_level = so.coarse_level == CoarseLevel::on;
                    r.relaxation = so.relaxation;
                    grid.emplace_back(r, so);
                }
            }
        }
    }
    return grid;
}

// Runs a configuration `repeat` times: the first run's trajectory is scored (the simulation is
// deterministic), the step-time medians of all runs give the time.
template <class RunOnce>
std::string measure_row(const SweepOptions& o, RunOnce run_once, Trajectory* first, Timing* timing) {
    for (uint32_t k = 0; k < std::max(1u, o.repeat); ++k) {
        Trajectory t;
        if (std::string err = run_once(&t); !err.empty()) return err;
        timing->cpu_us.push_back(median(t.step_us));
        timing->wall_us.push_back(median(t.step_wall_us));
        if (k == 0) *first = std::move(t);
    }
    return {};
}

void mark_pareto(std::vector<Row>& rows) {
    for (const char* solver : {"weft", "bullet"}) {
        std::vector<size_t> index;
        std::vector<double> time, error;
        for (size_t i = 0; i < rows.size(); ++i) {
            if (rows[i].solver != solver) continue;
            index.push_back(i);
            time.push_back(rows[i].us_per_step);
            error.push_back(rows[i].finite ? rows[i].trajectory_error : std::numeric_limits<double>::infinity());
        }
        const std::vector<bool> front = pareto_front(time, error);
        for (size_t k = 0; k < index.size(); ++k) rows[index[k]].pareto = front[k];
    }
}

// The least-error row of `solver` that fits `budget_ms`, or null.
Row* best_within(std::vector<Row>& rows, const char* solver, double budget_ms) {
    Row* best = nullptr;
    for (Row& r : rows) {
        if (r.solver != solver || !r.finite || !std::isfinite(r.trajectory_error)) continue;
        if (r.us_per_step > budget_ms * 1e3) continue;
        if (!best || r.trajectory_error < best->trajectory_error) best = &r;
    }
    return best;
}

double rounded(double v, int significant) {
    if (v == 0.0 || !std::isfinite(v)) return v;
    const double scale = std::pow(10.0, significant - 1 - int(std::floor(std::log10(std::fabs(v)))));
    return std::round(v * scale) / scale;
}

nlohmann::ordered_json json_number(double v, int significant = 4) {
    return std::isfinite(v) ? nlohmann::ordered_json(rounded(v, significant)) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json to_json(const SweepOptions& o, const Group& g, const Row& r) {
    nlohmann::ordered_json j;
    j["bench"] = "sweep";
    j["scene"] = scene_label(o);
    j["solver"] = r.solver;
    j["n"] = r.n;
    if (o.scene == SeedScene::flag) j["wind_m_s"] = r.wind_m_s;
    j["simd"] = r.simd;
    j["iterations"] = r.iterations;
    j["substeps"] = r.substeps;
    j["tethers"] = r.tethers;
    j["coarse_level"] = r.coarse_level;
    if (o.garment && r.solver == "bullet") j["body_collider"] = o.peer_body;  // --peer-no-body: false
    if (r.solver == "bullet") j["peer_voxel_m"] = rounded(o.peer_voxel_m, 3);
    j["relaxation"] = rounded(r.relaxation, 3);
    j["us_per_step"] = json_number(r.us_per_step);
    j["wall_us_per_step"] = json_number(r.wall_us_per_step);
    j["trajectory_error"] = json_number(r.trajectory_error);
    j["rest_error"] = r.rest_error ? json_number(*r.rest_error) : nlohmann::ordered_json(nullptr);
    j["max_strain"] = json_number(r.strain.max);
    j["mean_strain"] = json_number(r.strain.mean);
    j["max_penetration_m"] = json_number(r.max_penetration_m);
    j["finite"] = r.finite;
    j["pareto"] = r.pareto;
    j["best_within_ms"] = r.best_within_ms;
    j["frames"] = o.sampling.frames;
    j["sample_every"] = o.sampling.sample_every;
    j["reference_substeps"] = g.reference.substeps;
    j["reference_iterations"] = g.reference.iterations;
    j["reference_converged"] = g.reference.converged;
    j["reference_change"] = json_number(g.reference.change);
    j["reference_max_strain"] = json_number(g.reference_strain.max);
    j["load_avg_1min"] = rounded(load_average_1min(), 3);
    return j;
}

void print_reference(const SweepOptions& o, const Group& g) {
    std::printf("\n%s n=%u", scene_label(o), g.n);
    if (o.scene == SeedScene::flag) std::printf(" wind %g m/s", double(g.wind_m_s));
    std::printf(": %u frames, every %u-th sampled; diagonal %.3f m\n", o.sampling.frames, o.sampling.sample_every,
                g.reference.diagonal_m);
    std::printf("reference (plain, substeps doubled at 1 iteration each):");
    for (const ReferenceStep& s : g.reference.steps)
        std::printf(" %ux%u (%.2g, %.1f s)", s.substeps, s.iterations, s.change, s.seconds);
    std::printf("\n  -> %ux%u, %s (last change %.3g, tolerance %.0e); its strain at the end: mean %.3g, max %.3g\n",
                g.reference.substeps, g.reference.iterations,
                g.reference.converged ? "converged" : "NOT converged at the cap", g.reference.change,
                o.reference.tolerance, g.reference_strain.mean, g.reference_strain.max);
}

void print_rows(const Group& g) {
    std::printf("ms/step: median CPU time of the stepping thread (wall: median wall time)\n");
    std::printf("%-7s %-5s %-22s %10s %10s %10s %10s %10s %10s %11s %6s\n", "solver", "simd", "config", "ms/step",
                "wall", "traj err", "rest err", "max strain", "mean str", "penetr. mm", "pareto");
    for (const Row& r : g.rows) {
        char rest[32] = "-";
        if (r.rest_error) std::snprintf(rest, sizeof rest, "%.3g", *r.rest_error);
        std::printf("%-7s %-5s %-22s %10.4f %10.4f %10.3g %10s %10.3g %10.3g %11.3f %6s%s\n", r.solver.c_str(),
                    r.simd.c_str(), split_name(r).c_str(), r.us_per_step * 1e-3, r.wall_us_per_step * 1e-3,
                    r.trajectory_error, rest, r.strain.max, r.strain.mean,
                    r.max_penetration_m * 1e3, r.pareto ? "*" : "", r.finite ? "" : " NON-FINITE");
    }
}

void print_budgets(const SweepOptions& o, Group& g) {
    for (double budget : o.budgets_ms) {
        std::printf("within %g ms per step:", budget);
        for (const char* solver : {"weft", "bullet"}) {
            Row* best = best_within(g.rows, solver, budget);
            if (best) {
                std::printf("  %s %s (%.4f ms, error %.3g)", solver, split_name(*best).c_str(), best->us_per_step * 1e-3,
                            best->trajectory_error);
            } else if (solver == std::string("weft") || std::any_of(g.rows.begin(), g.rows.end(),
                                                                    [&](const Row& r) { return r.solver == solver; })) {
                std::printf("  %s: nothing fits", solver);
            }
        }
        std::printf("\n");
    }
}

bool write_csv(const SweepOptions& o, const std::vector<Group>& groups) {
    std::FILE* f = std::fopen(o.csv_path.c_str(), "w");
    if (!f) {
        std::fprintf(stderr, "weft-bench sweep: cannot write %s\n", o.csv_path.c_str());
        return false;
    }
    std::fprintf(f, "scene,solver,n,wind_m_s,simd,substeps,iterations,tethers,coarse_level,relaxation,us_per_step,"
                    "wall_us_per_step,"
                    "trajectory_error,rest_error,max_strain,mean_strain,max_penetration_m,finite,pareto,"
                    "reference_substeps,reference_iterations,reference_converged\n");
    for (const Group& g : groups)
        for (const Row& r : g.rows)
            std::fprintf(f, "%s,%s,%u,%g,%s,%u,%u,%d,%d,%g,%.3f,%.3f,%.6g,%s,%.6g,%.6g,%.6g,%d,%d,%u,%u,%d\n",
                         scene_label(o), r.solver.c_str(), r.n, double(r.wind_m_s), r.simd.c_str(),
                         r.substeps, r.iterations, r.tethers, r.coarse_level, double(r.relaxation), r.us_per_step,
                         r.wall_us_per_step,
                         r.trajectory_error, r.rest_error ? std::to_string(*r.rest_error).c_str() : "", r.strain.max,
                         r.strain.mean, r.max_penetration_m, r.finite, r.pareto, g.reference.substeps,
                         g.reference.iterations, g.reference.converged);
    return std::fclose(f) == 0;
}

// A gnuplot data block of (ms, error, label) for the rows that pass `keep`, sorted by time.
template <class Keep>
std::string data_block(const char* name, const std::vector<Row>& rows, Keep keep) {
    std::vector<const Row*> kept;
    for (const Row& r : rows)
        if (keep(r) && r.finite && std::isfinite(r.trajectory_error) && r.trajectory_error > 0.0) kept.push_back(&r);
    std::sort(kept.begin(), kept.end(), [](const Row* a, const Row* b) { return a->us_per_step < b->us_per_step; });
    std::string s = std::string("$") + name + " << EOD\n";
    char line[160];
    for (const Row* r : kept) {
        std::snprintf(line, sizeof line, "%.6g %.6g \"%s\"\n", r->us_per_step * 1e-3, r->trajectory_error,
                      split_name(*r).c_str());
        s += line;
    }
    if (kept.empty()) s += "NaN NaN \"\"\n";  // gnuplot refuses an empty block
    return s + "EOD\n";
}

// Writes one PNG per group through gnuplot (pngcairo): error (log) against ms per step (log).
bool write_plot(const SweepOptions& o, const Group& g, const std::string& path) {
    std::string script = "set terminal pngcairo size 1000,650 font 'DejaVu Sans,10'\n";
    script += "set output '" + path + "'\n";
    script += data_block("weft_tethers", g.rows, [](const Row& r) { return r.solver == "weft" && (r.tethers || r.coarse_level); });
    script += data_block("weft_plain", g.rows, [](const Row& r) { return r.solver == "weft" && !r.tethers && !r.coarse_level; });
    script += data_block("weft_front", g.rows, [](const Row& r) { return r.solver == "weft" && r.pareto; });
    script += data_block("bullet", g.rows, [](const Row& r) { return r.solver == "bullet"; });
    script += data_block("bullet_front", g.rows, [](const Row& r) { return r.solver == "bullet" && r.pareto; });
    char title[256];
    std::snprintf(title, sizeof title,
                  "%s n = %u%s: run time against error (reference %ux%u%s, %u frames, one thread)",
                  scene_label(o), g.n,
                  o.scene == SeedScene::flag ? (" wind " + std::to_string(int(g.wind_m_s)) + " m/s").c_str() : "",
                  g.reference.substeps, g.reference.iterations, g.reference.converged ? "" : " not converged",
                  o.sampling.frames);
    script += std::string("set title \"") + title + "\"\n";
    const char* long_range = o.scene == SeedScene::sphere ? "coarse level" : "tethers";
    script +=
        "set logscale xy\n"
        "set xlabel 'ms per step (median CPU time of the stepping thread)'\n"
        "set ylabel 'trajectory error (RMS distance to the reference / diagonal)'\n"
        "set grid\n"
        "set key outside right top\n"
        "set format y '10^{%L}'\n";
    script += std::string("plot $weft_plain using 1:2 with points pt 6 ps 1.2 lc rgb '#1f77b4' title 'Weft, no ") +
              long_range + "', \\\n";
    script += std::string("     $weft_tethers using 1:2 with points pt 7 ps 1.0 lc rgb '#1f77b4' title 'Weft, ") +
              long_range + "', \\\n";
    script += "     $weft_front using 1:2 with lines lw 2 lc rgb '#1f77b4' title 'Weft Pareto front', \\\n";
    script += "     $weft_front using 1:2:3 with labels offset 0.6,0.6 left font ',8' tc rgb '#1f77b4' notitle, \\\n";
    script += "     $bullet using 1:2 with points pt 5 ps 1.0 lc rgb '#d62728' title 'Bullet btSoftBody', \\\n";
    script += "     $bullet_front using 1:2 with lines lw 2 dt 2 lc rgb '#d62728' title 'Bullet Pareto front', \\\n";
    script += "     $bullet_front using 1:2:3 with labels offset 0.6,-0.8 left font ',8' tc rgb '#d62728' notitle";
    if (std::isfinite(g.reference.change) && g.reference.change > 0.0) {
        char line[200];  // errors below the reference's own last change are not resolved
        std::snprintf(line, sizeof line, ", \\\n     %.6g with lines dt 2 lw 1.5 lc rgb 'gray40' title \"reference's last change\"",
                      g.reference.change);
        script += line;
    }
    script += "\n";
    std::FILE* gp = popen("gnuplot", "w");
    if (!gp) {
        std::fprintf(stderr, "weft-bench sweep: cannot start gnuplot (install gnuplot-nox); no plot\n");
        return false;
    }
    std::fputs(script.c_str(), gp);
    const int status = pclose(gp);
    if (status != 0) {
        std::fprintf(stderr, "weft-bench sweep: gnuplot failed (status %d); is gnuplot-nox installed?\n", status);
        return false;
    }
    return true;
}

std::string plot_path_for(const SweepOptions& o, const Group& g, bool several) {
    if (!several) return o.plot_path;
    const size_t dot = o.plot_path.rfind('.');
    const std::string stem = dot == std::string::npos ? o.plot_path : o.plot_path.substr(0, dot);
    std::string suffix = "-n" + std::to_string(g.n);
    if (o.scene == SeedScene::flag) suffix += "-wind" + std::to_string(int(g.wind_m_s));
    return stem + suffix + ".png";
}

}  // namespace

void make_quick(SweepOptions& o) {
    o.iterations = {1, 4};
    o.substeps = {1, 2};
    o.long_range = {true};
    o.peer_iterations = {2};
    o.reference.max_substeps = 4;
}

int run_sweep(const SweepOptions& o) {
    std::vector<std::string> paths;
    for (const std::string& p : o.paths) {
        if (p == "avx2" && !simd_path_available(SimdPath::avx2)) {
            std::fprintf(stderr, "weft-bench sweep: no avx2 path in this build or on this CPU; skipping it\n");
            continue;
        }
        paths.push_back(p);
    }
    SweepOptions options = o;
    options.paths = paths;
    const bool peer = o.peer && bullet_available() && (o.garment || o.scene != SeedScene::flag);
    if (o.peer && !bullet_available() && !o.json)
        std::printf("bullet peer: not in this build (libbullet-dev not found at configure time); skipped\n");

    std::vector<Group> groups;
    bool ok = true;
    const std::vector<float> winds = o.scene == SeedScene::flag ? o.winds_m_s : std::vector<float>{0.0f};
    // The garment is one scene (the skirt on the walking mannequin, dressed once): no sizes.
    GarmentSweepScene garment;
    if (o.garment) {
        if (std::string err = make_garment_sweep_scene(&garment); !err.empty()) {
            std::fprintf(stderr, "weft-bench sweep: garment: %s\n", err.c_str());
            return 1;
        }
    }
    const std::vector<uint32_t> sizes = o.garment ? std::vector<uint32_t>{garment.asset().particle_count} : o.sizes;
    // One run of the scene at a split (a Weft configuration or the reference's plain method).
    auto run_weft = [&](const scenes::SceneOptions& so, Trajectory* out) {
        return o.garment ? run_garment_trajectory(garment, so, o.sampling, out) : run_trajectory(o.scene, so, o.sampling, out);
    };
    // Progress on a terminal: one step per reference, Weft configuration and Bullet run.
    const size_t weft_rows = options.paths.size() * o.long_range.size() * o.substeps.size() * o.iterations.size();
    const size_t per_group = 1 + weft_rows + (peer ? o.peer_iterations.size() : 0);
    progress::Bar bar("weft-bench sweep", sizes.size() * winds.size() * per_group, progress::wanted(o.json));
    uint64_t done = 0;
    for (uint32_t n : sizes) {
        for (float wind : winds) {
            Group g;
            g.n = n;
            g.wind_m_s = wind;
            const scenes::SceneOptions physics = physics_of(o, n, wind);
            bar.update(done, "n = " + std::to_string(n) + ": reference");
            const RunPlain run_plain = [&](uint32_t substeps, uint32_t iterations, Trajectory* out) {
                return run_weft(plain_split(physics, substeps, iterations), out);
            };
            if (std::string err = compute_reference(run_plain, o.reference, &g.reference); !err.empty()) {
                bar.finish();
                std::fprintf(stderr, "weft-bench sweep: reference: %s\n", err.c_str());
                return 1;
            }
            ++done;
            scenes::SeedWorld asset_world;  // the asset every configuration shares (for the strain)
            if (!o.garment)
                if (std::string err = scenes::make_seed_world(o.scene, physics, &asset_world); !err.empty()) {
                    bar.finish();
                    std::fprintf(stderr, "weft-bench sweep: %s\n", err.c_str());
                    return 1;
                }
            const ClothAsset& asset = o.garment ? garment.asset() : asset_world.asset();
            if (!g.reference.trajectory.frames.empty())
                g.reference_strain = metrics::stretch_strain(asset, g.reference.trajectory.frames.back());
            for (auto& [row, so] : weft_grid(options, physics)) {
                bar.update(done, "n = " + std::to_string(n) + ": " + split_name(row));
                Trajectory t;
                Timing timing;
                const std::string err = measure_row(
                    o, [&, &sim = so](Trajectory* out) { return run_weft(sim, out); }, &t, &timing);
                ++done;
                if (!err.empty()) {
                    bar.finish();
                    std::fprintf(stderr, "weft-bench sweep: %s: %s\n", split_name(row).c_str(), err.c_str());
                    ok = false;
                    continue;
                }
                row.n = n;
                row.wind_m_s = wind;
                score(t, g.reference, asset, comes_to_rest(o), timing, &row);
                g.rows.push_back(row);
            }
            if (peer) {
                for (uint32_t iterations : o.peer_iterations) {
                    Row row;
                    row.solver = "bullet";
                    row.simd = "-";
                    row.n = n;
                    row.iterations = iterations;
                    bar.update(done, "n = " + std::to_string(n) + ": bullet, " + std::to_string(iterations) + " iterations");
                    Trajectory t;
                    Timing timing;
                    const std::string err = measure_row(
                        o,
                        [&](Trajectory* out) {
                            return o.garment ? run_bullet_garment(garment, iterations, o.peer_body, o.sampling, out,
                                                                  o.peer_voxel_m)
                                             : run_bullet(o.scene, physics, iterations, o.sampling, out, o.peer_voxel_m);
                        },
                        &t, &timing);
                    ++done;
                    if (!err.empty()) {
                        bar.finish();
                        std::fprintf(stderr, "weft-bench sweep: bullet: %s\n", err.c_str());
                        ok = false;
                        continue;
                    }
                    score(t, g.reference, asset, comes_to_rest(o), timing, &row);
                    g.rows.push_back(row);
                }
            }
            mark_pareto(g.rows);
            for (double budget : o.budgets_ms)
                for (const char* solver : {"weft", "bullet"})
                    if (Row* best = best_within(g.rows, solver, budget)) best->best_within_ms.push_back(budget);
            bar.finish();  // the group's tables start on a clean line; the next update redraws the bar
            if (o.json) {
                for (const Row& r : g.rows) std::printf("%s\n", to_json(o, g, r).dump().c_str());
                std::fflush(stdout);
            } else {
                print_reference(o, g);
                print_rows(g);
                print_budgets(o, g);
            }
            for (const Row& r : g.rows)
                if (r.solver == "weft") ok = ok && r.finite;  // a peer blowing up is a result, not a failure
            groups.push_back(std::move(g));
        }
    }
    if (!o.csv_path.empty()) ok &= write_csv(o, groups);
    if (!o.plot_path.empty())
        for (const Group& g : groups) ok &= write_plot(o, g, plot_path_for(o, g, groups.size() > 1));
    return ok ? 0 : 1;
}

}  // namespace weft::bench
