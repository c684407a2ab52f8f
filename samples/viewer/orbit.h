// The viewer's camera: orbits a target point (azimuth, elevation, distance), pans by moving the
// target, zooms by changing the distance. Built on tools/render's frame_box, so the first view is
// exactly the framing weft-sim's pictures use (the viewer test relies on that).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "render/camera.h"

namespace weft::viewer {

struct Orbit {
    glm::vec3 target{0.0f};
    float azimuth_deg = 35.0f, elevation_deg = 20.0f;  // render::CameraAngles' defaults
    float distance_m = 1.0f;
};

// The view that frames `box` grown to a cube of its largest side (a cloth swings, falls and blows
// out of its start plane: a flag's start box is flat) from the default angles (render::frame_box).
inline Orbit frame_orbit(const render::Box& box, float aspect) {
    const render::CameraAngles angles;
    render::Box cube = box;
    if (!box.empty()) {
        const glm::vec3 half(0.5f * std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z}));
        cube.add(box.centre() - half);
        cube.add(box.centre() + half);
    }
    const render::Camera camera = render::frame_box(cube, angles, aspect);
    return {camera.target, angles.azimuth_deg, angles.elevation_deg, glm::length(camera.eye - camera.target)};
}

// The camera of a picture `aspect` wide (width / height) whose left `panel` fraction the viewer's
// panel covers: the picture is shifted right (a lens shift, no turn) so that the target sits in
// the middle of the part left free. frame_orbit with that part's aspect, (1 - panel) * aspect,
// frames the scene into it.
inline render::Camera orbit_camera(const Orbit& orbit, float aspect, float panel = 0.0f) {
    render::Box point;
    point.add(orbit.target);
    render::Camera camera = render::frame_box(point, {orbit.azimuth_deg, orbit.elevation_deg, orbit.distance_m}, aspect);
    // x_ndc += panel: the free part's centre, (-1 + 2 panel + 1) / 2.
    camera.projection = glm::translate(glm::mat4(1.0f), glm::vec3(panel, 0.0f, 0.0f)) * camera.projection;
    return camera;
}

// Mouse motion in pixels of a window `height` pixels high.
inline void rotate(Orbit* orbit, float dx, float dy) {
    orbit->azimuth_deg -= 0.3f * dx;
    orbit->elevation_deg = std::clamp(orbit->elevation_deg + 0.3f * dy, -89.0f, 89.0f);
}
inline void pan(Orbit* orbit, const render::Camera& camera, float dx, float dy, float height) {
    // The view matrix's rows are the camera's right and up axes; a pixel spans this many metres at
    // the target's distance.
    const glm::vec3 right{camera.view[0][0], camera.view[1][0], camera.view[2][0]};
    const glm::vec3 up{camera.view[0][1], camera.view[1][1], camera.view[2][1]};
    const float metres_per_pixel =
        2.0f * orbit->distance_m * std::tan(0.5f * glm::radians(render::kVerticalFieldOfView_deg)) / height;
    orbit->target += metres_per_pixel * (-dx * right + dy * up);
}
inline void zoom(Orbit* orbit, float wheel_steps) {
    orbit->distance_m = std::clamp(orbit->distance_m * std::pow(0.88f, wheel_steps), 0.05f, 1000.0f);
}

}  // namespace weft::viewer
