// Asset files (docs/asset-format.md): the runtime's XXH64 against libxxhash, the writer's
// determinism, the round trip of every field, a loaded asset stepping bit for bit like the cooked
// one, and the loader refusing broken files (truncated, flipped, huge counts, overlapping or
// misaligned sections, unaligned memory, other versions, big-endian) without touching its output.
#include "support/test_support.h"

#include <xxhash.h>

#include <cstddef>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <set>

#include "asset/xxh64.h"
#include "common/asset_writer.h"
#include "weft/asset_format.h"

using namespace weft;
using namespace weft::test;
using assets::AlignedBytes;
using assets::LoadedAsset;
using Bytes = std::vector<std::byte>;

namespace {

// A pinned grid with every kind of data: runs, indexed batches, tethers, wind runs, the coarse
// lattice (or, without the lattice, the general coarse form) and the garment data.
struct Source {
    scenes::GridMesh grid;
    scenes::GridGarment garment;
    CookedCloth cooked;
    Source(uint32_t n, bool lattice = true, const CookOptions& options = {}) {
        grid = scenes::make_grid(n, 1.0f, 1.0f, false, 1.0f);
        grid.masses[grid.index(0, 0)] = 0.0f;
        grid.masses[grid.index(0, n - 1)] = 0.0f;
        garment = scenes::make_grid_garment(grid);
        ClothMeshDesc desc = grid.desc();
        garment.apply(desc);
        if (!lattice) desc.lattice = nullptr;
        cooked = cook(desc, options);
    }
    const ClothAsset& asset() const { return cooked.asset(); }
};

Bytes write(const ClothAsset& asset) {
    Bytes file;
    const Result r = assets::write_asset(asset, &file);
    INFO(r.message);
    REQUIRE(r.ok());
    return file;
}

// The header's view of an asset's counts (what visit_asset_sections needs).
AssetFileHeader header_of(const ClothAsset& a) {
    AssetFileHeader h{};
    pair_asset_scalars(h, a, [](auto& to, const auto& from) { to = from; });
    h.has_uv = a.uv != nullptr;
    return h;
}

template <class T>
T read_at(const Bytes& file, size_t offset) {
    T value;
    std::memcpy(&value, file.data() + offset, sizeof(T));
    return value;
}
template <class T>
void write_at(Bytes& file, size_t offset, T value) {
    std::memcpy(file.data() + offset, &value, sizeof(T));
}

void fix_checksum(Bytes& file) {
    write_at(file, offsetof(AssetFileHeader, checksum),
             uint64_t(XXH64(file.data() + kAssetChecksumStart, file.size() - kAssetChecksumStart, 0)));
}

// The table starts at the file's header_size: 216 bytes in a 1.2 file (every asset without a render
// mesh), 224 in a 1.3 file.
size_t entry_offset(const Bytes& file, uint32_t i) {
    return read_at<uint32_t>(file, offsetof(AssetFileHeader, header_size)) + i * sizeof(AssetSectionEntry);
}
AssetSectionEntry entry(const Bytes& file, uint32_t i) { return read_at<AssetSectionEntry>(file, entry_offset(file, i)); }
void set_entry(Bytes& file, uint32_t i, const AssetSectionEntry& e) { write_at(file, entry_offset(file, i), e); }
uint32_t section_count(const Bytes& file) { return read_at<uint32_t>(file, offsetof(AssetFileHeader, section_count)); }

// The loader's output before a call, to check that a failed load left it as it was.
struct Output {
    ClothAsset asset;
    AlignedBytes bytes;  // what a loaded asset points into
    unsigned char before[sizeof(ClothAsset)];
    Output() {
        asset.particle_count = 777;  // anything a load would overwrite
        asset.start_x = reinterpret_cast<const float*>(this);
        std::memcpy(before, &asset, sizeof(asset));
    }
    bool untouched() const { return std::memcmp(before, &asset, sizeof(asset)) == 0; }
};

// Loads `file` from an aligned copy (plus `misalign` bytes) that `out` keeps.
Result load(const Bytes& file, Output& out, size_t misalign = 0) {
    std::vector<uint32_t> scratch(1 << 16);
    Bytes padded(misalign, std::byte{0});
    padded.insert(padded.end(), file.begin(), file.end());
    out.bytes = AlignedBytes(padded.data(), padded.size());
    return load_asset_in_place(out.bytes.data() + misalign, file.size(), scratch.data(), uint32_t(scratch.size()),
                               &out.asset);
}

// Loads a file that must be refused with `code`; the output must be untouched.
std::string expect_refused(const Bytes& file, ErrorCode code, size_t misalign = 0) {
    Output out;
    const Result r = load(file, out, misalign);
    INFO(r.message);
    CHECK(r.code == code);
    CHECK(r.message[0] != '\0');
    CHECK(out.untouched());
    return r.message;
}

LoadedAsset load_copy(const Bytes& file) {
    LoadedAsset loaded;
    const Result r = assets::load_asset_copy(file.data(), file.size(), &loaded);
    INFO(r.message);
    REQUIRE(r.ok());
    return loaded;
}

// Every section's bytes and every scalar of two assets are equal.
void check_same_asset(const ClothAsset& a, const ClothAsset& b) {
    AssetFileHeader ha = header_of(a), hb = header_of(b);
    CHECK(std::memcmp(&ha, &hb, sizeof(ha)) == 0);  // every scalar, the fabric and has_uv
    struct Array {
        const void* data;
        uint64_t bytes;
    };
    std::vector<Array> arrays;
    visit_asset_sections(ha, a, [&](AssetSectionKind, const auto& field, uint64_t count) {
        arrays.push_back({field, count * sizeof(*field)});
    });
    size_t i = 0;
    visit_asset_sections(hb, b, [&](AssetSectionKind kind, const auto& field, uint64_t count) {
        const Array& other = arrays[i++];
        CAPTURE(asset_section_name(uint32_t(kind)));
        REQUIRE(other.bytes == count * sizeof(*field));
        if (count > 0) CHECK(std::memcmp(other.data, field, other.bytes) == 0);
    });
}

// Steps two worlds, one holding each asset, with wind and gravity; positions bit-identical.
void check_steps_alike(const ClothAsset& cooked, const ClothAsset& loaded, uint32_t steps) {
    std::vector<Vec3> positions[2];
    const ClothAsset* assets[2] = {&cooked, &loaded};
    for (int k = 0; k < 2; ++k) {
        WorldDesc desc = world_for({assets[k]});
        desc.wind = true;
        OwnedWorld w;
        REQUIRE(make_world(desc, &w).ok());
        REQUIRE(set_wind(w.world, {4.0f, 0.0f, 1.0f}).ok());
        ClothDesc cd;
        cd.asset = assets[k];
        ClothId id;
        REQUIRE(add_cloth(w.world, cd, &id).ok());
        for (uint32_t i = 0; i < steps; ++i) REQUIRE(step(w.world, scenes::kSeedTimeStep_s).ok());
        positions[k] = read_all(w.world, id, assets[k]->particle_count);
    }
    CHECK(all_finite(positions[0]));
    CHECK(same_bits(positions[0], positions[1]));
}

// One element of one section overwritten: the file must be refused, naming the fault in `words`.
struct Corruption {
    const char* name;
    AssetSectionKind kind;
    uint32_t element;
    std::function<void(Bytes&, size_t)> write;  // at the element's offset
    const char* words;
};

template <size_t N>
void expect_each_refused(const Bytes& file, const Corruption (&cases)[N]) {
    for (const Corruption& c : cases) {
        CAPTURE(c.name);
        Bytes broken = file;
        bool found = false;
        for (uint32_t i = 0; i < section_count(broken); ++i) {
            const AssetSectionEntry e = entry(broken, i);
            if (e.kind != uint32_t(c.kind)) continue;
            c.write(broken, e.offset + size_t(c.element) * e.element_size);
            found = true;
        }
        REQUIRE(found);
        fix_checksum(broken);
        const std::string message = expect_refused(broken, ErrorCode::corrupt_asset);
        CHECK(message.find(c.words) != std::string::npos);
    }
}

}  // namespace

