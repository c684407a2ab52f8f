// Baked cloth assets: a versioned binary file that the runtime uses in place (docs/asset-format.md).
//
//   bytes = mmap(file) or an aligned read (64-byte aligned, alive and unchanged while in use)
//   AssetFileInfo info;  read_asset_header(bytes, size, &info);        // counts, for the scratch
//   std::vector<uint32_t> scratch(info.load_scratch_count);            // or the game's own memory
//   ClothAsset asset;    load_asset_in_place(bytes, size, scratch.data(), info.load_scratch_count, &asset);
//
// Loading copies nothing and allocates nothing: every ClothAsset array points into `bytes`. Every
// byte is checked before the asset is handed out, so no file, however broken, makes the loader or
// a later step() read out of bounds; on any error the output is left untouched.
//
// The format itself (header, section table, section kinds) is in weft/asset_format.h, for writers
// (lib/common/asset_writer.h), the loader and tools that inspect files.
#pragma once

#include <cstddef>
#include <cstdint>

#include "weft/cloth_asset.h"
#include "weft/types.h"

namespace weft {

// Most sections a file may have (AssetFileInfo::sections).
inline constexpr uint32_t kMaxAssetSections = 128;

struct AssetSectionInfo {
    uint32_t kind = 0;
    uint32_t element_size = 0;
    uint64_t offset = 0;
    uint64_t size = 0;
    uint32_t element_count = 0;
    uint32_t alignment = 0;
};

// What read_asset_header reports (weft-bake --info).
struct AssetFileInfo {
    uint16_t version_major = 0, version_minor = 0;
    uint64_t file_size = 0;
    uint64_t checksum = 0;  // as stored (and verified)
    uint32_t header_size = 0;
    // The asset's scalar fields: counts, simd_width, lattice sizes, fabric. Its pointers are null.
    ClothAsset counts;
    bool has_uv = false;
    // uint32 values load_asset_in_place needs as scratch (the larger of the slot counts).
    uint32_t load_scratch_count = 0;
    uint32_t section_count = 0;
    AssetSectionInfo sections[kMaxAssetSections];
};

// Checks everything about the file that needs no section contents: magic, endianness, version,
// sizes, checksum, and the section table (offsets in range, aligned, not overlapping, known kinds
// present exactly once with the counts the header gives). `bytes` must be 64-byte aligned.
// On error `*info` is left untouched.
Result read_asset_header(const void* bytes, size_t size, AssetFileInfo* info);

// The checks of read_asset_header, then the asset's own (validate_asset), using `scratch`
// (at least AssetFileInfo::load_scratch_count uint32 values, overwritten) instead of allocating.
// On success `*out` points into `bytes`, which must then stay alive and unchanged while the asset
// is used. On any error `*out` is left untouched.
Result load_asset_in_place(const void* bytes, size_t size, uint32_t* scratch, uint32_t scratch_count,
                           ClothAsset* out);

}  // namespace weft
