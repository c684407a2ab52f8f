// weft-sim's pictures drawn by tools/render on a headless OpenGL context, and the glTF export
// built from the same geometry (cloth surfaces, texture coordinates, collider meshes).
#include "sim/gltf_export.h"
#include "render/headless.h"
#include "sim/pictures.h"
#include "common/progress.h"
#include "render/renderer.h"
#include "render/scene_snapshot.h"

namespace weft::sim {

namespace {

std::string export_gltf(const std::string& path, const scenes::Scene& scene, const render::Snapshot& snapshot,
                        const std::vector<std::vector<std::vector<Vec3>>>& frames, const std::vector<float>& times_s,
                        bool show_progress) {
    GltfRun run;
    run.frames = frames;
    run.times_s = times_s;
    render::Box box;  // around every recorded frame: a plane collider's square is sized by it
    for (size_t i = 0; i < snapshot.cloths.size(); ++i) {
        run.cloths.push_back({scene.cloths[i].name, snapshot.cloths[i].triangles, snapshot.cloths[i].uv});
        for (const auto& frame : frames)
            for (const Vec3& p : frame[i]) box.add({p.x, p.y, p.z});
    }
    if (!snapshot.bodies.empty() && !frames.empty() && frames[0].size() > snapshot.cloths.size())
        run.cloths.push_back({"body", snapshot.bodies[0].triangles, {}, true});  // posed per frame (pictures.cpp)
    for (size_t i = 0; i < snapshot.colliders.size(); ++i) {
        render::SurfaceMesh m = render::collider_surface(snapshot.colliders[i], box);
        run.stills.push_back({"collider " + std::to_string(i), std::move(m.positions), std::move(m.normals),
                              std::move(m.indices)});
    }
    progress::Bar bar("weft-sim: writing " + path, run.cloths.size() * frames.size(), show_progress);
    return write_gltf(path, run, [&](size_t done, size_t) { bar.update(done); });
}

}  // namespace

bool renderer_built_in() { return true; }

std::string PictureRecorder::write(const scenes::Scene& scene, const scenes::SceneWorld& world, bool show_progress) const {
    render::Snapshot snapshot = render::snapshot_of_scene(scene, world);
    if (!options_.gltf.empty())
        if (std::string e = export_gltf(options_.gltf, scene, snapshot, gltf_frames_, gltf_times_s_, show_progress);
            !e.empty())
            return e;
    if (options_.png.empty() && options_.animation.empty()) return {};

    const int width = options_.width, height = options_.height;
    std::string error;
    const std::unique_ptr<render::HeadlessContext> context = render::HeadlessContext::create(width, height, &error);
    if (!context) return error;
    const std::unique_ptr<render::Renderer> renderer = render::Renderer::create(&error);
    if (!renderer) return error;

    const auto show = [&](const Frame& frame) {
        for (size_t i = 0; i < frame.cloths.size(); ++i) snapshot.cloths[i].positions = frame.cloths[i];
        if (!frame.body.empty() && !snapshot.bodies.empty()) snapshot.bodies[0].positions = frame.body;
    };
    const auto draw = [&](const render::Camera& camera) {
        context->begin_frame();
        renderer->draw(snapshot, camera, width, height);
        return context->read_image();
    };
    const render::CameraAngles angles{options_.azimuth_deg, options_.elevation_deg, options_.distance_m};
    const float aspect = float(width) / float(height);

    if (!options_.png.empty()) {
        show(png_frame_state_);
        const render::Camera camera = render::frame_box(render::bounds(snapshot), angles, aspect);
        if (!render::write_png(options_.png, draw(camera))) return "cannot write " + options_.png;
    }
    if (!options_.animation.empty()) {
        // One camera for the whole animation, framing every recorded frame.
        render::Box box;
        for (const Frame& frame : animation_frames_) {
            show(frame);
            box.add(render::bounds(snapshot));
        }
        const render::Camera camera = render::frame_box(box, angles, aspect);
        const double frames_per_second = 1.0 / (double(scene.dt_s) * options_.every);
        std::unique_ptr<render::AnimationWriter> writer =
            render::AnimationWriter::open(options_.animation, width, height, frames_per_second, &error);
        if (!writer) return error;
        progress::Bar bar("weft-sim: drawing " + options_.animation, animation_frames_.size(), show_progress);
        for (size_t f = 0; f < animation_frames_.size(); ++f) {
            show(animation_frames_[f]);
            if (!writer->add_frame(draw(camera))) break;  // close() reports why
            bar.update(f + 1);
        }
        bar.finish();
        if (!writer->close(&error)) return options_.animation + ": " + error;
    }
    return {};
}

}  // namespace weft::sim
