// Asset files: the writer side of docs/asset-format.md.
#include "common/asset_writer.h"
#include "weft/asset_format.h"

#include <xxhash.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace weft::assets {
namespace {

uint64_t round_up(uint64_t v, uint64_t m) { return (v + m - 1) / m * m; }

Result writer_error(const char* message) {
    Result r;
    r.code = ErrorCode::invalid_argument;
    std::snprintf(r.message, sizeof(r.message), "%s", message);
    return r;
}

}  // namespace

AlignedBytes::AlignedBytes(const void* data, size_t size) : size_(size) {
    const size_t rounded = round_up(size > 0 ? size : 1, kAssetSectionAlignment);
    memory_ = {static_cast<std::byte*>(std::aligned_alloc(kAssetSectionAlignment, rounded)), std::free};
    if (size > 0) std::memcpy(memory_.get(), data, size);
}

Result write_asset(const ClothAsset& asset, std::vector<std::byte>* out) {
    if (out == nullptr) return writer_error("out is null");
    if (Result r = validate_asset(asset); !r.ok()) return r;

    AssetFileHeader header{};  // no padding inside (load.cpp asserts the offsets): every byte is set
    std::memcpy(header.magic, kAssetMagic, sizeof(kAssetMagic));
    header.version_major = kAssetVersionMajor;
    // Without a render mesh the file is a 1.2 file, byte for byte what the writer wrote before 1.3.
    const bool render = asset.render.vertex_count > 0;
    header.version_minor = render ? kAssetVersionMinor : 2;
    header.endian_marker = kAssetEndianMarker;
    header.header_size = render ? uint32_t(sizeof(AssetFileHeader)) : kAssetHeaderSize_1_2;
    pair_asset_scalars(header, asset, [](auto& to, const auto& from) { to = from; });
    header.has_uv = asset.uv != nullptr;

    struct Section {
        AssetSectionEntry entry;
        const void* data;
    };
    std::vector<Section> sections;
    bool missing = false;
    visit_asset_sections(header, asset, [&](AssetSectionKind kind, const auto& field, uint64_t count) {
        if (count == 0) return;
        missing |= field == nullptr;
        AssetSectionEntry e{};
        e.kind = uint32_t(kind);
        e.element_size = sizeof(*field);
        e.element_count = uint32_t(count);  // validate_asset bounds every count well below 2^32
        e.size = count * e.element_size;
        e.alignment = kAssetSectionAlignment;
        sections.push_back({e, field});
    });
    if (missing) return writer_error("asset has a count but no array for it");

    header.section_count = uint32_t(sections.size());
    uint64_t offset = header.header_size + sections.size() * sizeof(AssetSectionEntry);
    for (Section& s : sections) {
        s.entry.offset = round_up(offset, kAssetSectionAlignment);
        offset = s.entry.offset + s.entry.size;
    }
    header.file_size = offset;

    std::vector<std::byte> file(offset, std::byte{0});
    for (size_t i = 0; i < sections.size(); ++i) {
        std::memcpy(file.data() + header.header_size + i * sizeof(AssetSectionEntry), &sections[i].entry,
                    sizeof(AssetSectionEntry));
        std::memcpy(file.data() + sections[i].entry.offset, sections[i].data, sections[i].entry.size);
    }
    std::memcpy(file.data(), &header, header.header_size);
    header.checksum = XXH64(file.data() + kAssetChecksumStart, file.size() - kAssetChecksumStart, 0);
    std::memcpy(file.data() + offsetof(AssetFileHeader, checksum), &header.checksum, sizeof(header.checksum));
    *out = std::move(file);
    return {};
}

Result load_asset_copy(const void* file, size_t size, LoadedAsset* out) {
    if (out == nullptr) return writer_error("out is null");
    LoadedAsset loaded;
    loaded.bytes = AlignedBytes(file, size);
    AssetFileInfo info;
    if (Result r = read_asset_header(loaded.bytes.data(), size, &info); !r.ok()) return r;
    loaded.scratch.resize(info.load_scratch_count);
    if (Result r = load_asset_in_place(loaded.bytes.data(), size, loaded.scratch.data(),
                                       uint32_t(loaded.scratch.size()), &loaded.asset);
        !r.ok())
        return r;
    *out = std::move(loaded);
    return {};
}

}  // namespace weft::assets
