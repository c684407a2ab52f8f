#include "bench/crowd.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "bench/bench_run.h"
#include "bench/garment.h"
#include "common/crowd.h"
#include "common/metrics.h"
#include "common/thread_pool.h"
#include "weft/debug.h"

namespace weft::bench {

namespace {

// Every cloth's positions, in cloth order.
std::vector<Vec3> all_positions(const scenes::Crowd& crowd) {
    std::vector<Vec3> all, p;
    for (const scenes::CrowdCharacter& who : crowd.characters)
        for (ClothId cloth : {who.skirt, who.tee}) {
            ClothView view;
            if (!view_cloth(crowd.world, cloth, &view).ok()) return {};
            p.resize(view.asset->particle_count);
            if (!read_positions(crowd.world, cloth, p.data(), uint32_t(p.size())).ok()) return {};
            all.insert(all.end(), p.begin(), p.end());
        }
    return all;
}

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

// The frame budget's priorities: nearness to a camera 3 m in front of the crowd's first row, at eye
// height, across from the grid's middle (priority = -distance in metres, so nearer is higher).
Result set_priorities_by_camera(scenes::Crowd& crowd) {
    float far_x = 0.0f;
    for (const scenes::CrowdCharacter& who : crowd.characters) far_x = std::max(far_x, who.offset_m.x);
    const Vec3 camera{0.5f * far_x, 1.6f, -3.0f};
    for (const scenes::CrowdCharacter& who : crowd.characters) {
        const Vec3 d{who.offset_m.x - camera.x, 1.0f - camera.y, who.offset_m.z - camera.z};  // to the waist
        const float priority = -std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        for (ClothId cloth : {who.skirt, who.tee})
            if (Result r = set_cloth_priority(crowd.world, cloth, priority); !r.ok()) return r;
    }
    return {};
}

// Each cloth's stretch strain over the measured frames, in cloth order: the worst frame's maximum
// and the frames' mean (as weft-bench garment reports them).
struct ClothStrain {
    double max = 0.0, mean_sum = 0.0;
};

void add_strain(const scenes::Crowd& crowd, std::vector<ClothStrain>* out) {
    out->resize(2 * crowd.characters.size());
    size_t k = 0;
    for (const scenes::CrowdCharacter& who : crowd.characters)
        for (ClothId cloth : {who.skirt, who.tee}) {
            ClothView view;
            ClothStrain& s = (*out)[k++];
            if (!view_cloth(crowd.world, cloth, &view).ok()) continue;
            const metrics::Strain strain = metrics::stretch_strain(view);
            s.max = std::max(s.max, strain.max);
            s.mean_sum += strain.mean;
        }
}

double median_of(std::vector<double> v) { return percentile(std::move(v), 0.5); }
double worst_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

}  // namespace

int run_crowd(const CrowdBenchOptions& o) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("weft_bench_crowd_" + std::to_string(getpid()));
    struct RemoveDir {
        std::filesystem::path dir;
        ~RemoveDir() { std::error_code ignored; std::filesystem::remove_all(dir, ignored); }
    } remove_dir{dir};
    bake::SewBody mannequin;
    if (std::string e = mannequin_sew_body(&mannequin); !e.empty())
        return std::fprintf(stderr, "weft-bench crowd: %s\n", e.c_str()), 1;
    const std::string samples = std::string(WEFT_SOURCE_DIR) + "/samples";
    scenes::CrowdOptions co;
    co.characters = o.characters;
    co.standing = std::min(o.standing, o.characters);
    co.sleep_speed_m_s = o.sleep_speed_m_s;
    co.skirt_scene = samples + "/scenes/skirt-walk.json";
    co.tee_scene = samples + "/scenes/tee-walk.json";
    co.asset_dirs = {dir.string()};
    for (const char* garment : {"skirt", "tee"}) {
        scenes::Scene scene;
        bake::Baked baked;
        const std::string scene_file = std::string(garment) == "skirt" ? co.skirt_scene : co.tee_scene;
        if (std::string e = dress_scene(scene_file, samples + "/patterns/" + garment + ".json", mannequin, dir, &scene, &baked);
            !e.empty())
            return std::fprintf(stderr, "weft-bench crowd: %s\n", e.c_str()), 1;
    }

