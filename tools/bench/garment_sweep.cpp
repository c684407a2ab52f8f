#include "bench/garment_sweep.h"

#include <unistd.h>

#include <cmath>

#include "bench/garment.h"
#include "weft/debug.h"

namespace weft::bench {

GarmentSweepScene::~GarmentSweepScene() {
    built.reset();
    std::error_code ignored;
    if (!dir.empty()) std::filesystem::remove_all(dir, ignored);
}

std::string make_garment_sweep_scene(GarmentSweepScene* out) {
    bake::SewBody mannequin;
    if (std::string e = mannequin_sew_body(&mannequin); !e.empty()) return e;
    out->dir = std::filesystem::temp_directory_path() / ("weft_sweep_garment_" + std::to_string(getpid()));
    bake::Baked baked;
    if (std::string e = dress_scene(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json",
                                    std::string(WEFT_SOURCE_DIR) + "/samples/patterns/skirt.json", mannequin, out->dir,
                                    &out->scene, &baked);
        !e.empty())
        return e;
    out->built = std::make_unique<scenes::SceneWorld>();
    return scenes::build_scene(out->scene, out->built.get(), {out->dir.string()});
}

std::string build_garment_world(const GarmentSweepScene& garment, const scenes::SceneOptions& split,
                                scenes::SceneWorld* out) {
    scenes::Scene scene = garment.scene;
    scene.simd = split.simd;
    ClothDesc& cd = scene.cloths[0].desc;
    cd.policy = BudgetPolicy::explicit_split;
    cd.substeps = split.substeps;
    cd.iterations = split.iterations;
    cd.sweeps = split.substeps * split.iterations;
    cd.tethers = split.tethers;
    cd.tethers_before_sweeps = split.tethers_before_sweeps;
    cd.coarse_level = split.coarse_level;
    cd.relaxation = split.relaxation;
    cd.projection = split.projection;
    return scenes::build_scene(scene, out, {garment.dir.string()});
}

std::string run_garment_trajectory(const GarmentSweepScene& garment, const scenes::SceneOptions& split,
                                   const Sampling& sampling, Trajectory* out) {
    *out = Trajectory{};
    scenes::SceneWorld sw;
    if (std::string e = build_garment_world(garment, split, &sw); !e.empty()) return e;
    const float dt_s = garment.scene.dt_s;
    const ClothId cloth = sw.cloths[0].id;
    const uint32_t count = sw.cloths[0].asset->particle_count;
    out->start.resize(count);
    if (Result r = read_positions(sw.world, cloth, out->start.data(), count); !r.ok()) return r.message;
    out->step_us.reserve(sampling.frames);
    out->step_wall_us.reserve(sampling.frames);
    StepClock clock;
    for (uint32_t frame = 1; frame <= sampling.frames; ++frame) {
        if (std::string e = scenes::animate_body(sw, float(frame) * dt_s); !e.empty()) return e;
        clock.start();
        const Result r = step(sw.world, dt_s);
        clock.stop(&out->step_us, &out->step_wall_us);
        if (!r.ok()) return std::string("step failed: ") + r.message;
        if (!sampling.sampled(frame)) continue;
        std::vector<Vec3> positions(count);
        if (Result rr = read_positions(sw.world, cloth, positions.data(), count); !rr.ok()) return rr.message;
        for (const Vec3& p : positions) out->finite = out->finite && std::isfinite(p.x + p.y + p.z);
        ClothView view;
        if (Result rv = view_cloth(sw.world, cloth, &view); !rv.ok()) return rv.message;
        out->max_penetration_m = std::max(out->max_penetration_m, metrics::max_body_penetration_m(sw.world, sw.body->id, view));
        out->frames.push_back(std::move(positions));
    }
    return {};
}

}  // namespace weft::bench
