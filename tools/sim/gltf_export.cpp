#include "sim/gltf_export.h"

#include <algorithm>
#include <cstring>

#include <stb_image_write.h>  // the implementation is in Debian's libstb
#include <tiny_gltf.h>

#include "common/mesh_normals.h"  // smooth_normals: the same normals the pictures are lit with
#include "common/progress.h"

namespace weft::sim {

namespace {

// Appends `bytes` to the model's one buffer as a new buffer view; returns the view's index.
int add_view(tinygltf::Model* model, const void* bytes, size_t size, int target) {
    std::vector<unsigned char>& data = model->buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    data.insert(data.end(), static_cast<const unsigned char*>(bytes), static_cast<const unsigned char*>(bytes) + size);
    data.resize((data.size() + 3) / 4 * 4);  // the next view starts 4-byte aligned (a PNG's length is any)
    model->bufferViews.push_back(view);
    return int(model->bufferViews.size() - 1);
}

// A float VEC3 accessor with its min and max (glTF requires them for positions).
int add_vec3(tinygltf::Model* model, const std::vector<Vec3>& values, bool bounds) {
    tinygltf::Accessor a;
    a.bufferView = add_view(model, values.data(), values.size() * sizeof(Vec3), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = TINYGLTF_TYPE_VEC3;
    a.count = values.size();
    if (bounds) {
        a.minValues = {1e30, 1e30, 1e30};
        a.maxValues = {-1e30, -1e30, -1e30};
        for (const Vec3& v : values) {
            const float c[3] = {v.x, v.y, v.z};
            for (int k = 0; k < 3; ++k) {
                a.minValues[size_t(k)] = std::min(a.minValues[size_t(k)], double(c[k]));
                a.maxValues[size_t(k)] = std::max(a.maxValues[size_t(k)], double(c[k]));
            }
        }
    }
    model->accessors.push_back(a);
    return int(model->accessors.size() - 1);
}

int add_scalars(tinygltf::Model* model, const std::vector<float>& values, int type, int target, bool bounds) {
    tinygltf::Accessor a;
    a.bufferView = add_view(model, values.data(), values.size() * sizeof(float), target);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = values.size() / (type == TINYGLTF_TYPE_VEC2 ? 2 : 1);
    if (bounds && !values.empty()) {
        a.minValues = {*std::min_element(values.begin(), values.end())};
        a.maxValues = {*std::max_element(values.begin(), values.end())};
    }
    model->accessors.push_back(a);
    return int(model->accessors.size() - 1);
}

int add_indices(tinygltf::Model* model, const std::vector<uint32_t>& indices) {
    tinygltf::Accessor a;
    a.bufferView = add_view(model, indices.data(), indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = indices.size();
    model->accessors.push_back(a);
    return int(model->accessors.size() - 1);
}

// The renderer's checker (tools/render: 10 cm squares, the darker ones at 0.75) as a texture:
// texture coordinates are metres on the flat cloth, so one repeat of this 1 m tile holds 10 x 10
// squares. White and 0.75 grey, tinted by the material's base colour.
int add_checker_texture(tinygltf::Model* model) {
    constexpr int kSquares = 10, kPixels = 8;  // per square
    tinygltf::Image image;
    image.name = "checker";
    constexpr int kSize = kSquares * kPixels;
    std::vector<unsigned char> grey;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) grey.push_back((x / kPixels + y / kPixels) % 2 ? 191 : 255);
    // The PNG goes into the binary buffer (a data URI inside a .glb draws a validator warning).
    std::vector<unsigned char> png;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
            auto* out = static_cast<std::vector<unsigned char>*>(context);
            out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
        },
        &png, kSize, kSize, 1, grey.data(), kSize);
    image.bufferView = add_view(model, png.data(), png.size(), 0);
    image.mimeType = "image/png";
    model->images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
    model->samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = int(model->images.size() - 1);
    texture.sampler = int(model->samplers.size() - 1);
    model->textures.push_back(texture);
    return int(model->textures.size() - 1);
}

int add_material(tinygltf::Model* model, const char* name, std::vector<double> colour, bool double_sided) {
    tinygltf::Material m;
    m.name = name;
    m.pbrMetallicRoughness.baseColorFactor = std::move(colour);
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 0.9;
    m.doubleSided = double_sided;
    model->materials.push_back(m);
    return int(model->materials.size() - 1);
}

// A mesh of one primitive (with `morph_targets` weights, all 0) in a node of the scene; returns the node.
int add_node(tinygltf::Model* model, const std::string& name, const tinygltf::Primitive& primitive, size_t morph_targets) {
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(primitive);
    mesh.weights.assign(morph_targets, 0.0);
    model->meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(model->meshes.size() - 1);
    model->nodes.push_back(node);
    model->scenes[0].nodes.push_back(int(model->nodes.size() - 1));
    return int(model->nodes.size() - 1);
}

std::vector<Vec3> difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    std::vector<Vec3> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = {a[i].x - b[i].x, a[i].y - b[i].y, a[i].z - b[i].z};
    return d;
}

}  // namespace

