// Weft's hello world in C++ (weft/weft.h): a baked sheet falls onto a swaying ball for one second.
//   hello-cpp build/samples/assets/sheet.weft
// Exits non-zero if a position is not finite, the cloth did not fall, a normal is not unit length
// or the cloth went into the ball.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <vector>

#include "weft/weft.h"

using namespace weft;

#define CHECK(call) do { const Result r_ = (call); if (!r_.ok()) { \
    std::fprintf(stderr, "%s: %s\n", #call, r_.message); return 1; } } while (0)

using Block = std::unique_ptr<void, decltype(&std::free)>;
static Block alloc_block(size_t bytes, size_t alignment) {  // aligned_alloc wants a multiple
    return {std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment), &std::free};
}

// The body: a ball of radius 0.5 m centred at (x, 1, 0), kRings + 1 rings of kSegments vertices
// (the pole rings' triangles have zero area: harmless), wound counter-clockwise from outside.
constexpr uint32_t kRings = 16, kSegments = 32, kVertices = (kRings + 1) * kSegments, kTriangles = 2 * kRings * kSegments;
static void ball_vertices(float x, Vec3* out) {
    for (uint32_t r = 0; r <= kRings; ++r)
        for (uint32_t k = 0; k < kSegments; ++k) {
            const float theta = 3.14159265f * float(r) / kRings, phi = 2.0f * 3.14159265f * float(k) / kSegments;
            out[r * kSegments + k] = {x + 0.5f * std::sin(theta) * std::cos(phi), 1.0f + 0.5f * std::cos(theta),
                                      0.5f * std::sin(theta) * std::sin(phi)};
        }
}
static std::vector<uint32_t> ball_triangles() {
    std::vector<uint32_t> t;
    for (uint32_t r = 0; r < kRings; ++r)
        for (uint32_t k = 0; k < kSegments; ++k) {
            const uint32_t a = r * kSegments + k, b = r * kSegments + (k + 1) % kSegments;
            t.insert(t.end(), {a, b, a + kSegments, b, b + kSegments, a + kSegments});
        }
    return t;
}

int main(int argc, char** argv) {
    if (argc != 2) { std::fprintf(stderr, "usage: hello-cpp ASSET.weft\n"); return 2; }
    // 1. The asset file, read into 64-byte aligned memory, loaded in place.
    std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
    if (!in) { std::fprintf(stderr, "cannot open %s\n", argv[1]); return 1; }
    const size_t size = size_t(in.tellg());
    Block file = alloc_block(size, 64);
    in.seekg(0);
    if (!in.read(static_cast<char*>(file.get()), std::streamsize(size))) { std::fprintf(stderr, "cannot read\n"); return 1; }
    AssetFileInfo info;
    CHECK(read_asset_header(file.get(), size, &info));
    std::vector<uint32_t> scratch(info.load_scratch_count);
    ClothAsset asset;
    CHECK(load_asset_in_place(file.get(), size, scratch.data(), info.load_scratch_count, &asset));

    // 2. A world sized for the cloth and one body, in a block of ours.
    WorldDesc desc;
    desc.max_cloths = 0;  // reserve_cloth counts them
    reserve_cloth(desc, asset);
    desc.max_skin_constraints = 0;  // none bound here
    desc.max_bodies = 1;
    desc.normals = true;  // each step ends with vertex normals (read_normals)
    desc.max_body_vertices = kVertices;
    desc.max_body_triangles = kTriangles;
    const MemoryRequirements need = world_memory_requirements(desc);
    Block world_block = alloc_block(need.bytes, need.alignment);
    World* world = nullptr;
    CHECK(create_world(desc, world_block.get(), need.bytes, &world));

    const AssetView view = view_asset(asset);  // counts, fabric, uv, triangles: no solver layout
    ClothDesc cloth_desc;
    cloth_desc.asset = &asset;
    cloth_desc.damping_per_s = view.fabric.damping_per_s;  // the baked fabric's (ClothDesc's if none)
    for (int k = 0; k < 3; ++k) cloth_desc.compliance_m_per_n[k] = view.fabric.compliance_m_per_n[k];
    ClothId cloth;
    CHECK(add_cloth(world, cloth_desc, &cloth));
    std::vector<Vec3> ball(kVertices);
    ball_vertices(0.0f, ball.data());
    const std::vector<uint32_t> ball_indices = ball_triangles();
    BodyDesc body_desc;
    body_desc.positions = ball.data();
    body_desc.vertex_count = kVertices;
    body_desc.triangles = ball_indices.data();
    body_desc.triangle_count = kTriangles;
    BodyId body;
    CHECK(add_body(world, body_desc, &body));

    // 3. The frame loop: move the body, step, read positions and normals.
    std::vector<Vec3> positions(view.particle_count), normals(view.particle_count);
    const float dt_s = 1.0f / 60.0f;
    float ball_x = 0.0f;
    for (int frame = 1; frame <= 60; ++frame) {
        ball_x = 0.03f * std::sin(3.0f * float(frame) * dt_s);
        ball_vertices(ball_x, ball.data());
        CHECK(set_body_vertices(world, body, ball.data(), kVertices));
        CHECK(step(world, dt_s));
        CHECK(read_positions(world, cloth, positions.data(), view.particle_count));
        CHECK(read_normals(world, cloth, normals.data(), view.particle_count));
    }

    // 4. Check what the frames did.
    float lowest = INFINITY;
    int bad = 0, inside = 0;
    for (uint32_t i = 0; i < view.particle_count; ++i) {
        const Vec3 p = positions[i], n = normals[i];
        bad += !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
               std::fabs(std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z) - 1.0f) > 1e-3f;
        inside += std::hypot(p.x - ball_x, p.y - 1.0f, p.z) < 0.49f;  // 1 cm deep
        lowest = std::fmin(lowest, p.y);
    }
    std::printf("hello-cpp: %u particles after 60 frames, lowest at %.3f m, %d bad, %d inside the ball\n",
                view.particle_count, double(lowest), bad, inside);
    destroy_world(world);  // releases the Embree device; the blocks are ours
    return bad == 0 && inside == 0 && lowest < 1.5f ? 0 : 1;
}
