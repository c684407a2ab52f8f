// Writes the asset loader's seed corpus (tests/fuzz/corpus/asset_loader/): small valid assets from
// the writer, each in every way the harness can use it, and a few broken ones. Run it again when
// the format changes:
//   build/tests/make_asset_corpus tests/fuzz/corpus/asset_loader
// Each file is the harness's mode byte (tests/fuzz/fuzz_asset_loader.cpp) followed by an asset file.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common/asset_writer.h"
#include "common/seed_scenes.h"
#include "weft/asset_format.h"
#include "weft/cook.h"

using namespace weft;

namespace {

using Bytes = std::vector<std::byte>;

bool save(const std::string& path, uint8_t mode, const Bytes& file) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) return false;
    const bool ok = std::fwrite(&mode, 1, 1, f) == 1 && std::fwrite(file.data(), 1, file.size(), f) == file.size();
    return std::fclose(f) == 0 && ok;
}

// A grid of n x n with two pinned corners; garment data, lattice and options as asked; `sewn`:
// format 1.1's sewn seams and body attachments (a made-up seam on the first row's two particles,
// the pinned corners attached to body triangles 0 and 1); `skinned`: format 1.2's skin constraints
// (the first row's two free particles bound to body triangles 2 and 3, one without a max distance);
// `render_levels` (not ~0u): format 1.3's render mesh, the grid's triangles subdivided that often.
Bytes grid_asset(uint32_t n, bool garment, bool lattice, const CookOptions& options, bool pinned = true,
                 bool sewn = false, bool skinned = false, uint32_t render_levels = ~0u) {
    scenes::GridMesh grid = scenes::make_grid(n, 1.0f, 1.0f, false, 1.0f);
    if (pinned) {
        grid.masses[grid.index(0, 0)] = 0.0f;
        grid.masses[grid.index(0, n - 1)] = 0.0f;
    }
    const scenes::GridGarment data = scenes::make_grid_garment(grid);
    ClothMeshDesc desc = grid.desc();
    if (garment) data.apply(desc);
    if (!lattice) desc.lattice = nullptr;
    const uint32_t sewn_particle[1] = {1}, uv_first[2] = {0, 2}, attached[2] = {grid.index(0, 0), grid.index(0, n - 1)};
    const uint32_t triangles[2] = {0, 1};
    const float sewn_uv[4] = {0.1f, 0.0f, 0.9f, 0.0f}, weights[6] = {1, 0, 0, 0.25f, 0.25f, 0.5f};
    if (sewn) {
        desc.seam_point_count = 0;
        desc.sewn_point_count = 1;
        desc.sewn_particle = sewn_particle;
        desc.sewn_uv_first = uv_first;
        desc.sewn_uv = sewn_uv;
        desc.attachment_count = 2;
        desc.attached_particle = attached;
        desc.attached_triangle = triangles;
        desc.attached_weight = weights;
    }
    const uint32_t skin_particle[2] = {grid.index(0, 1), grid.index(0, 2)}, skin_triangle[2] = {2, 3};
    const float skin_weight[6] = {0.5f, 0.5f, 0, 0.2f, 0.3f, 0.5f}, rest_offset[2] = {0.01f, -0.002f};
    const float max_distance[2] = {0.03f, kSkinNoMaxDistance_m}, backstop[2] = {-0.0015f, 0.0f};
    if (skinned) {
        desc.skin.count = 2;
        desc.skin.particle = skin_particle;
        desc.skin.triangle = skin_triangle;
        desc.skin.weight = skin_weight;
        desc.skin.rest_offset_m = rest_offset;
        desc.skin.max_distance_m = max_distance;
        desc.skin.backstop_m = backstop;
    }
    CookedCloth cooked;
    Bytes file;
    if (!cook_cloth(desc, options, &cooked).ok()) return {};
    if (render_levels != ~0u) {  // format 1.3's render mesh: the grid subdivided, bound back to it
        RenderMeshSource fine;
        if (!subdivide_cloth_mesh(cooked.asset(), render_levels, &fine).ok() || !bind_render_mesh(fine.desc(), &cooked).ok())
            return {};
    }
    if (!assets::write_asset(cooked.asset(), &file).ok()) return {};
    return file;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_asset_corpus DIRECTORY\n");
        return 2;
    }
    const std::string dir = argv[1];
    CookOptions wide, bare;
    wide.simd_width = 16;
    bare.coarse_spacing_m = 0.0f;
    bare.tethers_per_particle = 0;
    struct Seed {
        const char* name;
        Bytes file;
    };
    std::vector<Seed> valid = {
        {"grid3_garment", grid_asset(3, true, true, {})},
        {"grid4_garment_no_lattice", grid_asset(4, true, false, {})},
        {"grid6_lattice_coarse", grid_asset(6, false, true, {})},
        {"grid5_simd16", grid_asset(5, true, true, wide)},
        {"grid4_bare_unpinned", grid_asset(4, false, true, bare, false)},
        {"grid4_sewn_attached", grid_asset(4, true, true, {}, true, true)},
        {"grid4_sewn_skinned", grid_asset(4, true, true, {}, true, true, true)},
        {"grid4_render_subdivided", grid_asset(4, true, true, {}, true, false, false, 1)},
    };
    bool ok = true;
    for (const Seed& s : valid) {
        ok &= !s.file.empty();
        ok &= save(dir + "/" + s.name + "_stepped", 0x03, s.file);  // checksum fixed up, stepped
        ok &= save(dir + "/" + s.name + "_as_is", 0x00, s.file);    // loaded exactly as written
    }
    // Broken: truncated, a flipped section byte, another major version, big-endian.
    const Bytes& small = valid[0].file;
    ok &= save(dir + "/broken_truncated", 0x00, Bytes(small.begin(), small.begin() + small.size() / 2));
    Bytes flipped = small;
    flipped[flipped.size() - 3] ^= std::byte{0x40};
    ok &= save(dir + "/broken_flipped", 0x00, flipped);
    Bytes major = small;
    const uint16_t three = 3;
    std::memcpy(major.data() + offsetof(AssetFileHeader, version_major), &three, sizeof(three));
    ok &= save(dir + "/broken_major3", 0x01, major);
    Bytes big = small;
    const uint8_t big_endian[4] = {1, 2, 3, 4};
    std::memcpy(big.data() + offsetof(AssetFileHeader, endian_marker), big_endian, sizeof(big_endian));
    ok &= save(dir + "/broken_big_endian", 0x01, big);
    if (!ok) std::fprintf(stderr, "make_asset_corpus: could not write every file to %s\n", dir.c_str());
    return ok ? 0 : 1;
}
