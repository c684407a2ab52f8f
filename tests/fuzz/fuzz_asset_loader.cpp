// libFuzzer harness for the asset loader (scripts/fuzz.sh): no input may crash it, leak, or reach
// undefined behaviour, and whatever it accepts must step without doing so either (validate_asset's
// promise: a valid asset cannot make the step go out of bounds).
//
// The first byte of an input says how the rest is used, so the fuzzer gets past the checksum:
//   bit 0  fix up the copy's file_size and checksum before loading (else a mutation is nearly
//          always a checksum mismatch and nothing deeper is reached)
//   bit 1  when it loads, step it in a world with wind for a few frames (small assets only)
//   bit 2  ... on the scalar path rather than the widest one
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "asset/xxh64.h"
#include "weft/asset_format.h"
#include "weft/weft.h"

namespace {

using namespace weft;

constexpr uint32_t kMaxSteppedSlots = 1 << 12;  // a world for more would slow the fuzzer down

void step_a_little(const ClothAsset& asset, bool scalar) {
    if (asset.slot_count > kMaxSteppedSlots || asset.lane_count > 16 * kMaxSteppedSlots) return;
    WorldDesc desc;
    desc.max_cloths = 0;
    reserve_cloth(desc, asset);
    desc.wind = true;
    desc.tangents = asset.uv != nullptr;  // the render output too: tangents, the render mesh
    desc.render_meshes = true;
    desc.simd = scalar ? SimdPath::scalar : SimdPath::automatic;
    const MemoryRequirements need = world_memory_requirements(desc);
    if (need.bytes == 0) return;
    const size_t rounded = (need.bytes + need.alignment - 1) / need.alignment * need.alignment;
    void* memory = std::aligned_alloc(need.alignment, rounded);
    World* world = nullptr;
    if (create_world(desc, memory, need.bytes, &world).ok()) {
        set_wind(world, {5.0f, 0.0f, 2.0f});
        ClothDesc cloth;
        cloth.asset = &asset;
        ClothId id;
        if (add_cloth(world, cloth, &id).ok()) {
            for (int i = 0; i < 3; ++i) step(world, 0.033f);
            std::vector<Vec3> positions(asset.particle_count);
            read_positions(world, id, positions.data(), asset.particle_count);
            std::vector<Vec3> render(asset.render.vertex_count);
            if (!render.empty()) read_render_mesh(world, id, render.data(), nullptr, asset.render.vertex_count);
        }
    }
    std::free(memory);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const uint8_t mode = data[0];
    data += 1;
    size -= 1;
    // The loader wants 64-byte aligned bytes; libFuzzer's are not.
    const size_t rounded = (size + 64) / 64 * 64;
    uint8_t* file = static_cast<uint8_t*>(std::aligned_alloc(64, rounded));
    if (size > 0) std::memcpy(file, data, size);

    if ((mode & 1) && size >= sizeof(AssetFileHeader)) {
        const uint64_t file_size = size;
        std::memcpy(file + offsetof(AssetFileHeader, file_size), &file_size, sizeof(file_size));
        const uint64_t checksum = xxh64(file + kAssetChecksumStart, size - kAssetChecksumStart, 0);
        std::memcpy(file + offsetof(AssetFileHeader, checksum), &checksum, sizeof(checksum));
    }

    AssetFileInfo info;
    const bool header_ok = read_asset_header(file, size, &info).ok();
    // Scratch as the header asks, within reason; too little must be refused cleanly too.
    const uint32_t scratch_count = header_ok && info.load_scratch_count <= (1u << 20) ? info.load_scratch_count : 64;
    std::vector<uint32_t> scratch(scratch_count);
    ClothAsset asset;
    if (load_asset_in_place(file, size, scratch.data(), scratch_count, &asset).ok() && (mode & 2))
        step_a_little(asset, (mode & 4) != 0);
    std::free(file);
    return 0;
}
