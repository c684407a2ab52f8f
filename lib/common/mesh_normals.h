#pragma once

// Vertex normals of a triangle mesh for what draws or exports it (the renderer's lighting, weft-sim
// --gltf); the runtime's own normals (WorldDesc::normals, read_normals) are computed in the step.

#include <cstdint>
#include <vector>

#include "weft/types.h"

namespace weft::scenes {

// Smooth normals: each vertex gets the normalised sum of its triangles' area-weighted normals.
std::vector<Vec3> smooth_normals(const std::vector<Vec3>& positions, const std::vector<uint32_t>& triangles);

}  // namespace weft::scenes