TEST_CASE("xxh64: bit-equal to libxxhash on every length 0..300, any alignment, and big buffers") {
    std::mt19937_64 random(12345);
    std::vector<uint8_t> buffer(300 + 8);
    for (size_t length = 0; length <= 300; ++length) {
        for (uint32_t trial = 0; trial < 4; ++trial) {
            for (uint8_t& b : buffer) b = uint8_t(random());
            const size_t start = trial;  // unaligned starts
            const uint64_t seed = trial == 0 ? 0 : random();
            CAPTURE(length);
            REQUIRE(xxh64(buffer.data() + start, length, seed) == XXH64(buffer.data() + start, length, seed));
        }
    }
    for (size_t length : {size_t(1) << 16, (size_t(1) << 20) + 13, size_t(3000001)}) {
        std::vector<uint8_t> big(length);
        for (uint8_t& b : big) b = uint8_t(random());
        CHECK(xxh64(big.data(), big.size(), 0) == XXH64(big.data(), big.size(), 0));
    }
    CHECK(xxh64(nullptr, 0, 0) == XXH64(nullptr, 0, 0));
}

TEST_CASE("write_asset: the same mesh cooked twice gives the same bytes") {
    const Source a(12), b(12);
    const Bytes fa = write(a.asset()), fb = write(b.asset());
    CHECK(fa == fb);
    // The padding is zero: rewriting what was loaded gives the file back, byte for byte.
    const LoadedAsset loaded = load_copy(fa);
    CHECK(write(loaded.asset) == fa);
}

