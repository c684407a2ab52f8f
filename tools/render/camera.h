// The camera: frames a bounding box from a direction (azimuth, elevation) so that the whole box is in
// view, and projects world points to pixels (the render test uses it to say where the cloth must be).
// Pure maths, no OpenGL: the headless renderer and a future window share it.
#pragma once

#include <limits>

#include <vector>

#include <glm/glm.hpp>

#include "weft/types.h"

namespace weft::render {

// An axis-aligned box in metres; empty until a point is added.
struct Box {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{-std::numeric_limits<float>::max()};
    void add(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void add(const Box& b) {
        if (!b.empty()) add(b.min), add(b.max);
    }
    bool empty() const { return min.x > max.x; }
    glm::vec3 centre() const { return 0.5f * (min + max); }
    float diagonal() const { return empty() ? 0.0f : glm::length(max - min); }
};

// Where the camera looks from. y is up; azimuth 0 looks from +z towards -z, positive azimuths turn
// the camera towards +x; positive elevations look down on the scene.
struct CameraAngles {
    float azimuth_deg = 35.0f;
    float elevation_deg = 20.0f;
    float distance_m = 0.0f;  // from the box's centre; 0 = the nearest distance that shows the whole box
};

inline constexpr float kVerticalFieldOfView_deg = 35.0f;

struct Camera {
    glm::mat4 view{1.0f}, projection{1.0f};
    glm::vec3 eye{0.0f}, target{0.0f};
    glm::mat4 view_projection() const { return projection * view; }
};

// Aims at the box's centre from `angles`; `aspect` is width / height of the picture.
Camera frame_box(const Box& box, const CameraAngles& angles, float aspect);

// Pixel coordinates of a world point in a width x height picture: x to the right, y down from the
// top-left corner (the order of the rows in a PNG), pixel centres at half-integers.
glm::vec2 project_to_pixels(const Camera& camera, const glm::vec3& p, int width, int height);

// The smallest pixel rectangle holding every point's projection (project_to_pixels): where a
// cloth must appear in a width x height picture (the render and viewer tests check it).
struct PixelBox {
    glm::vec2 min{1e9f}, max{-1e9f};
};
PixelBox projected_box(const Camera& camera, const std::vector<Vec3>& points, int width, int height);

}  // namespace weft::render
