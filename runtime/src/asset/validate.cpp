// Asset validation: every invariant the step relies on, checked once before a cloth is added, so
// the step itself needs no checks. A baked file that passes this cannot make the step read or write
// out of bounds, divide by zero or see a NaN it did not make itself.
#include <algorithm>
#include <cmath>
#include <vector>

#include "asset/garment_checks.h"
#include "asset/validate.h"
#include "error.h"

namespace weft {
namespace {

bool finite_nonnegative(float v) { return std::isfinite(v) && v >= 0.0f; }

Result check_particles(const ClothAsset& a) {
    if (a.particle_count == 0) return make_error(ErrorCode::corrupt_asset, "asset has no particles");
    if (a.simd_width != kSimdWidth && a.simd_width != kMaxSimdWidth)
        return make_error(ErrorCode::corrupt_asset, "asset is padded for %u lanes (%u or %u)", a.simd_width,
                          kSimdWidth, kMaxSimdWidth);
    if (a.slot_count < a.particle_count || a.slot_count % a.simd_width != 0 || a.slot_count > (1u << 28))
        return make_error(ErrorCode::corrupt_asset, "slot count %u is not a padded multiple of %u >= %u",
                          a.slot_count, a.simd_width, a.particle_count);
    if (!a.slot_of_particle || !a.particle_of_slot || !a.start_x || !a.start_y || !a.start_z || !a.inverse_mass)
        return make_error(ErrorCode::corrupt_asset, "asset is missing a particle array");
    for (uint32_t p = 0; p < a.particle_count; ++p) {
        const uint32_t s = a.slot_of_particle[p];
        if (s >= a.slot_count || a.particle_of_slot[s] != p)
            return make_error(ErrorCode::corrupt_asset, "particle %u and its slot do not map both ways", p);
    }
    uint32_t mapped = 0;
    for (uint32_t s = 0; s < a.slot_count; ++s) {
        const float x = a.start_x[s], y = a.start_y[s], z = a.start_z[s];
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            return make_error(ErrorCode::corrupt_asset, "slot %u has a non-finite start position", s);
        if (std::fabs(x) > 1e6f || std::fabs(y) > 1e6f || std::fabs(z) > 1e6f)
            return make_error(ErrorCode::corrupt_asset, "slot %u lies beyond 1e6 m", s);
        if (!finite_nonnegative(a.inverse_mass[s]))
            return make_error(ErrorCode::corrupt_asset, "slot %u has a bad inverse mass", s);
        if (a.particle_of_slot[s] == kNoParticle) {
            if (a.inverse_mass[s] != 0.0f)
                return make_error(ErrorCode::corrupt_asset, "padding slot %u is not pinned", s);
        } else {
            ++mapped;
        }
    }
    if (mapped != a.particle_count)
        return make_error(ErrorCode::corrupt_asset, "%u slots hold particles, expected %u", mapped, a.particle_count);
    return {};
}

// One set of distance constraints in lanes and batches over `slot_count` slots: the springs, or
// the coarse level's constraints over node slots. Both are checked by the same rules.
struct LaneSet {
    const char* name;  // for messages
    uint32_t simd_width;  // runs are padded to a multiple of it
    uint32_t slot_count, lane_count, batch_count, colour_count;
    const float* rest_length;
    const float* lane_weight;
    const uint32_t* index_a;
    const uint32_t* index_b;
    const ConstraintBatch* batches;
};

LaneSet spring_set(const ClothAsset& a) {
    return {"spring", a.simd_width, a.slot_count, a.lane_count, a.batch_count, a.colour_count, a.rest_length, a.lane_weight,
            a.index_a, a.index_b, a.batches};
}

LaneSet coarse_set(const ClothAsset& a) {
    return {"coarse", a.simd_width, a.coarse_slot_count, a.coarse_lane_count, a.coarse_batch_count, a.coarse_colour_count,
            a.coarse_rest_length, a.coarse_lane_weight, a.coarse_index_a, a.coarse_index_b, a.coarse_batches};
}

// Checks the lanes and batches; counts the real constraints per kind and those on runs.
Result check_lanes(const LaneSet& a, uint32_t counted[kConstraintKindCount], uint32_t* on_runs) {
    if (a.lane_count > 0 && (!a.rest_length || !a.lane_weight || !a.index_a || !a.index_b))
        return make_error(ErrorCode::corrupt_asset, "asset is missing a %s constraint array", a.name);
    if (a.batch_count > 0 && a.batches == nullptr)
        return make_error(ErrorCode::corrupt_asset, "asset is missing its %s batches", a.name);
    for (uint32_t l = 0; l < a.lane_count; ++l) {
        if (!finite_nonnegative(a.rest_length[l]) || a.rest_length[l] > 1e6f)
            return make_error(ErrorCode::corrupt_asset, "%s lane %u has a bad rest length", a.name, l);
        if (a.lane_weight[l] != 0.0f && a.lane_weight[l] != 1.0f)
            return make_error(ErrorCode::corrupt_asset, "%s lane %u has weight other than 0 or 1", a.name, l);
        if (a.index_a[l] >= a.slot_count || a.index_b[l] >= a.slot_count)
            return make_error(ErrorCode::corrupt_asset, "%s lane %u indexes a slot past %u", a.name, l, a.slot_count);
    }
    uint32_t next_lane = 0;
    *on_runs = 0;
    for (uint32_t i = 0; i < a.batch_count; ++i) {
        const ConstraintBatch& b = a.batches[i];
        if (uint32_t(b.kind) >= kConstraintKindCount)
            return make_error(ErrorCode::corrupt_asset, "%s batch %u has an unknown kind", a.name, i);
        if (b.first_lane != next_lane || b.lane_count > a.lane_count - b.first_lane)
            return make_error(ErrorCode::corrupt_asset, "%s batch %u does not tile the lanes", a.name, i);
        next_lane += b.lane_count;
        if (b.layout == BatchLayout::run) {
            if (b.lane_count % a.simd_width != 0)
                return make_error(ErrorCode::corrupt_asset, "%s run %u is not padded to %u lanes", a.name, i, a.simd_width);
            if (b.lane_count > a.slot_count || b.a0 > a.slot_count - b.lane_count ||
                b.b0 > a.slot_count - b.lane_count)
                return make_error(ErrorCode::corrupt_asset, "%s run %u reaches past the slots", a.name, i);
            const uint32_t gap = b.a0 < b.b0 ? b.b0 - b.a0 : b.a0 - b.b0;
            if (gap < b.lane_count)  // both sides stored from one vector each: they must not overlap
                return make_error(ErrorCode::corrupt_asset, "%s run %u overlaps its own particles", a.name, i);
            for (uint32_t k = 0; k < b.lane_count; ++k)
                if (a.index_a[b.first_lane + k] != b.a0 + k || a.index_b[b.first_lane + k] != b.b0 + k)
                    return make_error(ErrorCode::corrupt_asset, "%s run %u is not contiguous at lane %u", a.name, i, k);
        } else if (b.layout != BatchLayout::indexed) {
            return make_error(ErrorCode::corrupt_asset, "%s batch %u has an unknown layout", a.name, i);
        }
        for (uint32_t k = 0; k < b.lane_count; ++k) {
            const uint32_t l = b.first_lane + k;
            if (a.lane_weight[l] == 0.0f) continue;
            if (a.index_a[l] == a.index_b[l])
                return make_error(ErrorCode::corrupt_asset, "%s lane %u joins a particle to itself", a.name, l);
            counted[uint32_t(b.kind)] += 1;
            if (b.layout == BatchLayout::run) ++*on_runs;
        }
    }
    if (next_lane != a.lane_count)
        return make_error(ErrorCode::corrupt_asset, "%s batches do not cover every lane", a.name);
    return {};
}

// Batches of one colour must touch disjoint particles (that is what makes a colour parallel);
// scratch[slot] holds the last colour (+1) that touched the slot.
Result check_colours(const LaneSet& a, uint32_t* scratch) {
    for (uint32_t s = 0; s < a.slot_count; ++s) scratch[s] = 0;
    uint32_t previous = 0;
    for (uint32_t i = 0; i < a.batch_count; ++i) {
        const ConstraintBatch& b = a.batches[i];
        if (b.colour < previous)
            return make_error(ErrorCode::corrupt_asset, "%s batches are not in colour order", a.name);
        previous = b.colour;
        if (b.colour == kOverflowColour) continue;  // the overflow colour is solved serially
        if (b.colour >= a.colour_count)
            return make_error(ErrorCode::corrupt_asset, "%s batch %u has colour %u of %u", a.name, i, b.colour,
                              a.colour_count);
        const uint32_t stamp = uint32_t(b.colour) + 1;
        for (uint32_t k = 0; k < b.lane_count; ++k) {
            const uint32_t l = b.first_lane + k;
            if (a.lane_weight[l] == 0.0f) continue;
            for (uint32_t s : {a.index_a[l], a.index_b[l]}) {
                if (scratch[s] == stamp)
                    return make_error(ErrorCode::corrupt_asset, "%s colour %u touches slot %u twice", a.name,
                                      b.colour, s);
                scratch[s] = stamp;
            }
        }
    }
    return {};
}

Result check_springs(const ClothAsset& a, uint32_t* scratch) {
    const LaneSet set = spring_set(a);
    uint32_t counted[kConstraintKindCount] = {}, on_runs = 0;
    if (Result r = check_lanes(set, counted, &on_runs); !r.ok()) return r;
    for (uint32_t k = 0; k < kConstraintKindCount; ++k)
        if (counted[k] != a.constraint_count[k])
            return make_error(ErrorCode::corrupt_asset, "constraint counts disagree with the batches");
    if (on_runs != a.constraints_on_runs)
        return make_error(ErrorCode::corrupt_asset, "run count disagrees with the batches");
    return check_colours(set, scratch);
}

Result check_tethers(const ClothAsset& a) {
    if (a.tether_batch_count > 0 && (!a.tether_batches || !a.tether_rest[0] || !a.tether_rest[1]))
        return make_error(ErrorCode::corrupt_asset, "asset is missing its tether arrays");
    if (a.tether_anchor_lane_count != 0 &&
        (a.tether_anchor_lane_count != a.tether_lane_count || !a.tether_anchor[0] || !a.tether_anchor[1]))
        return make_error(ErrorCode::corrupt_asset, "asset's per-lane tether anchors do not match its tether lanes");
    uint32_t next_lane = 0, real = 0;
    for (uint32_t i = 0; i < a.tether_batch_count; ++i) {
        const TetherBatch& t = a.tether_batches[i];
        if (t.first_lane != next_lane || t.lane_count % a.simd_width != 0 ||
            t.lane_count > a.tether_lane_count - t.first_lane)
            return make_error(ErrorCode::corrupt_asset, "tether batch %u does not tile the lanes", i);
        next_lane += t.lane_count;
        const bool per_lane = t.anchor[0] == kTetherLaneAnchors;
        if (per_lane && (t.anchor[1] != kTetherLaneAnchors || a.tether_anchor_lane_count == 0))
            return make_error(ErrorCode::corrupt_asset, "tether batch %u has per-lane anchors the asset does not hold", i);
        if (t.lane_count > a.slot_count || t.particle0 > a.slot_count - t.lane_count)
            return make_error(ErrorCode::corrupt_asset, "tether batch %u reaches past the slots", i);
        for (uint32_t k = 0; k < (per_lane ? t.lane_count : 1); ++k) {
            const uint32_t q0 = tether_anchor(a, t, k, 0), q1 = tether_anchor(a, t, k, 1);
            if (q0 >= a.slot_count || q1 >= a.slot_count)
                return make_error(ErrorCode::corrupt_asset, "tether batch %u reaches past the slots", i);
            if (a.inverse_mass[q0] != 0.0f || a.inverse_mass[q1] != 0.0f)
                return make_error(ErrorCode::corrupt_asset, "tether batch %u anchors to a free particle", i);
        }
        for (uint32_t k = 0; k < t.lane_count; ++k) {
            const float r0 = a.tether_rest[0][t.first_lane + k], r1 = a.tether_rest[1][t.first_lane + k];
            const bool pad0 = std::isinf(r0) && r0 > 0.0f, pad1 = std::isinf(r1) && r1 > 0.0f;
            if (pad0 && pad1) continue;  // padding
            if (!finite_nonnegative(r0) || !finite_nonnegative(r1) || r0 > 1e6f || r1 > 1e6f)
                return make_error(ErrorCode::corrupt_asset, "tether lane %u has a bad length", t.first_lane + k);
            ++real;
        }
    }
    if (next_lane != a.tether_lane_count || real != a.tethered_particles)
        return make_error(ErrorCode::corrupt_asset, "tether lanes disagree with their batches");
    return {};
}

Result check_triangles(const ClothAsset& a) {
    if (a.triangle_count > 0 && a.triangles == nullptr)
        return make_error(ErrorCode::corrupt_asset, "asset is missing its triangles");
    if (a.wind_run_count > 0 && (a.wind_runs == nullptr || a.wind_lane_weight == nullptr))
        return make_error(ErrorCode::corrupt_asset, "asset is missing its wind runs");
    uint32_t next_lane = 0, real = 0;
    for (uint32_t i = 0; i < a.wind_run_count; ++i) {
        const TriangleRun& r = a.wind_runs[i];
        if (r.first_lane != next_lane || r.lane_count % a.simd_width != 0 ||
            r.lane_count > a.wind_lane_count - r.first_lane)
            return make_error(ErrorCode::corrupt_asset, "wind run %u does not tile the lanes", i);
        next_lane += r.lane_count;
        if (r.lane_count > a.slot_count || r.a0 > a.slot_count - r.lane_count || r.b0 > a.slot_count - r.lane_count ||
            r.c0 > a.slot_count - r.lane_count)
            return make_error(ErrorCode::corrupt_asset, "wind run %u reaches past the slots", i);
        const auto apart = [&](uint32_t u, uint32_t v) { return (u > v ? u - v : v - u) >= r.lane_count; };
        if (!apart(r.a0, r.b0) || !apart(r.a0, r.c0) || !apart(r.b0, r.c0))
            return make_error(ErrorCode::corrupt_asset, "wind run %u overlaps its own corners", i);
        for (uint32_t k = 0; k < r.lane_count; ++k) {
            const float w = a.wind_lane_weight[r.first_lane + k];
            if (w != 0.0f && w != 1.0f) return make_error(ErrorCode::corrupt_asset, "wind lane weight is not 0 or 1");
            real += w == 1.0f;
        }
    }
    if (next_lane != a.wind_lane_count || real != a.wind_run_triangles || a.wind_run_triangles > a.triangle_count)
        return make_error(ErrorCode::corrupt_asset, "wind runs disagree with the triangles");
    for (uint32_t i = 0; i < 3 * a.triangle_count; ++i)
        if (a.triangles[i] >= a.slot_count || a.particle_of_slot[a.triangles[i]] == kNoParticle)
            return make_error(ErrorCode::corrupt_asset, "triangle %u uses a slot without a particle", i / 3);
    // Rest areas: one per wind lane (0 on padding), then one per triangle done one at a time.
    const uint64_t areas = uint64_t(a.wind_lane_count) + (a.triangle_count - a.wind_run_triangles);
    if (areas > 0 && a.wind_rest_area == nullptr)
        return make_error(ErrorCode::corrupt_asset, "asset is missing the triangles' rest areas");
    for (uint64_t i = 0; i < areas; ++i) {
        const float area = a.wind_rest_area[i];
        if (!finite_nonnegative(area) || area > 1e6f)
            return make_error(ErrorCode::corrupt_asset, "triangle rest area %llu is bad", (unsigned long long)i);
        if (i < a.wind_lane_count && a.wind_lane_weight[i] == 0.0f && area != 0.0f)
            return make_error(ErrorCode::corrupt_asset, "wind padding lane %llu has an area", (unsigned long long)i);
    }
    return {};
}

Result check_coarse(const ClothAsset& a, uint32_t* scratch) {
    const uint32_t nodes = a.coarse_node_count;
    // The plane sizes belong to the coarse lattice form (the world sizes a row buffer by them).
    if (a.coarse_lattice_cols == 0 && (a.lattice_plane_rows != 0 || a.lattice_plane_cols != 0))
        return make_error(ErrorCode::corrupt_asset, "lattice plane sizes without a coarse lattice");
    if (nodes == 0) {
        if (a.coarse_lattice_cols != 0 || a.coarse_constraint_count != 0 || a.coarse_slot_count != 0 ||
            a.coarse_lane_count != 0 || a.coarse_batch_count != 0)
            return make_error(ErrorCode::corrupt_asset, "coarse constraints, slots or lattice without coarse nodes");
        return {};
    }
    if (!a.coarse_node_slot || !a.coarse_slot_of_node || !a.coarse_node_of_slot || !a.coarse_inverse_mass)
        return make_error(ErrorCode::corrupt_asset, "asset is missing a coarse-level array");
    if (nodes > a.slot_count) return make_error(ErrorCode::corrupt_asset, "more coarse nodes than slots");
    if (a.coarse_slot_count < nodes || a.coarse_slot_count % a.simd_width != 0 || a.coarse_slot_count > (1u << 28))
        return make_error(ErrorCode::corrupt_asset, "coarse slot count %u is not a padded multiple of %u >= %u",
                          a.coarse_slot_count, a.simd_width, nodes);
    for (uint32_t j = 0; j < nodes; ++j) {
        const uint32_t s = a.coarse_slot_of_node[j];
        if (a.coarse_node_slot[j] >= a.slot_count || s >= a.coarse_slot_count || a.coarse_node_of_slot[s] != j)
            return make_error(ErrorCode::corrupt_asset, "coarse node %u is bad", j);
    }
    for (uint32_t s = 0; s < a.coarse_slot_count; ++s)
        if (a.coarse_node_of_slot[s] >= nodes || !finite_nonnegative(a.coarse_inverse_mass[s]) ||
            (a.coarse_slot_of_node[a.coarse_node_of_slot[s]] != s && a.coarse_inverse_mass[s] != 0.0f))
            return make_error(ErrorCode::corrupt_asset, "coarse node slot %u is bad", s);
    const LaneSet set = coarse_set(a);
    uint32_t counted[kConstraintKindCount] = {}, on_runs = 0;
    if (Result r = check_lanes(set, counted, &on_runs); !r.ok()) return r;
    if (counted[0] + counted[1] + counted[2] != a.coarse_constraint_count)
        return make_error(ErrorCode::corrupt_asset, "coarse constraint count disagrees with the batches");
    if (Result r = check_colours(set, scratch); !r.ok()) return r;
    for (uint32_t k = 0; k < kCoarseWeights; ++k) {
        if (!a.coarse_weight_node[k] || !a.coarse_weight[k])
            return make_error(ErrorCode::corrupt_asset, "asset is missing coarse weights");
        for (uint32_t s = 0; s < a.slot_count; ++s) {
            const float w = a.coarse_weight[k][s];
            if (a.coarse_weight_node[k][s] >= nodes || !(w >= 0.0f && w <= 1.0f) ||
                (w != 0.0f && a.inverse_mass[s] == 0.0f))
                return make_error(ErrorCode::corrupt_asset, "coarse weight of slot %u is bad", s);
        }
    }
    if (a.coarse_lattice_cols > 0) {  // the lattice form's tables
        const uint32_t cols = a.coarse_lattice_cols, rows = nodes / cols;
        if (cols < 2 || cols > 32 || nodes % cols != 0 || rows < 2)
            return make_error(ErrorCode::corrupt_asset, "coarse lattice of %u nodes in rows of %u", nodes, cols);
        const uint64_t lattice_slots = 4ull * a.lattice_plane_rows * a.lattice_plane_cols;
        if (lattice_slots == 0 || lattice_slots > a.slot_count)
            return make_error(ErrorCode::corrupt_asset, "lattice planes do not fit the slots");
        for (uint32_t parity = 0; parity < 2; ++parity) {
            if (!a.coarse_row_node[parity] || !a.coarse_row_frac[parity] || !a.coarse_col_node[parity] ||
                !a.coarse_col_frac[parity])
                return make_error(ErrorCode::corrupt_asset, "asset is missing a coarse lattice table");
            for (uint32_t r = 0; r < a.lattice_plane_rows; ++r)
                if (a.coarse_row_node[parity][r] > rows - 2 ||
                    !(a.coarse_row_frac[parity][r] >= 0.0f && a.coarse_row_frac[parity][r] <= 1.0f))
                    return make_error(ErrorCode::corrupt_asset, "coarse row table entry %u is bad", r);
            for (uint32_t c = 0; c < a.lattice_plane_cols; ++c) {
                const uint32_t* node = a.coarse_col_node[parity];
                // gather_near: any 8 consecutive columns lie within 8 nodes of the first, in order.
                const uint32_t ahead = std::min(c + 7, a.lattice_plane_cols - 1);
                if (node[c] > cols - 2 || (c > 0 && node[c] < node[c - 1]) || node[ahead] - node[c] > 7 ||
                    !(a.coarse_col_frac[parity][c] >= 0.0f && a.coarse_col_frac[parity][c] <= 1.0f))
                    return make_error(ErrorCode::corrupt_asset, "coarse column table entry %u is bad", c);
            }
        }
    }
    return {};
}

// The garment data (asset/garment_checks.h), every failure reported as a corrupt asset.
Result check_garment(const ClothAsset& a, uint32_t* scratch) {
    Result r = check_uv(a.uv, a.particle_count);
    if (r.ok()) r = check_seam_offsets(a.seam_point_count, a.seam_first);
    if (r.ok() && a.seam_point_count > 0 && a.seam_first[a.seam_point_count] != a.seam_source_count)
        r = make_error(ErrorCode::corrupt_asset, "seam_first ends at %u, seam_source_count is %u",
                       a.seam_first[a.seam_point_count], a.seam_source_count);
    if (r.ok() && a.seam_point_count == 0 && a.seam_source_count != 0)
        r = make_error(ErrorCode::corrupt_asset, "seam sources without seam points");
    if (r.ok()) r = check_seam_sources(a.seam_point_count, a.seam_first, a.seam_source, a.particle_count);
    if (r.ok()) r = check_panels(a.panel, a.panel_count, a.particle_count);
    if (r.ok()) r = check_sewn(a.sewn_point_count, a.sewn_particle, a.sewn_uv_first, a.sewn_uv, a.particle_count);
    if (r.ok() && a.sewn_point_count > 0 && a.sewn_uv_first[a.sewn_point_count] != a.sewn_uv_count)
        r = make_error(ErrorCode::corrupt_asset, "sewn_uv_first ends at %u, sewn_uv_count is %u",
                       a.sewn_uv_first[a.sewn_point_count], a.sewn_uv_count);
    if (r.ok())
        r = check_attachments(a.attachment_count, a.attached_particle, a.attached_triangle, a.attached_weight,
                              a.particle_count);
    if (r.ok()) r = check_skin_constraints(a.skin, a.particle_count, a.slot_of_particle, a.inverse_mass, scratch);
    if (r.ok() && a.sewn_point_count == 0 && a.sewn_uv_count != 0)
        r = make_error(ErrorCode::corrupt_asset, "sewn uvs without sewn points");
    if (r.ok()) r = check_fabric(a.fabric);
    if (r.ok()) r = check_render_mesh(a.render, a.triangle_count);
    if (!r.ok()) r.code = ErrorCode::corrupt_asset;
    return r;
}

}  // namespace

Result validate_asset_with_scratch(const ClothAsset& a, uint32_t* scratch, uint32_t scratch_count) {
    if (Result r = check_particles(a); !r.ok()) return r;
    if (a.slot_count > scratch_count)
        return make_error(ErrorCode::capacity_exceeded, "asset has %u slots, world holds %u", a.slot_count,
                          scratch_count);
    if (a.coarse_slot_count > scratch_count)
        return make_error(ErrorCode::capacity_exceeded, "asset has %u coarse node slots, world holds %u",
                          a.coarse_slot_count, scratch_count);
    if (Result r = check_springs(a, scratch); !r.ok()) return r;
    if (Result r = check_tethers(a); !r.ok()) return r;
    if (Result r = check_coarse(a, scratch); !r.ok()) return r;
    if (Result r = check_garment(a, scratch); !r.ok()) return r;  // scratch: slot_count >= particle_count
    return check_triangles(a);
}

Result validate_asset(const ClothAsset& asset) {
    if (asset.slot_count > (1u << 28))
        return make_error(ErrorCode::corrupt_asset, "slot count %u is absurd", asset.slot_count);
    if (asset.coarse_slot_count > (1u << 28))
        return make_error(ErrorCode::corrupt_asset, "coarse slot count %u is absurd", asset.coarse_slot_count);
    const uint32_t count = asset.slot_count > asset.coarse_slot_count ? asset.slot_count : asset.coarse_slot_count;
    std::vector<uint32_t> scratch(count);
    return validate_asset_with_scratch(asset, scratch.data(), count);
}

}  // namespace weft
