#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include "common/mesh_normals.h"

namespace weft::render {

namespace {


// Colours (linear RGB in [0, 1]). The cloth's two sides differ so that a fold shows which side is up.
constexpr glm::vec3 kClothFront{0.85f, 0.36f, 0.22f};  // brick red
constexpr glm::vec3 kClothBack{0.25f, 0.45f, 0.70f};   // denim blue
constexpr glm::vec3 kCollider{0.62f, 0.64f, 0.66f};
const glm::vec3 kColliderMask = glm::vec3(kColliderMaskRgb[0], kColliderMaskRgb[1], kColliderMaskRgb[2]) / 255.0f;
constexpr glm::vec3 kBody{0.80f, 0.76f, 0.70f};  // a tailor's dummy: pale, so the garment stands out
constexpr float kCheckerSquare_m = 0.1f;  // a 2 m cloth shows 20 squares a side

// ---- shaders ---------------------------------------------------------------------------------------

// The sky: one triangle covering the screen, from the horizon's haze at the bottom to blue at the top.
constexpr const char* kSkyVertex = R"(#version 330 core
void main() {
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
})";
constexpr const char* kSkyFragment = R"(#version 330 core
uniform float u_height;
out vec4 o_colour;
void main() {
    float t = gl_FragCoord.y / u_height;
    o_colour = vec4(mix(vec3(0.86, 0.89, 0.93), vec3(0.42, 0.60, 0.82), t * t), 1.0);
})";

// Cloths and colliders: a sun, a sky hemisphere and a little specular; the back side's normal is
// flipped so both sides are lit, and takes the back colour. A checker in texture space shows how
// the cloth stretches and shears.
constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
uniform mat4 u_view_projection;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_uv = a_uv;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
})";

// The ground: a large square (drawn with kMeshVertex) with grid lines, anti-aliased with screen-space
// derivatives, that fade into the horizon's haze with distance.
constexpr const char* kGroundFragment = R"(#version 330 core
in vec3 v_position;
uniform float u_spacing;
uniform vec3 u_centre;
uniform float u_fade_distance;
out vec4 o_colour;
void main() {
    vec2 cell = v_position.xz / u_spacing;
    vec2 to_line = abs(fract(cell - 0.5) - 0.5) / fwidth(cell);
    float line = 1.0 - min(min(to_line.x, to_line.y), 1.0);
    vec3 colour = mix(vec3(0.80, 0.80, 0.78), vec3(0.52, 0.53, 0.55), line);
    float haze = smoothstep(0.0, 1.0, length(v_position.xz - u_centre.xz) / u_fade_distance);
    o_colour = vec4(mix(colour, vec3(0.86, 0.89, 0.93), haze), 1.0);
})";

constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
uniform vec3 u_eye;
uniform vec3 u_front_colour;
uniform vec3 u_back_colour;
uniform float u_checker;  // square size in uv units; 0 = plain
uniform bool u_unlit;
out vec4 o_colour;
const vec3 kSun = normalize(vec3(0.45, 0.8, 0.4));
void main() {
    if (u_unlit) { o_colour = vec4(u_front_colour, 1.0); return; }
    vec3 n = normalize(v_normal);
    vec3 base = u_front_colour;
    if (!gl_FrontFacing) { n = -n; base = u_back_colour; }
    if (u_checker > 0.0) {
        vec2 square = floor(v_uv / u_checker);
        if (mod(square.x + square.y, 2.0) > 0.5) base *= 0.75;
    }
    float sun = max(dot(n, kSun), 0.0);
    float sky = 0.5 + 0.5 * n.y;
    vec3 to_eye = normalize(u_eye - v_position);
    float specular = 0.12 * pow(max(dot(n, normalize(kSun + to_eye)), 0.0), 32.0);
    o_colour = vec4(base * (0.18 + 0.22 * sky + 0.7 * sun) + specular, 1.0);
})";

