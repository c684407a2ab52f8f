// weft-sim's pictures and exports: --png (one frame), --gif / --mp4 (the animation), --gltf (the
// run as one glTF binary, gltf_export.h). While the scene runs the recorder keeps the positions of
// the frames it needs; at the end it renders or exports them with tools/render's geometry.
// The glTF export needs no OpenGL; built without the renderer (libepoxy missing), the pictures
// are refused with the reason.
#pragma once

#include <string>
#include <vector>

#include "common/scene.h"
#include "render/scene_snapshot.h"

namespace weft::sim {

struct PictureOptions {
    std::string png;                 // --png FILE
    uint32_t png_frame = 0;          // --frame N: the state after N frames; 0 = after the last
    std::string animation;           // --gif FILE or --mp4 FILE
    uint32_t every = 3;              // --every K: the animation keeps every K-th frame
    std::string gltf;                // --gltf FILE.glb
    uint32_t gltf_every = 1;         // the glTF keeps every frame unless --every says otherwise
    float azimuth_deg = 35.0f, elevation_deg = 20.0f;
    float distance_m = 0.0f;         // 0 = frame the scene
    int width = 1280, height = 720;  // --size WxH
    bool wanted() const { return !png.empty() || !animation.empty() || !gltf.empty(); }
};

// Parses --camera AZIMUTH,ELEVATION[,DISTANCE] (degrees, degrees, metres) and --size WxH into
// `options`; returns the error (empty when fine).
std::string parse_camera(const std::string& text, PictureOptions* options);
std::string parse_size(const std::string& text, PictureOptions* options);

// Whether this weft-sim was built with the renderer.
bool renderer_built_in();

class PictureRecorder {
public:
    PictureRecorder(const PictureOptions& options, uint32_t scene_frames, float dt_s);
    // Call with frame 0 before the first step, then after every step.
    void after_frame(uint32_t frame, const scenes::SceneWorld& world);
    // Renders and writes the files, with a progress bar when `show_progress`; returns the error
    // (empty when written).
    std::string write(const scenes::Scene& scene, const scenes::SceneWorld& world, bool show_progress) const;

private:
    using Positions = std::vector<std::vector<Vec3>>;  // per cloth, caller order
    struct Frame {
        Positions cloths;
        std::vector<Vec3> body;  // the body's pose (empty: no body, or still at rest)
    };
    static Frame frame_of(const scenes::SceneWorld& world);
    // Draws --png and --gif / --mp4 (pictures_render.cpp; pictures_none.cpp refuses).
    std::string draw(const scenes::Scene& scene, render::Snapshot snapshot, bool show_progress) const;
    PictureOptions options_;
    uint32_t png_frame_ = 0;
    Frame png_frame_state_;
    std::vector<Frame> animation_frames_;
    std::vector<Positions> gltf_frames_;
    std::vector<float> gltf_times_s_;
    float dt_s_ = 0.0f;
};

}  // namespace weft::sim
