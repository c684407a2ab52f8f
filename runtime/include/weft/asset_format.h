// The layout of a baked asset file (docs/asset-format.md): magic, versions, the fixed header, the
// section table, the section kinds, and the one table that maps sections to ClothAsset's arrays.
// For writers (lib/common/asset_writer.h), the loader (runtime/src/asset/load.cpp) and tools that
// inspect files; a game loads files through weft/asset_file.h alone.
#pragma once

#include <cstddef>
#include <cstdint>

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

// Every array of ClothAsset is one section. The numbers are the file's: never reuse one.
enum class AssetSectionKind : uint32_t {
    slot_of_particle = 1,
    particle_of_slot,
    start_x,
    start_y,
    start_z,
    inverse_mass,
    rest_length,
    lane_weight,
    index_a,
    index_b,
    batches,  // 11
    tether_rest_0,
    tether_rest_1,
    tether_batches,
    triangles,
    wind_runs,
    wind_lane_weight,
    coarse_node_slot,
    coarse_inverse_mass,
    retired_20,  // kinds 20-22 held the coarse constraints before they became lanes: never written
    retired_21,
    retired_22,
    coarse_weight_node_0,
    coarse_weight_node_1,
    coarse_weight_node_2,
    coarse_weight_node_3,
    coarse_weight_0,
    coarse_weight_1,
    coarse_weight_2,
    coarse_weight_3,
    coarse_row_node_0,  // 31
    coarse_row_node_1,
    coarse_row_frac_0,
    coarse_row_frac_1,
    coarse_col_node_0,
    coarse_col_node_1,
    coarse_col_frac_0,
    coarse_col_frac_1,
    uv,
    seam_first,
    seam_source,  // 41
    panel,
    coarse_slot_of_node,  // 43
    coarse_node_of_slot,
    coarse_rest_length,
    coarse_lane_weight,
    coarse_index_a,
    coarse_index_b,
    coarse_batches,  // 49
    wind_rest_area,  // 50
    sewn_particle,   // 51 (1.1)
    sewn_uv_first,
    sewn_uv,
    attached_particle,  // 54 (1.1)
    attached_triangle,
    attached_weight,
    tether_anchor_0,  // 57 (1.1, in place of the header's reserved word)
    tether_anchor_1,
    skin_particle,  // 59 (1.2)
    skin_triangle,
    skin_weight,
    skin_rest_offset,
    skin_max_distance,
    skin_backstop,  // 64
    render_cloth_triangle,  // 65 (1.3)
    render_weight_1,
    render_weight_2,
    render_offset,
    render_triangles,
    render_uv,  // 70
};
inline constexpr uint32_t kAssetSectionKindCount = 70;  // known kinds: 1..kAssetSectionKindCount

// Name of a section kind ("unknown" for kinds this runtime does not know).
const char* asset_section_name(uint32_t kind);

