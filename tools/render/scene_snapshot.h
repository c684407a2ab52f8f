// From a running scene (lib/common/scene.h) to what the renderer draws.
#pragma once

#include "render/renderer.h"
#include "common/scene.h"

namespace weft::render {

// The scene's cloths (positions now, triangles, texture coordinates: the asset's `uv` when it has
// them, else planar_uv of its start positions), colliders and the body in its current pose.
Snapshot snapshot_of_scene(const scenes::Scene& scene, const scenes::SceneWorld& world);

}  // namespace weft::render
