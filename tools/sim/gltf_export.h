// weft-sim --gltf: a whole run as one glTF 2.0 binary (.glb), written with tinygltf. Each cloth is
// one mesh whose first recorded frame is the base shape and every later frame a morph target
// (positions and normals as differences from the base); one STEP animation channel per cloth sets
// the weight of frame k to 1 at frame k's time, so any glTF viewer plays the run back exactly as it
// was simulated. Texture coordinates are the renderer's (metres on the flat cloth) with its checker
// as a repeating texture. A body (the scene's mannequin or mesh, posed every frame) is one more
// mesh of that kind, in the colliders' grey and without texture. Colliders are separate, still meshes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "render/scene_snapshot.h"
#include "weft/weft.h"

namespace weft::sim {

struct GltfSurface {
    std::string name;
    std::vector<uint32_t> triangles;  // 3 particle (or body vertex) indices per triangle
    std::vector<float> uv;            // 2 per particle; empty for a body
    bool is_body = false;             // drawn grey and untextured
};

struct GltfStill {  // a mesh that does not move (a collider)
    std::string name;
    std::vector<Vec3> positions, normals;
    std::vector<uint32_t> triangles;
};

struct GltfRun {
    std::vector<GltfSurface> cloths;  // the cloths, then the body if the scene has one
    // frames[f][c] = surface c's positions (caller order) in recorded frame f, at times_s[f].
    std::vector<std::vector<std::vector<Vec3>>> frames;
    std::vector<float> times_s;
    std::vector<GltfStill> stills;
};

// Writes `run` to `path` (.glb); `progress(done, total)` is called as the frames are packed.
// Returns the error (empty when written).
std::string write_gltf(const std::string& path, const GltfRun& run,
                       const std::function<void(size_t done, size_t total)>& progress = {});

// The run of `scene` as recorded by weft-sim (frames[f][c]: cloth c's positions, then the body's,
// at times_s[f]), its surfaces and colliders from `snapshot`, written to `path`. Returns the error.
std::string export_scene_gltf(const std::string& path, const scenes::Scene& scene, const render::Snapshot& snapshot,
                              const std::vector<std::vector<std::vector<Vec3>>>& frames,
                              const std::vector<float>& times_s, bool show_progress);

}  // namespace weft::sim
