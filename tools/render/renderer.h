// Weft's renderer: draws cloths, colliders, a ground grid and a sky gradient with OpenGL 3.3 core
// (through libepoxy). It draws into whatever framebuffer is bound in the current context, so the
// headless front end (headless.h: EGL surfaceless on Mesa's llvmpipe) and a window (GLFW, the
// interactive viewer) share it. Never part of the runtime.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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

// The smallest pixel rectangle holding every point's projection (project_to_pixels): where a
// cloth must appear in a width x height picture (the render and viewer tests check it).
struct PixelBox {
    glm::vec2 min{1e9f}, max{-1e9f};
};
PixelBox projected_box(const Camera& camera, const std::vector<Vec3>& points, int width, int height);

// Texture coordinates for a cloth without any: its rest positions projected on the plane of their two
// widest extents, so the checker is fixed to the cloth and follows it as it moves.
std::vector<float> planar_uv(const std::vector<Vec3>& rest_positions);

enum class Look : uint8_t {
    shaded,      // lit, checkered cloth (front and back in different colours), grey colliders, a pale body
    cloth_mask,  // the cloth unlit in kClothMaskRgb, colliders and bodies unlit: tests find the cloth's pixels
};
inline constexpr uint8_t kClothMaskRgb[3] = {255, 0, 255};
inline constexpr uint8_t kColliderMaskRgb[3] = {0, 153, 0};  // colliders and bodies in Look::cloth_mask

class Renderer {
public:
    // Compiles the shaders; needs a current OpenGL 3.3 core context. Null (and *error) on failure.
    static std::unique_ptr<Renderer> create(std::string* error);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Draws a width x height picture into the bound framebuffer (clears it first).
    void draw(const Snapshot& snapshot, const Camera& camera, int width, int height, Look look = Look::shaded);

    struct Mesh;  // one draw call's triangles and colours (renderer.cpp)

private:
    Renderer() = default;
    void draw_mesh(const Mesh& mesh);
    uint32_t sky_program_ = 0, ground_program_ = 0, mesh_program_ = 0;
    uint32_t vertex_array_ = 0, position_buffer_ = 0, normal_buffer_ = 0, uv_buffer_ = 0, index_buffer_ = 0;
};

}  // namespace weft::render
