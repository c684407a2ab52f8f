// Writing ClothAssets as asset files (docs/asset-format.md), and holding file bytes the way the
// runtime's loader wants them: 64-byte aligned. Tools and tests only; the runtime reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "weft/weft.h"

namespace weft::assets {

// Validates `asset`, then lays it out: the header, the section table, then every non-empty array
// as one section at the next multiple of 64 bytes, in kind order. Padding bytes are zero, so one
// asset always gives the same bytes. The checksum is libxxhash's XXH64, a check on the runtime's own.
Result write_asset(const ClothAsset& asset, std::vector<std::byte>* out);

// Bytes in 64-byte aligned memory, as load_asset_in_place needs them.
class AlignedBytes {
public:
    AlignedBytes() = default;
    AlignedBytes(const void* data, size_t size);
    std::byte* data() { return memory_.get(); }
    const std::byte* data() const { return memory_.get(); }
    size_t size() const { return size_; }

private:
    std::unique_ptr<std::byte[], void (*)(void*)> memory_{nullptr, nullptr};
    size_t size_ = 0;
};

// An asset loaded in place from its own aligned copy of a file, with the scratch loading needs.
// Moving it keeps the buffers, so the asset's pointers stay valid.
struct LoadedAsset {
    AlignedBytes bytes;
    std::vector<uint32_t> scratch;
    ClothAsset asset;
};
Result load_asset_copy(const void* file, size_t size, LoadedAsset* out);

}  // namespace weft::assets
