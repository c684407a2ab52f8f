// weft-sim: runs a scene file headless and reports every frame.
//
//   weft-sim SCENE.json [--frames N] [--out DIR] [--json] [--simd automatic|scalar|avx2] [--assets DIR] [--threads N]
//            [--png FILE [--frame N]] [--gif FILE | --mp4 FILE] [--gltf FILE.glb] [--every K]
//            [--camera AZ,EL[,DIST]] [--size WxH] [--progress-label TEXT]
//
// The world is created with exactly what the scene names (docs/scene-format.md). Every frame is one
// step(dt); its wall time is measured around that call only. --out writes one OBJ per frame (all
// cloths, caller particle order); --json prints one JSON object per frame and a last one with
// "summary": true and the medians. Exit codes: 0 done, 1 bad arguments or scene, 2 the simulation
// failed (a step refused, or a position stopped being finite). --png, --gif and --mp4 draw the scene
// (pictures.h) after the run, --gltf exports it (gltf_export.h); the step times do not include
// either. On a terminal a progress bar on stderr shows the run and the exports (not with --json,
// unless --progress-label names it: samples/figures/make-figures does).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/metrics.h"
#include "sim/pictures.h"
#include "common/progress.h"
#include "common/scene_json.h"
#include "common/thread_pool.h"
#include "weft/debug.h"

