// The layout of a baked asset file (docs/asset-format.md): magic, versions, the fixed header, the
// section table, and the one table of the sections (WEFT_ASSET_SECTIONS), ClothAsset's arrays.
// For writers (lib/common/asset_writer.h), the loader (runtime/src/asset/load.cpp) and tools that
// inspect files; a game loads files through weft/asset_file.h alone.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "weft/asset_file.h"

namespace weft {

// ---------------------------------------------------------------------------------------------
// The format. All integers and floats little-endian; offsets from the start of the file.

inline constexpr char kAssetMagic[8] = {'W', 'E', 'F', 'T', 'A', 'S', 'E', 'T'};
inline constexpr uint16_t kAssetVersionMajor = 1;  // a different major is refused
inline constexpr uint16_t kAssetVersionMinor = 3;  // a newer minor loads (unknown sections skipped)
// 1.1 appended sewn_point_count and sewn_uv_count to the header: a 1.0 file's is this long (read as 0).
inline constexpr uint32_t kAssetHeaderSize_1_0 = 192;
// 1.2 appended skin_constraint_count: a 1.1 file's header is this long (read as 0).
inline constexpr uint32_t kAssetHeaderSize_1_1 = 208;
// 1.3 appended the render mesh's counts: a 1.2 file's header is this long (read as 0). The writer
// still writes a 1.2 file (this header) for an asset without a render mesh: the same bytes as before.
inline constexpr uint32_t kAssetHeaderSize_1_2 = 216;
// Written as a little-endian uint32: the bytes 04 03 02 01. A big-endian writer gives 01 02 03 04.
inline constexpr uint32_t kAssetEndianMarker = 0x01020304u;
// Every section starts at a multiple of this (a cache line; also enough for any SIMD load).
inline constexpr uint32_t kAssetSectionAlignment = 64;
// The checksum (XXH64, seed 0) covers bytes [kAssetChecksumStart, file_size): everything after it.
inline constexpr uint32_t kAssetChecksumStart = 16;

// The fixed header at offset 0. The first 24 bytes (magic, checksum, version, endianness) keep
// their place in every version; a newer minor may append fields (header_size grows, the loader
// skips them) and section kinds (skipped too).
struct AssetFileHeader {
    char magic[8];
    uint64_t checksum;
    uint16_t version_major;
    uint16_t version_minor;
    uint32_t endian_marker;
    uint64_t file_size;        // the whole file, bytes
    uint32_t header_size;      // bytes; the section table follows at this offset
    uint32_t section_count;    // entries in the section table
    // ClothAsset's scalar fields (cloth_asset.h documents each).
    uint32_t simd_width;
    uint32_t particle_count;
    uint32_t slot_count;
    uint32_t lane_count;
    uint32_t batch_count;
    uint32_t colour_count;
    uint32_t constraint_count[kConstraintKindCount];
    uint32_t constraints_on_runs;
    uint32_t tether_lane_count;
    uint32_t tether_batch_count;
    uint32_t tethered_particles;
    uint32_t triangle_count;
    uint32_t wind_run_count;
    uint32_t wind_lane_count;
    uint32_t wind_run_triangles;
    uint32_t coarse_node_count;
    uint32_t coarse_constraint_count;
    uint32_t coarse_lattice_cols;
    uint32_t lattice_plane_rows;
    uint32_t lattice_plane_cols;
    uint32_t seam_point_count;
    uint32_t seam_source_count;
    uint32_t panel_count;
    uint32_t has_uv;      // 0 or 1
    uint32_t has_fabric;  // 0 or 1
    Fabric fabric;        // 7 floats
    // The coarse level's node slots and constraint lanes (ClothAsset).
    uint32_t coarse_slot_count;
    uint32_t coarse_lane_count;
    uint32_t coarse_batch_count;
    uint32_t coarse_colour_count;
    // 1.1: sewn seams (ClothAsset::sewn_*).
    uint32_t sewn_point_count;
    uint32_t sewn_uv_count;
    uint32_t attachment_count;  // body attachments (ClothAsset::attached_*)
    uint32_t tether_anchor_lane_count;  // per-lane tether anchors (0 in files written before them)
    // 1.2: skin constraints (ClothAsset::skin).
    uint32_t skin_constraint_count;
    uint32_t reserved_1_2;  // 0: keeps the header a multiple of 8 bytes
    // 1.3: the render mesh (ClothAsset::render).
    uint32_t render_vertex_count;
    uint32_t render_triangle_count;
};

// One entry of the section table (header_size + i * 32).
struct AssetSectionEntry {
    uint32_t kind;           // AssetSectionKind; unknown kinds are skipped
    uint32_t element_size;   // bytes per element
    uint64_t offset;         // from the start of the file, a multiple of `alignment`
    uint64_t size;           // bytes: element_count * element_size
    uint32_t element_count;
    uint32_t alignment;      // a power of two >= kAssetSectionAlignment
};

// The table of the file's sections: one row per array of ClothAsset, in the order the writer lays
// them out. It drives AssetSectionKind, asset_section_name, visit_asset_sections and
// CookedCloth::refresh_asset; tests/test_asset_file.cpp checks it against ClothAsset. Columns: kind;
// its number in the file (never reuse one; 51-58 came in 1.1, 59-64 in 1.2, 65-70 in 1.3); element
// type; ClothAsset field; CookedCloth vector; element count from the header `h` (the named counts
// are visit_asset_sections'), the section written when it is above 0.
#define WEFT_ASSET_SECTIONS(X) \
    X(slot_of_particle,      1,  uint32_t,        slot_of_particle,      slot_of_particle,      h.particle_count) \
    X(particle_of_slot,      2,  uint32_t,        particle_of_slot,      particle_of_slot,      h.slot_count) \
    X(start_x,               3,  float,           start_x,               start_x,               h.slot_count) \
    X(start_y,               4,  float,           start_y,               start_y,               h.slot_count) \
    X(start_z,               5,  float,           start_z,               start_z,               h.slot_count) \
    X(inverse_mass,          6,  float,           inverse_mass,          inverse_mass,          h.slot_count) \
    X(rest_length,           7,  float,           rest_length,           rest_length,           h.lane_count) \
    X(lane_weight,           8,  float,           lane_weight,           lane_weight,           h.lane_count) \
    X(index_a,               9,  uint32_t,        index_a,               index_a,               h.lane_count) \
    X(index_b,               10, uint32_t,        index_b,               index_b,               h.lane_count) \
    X(batches,               11, ConstraintBatch, batches,               batches,               h.batch_count) \
    X(tether_rest_0,         12, float,           tether_rest[0],        tether_rest[0],        h.tether_lane_count) \
    X(tether_rest_1,         13, float,           tether_rest[1],        tether_rest[1],        h.tether_lane_count) \
    X(tether_batches,        14, TetherBatch,     tether_batches,        tether_batches,        h.tether_batch_count) \
    X(triangles,             15, uint32_t,        triangles,             triangles,             3 * uint64_t(h.triangle_count)) \
    X(wind_runs,             16, TriangleRun,     wind_runs,             wind_runs,             h.wind_run_count) \
    X(wind_lane_weight,      17, float,           wind_lane_weight,      wind_lane_weight,      h.wind_lane_count) \
    X(wind_rest_area,        50, float,           wind_rest_area,        wind_rest_area,        wind_areas) \
    X(coarse_node_slot,      18, uint32_t,        coarse_node_slot,      coarse_node_slot,      h.coarse_node_count) \
    X(coarse_inverse_mass,   19, float,           coarse_inverse_mass,   coarse_inverse_mass,   h.coarse_slot_count) \
    X(coarse_slot_of_node,   43, uint32_t,        coarse_slot_of_node,   coarse_slot_of_node,   h.coarse_node_count) \
    X(coarse_node_of_slot,   44, uint32_t,        coarse_node_of_slot,   coarse_node_of_slot,   h.coarse_slot_count) \
    X(coarse_rest_length,    45, float,           coarse_rest_length,    coarse_rest_length,    h.coarse_lane_count) \
    X(coarse_lane_weight,    46, float,           coarse_lane_weight,    coarse_lane_weight,    h.coarse_lane_count) \
    X(coarse_index_a,        47, uint32_t,        coarse_index_a,        coarse_index_a,        h.coarse_lane_count) \
    X(coarse_index_b,        48, uint32_t,        coarse_index_b,        coarse_index_b,        h.coarse_lane_count) \
    X(coarse_batches,        49, ConstraintBatch, coarse_batches,        coarse_batches,        h.coarse_batch_count) \
    X(coarse_weight_node_0,  23, uint32_t,        coarse_weight_node[0], coarse_weight_node[0], coarse_slots) \
    X(coarse_weight_node_1,  24, uint32_t,        coarse_weight_node[1], coarse_weight_node[1], coarse_slots) \
    X(coarse_weight_node_2,  25, uint32_t,        coarse_weight_node[2], coarse_weight_node[2], coarse_slots) \
    X(coarse_weight_node_3,  26, uint32_t,        coarse_weight_node[3], coarse_weight_node[3], coarse_slots) \
    X(coarse_weight_0,       27, float,           coarse_weight[0],      coarse_weight[0],      coarse_slots) \
    X(coarse_weight_1,       28, float,           coarse_weight[1],      coarse_weight[1],      coarse_slots) \
    X(coarse_weight_2,       29, float,           coarse_weight[2],      coarse_weight[2],      coarse_slots) \
    X(coarse_weight_3,       30, float,           coarse_weight[3],      coarse_weight[3],      coarse_slots) \
    X(coarse_row_node_0,     31, uint32_t,        coarse_row_node[0],    coarse_row_node[0],    plane_rows) \
    X(coarse_row_node_1,     32, uint32_t,        coarse_row_node[1],    coarse_row_node[1],    plane_rows) \
    X(coarse_row_frac_0,     33, float,           coarse_row_frac[0],    coarse_row_frac[0],    plane_rows) \
    X(coarse_row_frac_1,     34, float,           coarse_row_frac[1],    coarse_row_frac[1],    plane_rows) \
    X(coarse_col_node_0,     35, uint32_t,        coarse_col_node[0],    coarse_col_node[0],    plane_cols) \
    X(coarse_col_node_1,     36, uint32_t,        coarse_col_node[1],    coarse_col_node[1],    plane_cols) \
    X(coarse_col_frac_0,     37, float,           coarse_col_frac[0],    coarse_col_frac[0],    plane_cols) \
    X(coarse_col_frac_1,     38, float,           coarse_col_frac[1],    coarse_col_frac[1],    plane_cols) \
    X(uv,                    39, float,           uv,                    uv,                    uv_floats) \
    X(seam_first,            40, uint32_t,        seam_first,            seam_first,            offsets(h.seam_point_count)) \
    X(seam_source,           41, uint32_t,        seam_source,           seam_source,           h.seam_source_count) \
    X(panel,                 42, uint16_t,        panel,                 panel,                 panels) \
    X(sewn_particle,         51, uint32_t,        sewn_particle,         sewn_particle,         h.sewn_point_count) \
    X(sewn_uv_first,         52, uint32_t,        sewn_uv_first,         sewn_uv_first,         offsets(h.sewn_point_count)) \
    X(sewn_uv,               53, float,           sewn_uv,               sewn_uv,               2 * uint64_t(h.sewn_uv_count)) \
    X(attached_particle,     54, uint32_t,        attached_particle,     attached_particle,     h.attachment_count) \
    X(attached_triangle,     55, uint32_t,        attached_triangle,     attached_triangle,     h.attachment_count) \
    X(attached_weight,       56, float,           attached_weight,       attached_weight,       3 * uint64_t(h.attachment_count)) \
    X(tether_anchor_0,       57, uint32_t,        tether_anchor[0],      tether_anchor[0],      h.tether_anchor_lane_count) \
    X(tether_anchor_1,       58, uint32_t,        tether_anchor[1],      tether_anchor[1],      h.tether_anchor_lane_count) \
    X(skin_particle,         59, uint32_t,        skin.particle,         skin.particle,         h.skin_constraint_count) \
    X(skin_triangle,         60, uint32_t,        skin.triangle,         skin.triangle,         h.skin_constraint_count) \
    X(skin_weight,           61, float,           skin.weight,           skin.weight,           3 * uint64_t(h.skin_constraint_count)) \
    X(skin_rest_offset,      62, float,           skin.rest_offset_m,    skin.rest_offset_m,    h.skin_constraint_count) \
    X(skin_max_distance,     63, float,           skin.max_distance_m,   skin.max_distance_m,   h.skin_constraint_count) \
    X(skin_backstop,         64, float,           skin.backstop_m,       skin.backstop_m,       h.skin_constraint_count) \
    X(render_cloth_triangle, 65, uint32_t,        render.cloth_triangle, render_cloth_triangle, h.render_vertex_count) \
    X(render_weight_1,       66, float,           render.weight_1,       render_weight_1,       h.render_vertex_count) \
    X(render_weight_2,       67, float,           render.weight_2,       render_weight_2,       h.render_vertex_count) \
    X(render_offset,         68, float,           render.offset_m,       render_offset,         h.render_vertex_count) \
    X(render_triangles,      69, uint32_t,        render.triangles,      render_triangles,      3 * uint64_t(h.render_triangle_count)) \
    X(render_uv,             70, float,           render.uv,             render_uv,             2 * uint64_t(h.render_vertex_count))

// The section kinds, numbered as in the file.
enum class AssetSectionKind : uint32_t {
#define WEFT_ASSET_KIND(kind, number, ...) kind = number,
    WEFT_ASSET_SECTIONS(WEFT_ASSET_KIND)
#undef WEFT_ASSET_KIND
    retired_20 = 20,  // kinds 20-22 held the coarse constraints before they became lanes: never written
    retired_21 = 21,
    retired_22 = 22,
};
#define WEFT_ASSET_NUMBER(kind, number, ...) number,
inline constexpr uint32_t kAssetSectionKindCount = std::max({WEFT_ASSET_SECTIONS(WEFT_ASSET_NUMBER)});
#undef WEFT_ASSET_NUMBER
// Known kinds are 1..kAssetSectionKindCount, each a row or retired (asset_section_name's switch
// refuses a number used twice).
#define WEFT_ASSET_ROW(...) +1
static_assert(WEFT_ASSET_SECTIONS(WEFT_ASSET_ROW) + 3 == kAssetSectionKindCount);
#undef WEFT_ASSET_ROW
// Each row's ClothAsset field points to the row's element type.
#define WEFT_ASSET_FIELD_TYPE(kind, number, type, field, ...) \
    static_assert(std::is_same_v<std::remove_cvref_t<decltype(std::declval<ClothAsset&>().field)>, const type*>);
WEFT_ASSET_SECTIONS(WEFT_ASSET_FIELD_TYPE)
#undef WEFT_ASSET_FIELD_TYPE

// Name of a section kind ("unknown" for kinds this runtime does not know).
const char* asset_section_name(uint32_t kind);

// Visits every section of ClothAsset `a` (const for a writer, mutable for the loader) in the
// table's order: visit(kind, field, element_count), `field` a reference to the asset's pointer.
// The counts come from the header `h`; a section is present in a file exactly when its count is
// above 0. The writer and the loader both walk it.
template <class Asset, class Visit>
void visit_asset_sections(const AssetFileHeader& h, Asset& a, Visit&& visit) {
    // The counts the table names: shared by rows, or conditional.
    const uint64_t coarse_slots = h.coarse_node_count > 0 ? h.slot_count : 0;
    const uint64_t plane_rows = h.coarse_lattice_cols > 0 ? h.lattice_plane_rows : 0;
    const uint64_t plane_cols = h.coarse_lattice_cols > 0 ? h.lattice_plane_cols : 0;
    const uint64_t wind_areas =  // the wind lanes, then the triangles done one at a time
        uint64_t(h.wind_lane_count) + (h.triangle_count >= h.wind_run_triangles ? h.triangle_count - h.wind_run_triangles : 0);
    const uint64_t uv_floats = h.has_uv != 0 ? 2 * uint64_t(h.particle_count) : 0;
    const uint64_t panels = h.panel_count > 0 ? h.particle_count : 0;
    const auto offsets = [](uint32_t points) { return points > 0 ? uint64_t(points) + 1 : 0; };  // CSR
#define WEFT_ASSET_VISIT(kind, number, type, field, storage, count) visit(AssetSectionKind::kind, a.field, uint64_t(count));
    WEFT_ASSET_SECTIONS(WEFT_ASSET_VISIT)
#undef WEFT_ASSET_VISIT
}

// Copies ClothAsset's scalar fields between the header and an asset, in either direction:
// copy(header_field, asset_field) for each. One list for the writer and the loader.
template <class Header, class Asset, class Copy>
void pair_asset_scalars(Header& h, Asset& a, Copy&& copy) {
    copy(h.simd_width, a.simd_width);
    copy(h.particle_count, a.particle_count);
    copy(h.slot_count, a.slot_count);
    copy(h.lane_count, a.lane_count);
    copy(h.batch_count, a.batch_count);
    copy(h.colour_count, a.colour_count);
    for (uint32_t k = 0; k < kConstraintKindCount; ++k) copy(h.constraint_count[k], a.constraint_count[k]);
    copy(h.constraints_on_runs, a.constraints_on_runs);
    copy(h.tether_lane_count, a.tether_lane_count);
    copy(h.tether_batch_count, a.tether_batch_count);
    copy(h.tethered_particles, a.tethered_particles);
    copy(h.triangle_count, a.triangle_count);
    copy(h.wind_run_count, a.wind_run_count);
    copy(h.wind_lane_count, a.wind_lane_count);
    copy(h.wind_run_triangles, a.wind_run_triangles);
    copy(h.coarse_node_count, a.coarse_node_count);
    copy(h.coarse_constraint_count, a.coarse_constraint_count);
    copy(h.coarse_lattice_cols, a.coarse_lattice_cols);
    copy(h.lattice_plane_rows, a.lattice_plane_rows);
    copy(h.lattice_plane_cols, a.lattice_plane_cols);
    copy(h.seam_point_count, a.seam_point_count);
    copy(h.seam_source_count, a.seam_source_count);
    copy(h.panel_count, a.panel_count);
    copy(h.has_fabric, a.has_fabric);
    copy(h.fabric, a.fabric);
    copy(h.coarse_slot_count, a.coarse_slot_count);
    copy(h.coarse_lane_count, a.coarse_lane_count);
    copy(h.coarse_batch_count, a.coarse_batch_count);
    copy(h.coarse_colour_count, a.coarse_colour_count);
    copy(h.sewn_point_count, a.sewn_point_count);
    copy(h.sewn_uv_count, a.sewn_uv_count);
    copy(h.attachment_count, a.attachment_count);
    copy(h.tether_anchor_lane_count, a.tether_anchor_lane_count);
    copy(h.skin_constraint_count, a.skin.count);
    copy(h.render_vertex_count, a.render.vertex_count);
    copy(h.render_triangle_count, a.render.triangle_count);
}

}  // namespace weft
