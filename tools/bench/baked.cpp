// weft-bench baked: see garment.h. Each pattern is baked once (bake_pattern, as weft-bake does)
// and its asset loaded back through the runtime's loader; the same meshed garment is cooked in memory
// twice, with its lattice coordinates and without. Each asset steps in its own world: one substep
// of `iterations` sweeps, no coarse level, no tethers, no colliders, so the constraint pass
// dominates; set_profiling times it. The figure is the constraint pass's median per-step time
// divided by the projections it ran (padding lanes excluded): ns per constraint projection. The
// variants take turns within each repeat, and the repeat with the lowest median is kept.
#include "bench/baked.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/asset_writer.h"
#include "bake/bake.h"
#include "bench/bench_run.h"
#include "weft/cook.h"

namespace weft::bench {
namespace {

struct GarmentOptions {
    std::vector<std::string> patterns;
    uint32_t iterations = 10;
    uint32_t steps = 200;
    uint32_t warmup = 20;
    uint32_t repeat = 5;
    std::vector<std::string> paths{"avx2"};
    bool json = false;
};
GarmentOptions g_options;

struct Variant {
    std::string name;
    const ClothAsset* asset = nullptr;
};

struct Timing {
    double constraint_ns_per_projection = 0.0;  // median over steps of the constraint pass / projections
    double step_ns_per_projection = 0.0;        // median step time (profiled) / projections
    uint64_t projections = 0;                   // per step
};

// One world around one asset; steps and times it. Returns the failure message (empty on success).
std::string time_asset(const ClothAsset& asset, SimdPath path, Timing* out) {
    WorldDesc wd;
    reserve_cloth(wd, asset);
    wd.simd = path;
    const MemoryRequirements need = world_memory_requirements(wd);
    const size_t bytes = (need.bytes + need.alignment - 1) / need.alignment * need.alignment;
    std::unique_ptr<unsigned char, void (*)(void*)> memory(static_cast<unsigned char*>(std::aligned_alloc(need.alignment, bytes)),
                                                           std::free);
    if (!memory) return "out of memory";
    World* world = nullptr;
    if (Result r = create_world(wd, memory.get(), bytes, &world); !r.ok()) return r.message;
    set_profiling(world, true);
    ClothDesc cd;
    cd.asset = &asset;
    cd.policy = BudgetPolicy::explicit_split;
    cd.substeps = 1;
    cd.iterations = g_options.iterations;
    cd.sweeps = g_options.iterations;
    cd.coarse_level = CoarseLevel::off;
    cd.tethers = false;
    ClothId id;
    if (Result r = add_cloth(world, cd, &id); !r.ok()) return r.message;
    const float dt = 1.0f / 60.0f;
    for (uint32_t s = 0; s < g_options.warmup; ++s)
        if (Result r = step(world, dt); !r.ok()) return r.message;
    std::vector<double> constraint_ns, step_ns;
    WorldStats before = world_stats(world);
    for (uint32_t s = 0; s < g_options.steps; ++s) {
        if (Result r = step(world, dt); !r.ok()) return r.message;
        const WorldStats after = world_stats(world);
        const int c = int(Pass::constraints);
        constraint_ns.push_back(double(after.pass_ns[c] - before.pass_ns[c]));
        uint64_t all = 0;
        for (int p = 0; p < kPassCount; ++p) all += after.pass_ns[p] - before.pass_ns[p];
        step_ns.push_back(double(all));
        out->projections = after.run_projections + after.indexed_projections;
        before = after;
    }
    if (out->projections == 0) return "no projections";
    out->constraint_ns_per_projection = summarise(constraint_ns).median / double(out->projections);
    out->step_ns_per_projection = summarise(step_ns).median / double(out->projections);
    return {};
}

std::string read_text(const std::string& path, bool* ok) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    *ok = bool(f) || f.eof();
    return s.str();
}

void print_row(const std::string& name, SimdPath simd, const std::string& variant, const ClothAsset& a, const Timing& t,
               double vs_mesh) {
    const LanePadding padding = lane_padding(a);
    const double cf = double(a.constraints_on_runs) / double(a.total_constraints());
    if (g_options.json) {
        nlohmann::json j = {{"pattern", name},
                            {"variant", variant},
                            {"path", simd_path_name(simd)},
                            {"particles", a.particle_count},
                            {"constraints", a.total_constraints()},
                            {"contiguous_fraction", cf},
                            {"padding_ratio", padding.ratio()},
                            {"projections_per_step", t.projections},
                            {"constraint_ns_per_projection", t.constraint_ns_per_projection},
                            {"step_ns_per_projection", t.step_ns_per_projection}};
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("%-34s %-6s %-13s %6u %6u   %5.3f   %5.3f   %8.3f   %8.3f   %5.2fx\n", name.c_str(), simd_path_name(simd),
                    variant.c_str(), a.particle_count, a.total_constraints(), cf, padding.ratio(), t.constraint_ns_per_projection,
                    t.step_ns_per_projection, vs_mesh);
    }
}

// A .weft asset (a garment sewn with --body, whose pattern alone would not give the same mesh):
// timed as stored, hanging from its pins with no body; no in-memory variants to compare.
int run_asset(const std::string& path, const std::vector<SimdPath>& paths) {
    bool ok = false;
    const std::string bytes = read_text(path, &ok);
    if (!ok || bytes.empty()) return std::fprintf(stderr, "weft-bench baked: cannot read '%s'\n", path.c_str()), 1;
    assets::LoadedAsset loaded;
    if (Result r = assets::load_asset_copy(bytes.data(), bytes.size(), &loaded); !r.ok())
        return std::fprintf(stderr, "weft-bench baked: %s: %s\n", path.c_str(), r.message), 1;
    const std::string name = path.substr(path.rfind('/') + 1);
    for (SimdPath simd : paths) {
        Timing best;
        for (uint32_t rep = 0; rep < g_options.repeat; ++rep) {
            Timing t;
            if (std::string err = time_asset(loaded.asset, simd, &t); !err.empty())
                return std::fprintf(stderr, "weft-bench baked: %s\n", err.c_str()), 1;
            if (rep == 0 || t.constraint_ns_per_projection < best.constraint_ns_per_projection) best = t;
        }
        print_row(name, simd, "asset", loaded.asset, best, 0.0);
    }
    return 0;
}

int run_pattern(const std::string& spec, const std::vector<SimdPath>& paths) {
    if (spec.size() > 5 && spec.compare(spec.size() - 5, 5, ".weft") == 0) return run_asset(spec, paths);
    std::string path = spec;
    bake::BakeOptions options;
    if (const size_t at = spec.rfind('@'); at != std::string::npos) {
        path = spec.substr(0, at);
        options.parse.placement_offset_m[1] = std::atof(spec.c_str() + at + 1);
    }
    bool ok = false;
    const std::string text = read_text(path, &ok);
    if (!ok || text.empty()) return std::fprintf(stderr, "weft-bench baked: cannot read '%s'\n", path.c_str()), 1;
    bake::Baked baked;
    if (bake::Status s = bake::bake_pattern(text, options, &baked); !s.ok())
        return std::fprintf(stderr, "weft-bench baked: %s: %s\n", path.c_str(), s.error.c_str()), 1;
    assets::LoadedAsset loaded;
    if (Result r = assets::load_asset_copy(baked.bytes.data(), baked.bytes.size(), &loaded); !r.ok())
        return std::fprintf(stderr, "weft-bench baked: %s\n", r.message), 1;

    // The same garment in memory: pins hold (as in the baked asset), with and without the lattice.
    std::vector<float> masses = baked.garment.masses;
    for (uint32_t p : baked.garment.pinned) masses[p] = 0.0f;
    ClothMeshDesc desc = bake::cloth_mesh_desc(baked.garment);
    desc.masses = masses.data();
    CookedCloth with_lattice, plain;
    if (Result r = cook_cloth(desc, options.cook, &with_lattice); !r.ok())
        return std::fprintf(stderr, "weft-bench baked: %s\n", r.message), 1;
    desc.lattice = nullptr;
    if (Result r = cook_cloth(desc, options.cook, &plain); !r.ok())
        return std::fprintf(stderr, "weft-bench baked: %s\n", r.message), 1;

    const Variant variants[] = {{"baked", &loaded.asset}, {"mesh+lattice", &with_lattice.asset()}, {"mesh", &plain.asset()}};
    const std::string name = path.substr(path.rfind('/') + 1);
    for (SimdPath simd : paths) {
        Timing best[3];
        for (uint32_t rep = 0; rep < g_options.repeat; ++rep)
            for (int v = 0; v < 3; ++v) {
                Timing t;
                if (std::string err = time_asset(*variants[v].asset, simd, &t); !err.empty())
                    return std::fprintf(stderr, "weft-bench baked: %s\n", err.c_str()), 1;
                if (rep == 0 || t.constraint_ns_per_projection < best[v].constraint_ns_per_projection) best[v] = t;
            }
        for (int v = 0; v < 3; ++v)
            print_row(name, simd, variants[v].name, *variants[v].asset, best[v],
                      best[2].constraint_ns_per_projection / best[v].constraint_ns_per_projection);
    }
    return 0;
}

}  // namespace