namespace {

using namespace weft;

struct FrameReport {
    uint32_t frame = 0;
    double us_step = 0.0;
    double max_strain = 0.0, mean_strain = 0.0;
    Vec3 max_strain_at{};  // the midpoint of the most strained spring
    double max_penetration_m = 0.0;
    double mean_speed_m_s = 0.0;
    bool finite = true;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

FrameReport measure(const scenes::Scene& scene, const scenes::SceneWorld& sw, uint32_t frame, double us) {
    FrameReport r;
    r.frame = frame;
    r.us_step = us;
    uint32_t particles = 0;
    for (const scenes::SceneCloth& c : sw.cloths) {
        ClothView view;
        view_cloth(sw.world, c.id, &view);
        const metrics::Strain s = metrics::stretch_strain(view);
        if (s.max >= r.max_strain) r.max_strain_at = s.max_at;
        r.max_strain = std::max(r.max_strain, s.max);
        r.mean_strain += s.mean * c.asset->particle_count;
        particles += c.asset->particle_count;
        r.max_penetration_m = std::max(r.max_penetration_m, metrics::max_penetration_m(view, scene.colliders.data(),
                                                                                     uint32_t(scene.colliders.size())));
        if (sw.body) r.max_penetration_m = std::max(r.max_penetration_m, metrics::max_body_penetration_m(sw.world, sw.body->id, view));
        r.mean_speed_m_s += metrics::mean_speed(view) * c.asset->particle_count;
        r.finite = r.finite && metrics::bounds(view).finite;
    }
    r.mean_strain /= particles;
    r.mean_speed_m_s /= particles;
    return r;
}

bool write_obj(const std::filesystem::path& file, const scenes::SceneWorld& sw, const scenes::Scene& scene) {
    std::ofstream out(file);
    out << "# weft-sim frame\n";
    uint32_t base = 1;  // OBJ indices start at 1
    const std::vector<std::vector<Vec3>> positions = scenes::cloth_positions(sw);
    for (size_t i = 0; i < sw.cloths.size(); ++i) {
        const scenes::SceneCloth& c = sw.cloths[i];
        const std::vector<Vec3>& p = positions[i];
        out << "o " << scene.cloths[i].name << "\n";
        for (const Vec3& v : p) out << "v " << v.x << ' ' << v.y << ' ' << v.z << "\n";
        const std::vector<uint32_t> t = scenes::caller_triangles(*c.asset);
        for (size_t k = 0; k < t.size(); k += 3)
            out << "f " << t[k] + base << ' ' << t[k + 1] + base << ' ' << t[k + 2] + base << "\n";
        base += uint32_t(p.size());
    }
    return bool(out);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-sim: runs a Weft scene file headless and reports every frame"};
    std::string scene_path, out_dir, simd;
    uint32_t frames = 0;
    bool json = false;
    app.add_option("scene", scene_path, "scene file (docs/scene-format.md)")->required();
    app.add_option("--frames", frames, "frames to run (default: the scene's)")->check(CLI::Range(1u, 10000000u));
    app.add_option("--out", out_dir, "write one OBJ per frame into this folder");
    std::vector<std::string> asset_dirs;
    app.add_option("--assets", asset_dirs, "folders to look for the scene's relative asset paths in (after the scene's own)");
    app.add_flag("--json", json, "one JSON object per frame, then a summary object");
    uint32_t threads = 1;
    app.add_option("--threads", threads, "threads the step's work items run on (the built-in pool; same bits on any count)")
        ->check(CLI::Range(1u, 256u))->capture_default_str();
    app.add_option("--simd", simd, "override the scene's SIMD path")
        ->check(CLI::IsMember({"automatic", "scalar", "avx2"}));
    sim::PictureOptions pictures;
    std::string camera, size, gif, mp4;
    app.add_option("--png", pictures.png, "write a picture of one frame (default: the last) to this PNG");
    app.add_option("--frame", pictures.png_frame, "--png shows the state after this many frames")
        ->check(CLI::Range(1u, 10000000u));
    auto* gif_option = app.add_option("--gif", gif, "write the animation as a GIF (ffmpeg)");
    app.add_option("--mp4", mp4, "write the animation as an MP4 (ffmpeg, H.264)")->excludes(gif_option);
    app.add_option("--gltf", pictures.gltf, "write the whole run as one glTF 2.0 binary (.glb): morph targets per frame");
    auto* every_option = app.add_option("--every", pictures.every, "the animation keeps every K-th frame (default 3; --gltf: 1)")
        ->check(CLI::Range(1u, 10000u));
    std::string progress_label;
    app.add_option("--progress-label", progress_label,
                   "label the progress bar with this, and show it even with --json or stdout captured (stderr must be a terminal)");
    app.add_option("--camera", camera, "AZIMUTH,ELEVATION[,DISTANCE]: degrees, degrees, metres (default 35,20 framing the scene)");
    app.add_option("--size", size, "picture size WxH (default 1280x720)");
    CLI11_PARSE(app, argc, argv);
    pictures.animation = gif.empty() ? mp4 : gif;
    if (every_option->count() > 0) pictures.gltf_every = pictures.every;
    for (std::string e : {camera.empty() ? std::string() : sim::parse_camera(camera, &pictures),
                          size.empty() ? std::string() : sim::parse_size(size, &pictures)}) {
        if (!e.empty()) {
            std::fprintf(stderr, "weft-sim: %s\n", e.c_str());
            return 1;
        }
    }
    if ((!pictures.png.empty() || !pictures.animation.empty()) && !sim::renderer_built_in()) {
        std::fprintf(stderr, "weft-sim: --png, --gif and --mp4 need the renderer, and this weft-sim was built without it (--gltf does not)\n");
        return 1;
    }

    scenes::Scene scene;
    if (std::string e = scenes::load_scene_file(scene_path, &scene); !e.empty()) {
        std::fprintf(stderr, "weft-sim: %s\n", e.c_str());
        return 1;
    }
    if (frames > 0) scene.frames = frames;
    if (pictures.png_frame > scene.frames) {
        std::fprintf(stderr, "weft-sim: --frame %u is past the last frame (%u)\n", pictures.png_frame, scene.frames);
        return 1;
    }
    if (simd == "scalar") scene.simd = SimdPath::scalar;
    if (simd == "avx2") scene.simd = SimdPath::avx2;
    if (simd == "automatic") scene.simd = SimdPath::automatic;
    tools::ThreadPool pool(threads);  // outlives the world (declared first)
    scene.scheduler = pool.scheduler();
    scenes::SceneWorld sw;
    if (std::string e = scenes::build_scene(scene, &sw, asset_dirs); !e.empty()) {
        std::fprintf(stderr, "weft-sim: %s: %s\n", scene_path.c_str(), e.c_str());
        return 1;
    }
    if (!out_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(out_dir, ec);
        if (ec) {
            std::fprintf(stderr, "weft-sim: cannot create '%s': %s\n", out_dir.c_str(), ec.message().c_str());
            return 1;
        }
    }

    uint32_t particles = 0;
    for (const scenes::SceneCloth& c : sw.cloths) particles += c.asset->particle_count;
    if (!json) {
        std::string body;  // the body and how the cloth collides with it
        if (sw.body) {
            body = std::string(", body by ") + scenes::body_collision_name(sw.body->spec.collision);
            if (!sw.body->limb_capsules.empty())
                body += " + " + std::to_string(sw.body->limb_capsules.size()) + " limb capsules";
        }
        std::printf("weft-sim %s: %zu cloth(s), %u particles, %zu collider(s)%s, %s, dt %.4g s, %u frames\n",
                    scene_path.c_str(), sw.cloths.size(), particles, scene.colliders.size(), body.c_str(),
                    simd_path_name(world_simd_path(sw.world)), double(scene.dt_s), scene.frames);
    }
    sim::PictureRecorder recorder(pictures, scene.frames, scene.dt_s);
    const bool show_progress = progress_label.empty() ? progress::wanted(json) : progress::stderr_is_terminal();
    progress::Bar bar(progress_label.empty() ? "weft-sim " + scene_path : progress_label, scene.frames, show_progress);
    if (pictures.wanted()) recorder.after_frame(0, sw);
    std::vector<double> us, max_strain;
    FrameReport last;
    double worst_penetration = 0.0;
    for (uint32_t f = 1; f <= scene.frames; ++f) {
        if (std::string e = scenes::animate_body(sw, float(f) * scene.dt_s); !e.empty()) {
            std::fprintf(stderr, "weft-sim: frame %u: body: %s\n", f, e.c_str());
            return 2;
        }
        const auto t0 = std::chrono::steady_clock::now();
        const Result r = step(sw.world, scene.dt_s);
        const auto t1 = std::chrono::steady_clock::now();
        if (!r.ok()) {
            bar.finish();
            std::fprintf(stderr, "weft-sim: step %u refused: %s\n", f, r.message);
            return 2;
        }
        last = measure(scene, sw, f, std::chrono::duration<double, std::micro>(t1 - t0).count());
        us.push_back(last.us_step);
        max_strain.push_back(last.max_strain);
        worst_penetration = std::max(worst_penetration, last.max_penetration_m);
        if (json) {
            const nlohmann::json j = {{"frame", f},
                                      {"us_step", last.us_step},
                                      {"max_strain", last.max_strain},
                                      {"max_strain_at_m", {last.max_strain_at.x, last.max_strain_at.y, last.max_strain_at.z}},
                                      {"mean_strain", last.mean_strain},
                                      {"max_penetration_m", last.max_penetration_m},
                                      {"mean_speed_m_s", last.mean_speed_m_s},
                                      {"particles", particles}};
            std::printf("%s\n", j.dump().c_str());
        }
        if (!out_dir.empty()) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%05u.obj", f);
            if (!write_obj(std::filesystem::path(out_dir) / name, sw, scene)) {
                bar.finish();
                std::fprintf(stderr, "weft-sim: cannot write %s/%s\n", out_dir.c_str(), name);
                return 1;
            }
        }
        if (!last.finite) {
            bar.finish();
            std::fprintf(stderr, "weft-sim: frame %u: a position is no longer finite\n", f);
            return 2;
        }
        if (pictures.wanted()) recorder.after_frame(f, sw);
        bar.update(f);
    }
    bar.finish();
    const double us_median = median(us), strain_median = median(max_strain);
    if (json) {
        const nlohmann::json j = {{"summary", true},
                                  {"scene", scene.name},
                                  {"frames", scene.frames},
                                  {"particles", particles},
                                  {"simd", simd_path_name(world_simd_path(sw.world))},
                                  {"us_step", us_median},
                                  {"max_strain", strain_median},
                                  {"final_max_strain", last.max_strain},
                                  {"final_mean_strain", last.mean_strain},
                                  {"max_penetration_m", worst_penetration},
                                  {"final_mean_speed_m_s", last.mean_speed_m_s}};
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("median step %.1f us (%.3f ms of a %.1f ms frame); median max strain %.3f%%\n", us_median,
                    us_median / 1000.0, 1000.0 * scene.dt_s, 100.0 * strain_median);
        std::printf("last frame: max strain %.3f%%, mean strain %.4f%%, mean speed %.4f m/s; deepest penetration %.2f mm\n",
                    100.0 * last.max_strain, 100.0 * last.mean_strain, last.mean_speed_m_s, 1000.0 * worst_penetration);
    }
    if (pictures.wanted()) {
        std::fflush(stdout);  // the report first, then any error from drawing
        if (std::string e = recorder.write(scene, sw, show_progress); !e.empty()) {
            std::fprintf(stderr, "weft-sim: %s\n", e.c_str());
            return 1;
        }
        if (!json) {
            if (!pictures.png.empty()) std::printf("picture: %s\n", pictures.png.c_str());
            if (!pictures.animation.empty()) std::printf("animation: %s\n", pictures.animation.c_str());
            if (!pictures.gltf.empty()) std::printf("glTF: %s\n", pictures.gltf.c_str());
        }
    }
    return 0;
}
