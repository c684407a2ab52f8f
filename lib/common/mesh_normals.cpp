#include "common/mesh_normals.h"

#include <glm/glm.hpp>

namespace weft::scenes {

namespace {

glm::vec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_weft(const glm::vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

std::vector<Vec3> smooth_normals(const std::vector<Vec3>& positions, const std::vector<uint32_t>& triangles) {
    std::vector<glm::vec3> sum(positions.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const glm::vec3 a = to_glm(positions[triangles[t]]), b = to_glm(positions[triangles[t + 1]]),
                        c = to_glm(positions[triangles[t + 2]]);
        const glm::vec3 n = glm::cross(b - a, c - a);  // length = twice the area
        for (int k = 0; k < 3; ++k) sum[triangles[t + k]] += n;
    }
    std::vector<Vec3> normals(positions.size());
    for (size_t i = 0; i < sum.size(); ++i) {
        const float length = glm::length(sum[i]);
        normals[i] = to_weft(length > 0.0f ? sum[i] / length : glm::vec3(0.0f, 1.0f, 0.0f));
    }
    return normals;
}

}  // namespace weft::scenes
