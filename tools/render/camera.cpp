#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace weft::render {

Camera frame_box(const Box& box, const CameraAngles& angles, float aspect) {
    Box b = box;
    if (b.empty()) b.add(glm::vec3(0.0f));
    const float azimuth = glm::radians(angles.azimuth_deg), elevation = glm::radians(angles.elevation_deg);
    // Unit vector from the target towards the eye, and the camera's right and up axes.
    const glm::vec3 back{std::sin(azimuth) * std::cos(elevation), std::sin(elevation), std::cos(azimuth) * std::cos(elevation)};
    const glm::vec3 right = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), back));
    const glm::vec3 up = glm::cross(back, right);
    const float tan_half_y = std::tan(0.5f * glm::radians(kVerticalFieldOfView_deg)), tan_half_x = aspect * tan_half_y;

    Camera cam;
    cam.target = b.centre();
    float distance = angles.distance_m;
    if (distance <= 0.0f) {
        // Every corner must lie inside the view pyramid: a corner at offset (x, y) across the view and
        // z towards the eye needs the eye at least z + |x| / tan(half width angle) away (same for y).
        distance = 0.0f;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p{corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z};
            const glm::vec3 d = p - cam.target;
            const float need = glm::dot(d, back) + std::max(std::abs(glm::dot(d, right)) / tan_half_x,
                                                            std::abs(glm::dot(d, up)) / tan_half_y);
            distance = std::max(distance, need);
        }
        distance = std::max(1.06f * distance, 0.1f);  // a thin margin around the scene
    }
    cam.eye = cam.target + distance * back;
    cam.view = glm::lookAt(cam.eye, cam.target, up);
    const float radius = std::max(0.5f * b.diagonal(), 0.05f);
    // Near plane in front of the box, far plane well behind it so that the ground grid reaches the horizon.
    const float near_m = std::max(0.01f, std::min(0.1f * distance, distance - radius));
    const float far_m = 20.0f * (distance + radius);
    cam.projection = glm::perspective(glm::radians(kVerticalFieldOfView_deg), aspect, near_m, far_m);
    return cam;
}

glm::vec2 project_to_pixels(const Camera& camera, const glm::vec3& p, int width, int height) {
    const glm::vec4 clip = camera.view_projection() * glm::vec4(p, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;  // [-1, 1], y up
    return {0.5f * (ndc.x + 1.0f) * float(width), 0.5f * (1.0f - ndc.y) * float(height)};
}

PixelBox projected_box(const Camera& camera, const std::vector<Vec3>& points, int width, int height) {
    PixelBox box;
    for (const Vec3& p : points) {
        const glm::vec2 q = project_to_pixels(camera, glm::vec3(p.x, p.y, p.z), width, height);
        box.min = glm::min(box.min, q);
        box.max = glm::max(box.max, q);
    }
    return box;
}

}  // namespace weft::render
