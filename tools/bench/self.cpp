// weft-bench self: per scene, one world without self-collision and one with it
// (ClothDesc::self_collision), stepped in turn every frame so that both see the same machine load;
// each row gives the median step and the frames in which the cloth passes through itself
// (metrics::self_crossings: mesh edges through triangles that share no particle with them).
//   weft-bench self [--frames N] [--json]
#include "bench/self.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/garment.h"
#include "common/metrics.h"
#include "common/scene.h"
#include "common/scene_json.h"
#include "common/seed_scenes.h"
#include "weft/debug.h"

namespace weft::bench {
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> x) {
    if (x.empty()) return 0.0;
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
}

struct Row {
    scenes::SceneWorld sw;
    std::vector<double> step_us, self_us;  // the step, and its self-collision pass
    uint32_t crossing_frames = 0, first_crossing = 0;
    uint64_t max_crossings = 0, contacts = 0;
};

}  // namespace

int run_self(const SelfBenchOptions& o) {
    const std::string source = WEFT_SOURCE_DIR;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("weft_bench_self_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    struct RemoveDir {
        std::filesystem::path dir;
        ~RemoveDir() { std::error_code ignored; std::filesystem::remove_all(dir, ignored); }
    } remove_dir{dir};

    struct Case {
        scenes::Scene scene;
        uint32_t warmup = 0;  // frames stepped before the measured ones (the walk's ramp)
    };
    std::vector<Case> cases;
    {
        scenes::Scene drape;
        if (std::string e = scenes::load_scene_file(source + "/samples/scenes/drape.json", &drape); !e.empty())
            return std::fprintf(stderr, "weft-bench self: %s\n", e.c_str()), 1;
        cases.push_back({drape, 0});
        cases.push_back({scenes::heap_scene(), 0});
        bake::SewBody mannequin;
        if (std::string e = mannequin_sew_body(&mannequin); !e.empty())
            return std::fprintf(stderr, "weft-bench self: %s\n", e.c_str()), 1;
        scenes::Scene skirt;
        bake::Baked baked;
        if (std::string e = dress_scene(source + "/samples/scenes/skirt-walk.json", source + "/samples/patterns/skirt.json",
                                        mannequin, dir, &skirt, &baked);
            !e.empty())
            return std::fprintf(stderr, "weft-bench self: %s\n", e.c_str()), 1;
        cases.push_back({skirt, uint32_t(skirt.body->ramp_s / skirt.dt_s + 0.5f)});
        // The same skirt while the mannequin bends forward and sits (its clip starts at rest).
        scenes::Scene sit;
        if (std::string e = dress_scene(source + "/samples/scenes/skirt-sit.json", source + "/samples/patterns/skirt.json",
                                        mannequin, dir, &sit, &baked);
            !e.empty())
            return std::fprintf(stderr, "weft-bench self: %s\n", e.c_str()), 1;
        cases.push_back({sit, 0});
    }
    if (!o.json)
        std::printf("weft-bench self: %u frames per scene, one thread; worlds without and with self-collision stepped "
                    "in turn\n%-12s %-5s %12s %12s %16s %14s %14s\n",
                    o.frames, "scene", "self", "us/step", "self us", "crossing frames", "max crossings", "contacts/step");
    for (Case& c : cases) {
        c.scene.profile = true;
        Row rows[2];
        for (int on = 0; on < 2; ++on) {
            scenes::Scene s = c.scene;
            for (scenes::ClothSpec& cloth : s.cloths) {
                cloth.desc.self_collision = on == 1;
                cloth.desc.self_thickness_m = o.thickness_m;
                cloth.desc.self_friction = o.friction;
            }
            if (std::string e = scenes::build_scene(s, &rows[on].sw, {dir.string()}); !e.empty())
                return std::fprintf(stderr, "weft-bench self: %s: %s\n", s.name.c_str(), e.c_str()), 1;
        }
        for (uint32_t f = 1; f <= c.warmup + o.frames; ++f) {
            for (Row& r : rows) {
                if (r.sw.body) scenes::animate_body(r.sw, float(f) * c.scene.dt_s);
                const uint64_t self_ns = world_stats(r.sw.world).pass_ns[int(Pass::self_collision)];
                const auto t0 = Clock::now();
                if (Result e = step(r.sw.world, c.scene.dt_s); !e.ok())
                    return std::fprintf(stderr, "weft-bench self: %s: %s\n", c.scene.name.c_str(), e.message), 1;
                const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
                if (f <= c.warmup) continue;
                r.step_us.push_back(us);
                r.self_us.push_back(double(world_stats(r.sw.world).pass_ns[int(Pass::self_collision)] - self_ns) / 1e3);
                ClothView cloth;
                view_cloth(r.sw.world, r.sw.cloths[0].id, &cloth);
                const uint64_t crossings = metrics::self_crossings(cloth);
                r.crossing_frames += crossings > 0;
                if (crossings > 0 && r.first_crossing == 0) r.first_crossing = f;
                r.max_crossings = std::max(r.max_crossings, crossings);
                r.contacts += world_stats(r.sw.world).self_contacts;
            }
        }
        const double off_us = median(rows[0].step_us);
        for (int on = 0; on < 2; ++on) {
            const Row& r = rows[on];
            const double us = median(r.step_us);
            const double contacts = double(r.contacts) / double(o.frames);
            if (o.json) {
                const nlohmann::json j = {{"scene", c.scene.name},
                                          {"self_collision", on == 1},
                                          {"particles", r.sw.cloths[0].asset->particle_count},
                                          {"us_per_step", us},
                                          {"vs_without", us / off_us},
                                          {"self_collision_us", median(r.self_us)},
                                          {"crossing_frames", r.crossing_frames},
                                          {"frames", o.frames},
                                          {"max_crossings", r.max_crossings},
                                          {"first_crossing_frame", r.first_crossing},
                                          {"contacts_per_step", contacts}};
                std::printf("%s\n", j.dump().c_str());
            } else {
                std::printf("%-12s %-5s %12.1f %12.1f %16u %14llu %14.1f\n", c.scene.name.c_str(), on ? "on" : "off", us,
                            median(r.self_us),
                            r.crossing_frames, static_cast<unsigned long long>(r.max_crossings), contacts);
            }
        }
    }
    return 0;
}

}  // namespace weft::bench
