// weft-sim's pictures drawn by tools/render on a headless OpenGL context.
#include "render/headless.h"
#include "sim/pictures.h"
#include "common/progress.h"
#include "render/renderer.h"

namespace weft::sim {

bool renderer_built_in() { return true; }

std::string PictureRecorder::draw(const scenes::Scene& scene, render::Snapshot snapshot, bool show_progress) const {
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
