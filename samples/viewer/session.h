// What the viewer simulates, without any window: a scene file or a baked asset built into a world
// (lib/common/scene.h), the controls the panel changes, and what it shows per step: the time of
// each pass (WorldStats with profiling on), the step's wall time, the live max strain and
// penetration.
#pragma once

#include <string>
#include <vector>

#include "render/renderer.h"
#include "common/scene.h"
#include "weft/debug.h"

namespace weft::viewer {

inline constexpr float kPanelWidth = 400.0f;  // pixels at scale 1, margin included: the camera frames the rest

// Everything the panel's sliders set. Changed between steps; `wind_on` needs a reset (the world
// is created with or without the wind pass).
struct Controls {
    bool wind_on = false;
    float wind_speed_m_s = 0.0f;
    float wind_direction_deg = 0.0f;  // in the ground plane: 0 blows towards +x, 90 towards +z
    float gravity_m_s2 = 9.81f;       // downwards
    bool explicit_split = false;      // false: the cloth's budget spent by the automatic policy
    int substeps = 1, iterations = 3;
    bool tethers = true;
    float inflation_m = 0.0f;         // every collider's collision skin
};

// The step's passes as the panel groups them (weft::Pass: coarse and tethers count as
// constraints, the body pass as collisions).
enum class PassGroup { integrate, constraints, collisions, wind, count };
inline constexpr const char* kPassGroupNames[] = {"integrate", "constraints", "collisions", "wind"};
PassGroup group_of(Pass pass);

struct StepReport {
    double pass_ms[int(PassGroup::count)] = {};
    double step_ms = 0.0;  // wall time of step()
    double max_strain = 0.0;
    double max_penetration_m = 0.0;
};

class Session {
public:
    // Opens a scene file (.json) or a baked asset (.weft: the asset alone, held by its own pins,
    // above a ground plane). Returns the error (empty on success).
    std::string open(const std::string& path, const std::vector<std::string>& asset_dirs);
    // Rebuilds the world from the scene at frame 0 with the current controls.
    std::string reset();
    // Sends the controls to the world (a changed wind_on resets).
    std::string apply(const Controls& controls);
    // One step of the scene's dt; false (and the message) when the step refused.
    bool step(std::string* error);

    const Controls& controls() const { return controls_; }
    const scenes::Scene& scene() const { return scene_; }
    const StepReport& last() const { return last_; }
    uint32_t frame() const { return frame_; }
    uint32_t particles() const;
    SolverSplit split() const;  // of the first cloth, as the runtime spends it
    const char* simd() const { return simd_path_name(world_simd_path(world_.world)); }
    // The cloths at the current frame and the colliders at their current settings.
    const render::Snapshot& snapshot();

private:
    scenes::Scene scene_;
    std::vector<std::string> asset_dirs_;
    scenes::SceneWorld world_;
    Controls controls_;
    render::Snapshot snapshot_;
    StepReport last_;
    uint32_t frame_ = 0;
};

}  // namespace weft::viewer