TEST_CASE("round trip: every field of the asset survives write and load") {
    CookOptions wide;
    wide.simd_width = 16;
    CookOptions flat;
    flat.coarse_spacing_m = 0.0f;  // no coarse level
    flat.tethers_per_particle = 0;
    struct Variant {
        const char* name;
        Source source;
    };
    Variant variants[] = {{"lattice", Source(14)},
                          {"no lattice (general coarse form)", Source(14, false)},
                          {"16 lanes", Source(14, true, wide)},
                          {"no coarse level, no tethers", Source(14, true, flat)}};
    for (const Variant& v : variants) {
        CAPTURE(v.name);
        const ClothAsset& a = v.source.asset();
        const LoadedAsset loaded = load_copy(write(a));
        check_same_asset(a, loaded.asset);
        CHECK(loaded.asset.uv != nullptr);
        CHECK(loaded.asset.seam_point_count > 0);
        CHECK(loaded.asset.panel_count == 2);
        CHECK(loaded.asset.has_fabric);
        // In place: the loaded arrays point into the file's bytes.
        const std::byte* begin = loaded.bytes.data();
        const auto* x = reinterpret_cast<const std::byte*>(loaded.asset.start_x);
        CHECK((x >= begin && x < begin + loaded.bytes.size()));
    }
    // And an asset with no garment data at all.
    const CookedCloth plain = cook(scenes::make_grid(10, 1.0f, 1.0f, false, 1.0f).desc());
    const LoadedAsset loaded = load_copy(write(plain.asset()));
    check_same_asset(plain.asset(), loaded.asset);
    CHECK(loaded.asset.uv == nullptr);
    CHECK(loaded.asset.panel == nullptr);
    CHECK(loaded.asset.seam_first == nullptr);
    CHECK(!loaded.asset.has_fabric);
}

// WEFT_ASSET_SECTIONS against the struct: an array added to ClothAsset (its skin or render mesh
// included) but not to the table, or a field listed twice, fails here.
TEST_CASE("the table of sections names every array of ClothAsset once, the header every scalar") {
    ClothAsset a;
    std::memset(static_cast<void*>(&a), 0, sizeof(a));
    AssetFileHeader h{};
    std::set<const void*> fields;
    uint32_t rows = 0;
    visit_asset_sections(h, a, [&](AssetSectionKind, auto& field, uint64_t) {
        fields.insert(&field);
        ++rows;
        std::memset(static_cast<void*>(&field), 0xFF, sizeof(field));
    });
    CHECK(fields.size() == rows);
    pair_asset_scalars(h, a, [](auto&, auto& scalar) { std::memset(static_cast<void*>(&scalar), 0xFF, sizeof(scalar)); });
    // Every 8-byte word of the struct holds a pointer or scalars: none may be left all zero.
    static_assert(sizeof(ClothAsset) % 8 == 0);
    for (size_t offset = 0; offset < sizeof(ClothAsset); offset += 8) {
        uint64_t word;
        std::memcpy(&word, reinterpret_cast<const std::byte*>(&a) + offset, sizeof(word));
        CAPTURE(offset);
        CHECK(word != 0);
    }
}