// Whether compiling a shader or linking a program worked; if not, *error gets the driver's message and
// the object is deleted. (glGetShaderiv, glGetShaderInfoLog, glDeleteShader or the program's three.)
template <typename GetStatus, typename GetLog, typename Delete>
bool worked(GLuint object, GLenum status, GetStatus get_status, GetLog get_log, Delete destroy, const char* what,
            std::string* error) {
    GLint ok = 0;
    get_status(object, status, &ok);
    if (ok) return true;
    char log[2048] = {};
    get_log(object, sizeof log, nullptr, log);
    *error = std::string(what) + " failed: " + log;
    destroy(object);
    return false;
}

GLuint compile(GLenum type, const char* source, std::string* error) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    return worked(shader, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader, "shader compilation", error)
               ? shader
               : 0;
}

GLuint link(const char* vertex_source, const char* fragment_source, std::string* error) {
    const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source, error);
    const GLuint fragment = vertex ? compile(GL_FRAGMENT_SHADER, fragment_source, error) : 0;
    if (!fragment) {
        glDeleteShader(vertex);
        return 0;
    }
    const GLuint program = glCreateProgram();
    glAttachShader(program, vertex);
    glAttachShader(program, fragment);
    glLinkProgram(program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    return worked(program, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram, "shader linking", error)
               ? program
               : 0;
}

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

}  // namespace

// ---- geometry ---------------------------------------------------------------------------------------

struct Renderer::Mesh : SurfaceMesh {
    std::vector<float> uv;  // empty: no checker
    glm::vec3 front_colour{}, back_colour{};
    bool unlit = false;
};

// ---- drawing ---------------------------------------------------------------------------------------

std::unique_ptr<Renderer> Renderer::create(std::string* error) {
    std::unique_ptr<Renderer> r(new Renderer());
    r->sky_program_ = link(kSkyVertex, kSkyFragment, error);
    if (r->sky_program_) r->ground_program_ = link(kMeshVertex, kGroundFragment, error);
    if (r->ground_program_) r->mesh_program_ = link(kMeshVertex, kMeshFragment, error);
    if (!r->mesh_program_) return nullptr;
    glGenVertexArrays(1, &r->vertex_array_);
    glGenBuffers(1, &r->position_buffer_);
    glGenBuffers(1, &r->normal_buffer_);
    glGenBuffers(1, &r->uv_buffer_);
    glGenBuffers(1, &r->index_buffer_);
    return r;
}

Renderer::~Renderer() {
    glDeleteBuffers(1, &position_buffer_);
    glDeleteBuffers(1, &normal_buffer_);
    glDeleteBuffers(1, &uv_buffer_);
    glDeleteBuffers(1, &index_buffer_);
    glDeleteVertexArrays(1, &vertex_array_);
    glDeleteProgram(sky_program_);
    glDeleteProgram(ground_program_);
    glDeleteProgram(mesh_program_);
}

// Streams one mesh's arrays into the shared buffers and draws it with the mesh program (bound).
void Renderer::draw_mesh(const Mesh& mesh) {
    const auto upload = [](GLuint buffer, GLuint location, GLint components, const void* data, size_t bytes) {
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(bytes), data, GL_STREAM_DRAW);
        glEnableVertexAttribArray(location);
        glVertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, 0, nullptr);
    };
    upload(position_buffer_, 0, 3, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
    upload(normal_buffer_, 1, 3, mesh.normals.data(), mesh.normals.size() * sizeof(Vec3));
    if (mesh.uv.empty()) {
        glDisableVertexAttribArray(2);
        glVertexAttrib2f(2, 0.0f, 0.0f);
    } else {
        upload(uv_buffer_, 2, 2, mesh.uv.data(), mesh.uv.size() * sizeof(float));
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(),
                 GL_STREAM_DRAW);
    glUniform3fv(uniform(mesh_program_, "u_front_colour"), 1, glm::value_ptr(mesh.front_colour));
    glUniform3fv(uniform(mesh_program_, "u_back_colour"), 1, glm::value_ptr(mesh.back_colour));
    glUniform1f(uniform(mesh_program_, "u_checker"), mesh.uv.empty() ? 0.0f : kCheckerSquare_m);
    glUniform1i(uniform(mesh_program_, "u_unlit"), mesh.unlit ? 1 : 0);
    glDrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT, nullptr);
}