std::string write_gltf(const std::string& path, const GltfRun& run,
                       const std::function<void(size_t, size_t)>& progress) {
    if (run.frames.empty() || run.frames.size() != run.times_s.size()) return "--gltf: no frames recorded";
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "weft-sim";
    model.buffers.resize(1);
    model.scenes.resize(1);
    model.defaultScene = 0;
    // The renderer's colours (tools/render): brick-red cloth, grey colliders.
    const int cloth_material = add_material(&model, "cloth", {0.85, 0.36, 0.22, 1.0}, true);
    const bool has_body = std::any_of(run.cloths.begin(), run.cloths.end(), [](const GltfSurface& c) { return c.is_body; });
    const int collider_material =
        run.stills.empty() && !has_body ? -1 : add_material(&model, "collider", {0.62, 0.64, 0.66, 1.0}, false);
    model.materials[size_t(cloth_material)].pbrMetallicRoughness.baseColorTexture.index = add_checker_texture(&model);

    const size_t targets = run.frames.size() - 1;  // the first frame is the base shape
    tinygltf::Animation animation;
    animation.name = "simulation";
    if (targets > 0) {
        // One STEP sampler shared by every cloth: at frame k's time, target k - 1 weighs 1, the rest 0.
        std::vector<float> weights(run.frames.size() * targets, 0.0f);
        for (size_t k = 1; k < run.frames.size(); ++k) weights[k * targets + (k - 1)] = 1.0f;
        tinygltf::AnimationSampler sampler;
        sampler.input = add_scalars(&model, run.times_s, TINYGLTF_TYPE_SCALAR, 0, true);
        sampler.output = add_scalars(&model, weights, TINYGLTF_TYPE_SCALAR, 0, false);
        sampler.interpolation = "STEP";
        animation.samplers.push_back(sampler);
    }

    const size_t work = run.cloths.size() * run.frames.size();
    for (size_t c = 0; c < run.cloths.size(); ++c) {
        const GltfSurface& cloth = run.cloths[c];
        const std::vector<Vec3>& base = run.frames[0][c];
        const std::vector<Vec3> base_normals = scenes::smooth_normals(base, cloth.triangles);
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.material = cloth.is_body ? collider_material : cloth_material;
        primitive.indices = add_indices(&model, cloth.triangles);
        primitive.attributes["POSITION"] = add_vec3(&model, base, true);
        primitive.attributes["NORMAL"] = add_vec3(&model, base_normals, false);
        if (cloth.uv.size() == 2 * base.size())
            primitive.attributes["TEXCOORD_0"] = add_scalars(&model, cloth.uv, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
        for (size_t f = 1; f < run.frames.size(); ++f) {
            const std::vector<Vec3>& p = run.frames[f][c];
            primitive.targets.push_back(
                {{"POSITION", add_vec3(&model, difference(p, base), true)},
                 {"NORMAL", add_vec3(&model, difference(scenes::smooth_normals(p, cloth.triangles), base_normals), false)}});
            if (progress) progress(c * run.frames.size() + f, work);
        }
        const int node = add_node(&model, cloth.name, primitive, targets);
        if (targets > 0) {
            tinygltf::AnimationChannel channel;
            channel.sampler = 0;
            channel.target_node = node;
            channel.target_path = "weights";
            animation.channels.push_back(channel);
        }
    }
    for (const GltfStill& still : run.stills) {
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.material = collider_material;
        primitive.indices = add_indices(&model, still.triangles);
        primitive.attributes["POSITION"] = add_vec3(&model, still.positions, true);
        primitive.attributes["NORMAL"] = add_vec3(&model, still.normals, false);
        add_node(&model, still.name, primitive, 0);
    }
    if (!animation.channels.empty()) model.animations.push_back(animation);

    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToFile(&model, path, true, true, false, true)) return "cannot write " + path;
    return {};
}

std::string export_scene_gltf(const std::string& path, const scenes::Scene& scene, const render::Snapshot& snapshot,
                        const std::vector<std::vector<std::vector<Vec3>>>& frames, const std::vector<float>& times_s,
                        bool show_progress) {
    GltfRun run;
    run.frames = frames;
    run.times_s = times_s;
    render::Box box;  // around every recorded frame: a plane collider's square is sized by it
    for (size_t i = 0; i < snapshot.cloths.size(); ++i) {
        run.cloths.push_back({scene.cloths[i].name, snapshot.cloths[i].triangles, snapshot.cloths[i].uv});
        for (const auto& frame : frames)
            for (const Vec3& p : frame[i]) box.add({p.x, p.y, p.z});
    }
    if (!snapshot.bodies.empty() && !frames.empty() && frames[0].size() > snapshot.cloths.size())
        run.cloths.push_back({"body", snapshot.bodies[0].triangles, {}, true});  // posed per frame (pictures.cpp)
    for (size_t i = 0; i < snapshot.colliders.size(); ++i) {
        render::SurfaceMesh m = render::collider_surface(snapshot.colliders[i], box);
        run.stills.push_back({"collider " + std::to_string(i), std::move(m.positions), std::move(m.normals),
                              std::move(m.indices)});
    }
    progress::Bar bar("weft-sim: writing " + path, run.cloths.size() * frames.size(), show_progress);
    return write_gltf(path, run, [&](size_t done, size_t) { bar.update(done); });
}


}  // namespace weft::sim
