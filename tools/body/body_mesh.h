// Body meshes from files, for tools and tests (the runtime takes plain arrays and reads no files):
// Wavefront OBJ through tinyobjloader, glTF 2.0 (.gltf, .glb) through tinygltf, both from Debian.
#pragma once

#include <string>
#include <vector>

#include "weft/types.h"

namespace weft::body {

struct BodyMesh {
    std::vector<Vec3> positions;      // metres, as stored in the file (glTF: node transforms applied)
    std::vector<uint32_t> triangles;  // 3 per triangle (polygons are fanned into triangles)
};

// Loads by extension (.obj, .gltf, .glb). Refuses non-finite positions and out-of-range indices.
// Returns the failure message (empty on success); `out` is only written on success.
std::string load_body_mesh(const std::string& path, BodyMesh* out);

// Writes positions and triangles as an OBJ file.
std::string save_obj(const std::string& path, const std::vector<Vec3>& positions, const std::vector<uint32_t>& triangles);

}  // namespace weft::body