CLI::App* add_baked_subcommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(
        "baked", "ns per constraint projection: a baked garment vs its mesh cooked in memory (with / without lattice)");
    GarmentOptions& o = g_options;
    cmd->add_option("patterns", o.patterns,
                    "sewing patterns (PATTERN@Y adds Y metres to every placement: GarmentCode v1), or .weft assets timed as stored")
        ->required();
    cmd->add_option("--iterations", o.iterations, "constraint sweeps per step (one substep)")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    cmd->add_option("--steps", o.steps, "timed steps per run")->check(CLI::Range(1u, 100000u))->capture_default_str();
    cmd->add_option("--warmup", o.warmup, "untimed steps first")->capture_default_str();
    cmd->add_option("--repeat", o.repeat, "runs per variant, taking turns; the lowest median is kept")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    cmd->add_option("--paths", o.paths, "SIMD paths: scalar, avx2")->delimiter(',')->check(CLI::IsMember({"scalar", "avx2"}));
    cmd->add_flag("--json", o.json, "one JSON object per pattern, variant and path");
    return cmd;
}

int run_baked() {
    std::vector<SimdPath> paths;
    for (const std::string& p : g_options.paths) {
        const SimdPath path = p == "scalar" ? SimdPath::scalar : SimdPath::avx2;
        if (!simd_path_available(path)) {
            std::fprintf(stderr, "weft-bench baked: the %s path is not available here\n", p.c_str());
            return 1;
        }
        paths.push_back(path);
    }
    if (!g_options.json)
        std::printf("%-34s %-6s %-13s %6s %6s   %5s   %5s   %8s   %8s   %s\n", "pattern", "path", "asset", "parts", "cons",
                    "cf", "pad", "ns/proj", "step/proj", "vs mesh");
    int status = 0;
    for (const std::string& pattern : g_options.patterns) status |= run_pattern(pattern, paths);
    return status;
}

}  // namespace weft::bench
