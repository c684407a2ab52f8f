/* Builds against the installed Weft (C99, weft/weft_c.h): creates a world; given an asset file, adds
 * it as a cloth and steps it once. Prints OK. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "weft/weft_c.h"

#define CHECK(call) do { WeftResult r_ = (call); if (r_.code != WEFT_OK) { \
    fprintf(stderr, "%s: %s\n", #call, r_.message); return 1; } } while (0)

/* malloc'd memory moved up to `alignment` (C99 has no aligned_alloc); freed at the end. */
static void* blocks[3];
static int block_count = 0;
static void* aligned_block(WeftMemoryRequirements need) {
    unsigned char* p = malloc(need.bytes + need.alignment);
    blocks[block_count++] = p;
    return p == NULL ? NULL : p + (need.alignment - (uintptr_t)p % need.alignment) % need.alignment;
}

int main(int argc, char** argv) {
    WeftWorldDesc desc = weft_default_world_desc();
    WeftMemoryRequirements need;
    WeftAsset* asset = NULL;
    void* file = NULL;
    size_t size = 0;
    if (argc > 1) {
        FILE* f = fopen(argv[1], "rb");
        if (f == NULL) { fprintf(stderr, "cannot open %s\n", argv[1]); return 1; }
        fseek(f, 0, SEEK_END);
        size = (size_t)ftell(f);
        fseek(f, 0, SEEK_SET);
        need.bytes = size;
        need.alignment = 64;
        file = aligned_block(need);
        if (fread(file, 1, size, f) != size) { fprintf(stderr, "cannot read %s\n", argv[1]); return 1; }
        fclose(f);
        CHECK(weft_asset_memory_requirements(file, size, &need));
        CHECK(weft_load_asset(file, size, aligned_block(need), need.bytes, &asset));
        CHECK(weft_reserve_cloth(&desc, asset));
    } else {
        desc.max_cloths = 1;
        desc.max_particles = 64;
    }
    CHECK(weft_world_memory_requirements(&desc, &need));
    WeftWorld* world = NULL;
    CHECK(weft_create_world(&desc, aligned_block(need), need.bytes, &world));
    if (asset != NULL) {
        WeftClothDesc cloth = weft_default_cloth_desc(asset);
        WeftClothId id;
        CHECK(weft_add_cloth(world, &cloth, &id));
        CHECK(weft_step(world, 1.0f / 60.0f));
    }
    weft_destroy_world(world);
    while (block_count > 0) free(blocks[--block_count]);
    printf("OK\n");
    return 0;
}