TEST_CASE("a loaded asset steps bit-identically to the cooked one (100 steps)") {
    const Source pinned(20);  // tethers, runs, wind
    check_steps_alike(pinned.asset(), load_copy(write(pinned.asset())).asset, 100);
    // Unpinned: the automatic policy runs substeps and the coarse level.
    const CookedCloth loose = cook(scenes::make_grid(20, 1.0f, 1.0f, false, 1.0f).desc());
    check_steps_alike(loose.asset(), load_copy(write(loose.asset())).asset, 100);
}

TEST_CASE("read_asset_header reports the version, counts, checksum and sections") {
    const Source s(8);
    const Bytes file = write(s.asset());
    const AlignedBytes bytes(file.data(), file.size());
    AssetFileInfo info;
    REQUIRE(read_asset_header(bytes.data(), bytes.size(), &info).ok());
    CHECK(info.version_major == kAssetVersionMajor);
    CHECK(info.version_minor == 2);  // no render mesh: written as a 1.2 file
    CHECK(info.file_size == file.size());
    CHECK(info.checksum == XXH64(file.data() + kAssetChecksumStart, file.size() - kAssetChecksumStart, 0));
    CHECK(info.counts.simd_width == kSimdWidth);
    CHECK(info.counts.particle_count == 64);
    CHECK(info.counts.slot_count == s.asset().slot_count);
    CHECK(info.counts.total_constraints() == s.asset().total_constraints());
    CHECK(info.counts.start_x == nullptr);
    CHECK(info.has_uv);
    CHECK(info.load_scratch_count == s.asset().slot_count);
    CHECK(info.section_count == section_count(file));
    for (uint32_t i = 0; i < info.section_count; ++i) {
        CHECK(info.sections[i].offset % kAssetSectionAlignment == 0);
        CHECK(std::string(asset_section_name(info.sections[i].kind)) != "unknown");
    }
    // The scratch is what loading needs, no less.
    std::vector<uint32_t> scratch(info.load_scratch_count);
    ClothAsset asset;
    CHECK(load_asset_in_place(bytes.data(), bytes.size(), scratch.data(), info.load_scratch_count - 1, &asset).code ==
          ErrorCode::memory_too_small);
    CHECK(load_asset_in_place(bytes.data(), bytes.size(), nullptr, 0, &asset).code == ErrorCode::memory_too_small);
    CHECK(load_asset_in_place(bytes.data(), bytes.size(), scratch.data(), info.load_scratch_count, &asset).ok());
}

TEST_CASE("broken files: every truncation is refused") {
    const Source s(4);
    const Bytes file = write(s.asset());
    for (size_t length = 0; length < file.size(); ++length) {
        CAPTURE(length);
        expect_refused(Bytes(file.begin(), file.begin() + length), ErrorCode::corrupt_asset);
    }
}

TEST_CASE("broken files: every byte flipped is refused, with the checksum fixed it loads or is refused") {
    const Source s(4);
    const Bytes file = write(s.asset());
    uint32_t loaded = 0, refused = 0;
    for (size_t i = 0; i < file.size(); ++i) {
        CAPTURE(i);
        Bytes flipped = file;
        flipped[i] ^= std::byte{0xFF};
        Output out;
        const Result r = load(flipped, out);
        REQUIRE(!r.ok());  // nothing escapes: the checksum covers every byte past the magic
        REQUIRE(out.untouched());
        if (i >= kAssetChecksumStart) fix_checksum(flipped);
        Output fixed;
        const Result again = load(flipped, fixed);
        if (again.ok()) {
            CHECK(validate_asset(fixed.asset).ok());
            ++loaded;
        } else {
            CHECK(fixed.untouched());
            ++refused;
        }
    }
    MESSAGE(loaded, " flips loaded once the checksum was fixed (padding, the minor version, floats still in range), ",
            refused, " refused");
    CHECK(refused > loaded);
}

