// Body meshes from files (lib/body/body_mesh.h): OBJ and glTF, the real bodies of ../shared, and
// files that must be refused.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include <tiny_gltf.h>

#include "body/body_mesh.h"
#include "body/mannequin.h"

namespace weft {
namespace {

const std::string kBodies = std::string(WEFT_SHARED_DATA_DIR) + "/bodies/";

TEST_CASE("body mesh: the shared A-pose and T-pose bodies load with the same faces") {
    if (!std::filesystem::exists(kBodies + "mean_all.obj")) {
        MESSAGE("skipped: " << kBodies << " is not there");
        return;
    }
    body::BodyMesh a, t;
    REQUIRE(body::load_body_mesh(kBodies + "mean_all.obj", &a).empty());
    REQUIRE(body::load_body_mesh(kBodies + "mean_all_tpose.obj", &t).empty());
    CHECK(a.positions.size() == 23752);
    CHECK(a.triangles.size() == 3 * 47500);
    CHECK(a.triangles == t.triangles);  // one topology, two poses: blending them animates the body
}

TEST_CASE("body mesh: OBJ round trip of the mannequin") {
    body::Mannequin m;
    REQUIRE(body::make_mannequin({}, {}, &m).empty());
    const std::string path = "weft_body_test_mannequin.obj";
    REQUIRE(body::save_obj(path, m.positions, m.triangles).empty());
    body::BodyMesh read;
    REQUIRE(body::load_body_mesh(path, &read).empty());
    CHECK(read.triangles == m.triangles);
    REQUIRE(read.positions.size() == m.positions.size());
    for (size_t i = 0; i < read.positions.size(); ++i)
        CHECK(read.positions[i].y == doctest::Approx(m.positions[i].y).epsilon(1e-5));
}

TEST_CASE("body mesh: glTF with a node translation") {
    // One triangle, its node moved 1 m up: the loader applies the node's transform.
    tinygltf::Model model;
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 0, 1};
    const uint16_t idx[3] = {0, 1, 2};
    tinygltf::Buffer buffer;
    buffer.data.resize(sizeof p + sizeof idx);
    std::memcpy(buffer.data.data(), p, sizeof p);
    std::memcpy(buffer.data.data() + sizeof p, idx, sizeof idx);
    model.buffers.push_back(buffer);
    tinygltf::BufferView positions, indices;
    positions.buffer = 0, positions.byteLength = sizeof p;
    indices.buffer = 0, indices.byteOffset = sizeof p, indices.byteLength = sizeof idx;
    model.bufferViews = {positions, indices};
    tinygltf::Accessor pa, ia;
    pa.bufferView = 0, pa.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT, pa.count = 3, pa.type = TINYGLTF_TYPE_VEC3;
    pa.minValues = {0, 0, 0}, pa.maxValues = {1, 0, 1};
    ia.bufferView = 1, ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, ia.count = 3, ia.type = TINYGLTF_TYPE_SCALAR;
    model.accessors = {pa, ia};
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = 0;
    prim.indices = 1;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(prim);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.translation = {0.0, 1.0, 0.0};
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes = {0};
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    model.asset.version = "2.0";
    const std::string path = "weft_body_test_triangle.glb";
    tinygltf::TinyGLTF writer;
    REQUIRE(writer.WriteGltfSceneToFile(&model, path, true, true, false, true));
    body::BodyMesh read;
    const std::string error = body::load_body_mesh(path, &read);
    INFO(error);
    REQUIRE(error.empty());
    REQUIRE(read.positions.size() == 3);
    CHECK(read.positions[1].x == 1.0f);
    CHECK(read.positions[1].y == 1.0f);
    CHECK(read.triangles == std::vector<uint32_t>{0, 1, 2});
}

TEST_CASE("body mesh: broken files are refused") {
    body::BodyMesh out;
    CHECK_FALSE(body::load_body_mesh("no-such-body.obj", &out).empty());
    CHECK_FALSE(body::load_body_mesh("body.stl", &out).empty());
    std::ofstream("weft_body_test_bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    CHECK_FALSE(body::load_body_mesh("weft_body_test_bad.obj", &out).empty());
    std::ofstream("weft_body_test_empty.obj") << "v 0 0 0\nv 1 0 0\n";
    CHECK_FALSE(body::load_body_mesh("weft_body_test_empty.obj", &out).empty());  // no triangles
    std::ofstream("weft_body_test_bad.glb") << "glTF garbage";
    CHECK_FALSE(body::load_body_mesh("weft_body_test_bad.glb", &out).empty());
    CHECK(out.positions.empty());
}

}  // namespace
}  // namespace weft
