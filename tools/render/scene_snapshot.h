// What a picture or an export shows of a running scene (lib/common/scene.h): the cloths' and the
// body's surfaces and the colliders' meshes. Geometry only, no OpenGL: the renderer (renderer.h)
// draws it, weft-sim --gltf exports it.
#pragma once

#include <cstdint>
#include <vector>

#include "common/scene.h"
#include "render/camera.h"
#include "weft/weft.h"

namespace weft::render {

// One cloth as drawn: its particles and triangles in caller order.
struct ClothSurface {
    std::vector<Vec3> positions;
    std::vector<uint32_t> triangles;  // 3 caller particle indices per triangle, counter-clockwise seen from the front
    std::vector<float> uv;            // 2 per particle, metres on the flat cloth (the checker's coordinates)
};

// A body collider (weft/body.h) as drawn: its vertices in the pose of the picture.
struct BodySurface {
    std::vector<Vec3> positions;
    std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise seen from outside
};

// Everything one picture shows.
struct Snapshot {
    std::vector<ClothSurface> cloths;
    std::vector<ColliderDesc> colliders;
    std::vector<BodySurface> bodies;
};

// Box around the cloths, the bodies and the bounded colliders (planes are infinite: only a floor's
// point under the cloths is in).
Box bounds(const Snapshot& snapshot);
// Box around the cloths only (the render test projects it).
Box cloth_bounds(const Snapshot& snapshot);

// Triangles with a normal per vertex, in metres: a collider's surface (collider_surface) or a cloth's.
struct SurfaceMesh {
    std::vector<Vec3> positions, normals;
    std::vector<uint32_t> indices;  // 3 per triangle, counter-clockwise seen from outside
};

// The collider's shape as the solver sees it without the inflation (a skin the cloth keeps above it:
// seed figure 8); a plane as a square three scene sizes wide around the point nearest `scene`'s
// centre. Drawn by the renderer, exported by weft-sim --gltf.
SurfaceMesh collider_surface(const ColliderDesc& collider, const Box& scene);

// A plane collider facing up: the ground the scene stands on (the renderer draws it as a grid).
bool is_floor(const ColliderDesc& collider);

// Texture coordinates for a cloth without any: its rest positions projected on the plane of their two
// widest extents, so the checker is fixed to the cloth and follows it as it moves.
std::vector<float> planar_uv(const std::vector<Vec3>& rest_positions);


// The scene's cloths (positions now, triangles, texture coordinates: the asset's `uv` when it has
// them, else planar_uv of its start positions), colliders and the body in its current pose.
Snapshot snapshot_of_scene(const scenes::Scene& scene, const scenes::SceneWorld& world);

}  // namespace weft::render