TEST_CASE("broken files: huge counts") {
    const Source s(4);
    const Bytes file = write(s.asset());
    for (size_t field : {offsetof(AssetFileHeader, particle_count), offsetof(AssetFileHeader, slot_count),
                         offsetof(AssetFileHeader, triangle_count), offsetof(AssetFileHeader, lane_count),
                         offsetof(AssetFileHeader, seam_point_count), offsetof(AssetFileHeader, coarse_node_count)}) {
        for (uint32_t value : {0xFFFFFFFFu, 0x80000000u, 0x55555556u}) {  // 3 * 0x55555556 wraps a uint32
            CAPTURE(field);
            CAPTURE(value);
            Bytes broken = file;
            write_at(broken, field, value);
            fix_checksum(broken);
            expect_refused(broken, ErrorCode::corrupt_asset);
        }
    }
    Bytes broken = file;
    write_at(broken, offsetof(AssetFileHeader, section_count), 0xFFFFFFFFu);
    fix_checksum(broken);
    expect_refused(broken, ErrorCode::corrupt_asset);
}

TEST_CASE("broken files: overlapping, misaligned, out-of-range, duplicate and missing sections") {
    const Source s(4);
    const Bytes file = write(s.asset());
    struct Case {
        uint32_t section;  // the table entry changed
        std::function<void(AssetSectionEntry&)> change;
        const char* words;  // in the message
    };
    const Case cases[] = {
        {1, [&](AssetSectionEntry& e) { e.offset = entry(file, 0).offset; }, "overlap"},
        {2, [](AssetSectionEntry& e) { e.offset += 4; }, "aligned"},
        {2, [](AssetSectionEntry& e) { e.alignment = 32; }, "aligned"},
        {3, [](AssetSectionEntry& e) { e.offset = 0xFFFFFFFFFFFFFFC0ull; }, "outside"},  // offset + size wraps
        {3, [](AssetSectionEntry& e) { e.offset = 0; }, "outside"},                     // over the header
        {3, [](AssetSectionEntry& e) { e.size += 4; }, "bytes"},
        {3, [&](AssetSectionEntry& e) { e.kind = entry(file, 2).kind; }, "twice"},
        {3, [](AssetSectionEntry& e) { e.kind = 999; }, "missing"},  // unknown now: its kind is missing
        {0, [](AssetSectionEntry& e) { e.element_count -= 1, e.size -= e.element_size; }, "elements"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.words);
        Bytes broken = file;
        AssetSectionEntry e = entry(broken, c.section);
        c.change(e);
        set_entry(broken, c.section, e);
        fix_checksum(broken);
        const std::string message = expect_refused(broken, ErrorCode::corrupt_asset);
        CHECK(message.find(c.words) != std::string::npos);
    }
}

TEST_CASE("broken files: a file that is sound but whose asset is not fails validation") {
    const Source s(6);
    Bytes file = write(s.asset());
    for (uint32_t i = 0; i < section_count(file); ++i) {
        const AssetSectionEntry e = entry(file, i);
        if (e.kind == uint32_t(AssetSectionKind::index_a)) write_at(file, e.offset, uint32_t(1) << 30);
    }
    fix_checksum(file);
    expect_refused(file, ErrorCode::corrupt_asset);
}

TEST_CASE("broken files: memory that is not 64-byte aligned") {
    const Source s(4);
    const Bytes file = write(s.asset());
    for (size_t misalign : {1, 4, 8, 32}) {
        const std::string message = expect_refused(file, ErrorCode::invalid_argument, misalign);
        CHECK(message.find("64-byte aligned") != std::string::npos);
    }
    Output out;
    uint32_t scratch[1];
    CHECK(load_asset_in_place(nullptr, 0, scratch, 1, &out.asset).code == ErrorCode::invalid_argument);
    CHECK(out.untouched());
}

