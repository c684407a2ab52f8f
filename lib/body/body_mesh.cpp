#include "body/body_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <utility>

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

namespace weft::body {
namespace {

bool ends_with(const std::string& s, const char* suffix) {
    const size_t n = std::strlen(suffix);
    if (s.size() < n) return false;
    for (size_t i = 0; i < n; ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
    return true;
}

std::string load_obj(const std::string& path, BodyMesh* out) {
    tinyobj::ObjReader reader;
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    if (!reader.ParseFromFile(path, config)) return "cannot read '" + path + "': " + reader.Error();
    const tinyobj::attrib_t& a = reader.GetAttrib();
    for (size_t i = 0; i + 2 < a.vertices.size(); i += 3)
        out->positions.push_back({a.vertices[i], a.vertices[i + 1], a.vertices[i + 2]});
    for (const tinyobj::shape_t& shape : reader.GetShapes())
        for (const tinyobj::index_t& index : shape.mesh.indices) {
            if (index.vertex_index < 0) return "'" + path + "': a face refers to a missing vertex";
            out->triangles.push_back(uint32_t(index.vertex_index));
            if (index.texcoord_index >= 0 && size_t(2 * index.texcoord_index + 1) < a.texcoords.size()) {
                out->uv.resize(2 * out->positions.size());  // a cloth frame (save_obj with uv): one vt per vertex
                if (size_t(index.vertex_index) < out->positions.size()) {
                    out->uv[2 * size_t(index.vertex_index)] = a.texcoords[2 * size_t(index.texcoord_index)];
                    out->uv[2 * size_t(index.vertex_index) + 1] = a.texcoords[2 * size_t(index.texcoord_index) + 1];
                }
            }
        }
    return {};
}

// Column-major 4x4 matrices, as glTF stores them.
using Matrix = std::array<double, 16>;
constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) m[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
    return m;
}

Matrix local_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Matrix m;
        for (int i = 0; i < 16; ++i) m[i] = node.matrix[i];
        return m;
    }
    Matrix t = kIdentity, r = kIdentity, s = kIdentity;
    if (node.translation.size() == 3) t[12] = node.translation[0], t[13] = node.translation[1], t[14] = node.translation[2];
    if (node.rotation.size() == 4) {  // unit quaternion (x, y, z, w)
        const double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
             2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
             2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
             0,                       0,                       0,                       1};
    }
    if (node.scale.size() == 3) s[0] = node.scale[0], s[5] = node.scale[1], s[10] = node.scale[2];
    return multiply(t, multiply(r, s));
}

// Reads one accessor as doubles (float or integer components), `components` per element.
std::string read_accessor(const tinygltf::Model& model, int index, int components, std::vector<double>* out) {
    if (index < 0 || size_t(index) >= model.accessors.size()) return "an accessor index is out of range";
    const tinygltf::Accessor& acc = model.accessors[size_t(index)];
    if (tinygltf::GetNumComponentsInType(uint32_t(acc.type)) != components) return "an accessor has the wrong type";
    if (acc.bufferView < 0 || size_t(acc.bufferView) >= model.bufferViews.size()) return "a sparse or empty accessor";
    const tinygltf::BufferView& view = model.bufferViews[size_t(acc.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) return "a buffer index is out of range";
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    if (size <= 0) return "an accessor has an unknown component type";
    const size_t stride = view.byteStride ? view.byteStride : size_t(size) * components;
    const size_t start = view.byteOffset + acc.byteOffset;
    if (acc.count > 0 && start + (acc.count - 1) * stride + size_t(size) * components > data.size())
        return "an accessor reaches past its buffer";
    for (size_t i = 0; i < acc.count; ++i)
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = data.data() + start + i * stride + size_t(c) * size;
            double v = 0.0;
            switch (acc.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); v = f; break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); v = u; break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; break;
                default: return "an accessor has an unsupported component type";
            }
            out->push_back(v);
        }
    return {};
}

