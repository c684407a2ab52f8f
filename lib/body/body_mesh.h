// Body meshes for tools and tests (the runtime takes plain arrays and reads no files): Wavefront OBJ
// through tinyobjloader, glTF 2.0 (.gltf, .glb) through tinygltf, both from Debian; a procedural
// icosphere and box; and the A-pose to T-pose blend of the shared body.
#pragma once

#include <string>
#include <vector>

#include "weft/types.h"

namespace weft::body {

struct BodyMesh {
    std::vector<Vec3> positions;      // metres, as stored in the file (glTF: node transforms applied)
    std::vector<uint32_t> triangles;  // 3 per triangle (polygons are fanned into triangles)
    std::vector<float> uv;            // OBJ with vt: 2 per vertex (a face corner's vt), else empty
    uint32_t vertex_count() const { return uint32_t(positions.size()); }
    uint32_t triangle_count() const { return uint32_t(triangles.size() / 3); }
};

// Loads by extension (.obj, .gltf, .glb). Refuses non-finite positions and out-of-range indices.
// Returns the failure message (empty on success); `out` is only written on success.
std::string load_body_mesh(const std::string& path, BodyMesh* out);

// Writes positions (to the float's last digit: they read back exactly), triangles and, when `uv`
// has 2 per vertex, texture coordinates (vt, one per vertex).
std::string save_obj(const std::string& path, const std::vector<Vec3>& positions, const std::vector<uint32_t>& triangles,
                     const std::vector<float>& uv = {});

// A sphere of `radius` around `centre`: an icosahedron subdivided `subdivisions` times.
BodyMesh make_icosphere(Vec3 centre, float radius, uint32_t subdivisions);

// An axis-aligned box from `min` to `max` (12 triangles): a slab when one side is thin.
BodyMesh make_box(Vec3 min, Vec3 max);

// Vertex by vertex a + (b - a) * t: two poses with the same faces give an animated body.
void blend(const BodyMesh& a, const BodyMesh& b, float t, std::vector<Vec3>* out);

// Where the shared data lives (WEFT_SHARED_DATA_DIR at build time), and the two poses of mean_all.
std::string shared_body_path(const char* file_name);

}  // namespace weft::body
