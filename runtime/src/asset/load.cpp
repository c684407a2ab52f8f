// Loading a baked asset in place (weft/asset_file.h, docs/asset-format.md). The order of the checks
// is the order in which a byte may be trusted: nothing is read before the check that makes reading
// it safe, and nothing is written to the caller's output before every check has passed.
//
//   1. the buffer: not null, 64-byte aligned
//   2. the frozen first 24 bytes: magic, endianness, major version (the checksum is checked in 3)
//   3. the header: sizes agree with the buffer, then the checksum over the rest of the file
//   4. the section table: each section inside the file, aligned, overlapping nothing; each known
//      kind at most once, with the element size and count the header implies; none missing
//   5. (load only) the sections mapped into a ClothAsset, then validate_asset on it
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include "asset/validate.h"
#include "asset/xxh64.h"
#include "error.h"
#include "weft/asset_format.h"

namespace weft {

// The file is read in place: its bytes are the runtime's structs. Little-endian hosts only, and the
// structs stored as arrays have exactly the documented layout (plain 4-, 2- and 1-byte fields).
static_assert(std::endian::native == std::endian::little, "asset files are little-endian");
static_assert(sizeof(ConstraintBatch) == 20 && offsetof(ConstraintBatch, first_lane) == 0 &&
              offsetof(ConstraintBatch, lane_count) == 4 && offsetof(ConstraintBatch, a0) == 8 &&
              offsetof(ConstraintBatch, b0) == 12 && offsetof(ConstraintBatch, kind) == 16 &&
              offsetof(ConstraintBatch, layout) == 17 && offsetof(ConstraintBatch, colour) == 18);
static_assert(sizeof(TetherBatch) == 20 && offsetof(TetherBatch, first_lane) == 0 &&
              offsetof(TetherBatch, lane_count) == 4 && offsetof(TetherBatch, particle0) == 8 &&
              offsetof(TetherBatch, anchor) == 12);
static_assert(sizeof(TriangleRun) == 20 && offsetof(TriangleRun, first_lane) == 0 &&
              offsetof(TriangleRun, lane_count) == 4 && offsetof(TriangleRun, a0) == 8 &&
              offsetof(TriangleRun, b0) == 12 && offsetof(TriangleRun, c0) == 16);
static_assert(std::is_trivially_copyable_v<ConstraintBatch> && std::is_trivially_copyable_v<TetherBatch> &&
              std::is_trivially_copyable_v<TriangleRun>);
// The header table in docs/asset-format.md.
static_assert(sizeof(Fabric) == 28);
static_assert(offsetof(AssetFileHeader, checksum) == 8 && offsetof(AssetFileHeader, version_major) == 16 &&
              offsetof(AssetFileHeader, endian_marker) == 20 && offsetof(AssetFileHeader, file_size) == 24 &&
              offsetof(AssetFileHeader, header_size) == 32 && offsetof(AssetFileHeader, simd_width) == 40 &&
              offsetof(AssetFileHeader, constraint_count) == 64 && offsetof(AssetFileHeader, seam_point_count) == 128 &&
              offsetof(AssetFileHeader, has_uv) == 140 && offsetof(AssetFileHeader, fabric) == 148 &&
              offsetof(AssetFileHeader, coarse_slot_count) == 176 &&
              offsetof(AssetFileHeader, sewn_point_count) == kAssetHeaderSize_1_0 &&
              offsetof(AssetFileHeader, skin_constraint_count) == kAssetHeaderSize_1_1 &&
              offsetof(AssetFileHeader, render_vertex_count) == kAssetHeaderSize_1_2 && sizeof(AssetFileHeader) == 224);
static_assert(sizeof(AssetSectionEntry) == 32 && offsetof(AssetSectionEntry, offset) == 8 &&
              offsetof(AssetSectionEntry, size) == 16 && offsetof(AssetSectionEntry, element_count) == 24);
static_assert(kAssetChecksumStart == offsetof(AssetFileHeader, checksum) + sizeof(uint64_t));

const char* asset_section_name(uint32_t kind) {
    using K = AssetSectionKind;
    switch (K(kind)) {
#define WEFT_ASSET_NAME(name, ...) case K::name: return #name;
        WEFT_ASSET_SECTIONS(WEFT_ASSET_NAME)
#undef WEFT_ASSET_NAME
        case K::retired_20: return "retired_20";
        case K::retired_21: return "retired_21";
        case K::retired_22: return "retired_22";
    }
    return "unknown";
}

namespace {

bool is_known(uint32_t kind) { return kind >= 1 && kind <= kAssetSectionKindCount; }

// What the header implies for each known section kind (index = kind).
struct ExpectedSections {
    uint64_t count[kAssetSectionKindCount + 1] = {};
    uint32_t element_size[kAssetSectionKindCount + 1] = {};
};

ExpectedSections expected_sections(const AssetFileHeader& h) {
    ExpectedSections e;
    ClothAsset shape;  // only the field types matter here
    visit_asset_sections(h, shape, [&](AssetSectionKind kind, auto& field, uint64_t count) {
        e.count[uint32_t(kind)] = count;
        e.element_size[uint32_t(kind)] = sizeof(*field);
    });
    return e;
}

Result check_entry(const AssetSectionEntry& s, uint32_t index, uint64_t table_end, uint64_t file_size) {
    if (s.alignment < kAssetSectionAlignment || !std::has_single_bit(s.alignment) || s.offset % s.alignment != 0)
        return make_error(ErrorCode::corrupt_asset, "section %u (%s) at offset %llu is not aligned to %u >= 64",
                          index, asset_section_name(s.kind), (unsigned long long)s.offset, s.alignment);
    // 64-bit and in this order, so no sum can wrap: offset <= file_size, then size <= the rest.
    if (s.offset < table_end || s.offset > file_size || s.size > file_size - s.offset)
        return make_error(ErrorCode::corrupt_asset, "section %u (%s) lies outside the file's data", index,
                          asset_section_name(s.kind));
    if (s.element_size == 0 || uint64_t(s.element_count) * s.element_size != s.size)
        return make_error(ErrorCode::corrupt_asset, "section %u (%s): %u elements of %u bytes are not %llu bytes",
                          index, asset_section_name(s.kind), s.element_count, s.element_size,
                          (unsigned long long)s.size);
    return {};
}

bool overlap(const AssetSectionInfo& a, const AssetSectionEntry& b) {
    return a.size > 0 && b.size > 0 && a.offset < b.offset + b.size && b.offset < a.offset + a.size;
}

// Steps 1-4 of the file comment. Fills `info`, a scratch copy: the caller's is written only on success.
Result check_file(const void* bytes, size_t size, AssetFileInfo& info, AssetFileHeader& header) {
    if (bytes == nullptr) return make_error(ErrorCode::invalid_argument, "asset bytes are null");
    if (reinterpret_cast<uintptr_t>(bytes) % kAssetSectionAlignment != 0)
        return make_error(ErrorCode::invalid_argument,
                          "asset bytes must be 64-byte aligned (mmap the file or read it into aligned memory)");
    const uint8_t* file = static_cast<const uint8_t*>(bytes);
    if (size < 24)
        return make_error(ErrorCode::corrupt_asset, "%zu bytes are too few for an asset file", size);
    if (std::memcmp(file, kAssetMagic, sizeof(kAssetMagic)) != 0)
        return make_error(ErrorCode::corrupt_asset, "not a Weft asset file (no WEFTASET magic)");
    uint32_t marker;
    std::memcpy(&marker, file + offsetof(AssetFileHeader, endian_marker), sizeof(marker));
    if (marker == 0x04030201u)  // kAssetEndianMarker with its bytes reversed
        return make_error(ErrorCode::unsupported, "asset file is big-endian; this runtime reads little-endian files");
    if (marker != kAssetEndianMarker)
        return make_error(ErrorCode::corrupt_asset, "asset file has a bad endianness marker %08x", marker);
    uint16_t version[2];
    std::memcpy(version, file + offsetof(AssetFileHeader, version_major), sizeof(version));
    if (version[0] != kAssetVersionMajor)
        return make_error(ErrorCode::unsupported, "asset format version %u.%u is not supported by this runtime (%u.x)",
                          version[0], version[1], kAssetVersionMajor);

    // An older minor's header ends before the later fields (1.0: sewn seams, 1.1: skin constraints,
    // 1.2: the render mesh): they read as 0.
    const uint32_t least_header = version[1] == 0   ? kAssetHeaderSize_1_0
                                  : version[1] == 1 ? kAssetHeaderSize_1_1
                                  : version[1] == 2 ? kAssetHeaderSize_1_2
                                                    : uint32_t(sizeof(AssetFileHeader));
    if (size < least_header)
        return make_error(ErrorCode::corrupt_asset, "asset file of %zu bytes is shorter than its header", size);
    header = AssetFileHeader{};
    std::memcpy(&header, file, least_header);
    if (header.file_size != size)
        return make_error(ErrorCode::corrupt_asset, "asset file says %llu bytes, %zu given (truncated?)",
                          (unsigned long long)header.file_size, size);
    if (header.header_size < least_header || header.header_size % 8 != 0 || header.header_size > size)
        return make_error(ErrorCode::corrupt_asset, "bad header size %u", header.header_size);
    if (header.section_count > kMaxAssetSections)
        return make_error(ErrorCode::corrupt_asset, "%u sections (at most %u)", header.section_count,
                          kMaxAssetSections);
    const uint64_t table_end =
        uint64_t(header.header_size) + uint64_t(header.section_count) * sizeof(AssetSectionEntry);
    if (table_end > size) return make_error(ErrorCode::corrupt_asset, "section table runs past the end of the file");
    const uint64_t checksum = xxh64(file + kAssetChecksumStart, size - kAssetChecksumStart, 0);
    if (checksum != header.checksum)
        return make_error(ErrorCode::corrupt_asset, "checksum mismatch: file says %016llx, contents give %016llx",
                          (unsigned long long)header.checksum, (unsigned long long)checksum);
    if (header.has_uv > 1 || header.has_fabric > 1)
        return make_error(ErrorCode::corrupt_asset, "has_uv or has_fabric is neither 0 nor 1");

    const ExpectedSections expected = expected_sections(header);
    bool seen[kAssetSectionKindCount + 1] = {};  // known kind k was present
    for (uint32_t i = 0; i < header.section_count; ++i) {
        AssetSectionEntry s;
        std::memcpy(&s, file + header.header_size + uint64_t(i) * sizeof(AssetSectionEntry), sizeof(s));
        if (Result r = check_entry(s, i, table_end, size); !r.ok()) return r;
        for (uint32_t j = 0; j < i; ++j)
            if (overlap(info.sections[j], s))
                return make_error(ErrorCode::corrupt_asset, "sections %u (%s) and %u (%s) overlap", j,
                                  asset_section_name(info.sections[j].kind), i, asset_section_name(s.kind));
        info.sections[i] = {s.kind, s.element_size, s.offset, s.size, s.element_count, s.alignment};
        if (!is_known(s.kind)) continue;  // a newer minor's section: skipped
        const char* name = asset_section_name(s.kind);
        if (seen[s.kind]) return make_error(ErrorCode::corrupt_asset, "section %s appears twice", name);
        seen[s.kind] = true;
        if (s.element_size != expected.element_size[s.kind])
            return make_error(ErrorCode::corrupt_asset, "section %s has %u-byte elements, expected %u", name,
                              s.element_size, expected.element_size[s.kind]);
        if (expected.count[s.kind] == 0)  // the writer leaves empty arrays out: one form per asset
            return make_error(ErrorCode::corrupt_asset, "section %s is present, the header implies none", name);
        if (s.element_count != expected.count[s.kind])
            return make_error(ErrorCode::corrupt_asset, "section %s has %u elements, the header implies %llu", name,
                              s.element_count, (unsigned long long)expected.count[s.kind]);
    }
    for (uint32_t kind = 1; kind <= kAssetSectionKindCount; ++kind)
        if (expected.count[kind] > 0 && !seen[kind])
            return make_error(ErrorCode::corrupt_asset, "section %s is missing", asset_section_name(kind));

    info.version_major = header.version_major;
    info.version_minor = header.version_minor;
    info.file_size = header.file_size;
    info.checksum = header.checksum;
    info.header_size = header.header_size;
    info.counts = ClothAsset();
    pair_asset_scalars(header, info.counts, [](const auto& from, auto& to) { to = from; });
    info.has_uv = header.has_uv != 0;
    info.load_scratch_count = std::max(header.slot_count, header.coarse_slot_count);  // validation colours both
    info.section_count = header.section_count;
    return {};
}

}  // namespace

Result read_asset_header(const void* bytes, size_t size, AssetFileInfo* info) {
    if (info == nullptr) return make_error(ErrorCode::invalid_argument, "info is null");
    AssetFileInfo checked;
    AssetFileHeader header;
    if (Result r = check_file(bytes, size, checked, header); !r.ok()) return r;
    *info = checked;
    return {};
}

Result load_asset_in_place(const void* bytes, size_t size, uint32_t* scratch, uint32_t scratch_count,
                           ClothAsset* out) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    AssetFileInfo info;
    AssetFileHeader header;
    if (Result r = check_file(bytes, size, info, header); !r.ok()) return r;
    if (scratch == nullptr || scratch_count < info.load_scratch_count)
        return make_error(ErrorCode::memory_too_small, "loading needs %u uint32 of scratch, %u given",
                          info.load_scratch_count, scratch == nullptr ? 0 : scratch_count);

    // Every section passed check_file: inside the file, aligned (the file is 64-byte aligned, so
    // every section is too) and of the size its count needs.
    ClothAsset asset = info.counts;
    const uint8_t* file = static_cast<const uint8_t*>(bytes);
    for (uint32_t i = 0; i < info.section_count; ++i) {
        const AssetSectionInfo& s = info.sections[i];
        if (!is_known(s.kind)) continue;
        visit_asset_sections(header, asset, [&](AssetSectionKind kind, auto& field, uint64_t) {
            using Pointer = std::remove_reference_t<decltype(field)>;
            if (uint32_t(kind) == s.kind) field = reinterpret_cast<Pointer>(file + s.offset);
        });
    }
    if (Result r = validate_asset_with_scratch(asset, scratch, scratch_count); !r.ok()) return r;
    *out = asset;
    return {};
}

}  // namespace weft
