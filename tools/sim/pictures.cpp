#include "sim/pictures.h"

#include <cstdio>

#include "render/scene_snapshot.h"
#include "sim/gltf_export.h"

namespace weft::sim {

std::string parse_camera(const std::string& text, PictureOptions* options) {
    float azimuth = 0.0f, elevation = 0.0f, distance = 0.0f;
    char end = 0;
    const int n = std::sscanf(text.c_str(), "%f,%f,%f%c", &azimuth, &elevation, &distance, &end);
    if (n != 2 && n != 3) return "--camera: expected AZIMUTH,ELEVATION[,DISTANCE], got '" + text + "'";
    if (elevation < -89.0f || elevation > 89.0f) return "--camera: elevation must be in [-89, 89] degrees";
    if (distance < 0.0f) return "--camera: distance must be positive (or 0: frame the scene)";
    options->azimuth_deg = azimuth;
    options->elevation_deg = elevation;
    options->distance_m = distance;
    return {};
}

std::string parse_size(const std::string& text, PictureOptions* options) {
    int width = 0, height = 0;
    char end = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &end) != 2 || width < 16 || height < 16 ||
        width > 8192 || height > 8192)
        return "--size: expected WIDTHxHEIGHT, each 16 to 8192 pixels, got '" + text + "'";
    options->width = width;
    options->height = height;
    return {};
}

PictureRecorder::PictureRecorder(const PictureOptions& options, uint32_t scene_frames, float dt_s)
    : options_(options), png_frame_(options.png_frame == 0 ? scene_frames : options.png_frame), dt_s_(dt_s) {}

PictureRecorder::Frame PictureRecorder::frame_of(const scenes::SceneWorld& world) {
    return {scenes::cloth_positions(world), world.body ? world.body->pose : std::vector<Vec3>{}};
}

void PictureRecorder::after_frame(uint32_t frame, const scenes::SceneWorld& world) {
    if (!options_.png.empty() && frame == png_frame_) png_frame_state_ = frame_of(world);
    if (!options_.animation.empty() && frame % options_.every == 0) animation_frames_.push_back(frame_of(world));
    if (!options_.gltf.empty() && frame % options_.gltf_every == 0) {
        gltf_frames_.push_back(scenes::cloth_positions(world));
        if (world.body) gltf_frames_.back().push_back(world.body->pose.empty() ? world.body->rest : world.body->pose);
        gltf_times_s_.push_back(float(frame) * dt_s_);
    }
}

std::string PictureRecorder::write(const scenes::Scene& scene, const scenes::SceneWorld& world, bool show_progress) const {
    render::Snapshot snapshot = render::snapshot_of_scene(scene, world);
    if (!options_.gltf.empty())
        if (std::string e = export_scene_gltf(options_.gltf, scene, snapshot, gltf_frames_, gltf_times_s_, show_progress);
            !e.empty())
            return e;
    if (options_.png.empty() && options_.animation.empty()) return {};
    return draw(scene, std::move(snapshot), show_progress);
}

}  // namespace weft::sim