    // One crowd per thread count, stepped in turn frame by frame, so a change in the machine's
    // load falls on all of them alike.
    // With a budget, each thread count has a second crowd under it, stepped in the same turn.
    struct Run {
        uint32_t threads;
        bool budgeted;
        std::unique_ptr<tools::ThreadPool> pool;
        std::unique_ptr<scenes::Crowd> crowd;
        std::vector<double> step_us;
        std::vector<ClothStrain> strain;  // with a budget only
        uint64_t cut_sum = 0;               // WorldStats::budget_cloths_cut over the measured frames
        double estimate_us_sum = 0.0;       // WorldStats::budget_estimate_us over them
    };
    std::vector<Run> runs;
    for (uint32_t threads : o.threads)
        for (bool budgeted : {false, true}) {
            if (budgeted && !(o.budget_us > 0.0f)) continue;
            Run r{threads, budgeted, std::make_unique<tools::ThreadPool>(threads), std::make_unique<scenes::Crowd>(), {}, {}};
            co.scheduler = r.pool->scheduler();
            if (std::string e = scenes::build_crowd(co, r.crowd.get()); !e.empty())
                return std::fprintf(stderr, "weft-bench crowd: %s\n", e.c_str()), 1;
            if (Result res = set_priorities_by_camera(*r.crowd); !res.ok())
                return std::fprintf(stderr, "weft-bench crowd: %s\n", res.message), 1;
            if (Result res = set_frame_budget_us(r.crowd->world, budgeted ? o.budget_us : 0.0f); !res.ok())
                return std::fprintf(stderr, "weft-bench crowd: %s\n", res.message), 1;
            runs.push_back(std::move(r));
        }
    const float dt = runs[0].crowd->dt_s;
    const uint32_t ramp = uint32_t(1.0f / dt + 0.5f);  // the walk's entry (the scenes' ramp_s)
    for (uint32_t frame = 1; frame <= ramp + o.frames; ++frame) {
        for (Run& r : runs) {
            if (std::string e = scenes::animate_crowd(*r.crowd, float(frame) * dt); !e.empty())
                return std::fprintf(stderr, "weft-bench crowd: %s\n", e.c_str()), 1;
            const auto start = std::chrono::steady_clock::now();
            if (Result res = step(r.crowd->world, dt); !res.ok())
                return std::fprintf(stderr, "weft-bench crowd: step: %s\n", res.message), 1;
            const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
            if (frame <= ramp) continue;
            r.step_us.push_back(us);
            if (!(o.budget_us > 0.0f)) continue;  // strain and the budget's counters: outside the timing
            add_strain(*r.crowd, &r.strain);
            const WorldStats stats = world_stats(r.crowd->world);
            r.cut_sum += stats.budget_cloths_cut;
            r.estimate_us_sum += stats.budget_estimate_us;
        }
    }
    const Run& first = runs[0];  // the first thread count without the budget
    const std::vector<Vec3> first_positions = all_positions(*first.crowd);
    const double one_thread_us = summarise(first.step_us).median;
    if (!o.json)
        std::printf("weft-bench crowd: %u mannequins in skirt and tee (%u standing still), sleep speed %g m/s, "
                    "frame budget %g us, %u frames after the 1 s ramp; the crowds step in turn\n",
                    o.characters, co.standing, double(o.sleep_speed_m_s), double(o.budget_us), o.frames);
    const Run* first_budgeted = nullptr;
    for (const Run& r : runs) {
        if (r.budgeted && first_budgeted == nullptr) first_budgeted = &r;
        const scenes::Crowd& c = *r.crowd;
        const double median = summarise(r.step_us).median, p99 = percentile(r.step_us, 0.99);
        const std::vector<Vec3> positions = all_positions(c);
        // Same bits as the first crowd of its kind (without the budget, or with it).
        const std::vector<Vec3> reference = r.budgeted ? all_positions(*first_budgeted->crowd) : first_positions;
        const uint64_t sleeping = world_stats(c.world).sleeping_cloths;  // after the last frame
        const bool same = !positions.empty() && positions.size() == reference.size() &&
                          std::memcmp(positions.data(), reference.data(), positions.size() * sizeof(Vec3)) == 0;
        if (o.json) {
            std::printf("{\"bench\":\"crowd\",\"threads\":%u,\"characters\":%zu,\"instances\":%zu,\"particles\":%u,"
                        "\"bodies\":%zu,\"frames\":%u,\"us_per_frame\":%.1f,\"p99_us\":%.1f,\"speedup_vs_first\":%.3f,"
                        "\"same_bits_as_first\":%s,\"standing\":%u,\"sleep_speed_m_s\":%g,\"sleeping\":%llu,"
                        "\"budget_us\":%g",
                        r.threads, c.characters.size(), 2 * c.characters.size(), c.particles, c.characters.size(),
                        o.frames, median, p99, one_thread_us / median, same ? "true" : "false", co.standing,
                        double(o.sleep_speed_m_s), static_cast<unsigned long long>(sleeping),
                        r.budgeted ? double(o.budget_us) : 0.0);
        } else {
            std::printf("  %u thread%s%s: %8.1f us a frame (median), p99 %8.1f us, %.2fx the first row, %s bits, "
                        "%llu cloths asleep\n",
                        r.threads, r.threads == 1 ? " " : "s", r.budgeted ? " budgeted" : "", median, p99,
                        one_thread_us / median, same ? "same" : "DIFFERENT", static_cast<unsigned long long>(sleeping));
        }
        if (r.budgeted) {  // against the crowd of its thread count without the budget (the row before)
            const Run& free = *(&r - 1);
            const double free_median = summarise(free.step_us).median;
            const double frames = double(r.step_us.size());
            std::vector<double> max_with, max_without, max_increase, mean_increase;
            for (size_t k = 0; k < r.strain.size(); ++k) {
                max_with.push_back(r.strain[k].max);
                max_without.push_back(free.strain[k].max);
                max_increase.push_back(r.strain[k].max - free.strain[k].max);
                mean_increase.push_back((r.strain[k].mean_sum - free.strain[k].mean_sum) / frames);
            }
            if (o.json)
                std::printf(",\"us_per_frame_without_budget\":%.1f,\"time_ratio\":%.3f,\"estimate_us\":%.1f,"
                            "\"estimate_us_without_budget\":%.1f,\"cloths_cut\":%.2f,"
                            "\"max_strain_median\":%.5f,\"max_strain_median_without_budget\":%.5f,"
                            "\"max_strain_worst\":%.5f,\"max_strain_worst_without_budget\":%.5f,"
                            "\"max_strain_increase_median\":%.5f,\"max_strain_increase_worst\":%.5f,"
                            "\"mean_strain_increase_median\":%.5f,\"mean_strain_increase_worst\":%.5f}\n",
                            free_median, median / free_median, r.estimate_us_sum / frames, free.estimate_us_sum / frames,
                            double(r.cut_sum) / frames, median_of(max_with), median_of(max_without), worst_of(max_with),
                            worst_of(max_without), median_of(max_increase), worst_of(max_increase),
                            median_of(mean_increase), worst_of(mean_increase));
            else
                std::printf("    the budget: %.2fx the time without it (%.1f us), estimate %.1f us (%.1f without), "
                            "%.1f cloths cut a frame; each instance's max strain %.2f%% (median; %.2f%% without), "
                            "worst %.2f%% (%.2f%%); it pays +%.3f%% max strain (median; worst +%.3f%%), "
                            "+%.4f%% mean strain (median; worst +%.4f%%)\n",
                            median / free_median, free_median, r.estimate_us_sum / frames, free.estimate_us_sum / frames,
                            double(r.cut_sum) / frames, 100 * median_of(max_with), 100 * median_of(max_without),
                            100 * worst_of(max_with), 100 * worst_of(max_without), 100 * median_of(max_increase),
                            100 * worst_of(max_increase), 100 * median_of(mean_increase), 100 * worst_of(mean_increase));
        } else if (o.json) {
            std::printf("}\n");
        }
        if (!same) return std::fprintf(stderr, "weft-bench crowd: %u threads gave other bits\n", r.threads), 1;
    }
    return 0;
}

}  // namespace weft::bench
