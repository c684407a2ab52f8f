// weft-bench garment: per scene (samples/scenes/skirt-walk.json, tee-walk.json and, with ../shared,
// tests/scenes/dress-garmentcode.json), the garment is baked onto its body (weft-bake's
// bake_pattern with --body), the scene file is built and run, and every step is timed per pass
// (set_profiling, weft/debug.h). In the same run, after every step, a plain baseline of the body pass is
// timed with Embree directly: refit of a dynamic scene over the same offset hull, then one
// rtcPointQuery (closest point within thickness + margin) per particle per substep, no rays.
// One world per body collision model (--collision), stepped in turn every frame; every row gives
// the deepest particle by the exact hull query, the cloth's strain over the measured frames and
// the frames in which it passes through itself (metrics::self_crossings).
//   weft-bench garment [--steps N] [--collision exact,cached_planes] [--json]
#include "bench/garment.h"

#include <embree3/rtcore.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake/bake.h"
#include "body/body_mesh.h"
#include "body/mannequin.h"
#include "common/metrics.h"
#include "common/scene.h"
#include "common/scene_json.h"
#include "weft/closest_point.h"
#include "weft/debug.h"

namespace weft::bench {
namespace {

using Clock = std::chrono::steady_clock;

std::string read_text(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// The plain pass: its own Embree device and dynamic scene over a copy of the world's offset hull.
struct PlainPass {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;
    std::vector<float> hull;  // 4 per vertex (Embree's layout), + 4 of padding
    std::vector<uint32_t> triangles;
    float reach = 0.0f;

    struct Query {
        const PlainPass* pass;
        float p[3];
        float best2;
    };
    // Distance squared to the closest point on a triangle (Ericson 5.1.5, weft/closest_point.h).
    static float distance2(const float* p, const float* a, const float* b, const float* c) {
        const BarycentricWeights<float> w = closest_on_triangle(p, a, b, c);
        float d[3];
        for (int k = 0; k < 3; ++k) d[k] = p[k] - (a[k] + (b[k] - a[k]) * w.w1 + (c[k] - a[k]) * w.w2);
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    }
    static bool callback(RTCPointQueryFunctionArguments* args) {
        Query& q = *static_cast<Query*>(args->userPtr);
        const uint32_t* t = q.pass->triangles.data() + 3 * args->primID;
        const float* h = q.pass->hull.data();
        const float d2 = distance2(q.p, h + 4 * t[0], h + 4 * t[1], h + 4 * t[2]);
        if (!(d2 < q.best2)) return false;
        q.best2 = d2;
        args->query->radius = std::sqrt(d2);
        return true;
    }

    bool open(const BodyView& v) {
        device = rtcNewDevice(nullptr);
        if (device == nullptr) return false;
        scene = rtcNewScene(device);
        rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
        geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_REFIT);
        hull.assign(v.hull, v.hull + 4 * size_t(v.vertex_count));
        hull.resize(hull.size() + 4, 0.0f);
        triangles.assign(v.triangles, v.triangles + 3 * size_t(v.triangle_count));
        triangles.resize(triangles.size() + 4, 0u);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, hull.data(), 0, 16, v.vertex_count);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, triangles.data(), 0, 12,
                                   v.triangle_count);
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
        rtcCommitScene(scene);
        reach = v.thickness_m + v.margin_m;
        return true;
    }
    // The hull of this step (copied untimed), then timed: refit + one query per particle per substep.
    double run(const BodyView& v, const ClothView& cloth, uint32_t substeps) {
        std::copy(v.hull, v.hull + 4 * size_t(v.vertex_count), hull.begin());
        const auto t0 = Clock::now();
        rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(geometry);
        rtcCommitScene(scene);
        RTCPointQueryContext context;
        for (uint32_t s = 0; s < substeps; ++s)
            for (uint32_t i = 0; i < cloth.asset->slot_count; ++i) {
                if (!(cloth.inverse_mass[i] > 0.0f)) continue;
                Query q{this, {cloth.x[i], cloth.y[i], cloth.z[i]}, reach * reach};
                RTCPointQuery pq{};
                pq.x = q.p[0], pq.y = q.p[1], pq.z = q.p[2], pq.radius = reach, pq.time = 0.0f;
                rtcInitPointQueryContext(&context);
                rtcPointQuery(scene, &pq, &context, callback, &q);
            }
        return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    }
    ~PlainPass() {
        if (geometry) rtcReleaseGeometry(geometry);
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

double median(std::vector<double> x) {
    if (x.empty()) return 0.0;
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
}

struct Case {
    std::string scene_file, pattern;
    bool mannequin;  // else the shared mean_all
};

}  // namespace

bool garment_model_from_name(const std::string& name, GarmentModel* out) {
    const std::string suffix = "+limb_capsules";
    const bool capsules = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    out->limb_capsules = capsules;
    return scenes::body_collision_from_name(capsules ? name.substr(0, name.size() - suffix.size()) : name, &out->collision);
}

std::string garment_model_name(const GarmentModel& model) {
    return std::string(scenes::body_collision_name(model.collision)) + (model.limb_capsules ? "+limb_capsules" : "");
}

std::string mannequin_sew_body(bake::SewBody* out) {
    body::Mannequin m;
    if (std::string e = body::make_mannequin(body::Measurements{}, body::MannequinOptions{}, &m); !e.empty())
        return "mannequin: " + e;
    *out = {m.positions, m.triangles};
    return {};
}

std::string dress_scene(const std::string& scene_file, const std::string& pattern, const bake::SewBody& body,
                        const std::filesystem::path& dir, scenes::Scene* scene, bake::Baked* baked) {
    if (std::string e = scenes::load_scene_file(scene_file, scene); !e.empty()) return e;
    bake::BakeOptions options;
    options.body = &body;
    options.sew.sweeps = scene->cloths[0].desc.sweeps;  // dressed at the budget the scene runs it at
    options.render_subdivide = 1;  // a render mesh of 4 triangles a cloth triangle: the render world's
    if (bake::Status s = bake::bake_pattern(read_text(pattern), options, baked); !s.ok()) return pattern + ": " + s.error;
    std::filesystem::create_directories(dir);
    std::ofstream f((dir / scene->cloths[0].asset_path).string(), std::ios::binary);
    f.write(reinterpret_cast<const char*>(baked->bytes.data()), std::streamsize(baked->bytes.size()));
    return f ? std::string() : "cannot write " + (dir / scene->cloths[0].asset_path).string();
}

int run_garment(uint32_t steps, bool as_json, const std::vector<GarmentModel>& all_models, SimdPath simd) {
    const std::string shared = WEFT_SHARED_DATA_DIR;
    std::vector<Case> cases = {{std::string(WEFT_SOURCE_DIR) + "/samples/scenes/skirt-walk.json",
                                std::string(WEFT_SOURCE_DIR) + "/samples/patterns/skirt.json", true},
                               {std::string(WEFT_SOURCE_DIR) + "/samples/scenes/tee-walk.json",
                                std::string(WEFT_SOURCE_DIR) + "/samples/patterns/tee.json", true}};
    if (std::filesystem::exists(shared + "/bodies/mean_all.obj"))
        cases.push_back({std::string(WEFT_SOURCE_DIR) + "/tests/scenes/dress-garmentcode.json",
                         shared + "/patterns/garmentcode/dress_pencil_specification.json", false});
    // One folder per process: two runs at once (a Release and a sanitizer test suite) must not
    // read each other's half-written assets.
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("weft_bench_garment_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    struct RemoveDir {
        std::filesystem::path dir;
        ~RemoveDir() { std::error_code ignored; std::filesystem::remove_all(dir, ignored); }
    } remove_dir{dir};
    bake::SewBody mannequin, mean_all;
    {
        if (std::string e = mannequin_sew_body(&mannequin); !e.empty())
            return std::fprintf(stderr, "weft-bench garment: %s\n", e.c_str()), 1;
        body::BodyMesh b;
        if (cases.size() > 2 && body::load_body_mesh(shared + "/bodies/mean_all.obj", &b).empty())
            mean_all = {b.positions, b.triangles};
    }
    if (!as_json)
        std::printf("weft-bench garment: %u steps per scene after the walk's 1 s ramp, one thread; us per step (medians); "
                    "the models' worlds step in turn, frame by frame\n", steps);
    for (const Case& c : cases) {
        std::vector<GarmentModel> models;  // limb capsules follow the mannequin's bones
        for (const GarmentModel& m : all_models)
            if (!m.limb_capsules || c.mannequin) models.push_back(m);
        if (models.empty()) {  // only limb capsules asked for, on a body without bones
            std::fprintf(stderr, "weft-bench garment: %s skipped: its body has no bones for limb capsules\n",
                         c.scene_file.c_str());
            continue;
        }
        scenes::Scene scene;
        bake::Baked baked;
        if (std::string e = dress_scene(c.scene_file, c.pattern, c.mannequin ? mannequin : mean_all, dir, &scene, &baked);
            !e.empty())
            return std::fprintf(stderr, "weft-bench garment: %s\n", e.c_str()), 1;
        scene.profile = true;
        scene.simd = simd;
        scene.normals = true;  // a game renders the garment: the step ends with its vertex normals
        const std::vector<std::string> scene_capsules = scene.body->limb_capsules;
        // One world per model, stepped in turn every frame: the same load on each, so the ratios
        // between them hold even when the machine's speed drifts.
        struct Run {
            GarmentModel model;
            scenes::SceneWorld sw;
            std::vector<double> step_us, integrate_us, constraints_us, body_us, capsules_us, normals_us, health_us, other_us, plain_us;
            std::vector<double> springs_us, coarse_us, tethers_us;  // the parts of constraints_us
            double deepest = 0.0, max_strain = 0.0, strain_sum = 0.0, queried = 0.0;
            uint32_t crossing_frames = 0;  // frames where the cloth passes through itself (metrics::self_crossings)
            uint64_t max_crossings = 0;
            uint64_t projections = 0;  // spring lanes projected a step (padding excluded)
        };
        std::vector<Run> runs(models.size());
        for (size_t m = 0; m < models.size(); ++m) {
            runs[m].model = models[m];
            scene.body->collision = models[m].collision;
            scene.body->limb_capsules.clear();
            if (models[m].limb_capsules)
                scene.body->limb_capsules = scene_capsules.empty() ? std::vector<std::string>{"thigh.L", "thigh.R"} : scene_capsules;
            if (std::string e = scenes::build_scene(scene, &runs[m].sw, {dir.string()}); !e.empty())
                return std::fprintf(stderr, "weft-bench garment: %s: %s\n", scene.name.c_str(), e.c_str()), 1;
        }
        // The render output a game would also ask for, in one more world of the first model: tangents
        // (the normals pass with them, against the first model's without) and the render mesh.
        Run render;
        render.model = models[0];
        {
            scenes::Scene with = scene;
            with.body->collision = models[0].collision;
            with.body->limb_capsules.clear();
            if (models[0].limb_capsules)
                with.body->limb_capsules = scene_capsules.empty() ? std::vector<std::string>{"thigh.L", "thigh.R"} : scene_capsules;
            with.tangents = with.render_meshes = true;
            if (std::string e = scenes::build_scene(with, &render.sw, {dir.string()}); !e.empty())
                return std::fprintf(stderr, "weft-bench garment: %s: %s\n", scene.name.c_str(), e.c_str()), 1;
        }
        std::vector<double> render_us;
        BodyView view;
        view_body(runs[0].sw.world, runs[0].sw.body->id, &view);
        PlainPass plain;
        if (!plain.open(view)) return std::fprintf(stderr, "weft-bench garment: no Embree device\n"), 1;
        SolverSplit first_split;  // the first model's, for the plain pass's substeps
        cloth_solver_split(runs[0].sw.world, runs[0].sw.cloths[0].id, &first_split);
        const uint32_t warmup = uint32_t(std::lround((scene.body->ramp_s + 0.05f) / scene.dt_s));
        for (uint32_t f = 1; f <= warmup + steps; ++f) {
            for (Run& r : runs) {
                scenes::SceneWorld& sw = r.sw;
                scenes::animate_body(sw, float(f) * scene.dt_s);
                const WorldStats before = world_stats(sw.world);
                const auto t0 = Clock::now();
                step(sw.world, scene.dt_s);
                const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
                const WorldStats after = world_stats(sw.world);
                ClothView cloth;
                view_cloth(sw.world, sw.cloths[0].id, &cloth);
                view_body(sw.world, sw.body->id, &view);
                // The plain pass once a frame, on the first model's cloth (the exact one by default).
                const double baseline = &r == &runs[0] ? plain.run(view, cloth, first_split.substeps) : 0.0;
                if (f <= warmup) continue;
                auto pass = [&](Pass p) { return double(after.pass_ns[int(p)] - before.pass_ns[int(p)]) / 1e3; };
                const double integrate = pass(Pass::integrate) + pass(Pass::wind);
                const double constraints = pass(Pass::coarse) + pass(Pass::constraints) + pass(Pass::tethers);
                const double body = pass(Pass::body) + pass(Pass::collide);  // limb capsules are colliders
                r.step_us.push_back(us);
                r.integrate_us.push_back(integrate);
                r.constraints_us.push_back(constraints);
                r.springs_us.push_back(pass(Pass::constraints));
                r.coarse_us.push_back(pass(Pass::coarse));
                r.tethers_us.push_back(pass(Pass::tethers));
                r.body_us.push_back(body);
                r.capsules_us.push_back(pass(Pass::collide));
                r.normals_us.push_back(pass(Pass::normals));
                r.health_us.push_back(pass(Pass::health));
                r.other_us.push_back(us - integrate - constraints - body - pass(Pass::normals) - pass(Pass::health));
                if (&r == &runs[0]) r.plain_us.push_back(baseline);
                // Penetration by the exact hull query (query_body), whatever model stepped the cloth.
                r.deepest = std::max(r.deepest, metrics::max_body_penetration_m(sw.world, sw.body->id, cloth));
                const metrics::Strain strain = metrics::stretch_strain(cloth);
                r.max_strain = std::max(r.max_strain, strain.max);
                r.strain_sum += strain.mean;
                const uint64_t crossings = metrics::self_crossings(cloth);
                r.crossing_frames += crossings > 0;
                r.max_crossings = std::max(r.max_crossings, crossings);
                r.queried += double(after.body_queried);
                r.projections = after.run_projections + after.indexed_projections;
            }
            scenes::SceneWorld& rw = render.sw;
            scenes::animate_body(rw, float(f) * scene.dt_s);
            const WorldStats before = world_stats(rw.world);
            step(rw.world, scene.dt_s);
            const WorldStats after = world_stats(rw.world);
            if (f <= warmup) continue;
            render.normals_us.push_back(double(after.pass_ns[int(Pass::normals)] - before.pass_ns[int(Pass::normals)]) / 1e3);
            render_us.push_back(double(after.pass_ns[int(Pass::render_mesh)] - before.pass_ns[int(Pass::render_mesh)]) / 1e3);
        }
        const uint32_t render_vertices = render.sw.cloths[0].asset->render.vertex_count;
        const double tangents_us = median(render.normals_us) - median(runs[0].normals_us);
        const double plain_us = median(runs[0].plain_us);
        const Run* exact = nullptr;
        for (const Run& r : runs)
            if (r.model.collision == BodyCollision::exact && !r.model.limb_capsules) exact = &r;
        for (const Run& r : runs) {
            const scenes::SceneWorld& sw = r.sw;
            const double body_us = median(r.body_us), step_us = median(r.step_us);
            SolverSplit split;  // each model's own
            cloth_solver_split(sw.world, sw.cloths[0].id, &split);
            nlohmann::json j = {{"scene", scene.name},
                                {"collision", garment_model_name(r.model)},
                                {"simd", simd_path_name(world_simd_path(sw.world))},
                                {"limb_capsules", sw.body->limb_capsules.size()},
                                {"particles", sw.cloths[0].asset->particle_count},
                                {"body_triangles", sw.body->triangles.size() / 3},
                                {"steps", steps},
                                {"substeps", split.substeps},
                                {"iterations", split.iterations},
                                {"us_per_step", step_us},
                                {"integrate_us", median(r.integrate_us)},
                                {"constraints_us", median(r.constraints_us)},
                                {"springs_us", median(r.springs_us)},
                                {"coarse_us", median(r.coarse_us)},
                                {"tethers_us", median(r.tethers_us)},
                                {"spring_projections_per_step", double(r.projections)},
                                {"body_us", body_us},
                                {"limb_capsules_us", median(r.capsules_us)},
                                {"body_share", step_us > 0 ? body_us / step_us : 0.0},
                                {"normals_us", median(r.normals_us)},
                                {"health_us", median(r.health_us)},  // cloth_health's pass
                                // The render output, measured once per scene in the render world (above).
                                {"normals_with_tangents_us", median(render.normals_us)},
                                {"tangents_us", tangents_us},
                                {"render_vertices", render_vertices},
                                {"render_us", median(render_us)},
                                {"ns_per_render_vertex", render_vertices > 0 ? 1e3 * median(render_us) / render_vertices : 0.0},
                                {"other_us", median(r.other_us)},
                                {"baseline_point_query_us", plain_us},
                                {"body_vs_baseline", plain_us > 0 ? body_us / plain_us : 0.0},
                                {"max_penetration_m", r.deepest},
                                {"max_strain", r.max_strain},
                                {"body_queried_per_step", r.queried / double(steps)},
                                {"mean_strain", r.strain_sum / double(steps)},
                                {"self_crossing_frames", r.crossing_frames},
                                {"max_self_crossings", r.max_crossings},
                                {"sewing_s", baked.sew_report.sewing_s},
                                {"world_bytes", sw.memory_bytes}};
            if (exact != nullptr) {  // same-run ratios against the exact model (< 1: cheaper)
                j["step_vs_exact"] = median(exact->step_us) > 0 ? step_us / median(exact->step_us) : 0.0;
                j["body_vs_exact"] = median(exact->body_us) > 0 ? body_us / median(exact->body_us) : 0.0;
                j["max_strain_vs_exact"] = exact->max_strain > 0 ? r.max_strain / exact->max_strain : 0.0;
            }
            if (as_json) {
                std::printf("%s\n", j.dump().c_str());
            } else {
                std::printf("  %-18s %-13s %5u particles, %5zu body triangles: step %7.0f (integrate %5.0f, constraints %5.0f, "
                            "body %6.0f, normals %4.0f, other %5.0f); plain rtcPointQuery pass %6.0f; deepest %.2f mm; strain max %.1f%% "
                            "mean %.2f%%; %.0f particles searched a step; render output: tangents %.0f (normals with them %.0f), "
                            "%u render vertices %.0f (%.2f ns each)\n",
                            scene.name.c_str(), garment_model_name(r.model).c_str(), sw.cloths[0].asset->particle_count,
                            sw.body->triangles.size() / 3, step_us, median(r.integrate_us), median(r.constraints_us), body_us,
                            median(r.normals_us), median(r.other_us), plain_us, r.deepest * 1e3, 100.0 * r.max_strain,
                            100.0 * r.strain_sum / double(steps), r.queried / double(steps), tangents_us, median(render.normals_us),
                            render_vertices, median(render_us), render_vertices > 0 ? 1e3 * median(render_us) / render_vertices : 0.0);
            }
        }
        std::fflush(stdout);
    }
    std::filesystem::remove_all(dir);
    return 0;
}

}  // namespace weft::bench
