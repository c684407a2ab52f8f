// Body meshes for tests and tools (the runtime takes plain arrays and reads no files): OBJ through
// tinyobjloader, a procedural icosphere and box, and the A-pose to T-pose blend of the shared body.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "weft/types.h"

namespace weft::bodies {

struct BodyMesh {
    std::vector<Vec3> positions;
    std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise seen from outside
    uint32_t vertex_count() const { return uint32_t(positions.size()); }
    uint32_t triangle_count() const { return uint32_t(triangles.size() / 3); }
};

// Reads positions and triangles (faces with more corners are fanned). Empty string on success.
std::string load_obj(const std::string& path, BodyMesh* out);

// A sphere of `radius` around `centre`: an icosahedron subdivided `subdivisions` times.
BodyMesh make_icosphere(Vec3 centre, float radius, uint32_t subdivisions);

// An axis-aligned box from `min` to `max` (12 triangles): a slab when one side is thin.
BodyMesh make_box(Vec3 min, Vec3 max);

// Vertex by vertex a + (b - a) * t: two poses with the same faces give an animated body.
void blend(const BodyMesh& a, const BodyMesh& b, float t, std::vector<Vec3>* out);

// Where the shared data lives (WEFT_SHARED_DATA_DIR at build time), and the two poses of mean_all.
std::string shared_body_path(const char* file_name);

}  // namespace weft::bodies