// Visits every section of ClothAsset `a` (const for a writer, mutable for the loader) in kind
// order: visit(kind, field, element_count), `field` a reference to the asset's pointer. The counts
// come from the header `h`; a section is present in a file exactly when its count is above 0.
// This is the one table of sections: the writer and the loader both walk it.
template <class Asset, class Visit>
void visit_asset_sections(const AssetFileHeader& h, Asset& a, Visit&& visit) {
    using K = AssetSectionKind;
    const uint64_t slots = h.slot_count, coarse_slots = h.coarse_node_count > 0 ? h.slot_count : 0;
    const uint64_t plane_rows = h.coarse_lattice_cols > 0 ? h.lattice_plane_rows : 0;
    const uint64_t plane_cols = h.coarse_lattice_cols > 0 ? h.lattice_plane_cols : 0;
    visit(K::slot_of_particle, a.slot_of_particle, uint64_t(h.particle_count));
    visit(K::particle_of_slot, a.particle_of_slot, slots);
    visit(K::start_x, a.start_x, slots);
    visit(K::start_y, a.start_y, slots);
    visit(K::start_z, a.start_z, slots);
    visit(K::inverse_mass, a.inverse_mass, slots);
    visit(K::rest_length, a.rest_length, uint64_t(h.lane_count));
    visit(K::lane_weight, a.lane_weight, uint64_t(h.lane_count));
    visit(K::index_a, a.index_a, uint64_t(h.lane_count));
    visit(K::index_b, a.index_b, uint64_t(h.lane_count));
    visit(K::batches, a.batches, uint64_t(h.batch_count));
    visit(K::tether_rest_0, a.tether_rest[0], uint64_t(h.tether_lane_count));
    visit(K::tether_rest_1, a.tether_rest[1], uint64_t(h.tether_lane_count));
    visit(K::tether_batches, a.tether_batches, uint64_t(h.tether_batch_count));
    visit(K::triangles, a.triangles, 3 * uint64_t(h.triangle_count));
    visit(K::wind_runs, a.wind_runs, uint64_t(h.wind_run_count));
    visit(K::wind_lane_weight, a.wind_lane_weight, uint64_t(h.wind_lane_count));
    visit(K::wind_rest_area, a.wind_rest_area,
          uint64_t(h.wind_lane_count) + (h.triangle_count >= h.wind_run_triangles ? h.triangle_count - h.wind_run_triangles : 0));
    visit(K::coarse_node_slot, a.coarse_node_slot, uint64_t(h.coarse_node_count));
    visit(K::coarse_inverse_mass, a.coarse_inverse_mass, uint64_t(h.coarse_slot_count));
    visit(K::coarse_slot_of_node, a.coarse_slot_of_node, uint64_t(h.coarse_node_count));
    visit(K::coarse_node_of_slot, a.coarse_node_of_slot, uint64_t(h.coarse_slot_count));
    visit(K::coarse_rest_length, a.coarse_rest_length, uint64_t(h.coarse_lane_count));
    visit(K::coarse_lane_weight, a.coarse_lane_weight, uint64_t(h.coarse_lane_count));
    visit(K::coarse_index_a, a.coarse_index_a, uint64_t(h.coarse_lane_count));
    visit(K::coarse_index_b, a.coarse_index_b, uint64_t(h.coarse_lane_count));
    visit(K::coarse_batches, a.coarse_batches, uint64_t(h.coarse_batch_count));
    for (uint32_t k = 0; k < kCoarseWeights; ++k)
        visit(K(uint32_t(K::coarse_weight_node_0) + k), a.coarse_weight_node[k], coarse_slots);
    for (uint32_t k = 0; k < kCoarseWeights; ++k)
        visit(K(uint32_t(K::coarse_weight_0) + k), a.coarse_weight[k], coarse_slots);
    for (uint32_t p = 0; p < 2; ++p) visit(K(uint32_t(K::coarse_row_node_0) + p), a.coarse_row_node[p], plane_rows);
    for (uint32_t p = 0; p < 2; ++p) visit(K(uint32_t(K::coarse_row_frac_0) + p), a.coarse_row_frac[p], plane_rows);
    for (uint32_t p = 0; p < 2; ++p) visit(K(uint32_t(K::coarse_col_node_0) + p), a.coarse_col_node[p], plane_cols);
    for (uint32_t p = 0; p < 2; ++p) visit(K(uint32_t(K::coarse_col_frac_0) + p), a.coarse_col_frac[p], plane_cols);
    visit(K::uv, a.uv, h.has_uv != 0 ? 2 * uint64_t(h.particle_count) : 0);
    visit(K::seam_first, a.seam_first, h.seam_point_count > 0 ? uint64_t(h.seam_point_count) + 1 : 0);
    visit(K::seam_source, a.seam_source, uint64_t(h.seam_source_count));
    visit(K::panel, a.panel, h.panel_count > 0 ? uint64_t(h.particle_count) : 0);
    visit(K::sewn_particle, a.sewn_particle, uint64_t(h.sewn_point_count));
    visit(K::sewn_uv_first, a.sewn_uv_first, h.sewn_point_count > 0 ? uint64_t(h.sewn_point_count) + 1 : 0);
    visit(K::sewn_uv, a.sewn_uv, 2 * uint64_t(h.sewn_uv_count));
    visit(K::attached_particle, a.attached_particle, uint64_t(h.attachment_count));
    visit(K::attached_triangle, a.attached_triangle, uint64_t(h.attachment_count));
    visit(K::attached_weight, a.attached_weight, 3 * uint64_t(h.attachment_count));
    visit(K::tether_anchor_0, a.tether_anchor[0], uint64_t(h.tether_anchor_lane_count));
    visit(K::tether_anchor_1, a.tether_anchor[1], uint64_t(h.tether_anchor_lane_count));
    const uint64_t skin = h.skin_constraint_count;
    visit(K::skin_particle, a.skin.particle, skin);
    visit(K::skin_triangle, a.skin.triangle, skin);
    visit(K::skin_weight, a.skin.weight, 3 * skin);
    visit(K::skin_rest_offset, a.skin.rest_offset_m, skin);
    visit(K::skin_max_distance, a.skin.max_distance_m, skin);
    visit(K::skin_backstop, a.skin.backstop_m, skin);
    const uint64_t render = h.render_vertex_count;
    visit(K::render_cloth_triangle, a.render.cloth_triangle, render);
    visit(K::render_weight_1, a.render.weight_1, render);
    visit(K::render_weight_2, a.render.weight_2, render);
    visit(K::render_offset, a.render.offset_m, render);
    visit(K::render_triangles, a.render.triangles, 3 * uint64_t(h.render_triangle_count));
    visit(K::render_uv, a.render.uv, 2 * render);
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
