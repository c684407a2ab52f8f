#include "body_mesh.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace weft::bodies {

std::string load_obj(const std::string& path, BodyMesh* out) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;  // fans polygons
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) return path + ": " + reader.Error();
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    out->positions.resize(attrib.vertices.size() / 3);
    for (size_t i = 0; i < out->positions.size(); ++i)
        out->positions[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
    out->triangles.clear();
    for (const tinyobj::shape_t& shape : reader.GetShapes())
        for (const tinyobj::index_t& index : shape.mesh.indices) {
            if (index.vertex_index < 0 || size_t(index.vertex_index) >= out->positions.size())
                return path + ": a face uses a vertex out of range";
            out->triangles.push_back(uint32_t(index.vertex_index));
        }
    if (out->triangles.empty()) return path + ": no triangles";
    return {};
}

BodyMesh make_icosphere(Vec3 centre, float radius, uint32_t subdivisions) {
    const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3> unit = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                              {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    std::vector<uint32_t> faces = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                   11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                                   3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    auto normalise = [](Vec3 v) {
        const float l = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
        return Vec3{v.x / l, v.y / l, v.z / l};
    };
    for (Vec3& v : unit) v = normalise(v);
    for (uint32_t s = 0; s < subdivisions; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> middle;
        auto mid = [&](uint32_t a, uint32_t b) {
            const auto key = std::minmax(a, b);
            if (auto it = middle.find(key); it != middle.end()) return it->second;
            const Vec3 pa = unit[a], pb = unit[b];
            unit.push_back(normalise({pa.x + pb.x, pa.y + pb.y, pa.z + pb.z}));
            return middle[key] = uint32_t(unit.size() - 1);
        };
        std::vector<uint32_t> next;
        for (size_t f = 0; f < faces.size(); f += 3) {
            const uint32_t a = faces[f], b = faces[f + 1], c = faces[f + 2];
            const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        faces = std::move(next);
    }
    BodyMesh mesh;
    for (const Vec3& v : unit) mesh.positions.push_back({centre.x + radius * v.x, centre.y + radius * v.y, centre.z + radius * v.z});
    mesh.triangles = std::move(faces);
    return mesh;
}

BodyMesh make_box(Vec3 lo, Vec3 hi) {
    BodyMesh mesh;
    for (uint32_t i = 0; i < 8; ++i)
        mesh.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    // Two triangles per face, counter-clockwise seen from outside.
    mesh.triangles = {0, 4, 6, 0, 6, 2,   1, 3, 7, 1, 7, 5,   0, 1, 5, 0, 5, 4,
                      2, 6, 7, 2, 7, 3,   0, 2, 3, 0, 3, 1,   4, 5, 7, 4, 7, 6};
    return mesh;
}

void blend(const BodyMesh& a, const BodyMesh& b, float t, std::vector<Vec3>* out) {
    out->resize(a.positions.size());
    for (size_t i = 0; i < a.positions.size(); ++i) {
        const Vec3 p = a.positions[i], q = b.positions[i];
        (*out)[i] = {p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t, p.z + (q.z - p.z) * t};
    }
}

std::string shared_body_path(const char* file_name) {
    return std::string(WEFT_SHARED_DATA_DIR) + "/bodies/" + file_name;
}

}  // namespace weft::bodies
