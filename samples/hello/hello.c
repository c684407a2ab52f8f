/* Weft's hello world in C (weft/weft_c.h): a baked sheet falls onto a swaying ball for one second.
 *   hello-c build/samples/assets/sheet.weft
 * Exits non-zero if a position is not finite, the cloth did not fall, a normal is not unit
 * length or the cloth went into the ball. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "weft/weft_c.h"

#define CHECK(call) do { WeftResult r_ = (call); if (r_.code != WEFT_OK) { \
    fprintf(stderr, "%s: %s (%s)\n", #call, r_.message, weft_error_name(r_.code)); return 1; } } while (0)

static void* alloc_block(WeftMemoryRequirements need) {  /* aligned_alloc wants a multiple */
    return aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment);
}

/* The body: a ball of radius 0.5 m centred at (x, 1, 0), RINGS + 1 rings of SEGMENTS vertices
 * (the pole rings' triangles have zero area: harmless), wound counter-clockwise from outside. */
enum { RINGS = 16, SEGMENTS = 32, VERTICES = (RINGS + 1) * SEGMENTS, TRIANGLES = 2 * RINGS * SEGMENTS };
static void ball_vertices(float x, WeftVec3* out) {
    for (int r = 0; r <= RINGS; ++r)
        for (int k = 0; k < SEGMENTS; ++k) {
            const float theta = 3.14159265f * (float)r / RINGS, phi = 2.0f * 3.14159265f * (float)k / SEGMENTS;
            const WeftVec3 v = {x + 0.5f * sinf(theta) * cosf(phi), 1.0f + 0.5f * cosf(theta), 0.5f * sinf(theta) * sinf(phi)};
            out[r * SEGMENTS + k] = v;
        }
}
static void ball_triangles(uint32_t* out) {
    for (uint32_t r = 0; r < RINGS; ++r)
        for (uint32_t k = 0; k < SEGMENTS; ++k, out += 6) {
            const uint32_t a = r * SEGMENTS + k, b = r * SEGMENTS + (k + 1) % SEGMENTS;
            const uint32_t t[6] = {a, b, a + SEGMENTS, b, b + SEGMENTS, a + SEGMENTS};
            for (int i = 0; i < 6; ++i) out[i] = t[i];
        }
}

int main(int argc, char** argv) {
    if (argc != 2) { fprintf(stderr, "usage: hello-c ASSET.weft\n"); return 2; }
    /* 1. The asset file, read into 64-byte aligned memory, loaded in place. */
    FILE* f = fopen(argv[1], "rb");
    if (f == NULL) { fprintf(stderr, "cannot open %s\n", argv[1]); return 1; }
    fseek(f, 0, SEEK_END);
    const size_t size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    void* file = aligned_alloc(64, (size + 63) / 64 * 64);
    const size_t read = fread(file, 1, size, f);
    fclose(f);
    if (read != size) { fprintf(stderr, "cannot read %s\n", argv[1]); return 1; }
    WeftMemoryRequirements need;
    CHECK(weft_asset_memory_requirements(file, size, &need));
    void* asset_block = alloc_block(need);
    WeftAsset* asset;
    CHECK(weft_load_asset(file, size, asset_block, need.bytes, &asset));
    WeftAssetInfo info;
    CHECK(weft_asset_info(asset, &info));

    /* 2. A world sized for the cloth and one body, in a block of ours. */
    WeftWorldDesc desc = weft_default_world_desc();
    CHECK(weft_reserve_cloth(&desc, asset));
    desc.max_bodies = 1;
    desc.normals = 1; /* each step ends with vertex normals (weft_read_normals) */
    desc.max_body_vertices = VERTICES;
    desc.max_body_triangles = TRIANGLES;
    CHECK(weft_world_memory_requirements(&desc, &need));
    void* world_block = alloc_block(need);
    WeftWorld* world;
    CHECK(weft_create_world(&desc, world_block, need.bytes, &world));

    WeftClothDesc cloth_desc = weft_default_cloth_desc(asset);
    WeftClothId cloth;
    CHECK(weft_add_cloth(world, &cloth_desc, &cloth));
    static WeftVec3 ball[VERTICES];
    static uint32_t ball_indices[3 * TRIANGLES];
    ball_vertices(0.0f, ball);
    ball_triangles(ball_indices);
    WeftBodyDesc body_desc = weft_default_body_desc();
    body_desc.positions = ball;
    body_desc.vertex_count = VERTICES;
    body_desc.triangles = ball_indices;
    body_desc.triangle_count = TRIANGLES;
    WeftBodyId body;
    CHECK(weft_add_body(world, &body_desc, &body));

    /* 3. The frame loop: move the body, step, read positions and normals. */
    WeftVec3* positions = malloc(sizeof(WeftVec3) * info.particle_count);
    WeftVec3* normals = malloc(sizeof(WeftVec3) * info.particle_count);
    const float dt_s = 1.0f / 60.0f;
    float ball_x = 0.0f;
    for (int frame = 1; frame <= 60; ++frame) {
        ball_x = 0.03f * sinf(3.0f * (float)frame * dt_s);
        ball_vertices(ball_x, ball);
        CHECK(weft_set_body_vertices(world, body, ball, VERTICES));
        CHECK(weft_step(world, dt_s));
        CHECK(weft_read_positions(world, cloth, positions, info.particle_count));
        CHECK(weft_read_normals(world, cloth, normals, info.particle_count));
    }

    /* 4. Check what the frames did. */
    float lowest = INFINITY;
    int bad = 0, inside = 0;
    for (uint32_t i = 0; i < info.particle_count; ++i) {
        const WeftVec3 p = positions[i], n = normals[i];
        bad += !isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z) || fabsf(sqrtf(n.x * n.x + n.y * n.y + n.z * n.z) - 1.0f) > 1e-3f;
        inside += (p.x - ball_x) * (p.x - ball_x) + (p.y - 1.0f) * (p.y - 1.0f) + p.z * p.z < 0.49f * 0.49f;  /* 1 cm deep */
        lowest = p.y < lowest ? p.y : lowest;
    }
    printf("hello-c: %u particles after 60 frames, lowest at %.3f m, %d bad, %d inside the ball\n",
           info.particle_count, (double)lowest, bad, inside);
    weft_destroy_world(world);
    free(normals);
    free(positions);
    free(world_block);
    free(asset_block);
    free(file);
    return bad == 0 && inside == 0 && lowest < 1.5f ? 0 : 1;
}