TEST_CASE("versions: another major is refused by name, a newer minor loads and skips what it does not know") {
    const Source s(4);
    const Bytes file = write(s.asset());
    SUBCASE("major 3") {
        Bytes other = file;
        write_at(other, offsetof(AssetFileHeader, version_major), uint16_t(3));
        fix_checksum(other);
        CHECK(expect_refused(other, ErrorCode::unsupported) ==
              "asset format version 3.2 is not supported by this runtime (1.x)");  // no render mesh: a 1.2 file
    }
    SUBCASE("major 0") {
        Bytes other = file;
        write_at(other, offsetof(AssetFileHeader, version_major), uint16_t(0));
        write_at(other, offsetof(AssetFileHeader, version_minor), uint16_t(9));
        fix_checksum(other);
        CHECK(expect_refused(other, ErrorCode::unsupported) ==
              "asset format version 0.9 is not supported by this runtime (1.x)");
    }
    SUBCASE("a newer minor with a longer header and an unknown section") {
        // The next minor as a future writer might make it: 1.3's 8 header bytes (no render mesh: 0),
        // 16 more, a section of kind 1000. Every section moves 128 bytes on (room for the longer
        // header and one more table entry).
        const uint32_t extra_header = 24, shift = 128, sections = section_count(file);
        const uint64_t first = entry(file, 0).offset;
        Bytes newer(file.size() + shift, std::byte{0});
        std::memcpy(newer.data(), file.data(), kAssetHeaderSize_1_2);
        for (uint32_t i = 8; i < extra_header; ++i) newer[kAssetHeaderSize_1_2 + i] = std::byte(0xA0 + i);
        const uint32_t header_size = kAssetHeaderSize_1_2 + extra_header;
        for (uint32_t i = 0; i < sections; ++i) {
            AssetSectionEntry e = entry(file, i);
            e.offset += shift;
            write_at(newer, header_size + i * sizeof(AssetSectionEntry), e);
        }
        std::memcpy(newer.data() + first + shift, file.data() + first, file.size() - first);
        AssetSectionEntry unknown{};
        unknown.kind = 1000;
        unknown.element_size = 4;
        unknown.element_count = 16;
        unknown.size = 64;
        unknown.alignment = 64;
        unknown.offset = (newer.size() + 63) / 64 * 64;
        newer.resize(unknown.offset + unknown.size, std::byte{0x5A});
        write_at(newer, header_size + sections * sizeof(AssetSectionEntry), unknown);
        write_at(newer, offsetof(AssetFileHeader, version_minor), uint16_t(kAssetVersionMinor + 1));
        write_at(newer, offsetof(AssetFileHeader, header_size), header_size);
        write_at(newer, offsetof(AssetFileHeader, section_count), sections + 1);
        write_at(newer, offsetof(AssetFileHeader, file_size), uint64_t(newer.size()));
        fix_checksum(newer);
        const LoadedAsset loaded = load_copy(newer);
        check_same_asset(s.asset(), loaded.asset);
        AssetFileInfo info;
        REQUIRE(read_asset_header(loaded.bytes.data(), loaded.bytes.size(), &info).ok());
        CHECK(info.version_minor == kAssetVersionMinor + 1);
        CHECK(info.sections[sections].kind == 1000);
        CHECK(std::string(asset_section_name(1000)) == "unknown");
    }
    SUBCASE("a 1.0 file (192-byte header) and a 1.1 file (208 bytes, no skin constraints) still load") {
        // An older minor ended its header earlier: the table moves up, the sections stay. Its later
        // counts read as 0; a file claiming the next minor with that short a header is refused.
        struct Older {
            uint16_t minor;
            uint32_t header_size;
        };
        for (const Older o : {Older{0, kAssetHeaderSize_1_0}, Older{1, kAssetHeaderSize_1_1}}) {
            CAPTURE(o.minor);
            Bytes older = file;
            const uint32_t sections = section_count(file);
            std::memmove(older.data() + o.header_size, file.data() + kAssetHeaderSize_1_2,
                         sections * sizeof(AssetSectionEntry));
            std::memset(older.data() + o.header_size + sections * sizeof(AssetSectionEntry), 0,
                        kAssetHeaderSize_1_2 - o.header_size);
            write_at(older, offsetof(AssetFileHeader, version_minor), o.minor);
            write_at(older, offsetof(AssetFileHeader, header_size), o.header_size);
            fix_checksum(older);
            const LoadedAsset loaded = load_copy(older);
            check_same_asset(s.asset(), loaded.asset);
            CHECK(loaded.asset.skin.count == 0);  // 1.0 and 1.1: no skin constraints
            if (o.minor == 0) CHECK(loaded.asset.sewn_point_count == 0);
            if (o.minor == 0) CHECK(loaded.asset.attachment_count == 0);
            write_at(older, offsetof(AssetFileHeader, version_minor), uint16_t(o.minor + 1));
            fix_checksum(older);
            CHECK(expect_refused(older, ErrorCode::corrupt_asset) == "bad header size " + std::to_string(o.header_size));
        }
    }
}