std::string add_gltf_node(const tinygltf::Model& model, int index, const Matrix& parent, int depth, BodyMesh* out) {
    if (index < 0 || size_t(index) >= model.nodes.size() || depth > 64) return "a node index is out of range";
    const tinygltf::Node& node = model.nodes[size_t(index)];
    const Matrix world = multiply(parent, local_matrix(node));
    if (node.mesh >= 0 && size_t(node.mesh) < model.meshes.size()) {
        for (const tinygltf::Primitive& prim : model.meshes[size_t(node.mesh)].primitives) {
            if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;  // points and lines are no body
            const auto position = prim.attributes.find("POSITION");
            if (position == prim.attributes.end()) continue;
            std::vector<double> p, idx;
            if (std::string e = read_accessor(model, position->second, 3, &p); !e.empty()) return e;
            const uint32_t base = uint32_t(out->positions.size()), count = uint32_t(p.size() / 3);
            for (size_t i = 0; i < p.size(); i += 3) {
                const double x = p[i], y = p[i + 1], z = p[i + 2];
                out->positions.push_back({float(world[0] * x + world[4] * y + world[8] * z + world[12]),
                                          float(world[1] * x + world[5] * y + world[9] * z + world[13]),
                                          float(world[2] * x + world[6] * y + world[10] * z + world[14])});
            }
            if (prim.indices >= 0) {
                if (std::string e = read_accessor(model, prim.indices, 1, &idx); !e.empty()) return e;
            } else {
                for (uint32_t i = 0; i < count; ++i) idx.push_back(i);
            }
            for (double i : idx) {
                if (!(i >= 0 && i < count)) return "a primitive's index is out of range";
                out->triangles.push_back(base + uint32_t(i));
            }
        }
    }
    for (int child : node.children)
        if (std::string e = add_gltf_node(model, child, world, depth + 1, out); !e.empty()) return e;
    return {};
}

std::string load_gltf(const std::string& path, bool binary, BodyMesh* out) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : loader.LoadASCIIFromFile(&model, &error, &warning, path);
    if (!ok) return "cannot read '" + path + "': " + error;
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(scene) < model.scenes.size()) {
        for (int node : model.scenes[size_t(scene)].nodes)
            if (std::string e = add_gltf_node(model, node, kIdentity, 0, out); !e.empty()) return "'" + path + "': " + e;
    } else {
        for (size_t n = 0; n < model.nodes.size(); ++n)  // no scene: every node as a root
            if (std::string e = add_gltf_node(model, int(n), kIdentity, 0, out); !e.empty()) return "'" + path + "': " + e;
    }
    return {};
}

}  // namespace

std::string load_body_mesh(const std::string& path, BodyMesh* out) {
    BodyMesh mesh;
    std::string error;
    if (ends_with(path, ".obj")) error = load_obj(path, &mesh);
    else if (ends_with(path, ".glb")) error = load_gltf(path, true, &mesh);
    else if (ends_with(path, ".gltf")) error = load_gltf(path, false, &mesh);
    else error = "'" + path + "': not .obj, .gltf or .glb";
    if (!error.empty()) return error;
    if (mesh.triangles.empty() || mesh.triangles.size() % 3 != 0) return "'" + path + "': no triangles";
    for (const Vec3& p : mesh.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "'" + path + "': a position is not finite";
    for (uint32_t i : mesh.triangles)
        if (i >= mesh.positions.size()) return "'" + path + "': a triangle refers to a missing vertex";
    *out = std::move(mesh);
    return {};
}

std::string save_obj(const std::string& path, const std::vector<Vec3>& positions, const std::vector<uint32_t>& triangles,
                     const std::vector<float>& uv) {
    std::ofstream file(path);
    file.precision(std::numeric_limits<float>::max_digits10);
    for (const Vec3& p : positions) file << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    const bool with_uv = uv.size() == 2 * positions.size();
    if (with_uv)
        for (size_t v = 0; v < positions.size(); ++v) file << "vt " << uv[2 * v] << ' ' << uv[2 * v + 1] << '\n';
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        file << 'f';
        for (size_t k = 0; k < 3; ++k) {
            file << ' ' << triangles[t + k] + 1;
            if (with_uv) file << '/' << triangles[t + k] + 1;
        }
        file << '\n';
    }
    return file ? std::string() : "cannot write '" + path + "'";
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

}  // namespace weft::body
