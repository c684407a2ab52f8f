#include "bench/crowd.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "bench/bench_run.h"
#include "bench/garment.h"
#include "common/crowd.h"
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
    struct Run {
        uint32_t threads;
        std::unique_ptr<tools::ThreadPool> pool;
        std::unique_ptr<scenes::Crowd> crowd;
        std::vector<double> step_us;
    };
    std::vector<Run> runs;
    for (uint32_t threads : o.threads) {
        Run r{threads, std::make_unique<tools::ThreadPool>(threads), std::make_unique<scenes::Crowd>(), {}};
        co.scheduler = r.pool->scheduler();
        if (std::string e = scenes::build_crowd(co, r.crowd.get()); !e.empty())
            return std::fprintf(stderr, "weft-bench crowd: %s\n", e.c_str()), 1;
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
            if (frame > ramp) r.step_us.push_back(us);
        }
    }
    const std::vector<Vec3> first_positions = all_positions(*runs[0].crowd);
    const double one_thread_us = summarise(runs[0].step_us).median;
    if (!o.json)
        std::printf("weft-bench crowd: %u mannequins in skirt and tee (%u standing still), sleep speed %g m/s, "
                    "%u frames after the 1 s ramp; the thread counts' crowds step in turn\n",
                    o.characters, co.standing, double(o.sleep_speed_m_s), o.frames);
    for (const Run& r : runs) {
        const scenes::Crowd& c = *r.crowd;
        const double median = summarise(r.step_us).median, p99 = percentile(r.step_us, 0.99);
        const std::vector<Vec3> positions = all_positions(c);
        const uint64_t sleeping = world_stats(c.world).sleeping_cloths;  // after the last frame
        const bool same = !positions.empty() && positions.size() == first_positions.size() &&
                          std::memcmp(positions.data(), first_positions.data(), positions.size() * sizeof(Vec3)) == 0;
        if (o.json) {
            std::printf("{\"bench\":\"crowd\",\"threads\":%u,\"characters\":%zu,\"instances\":%zu,\"particles\":%u,"
                        "\"bodies\":%zu,\"frames\":%u,\"us_per_frame\":%.1f,\"p99_us\":%.1f,\"speedup_vs_first\":%.3f,"
                        "\"same_bits_as_first\":%s,\"standing\":%u,\"sleep_speed_m_s\":%g,\"sleeping\":%llu}\n",
                        r.threads, c.characters.size(), 2 * c.characters.size(), c.particles, c.characters.size(),
                        o.frames, median, p99, one_thread_us / median, same ? "true" : "false", co.standing,
                        double(o.sleep_speed_m_s), static_cast<unsigned long long>(sleeping));
        } else {
            std::printf("  %u thread%s: %8.1f us a frame (median), p99 %8.1f us, %.2fx the first row, %s bits, "
                        "%llu cloths asleep\n",
                        r.threads, r.threads == 1 ? " " : "s", median, p99, one_thread_us / median,
                        same ? "same" : "DIFFERENT", static_cast<unsigned long long>(sleeping));
        }
        if (!same) return std::fprintf(stderr, "weft-bench crowd: %u threads gave other bits\n", r.threads), 1;
    }
    return 0;
}

}  // namespace weft::bench