void Renderer::draw(const Snapshot& snapshot, const Camera& camera, int width, int height, Look look) {
    const Box box = bounds(snapshot);
    const float size = std::max(box.empty() ? 1.0f : box.diagonal(), 0.1f);
    const glm::mat4 view_projection = camera.view_projection();

    glViewport(0, 0, width, height);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_CULL_FACE);  // cloth has two sides; open cylinders show their inside
    glBindVertexArray(vertex_array_);

    // Sky, behind everything.
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glUseProgram(sky_program_);
    glUniform1f(uniform(sky_program_, "u_height"), float(height));
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);

    // Ground: just under the lowest point of the scene, grid lines about a tenth of the scene apart;
    // a plane collider facing up is the ground itself, drawn as the grid at its height.
    const auto floor = std::find_if(snapshot.colliders.begin(), snapshot.colliders.end(), is_floor);
    {
        const float ground_y = floor != snapshot.colliders.end() ? floor->p0.y
                                                                 : (box.empty() ? 0.0f : box.min.y) - 0.02f * size;
        const glm::vec3 centre = box.empty() ? glm::vec3(0.0f) : box.centre();
        const float half = 40.0f * size;
        const Vec3 corners[4] = {{centre.x - half, ground_y, centre.z - half}, {centre.x + half, ground_y, centre.z - half},
                                 {centre.x - half, ground_y, centre.z + half}, {centre.x + half, ground_y, centre.z + half}};
        glUseProgram(ground_program_);
        glUniformMatrix4fv(uniform(ground_program_, "u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
        glUniform1f(uniform(ground_program_, "u_spacing"), std::pow(10.0f, std::floor(std::log10(size))) / 4.0f);
        glUniform3fv(uniform(ground_program_, "u_centre"), 1, glm::value_ptr(centre));
        glUniform1f(uniform(ground_program_, "u_fade_distance"), 6.0f * size);
        glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
        glBufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STREAM_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glDisableVertexAttribArray(1);
        glDisableVertexAttribArray(2);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }

    // Colliders and cloths.
    glUseProgram(mesh_program_);
    glUniformMatrix4fv(uniform(mesh_program_, "u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
    glUniform3fv(uniform(mesh_program_, "u_eye"), 1, glm::value_ptr(camera.eye));
    const bool mask = look == Look::cloth_mask;
    for (const ColliderDesc& c : snapshot.colliders) {
        if (is_floor(c)) continue;  // the ground grid
        Mesh mesh;
        static_cast<SurfaceMesh&>(mesh) = collider_surface(c, box);
        mesh.front_colour = mesh.back_colour = mask ? kColliderMask : kCollider;
        mesh.unlit = mask;
        draw_mesh(mesh);
    }
    for (const BodySurface& body : snapshot.bodies) {
        Mesh mesh;
        mesh.positions = body.positions;
        mesh.normals = scenes::smooth_normals(body.positions, body.triangles);
        mesh.indices = body.triangles;
        mesh.front_colour = mesh.back_colour = mask ? kColliderMask : kBody;
        mesh.unlit = mask;
        draw_mesh(mesh);
    }
    for (const ClothSurface& cloth : snapshot.cloths) {
        Mesh mesh;
        mesh.positions = cloth.positions;
        mesh.normals = scenes::smooth_normals(cloth.positions, cloth.triangles);
        mesh.indices = cloth.triangles;
        if (mask) {
            mesh.front_colour = mesh.back_colour = glm::vec3(kClothMaskRgb[0], kClothMaskRgb[1], kClothMaskRgb[2]) / 255.0f;
            mesh.unlit = true;
        } else {
            mesh.uv = cloth.uv;
            mesh.front_colour = kClothFront;
            mesh.back_colour = kClothBack;
        }
        draw_mesh(mesh);
    }
    glBindVertexArray(0);
}

}  // namespace weft::render
