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
#include "render/scene_snapshot.h"
#include "weft/weft.h"

namespace weft::render {

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