// Format 1.2's skin constraints on a grid's first row of free particles (as the fuzz corpus has them).
CookedCloth skinned_grid(uint32_t n) {
    scenes::GridMesh grid = scenes::make_grid(n, 1.0f, 1.0f, false, 1.0f);
    grid.masses[grid.index(0, 0)] = 0.0f;
    grid.masses[grid.index(0, n - 1)] = 0.0f;
    ClothMeshDesc desc = grid.desc();
    const uint32_t particle[2] = {grid.index(0, 1), grid.index(0, 2)}, triangle[2] = {2, 3};
    const float weight[6] = {0.5f, 0.5f, 0, 0.2f, 0.3f, 0.5f}, rest_offset[2] = {0.01f, -0.002f};
    const float max_distance[2] = {0.03f, kSkinNoMaxDistance_m}, backstop[2] = {-0.0015f, 0.0f};
    desc.skin = {2, particle, triangle, weight, rest_offset, max_distance, backstop};
    return cook(desc);
}

TEST_CASE("skin constraints: their sections round-trip, and a corrupt one is refused by name, nothing lost") {
    const CookedCloth cooked = skinned_grid(6);
    const Bytes file = write(cooked.asset());
    const LoadedAsset loaded = load_copy(file);
    check_same_asset(cooked.asset(), loaded.asset);
    REQUIRE(loaded.asset.skin.count == 2);
    CHECK(loaded.asset.skin.max_distance_m[1] == kSkinNoMaxDistance_m);
    // A cooked asset without them writes no skin section.
    const Source plain(6);
    CHECK(header_of(plain.asset()).skin_constraint_count == 0);

    using K = AssetSectionKind;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const ClothAsset& a = cooked.asset();
    uint32_t pinned = 0;  // a pinned corner
    while (a.inverse_mass[a.slot_of_particle[pinned]] != 0.0f) ++pinned;
    const Corruption cases[] = {
        {"particle past the cloth's", K::skin_particle, 0, [](Bytes& f, size_t at) { write_at(f, at, uint32_t(36)); },
         "names particle 36 of 36"},
        {"particle bound twice", K::skin_particle, 1,
         [&](Bytes& f, size_t at) { write_at(f, at, cooked.asset().skin.particle[0]); }, "two skin constraints"},
        {"pinned particle", K::skin_particle, 0, [&](Bytes& f, size_t at) { write_at(f, at, pinned); }, "is pinned"},
        {"weight not finite", K::skin_weight, 1, [&](Bytes& f, size_t at) { write_at(f, at, nan); }, "weights"},
        {"rest offset not finite", K::skin_rest_offset, 0, [&](Bytes& f, size_t at) { write_at(f, at, nan); }, "not finite"},
        {"negative max distance", K::skin_max_distance, 1, [](Bytes& f, size_t at) { write_at(f, at, -0.01f); },
         "max distance -0.01 m < 0"},
        {"backstop not finite", K::skin_backstop, 0,
         [](Bytes& f, size_t at) { write_at(f, at, std::numeric_limits<float>::infinity()); }, "not finite"},
    };
    expect_each_refused(file, cases);
    // The header's count without the sections, and a section count that disagrees with it.
    Bytes counted = write(plain.asset());
    write_at(counted, offsetof(AssetFileHeader, skin_constraint_count), uint32_t(2));
    fix_checksum(counted);
    CHECK(expect_refused(counted, ErrorCode::corrupt_asset) == "section skin_particle is missing");
    Bytes more = file;
    write_at(more, offsetof(AssetFileHeader, skin_constraint_count), uint32_t(3));
    fix_checksum(more);
    CHECK(expect_refused(more, ErrorCode::corrupt_asset).find("the header implies") != std::string::npos);
}

// Format 1.3's render mesh: a 6 x 6 grid's triangles subdivided once, bound back to the grid.
CookedCloth render_grid(uint32_t n) {
    CookedCloth cooked = cook(scenes::make_grid(n, 1.0f, 1.0f, false, 1.0f).desc());
    RenderMeshSource fine;
    REQUIRE(subdivide_cloth_mesh(cooked.asset(), 1, &fine).ok());
    REQUIRE(bind_render_mesh(fine.desc(), &cooked).ok());
    return cooked;
}

TEST_CASE("render mesh: its sections round-trip in a 1.3 file, an asset without one stays a 1.2 file, a corrupt one is refused by name") {
    const CookedCloth cooked = render_grid(6);
    const Bytes file = write(cooked.asset());
    CHECK(read_at<uint16_t>(file, offsetof(AssetFileHeader, version_minor)) == 3);
    CHECK(read_at<uint32_t>(file, offsetof(AssetFileHeader, header_size)) == sizeof(AssetFileHeader));
    const LoadedAsset loaded = load_copy(file);
    check_same_asset(cooked.asset(), loaded.asset);
    REQUIRE(loaded.asset.render.vertex_count == cooked.asset().render.vertex_count);
    CHECK(loaded.asset.render.triangle_count == 4 * cooked.asset().triangle_count);
    // Without a render mesh: the 1.2 header, as every file written before 1.3.
    const Source plain(6);
    const Bytes plain_file = write(plain.asset());
    CHECK(read_at<uint16_t>(plain_file, offsetof(AssetFileHeader, version_minor)) == 2);
    CHECK(read_at<uint32_t>(plain_file, offsetof(AssetFileHeader, header_size)) == kAssetHeaderSize_1_2);
    Bytes claims = plain_file;  // a 1.3 file must carry the whole header
    write_at(claims, offsetof(AssetFileHeader, version_minor), uint16_t(3));
    fix_checksum(claims);
    CHECK(expect_refused(claims, ErrorCode::corrupt_asset) == "bad header size 216");

    using K = AssetSectionKind;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const uint32_t triangles = cooked.asset().triangle_count, vertices = cooked.asset().render.vertex_count;
    const Corruption cases[] = {
        {"cloth triangle past the cloth's", K::render_cloth_triangle, 3, [&](Bytes& f, size_t at) { write_at(f, at, triangles); },
         "is bound to triangle"},
        {"weight not finite", K::render_weight_1, 2, [&](Bytes& f, size_t at) { write_at(f, at, nan); }, "not finite"},
        {"weight far outside", K::render_weight_2, 2, [&](Bytes& f, size_t at) { write_at(f, at, 7.0f); }, "out of range"},
        {"offset not finite", K::render_offset, 0,
         [&](Bytes& f, size_t at) { write_at(f, at, std::numeric_limits<float>::infinity()); }, "not finite"},
        {"render triangle past the vertices", K::render_triangles, 5, [&](Bytes& f, size_t at) { write_at(f, at, vertices); },
         "names vertex"},
        {"uv not finite", K::render_uv, 1, [&](Bytes& f, size_t at) { write_at(f, at, nan); }, "not finite"},
    };
    expect_each_refused(file, cases);
    Bytes more = file;
    write_at(more, offsetof(AssetFileHeader, render_vertex_count), vertices + 1);
    fix_checksum(more);
    CHECK(expect_refused(more, ErrorCode::corrupt_asset).find("the header implies") != std::string::npos);
    Bytes missing = file;
    write_at(missing, offsetof(AssetFileHeader, render_triangle_count), uint32_t(0));
    fix_checksum(missing);
    CHECK(expect_refused(missing, ErrorCode::corrupt_asset) == "section render_triangles is present, the header implies none");
}

TEST_CASE("big-endian files are refused with a message") {
    const Source s(4);
    Bytes file = write(s.asset());
    const uint8_t big[4] = {0x01, 0x02, 0x03, 0x04};
    std::memcpy(file.data() + offsetof(AssetFileHeader, endian_marker), big, 4);
    fix_checksum(file);
    const std::string message = expect_refused(file, ErrorCode::unsupported);
    CHECK(message.find("big-endian") != std::string::npos);
}

TEST_CASE("not an asset file at all") {
    Bytes text(400, std::byte{'x'});
    CHECK(expect_refused(text, ErrorCode::corrupt_asset).find("magic") != std::string::npos);
}
