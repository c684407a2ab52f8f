// Cooking: an in-memory triangle mesh -> ClothAsset (the creation-time twin of weft-bake).
//
//   1. springs from topology (seed section 1.1): a stretch (or shear) spring on every edge, a bend
//      spring across every interior edge joining the two vertices opposite it
//   2. particle slots: lattice particles in four parity planes, so every spring family becomes a
//      contiguous run (docs/architecture.md), the rest after them in caller order
//   3. runs: springs with the same slot offset b - a and consecutive a, padded to the SIMD width
//      (CookOptions::simd_width)
//   4. colouring: runs and leftover springs into particle-disjoint colours, greedily
//   5. tethers to the nearest pinned particles, in runs of slots by anchor pair (or per-lane anchors)
//   6. the coarse level (cook/coarse.cpp)
//   7. the garment data (texture coordinates, seam points, panels, fabric), copied as given
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <utility>

#include "cook/coarse.h"
#include "cook/lanes.h"
#include "asset/garment_checks.h"
#include "error.h"
#include "weft/asset_format.h"
#include "weft/cook.h"

namespace weft {

void CookedCloth::refresh_asset(uint32_t particle_count, uint32_t colour_count, const uint32_t counts[3],
                                uint32_t on_runs, uint32_t tethered_particles) {
    ClothAsset& a = asset_;
    a = ClothAsset();
    // Every array, by the table of the file's sections (weft/asset_format.h).
#define WEFT_ASSET_POINT(kind, number, type, field, storage, count) a.field = storage.empty() ? nullptr : storage.data();
    WEFT_ASSET_SECTIONS(WEFT_ASSET_POINT)
#undef WEFT_ASSET_POINT
    // The counts and the other scalars.
    a.particle_count = particle_count;
    a.slot_count = uint32_t(particle_of_slot.size());
    a.lane_count = uint32_t(rest_length.size());
    a.batch_count = uint32_t(batches.size());
    a.colour_count = colour_count;
    for (uint32_t k = 0; k < kConstraintKindCount; ++k) a.constraint_count[k] = counts[k];
    a.constraints_on_runs = on_runs;
    a.tether_lane_count = uint32_t(tether_rest[0].size());
    a.tether_batch_count = uint32_t(tether_batches.size());
    a.tethered_particles = tethered_particles;
    a.tether_anchor_lane_count = uint32_t(tether_anchor[0].size());
    a.triangle_count = uint32_t(triangles.size() / 3);
    a.wind_run_count = uint32_t(wind_runs.size());
    a.wind_lane_count = uint32_t(wind_lane_weight.size());
    a.wind_run_triangles = wind_run_triangles;
    a.coarse_node_count = uint32_t(coarse_node_slot.size());
    a.coarse_slot_count = uint32_t(coarse_node_of_slot.size());
    a.coarse_constraint_count = coarse_constraint_count;
    a.coarse_lane_count = uint32_t(coarse_rest_length.size());
    a.coarse_batch_count = uint32_t(coarse_batches.size());
    a.coarse_colour_count = coarse_colour_count;
    a.coarse_lattice_cols = coarse_lattice_cols;
    a.lattice_plane_rows = lattice_plane_rows;
    a.lattice_plane_cols = lattice_plane_cols;
    a.simd_width = simd_width;
    a.seam_point_count = seam_first.empty() ? 0 : uint32_t(seam_first.size() - 1);
    a.seam_source_count = uint32_t(seam_source.size());
    a.panel_count = panel_count;
    a.has_fabric = has_fabric;
    a.fabric = fabric;
    a.sewn_point_count = uint32_t(sewn_particle.size());
    a.sewn_uv_count = uint32_t(sewn_uv.size() / 2);
    a.attachment_count = uint32_t(attached_particle.size());
    a.skin.count = uint32_t(skin.particle.size());
    a.render.vertex_count = uint32_t(render_cloth_triangle.size());
    a.render.triangle_count = uint32_t(render_triangles.size() / 3);
}

namespace {

constexpr uint32_t kMaxColours = 64;          // one bit each in a per-slot mask

// A unit of colouring: a run (first..first+count of the sorted springs, lanes a0 + k) or one spring.
struct Unit {
    uint32_t first, count;  // into the sorted springs
    uint32_t a0, b0, lanes;  // run only (lanes includes gaps and padding); lanes == 0: single
    ConstraintKind kind;
    uint16_t colour;
};

uint32_t round_up(uint32_t v, uint32_t m) { return (v + m - 1) / m * m; }

float distance(const Vec3& p, const Vec3& q) {
    const double dx = double(p.x) - q.x, dy = double(p.y) - q.y, dz = double(p.z) - q.z;
    return float(std::sqrt(dx * dx + dy * dy + dz * dz));
}

// Triangle area in double precision, m^2.
float triangle_area(const Vec3& p, const Vec3& q, const Vec3& r) {
    const double ux = double(q.x) - p.x, uy = double(q.y) - p.y, uz = double(q.z) - p.z;
    const double vx = double(r.x) - p.x, vy = double(r.y) - p.y, vz = double(r.z) - p.z;
    const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
    return float(0.5 * std::sqrt(cx * cx + cy * cy + cz * cz));
}

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Result check_mesh(const ClothMeshDesc& mesh) {
    if (mesh.particle_count == 0 || mesh.positions == nullptr)
        return make_error(ErrorCode::invalid_argument, "mesh has no particles");
    if (mesh.particle_count > (1u << 26))
        return make_error(ErrorCode::out_of_range, "mesh has %u particles (at most 2^26)", mesh.particle_count);
    if (mesh.triangle_count > 0 && mesh.triangles == nullptr)
        return make_error(ErrorCode::invalid_argument, "triangle_count > 0 but triangles is null");
    if (mesh.triangle_count > (1u << 27))
        return make_error(ErrorCode::out_of_range, "mesh has too many triangles");
    if ((mesh.masses == nullptr) == (mesh.inverse_masses == nullptr))
        return make_error(ErrorCode::invalid_argument, "give exactly one of masses and inverse_masses");
    for (uint32_t i = 0; i < mesh.particle_count; ++i) {
        if (!finite(mesh.positions[i]) || (mesh.rest_positions && !finite(mesh.rest_positions[i])))
            return make_error(ErrorCode::non_finite, "particle %u has a non-finite position", i);
        const Vec3& p = mesh.positions[i];
        if (std::fabs(p.x) > 1e6f || std::fabs(p.y) > 1e6f || std::fabs(p.z) > 1e6f)
            return make_error(ErrorCode::out_of_range, "particle %u lies beyond 1e6 m", i);
        const float m = mesh.masses ? mesh.masses[i] : mesh.inverse_masses[i];
        if (!std::isfinite(m)) return make_error(ErrorCode::non_finite, "particle %u has a non-finite mass", i);
        if (m < 0.0f) return make_error(ErrorCode::out_of_range, "particle %u has a negative mass", i);
    }
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        if (v[0] >= mesh.particle_count || v[1] >= mesh.particle_count || v[2] >= mesh.particle_count)
            return make_error(ErrorCode::out_of_range, "triangle %u indexes a particle past %u", t,
                              mesh.particle_count);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            return make_error(ErrorCode::invalid_argument, "triangle %u repeats a vertex", t);
    }
    if (Result r = check_uv(mesh.uv, mesh.particle_count); !r.ok()) return r;
    if (Result r = check_seam_offsets(mesh.seam_point_count, mesh.seam_first); !r.ok()) return r;
    if (Result r = check_seam_sources(mesh.seam_point_count, mesh.seam_first, mesh.seam_source, mesh.particle_count);
        !r.ok())
        return r;
    if (Result r = check_panels(mesh.panel, mesh.panel_count, mesh.particle_count); !r.ok()) return r;
    if (Result r = check_sewn(mesh.sewn_point_count, mesh.sewn_particle, mesh.sewn_uv_first, mesh.sewn_uv,
                              mesh.particle_count);
        !r.ok())
        return r;
    if (Result r = check_attachments(mesh.attachment_count, mesh.attached_particle, mesh.attached_triangle,
                                     mesh.attached_weight, mesh.particle_count);
        !r.ok())
        return r;
    if (mesh.skin.count > 0) {  // pinned: a mass of 0 or an inverse mass of 0
        std::vector<uint32_t> seen(mesh.particle_count);
        if (Result r = check_skin_constraints(mesh.skin, mesh.particle_count, nullptr,
                                              mesh.masses ? mesh.masses : mesh.inverse_masses, seen.data());
            !r.ok())
            return r;
    }
    if (mesh.rest_corners != nullptr)
        for (uint32_t i = 0; i < 3 * mesh.triangle_count; ++i)
            if (!finite(mesh.rest_corners[i]))
                return make_error(ErrorCode::non_finite, "rest corner %u of triangle %u is not finite", i % 3, i / 3);
    if (mesh.fabric != nullptr) return check_fabric(*mesh.fabric);
    return {};
}

Result check_options(const CookOptions& options) {
    if (options.simd_width != kSimdWidth && options.simd_width != kMaxSimdWidth)
        return make_error(ErrorCode::invalid_argument, "simd_width is %u: %u or %u lanes", options.simd_width,
                          kSimdWidth, kMaxSimdWidth);
    return {};
}

// Step 7: the garment data, in caller particle order as given.
void copy_garment(const ClothMeshDesc& mesh, CookedCloth& out) {
    const uint32_t n = mesh.particle_count;
    if (mesh.uv != nullptr) out.uv.assign(mesh.uv, mesh.uv + 2 * size_t(n));
    if (mesh.seam_point_count > 0) {
        out.seam_first.assign(mesh.seam_first, mesh.seam_first + mesh.seam_point_count + 1);
        out.seam_source.assign(mesh.seam_source, mesh.seam_source + mesh.seam_first[mesh.seam_point_count]);
    }
    if (mesh.panel != nullptr) out.panel.assign(mesh.panel, mesh.panel + n);
    out.panel_count = mesh.panel != nullptr ? mesh.panel_count : 0;
    out.has_fabric = mesh.fabric != nullptr;
    out.fabric = mesh.fabric != nullptr ? *mesh.fabric : Fabric{};
    if (mesh.sewn_point_count > 0) {
        const uint32_t sources = mesh.sewn_uv_first[mesh.sewn_point_count];
        out.sewn_particle.assign(mesh.sewn_particle, mesh.sewn_particle + mesh.sewn_point_count);
        out.sewn_uv_first.assign(mesh.sewn_uv_first, mesh.sewn_uv_first + mesh.sewn_point_count + 1);
        out.sewn_uv.assign(mesh.sewn_uv, mesh.sewn_uv + 2 * size_t(sources));
    }
    if (mesh.attachment_count > 0) {
        out.attached_particle.assign(mesh.attached_particle, mesh.attached_particle + mesh.attachment_count);
        out.attached_triangle.assign(mesh.attached_triangle, mesh.attached_triangle + mesh.attachment_count);
        out.attached_weight.assign(mesh.attached_weight, mesh.attached_weight + 3 * size_t(mesh.attachment_count));
    }
    if (mesh.skin.count > 0) {
        const SkinConstraints& k = mesh.skin;
        SkinBinding& b = out.skin;
        b.particle.assign(k.particle, k.particle + k.count);
        b.triangle.assign(k.triangle, k.triangle + k.count);
        b.weight.assign(k.weight, k.weight + 3 * size_t(k.count));
        b.rest_offset_m.assign(k.rest_offset_m, k.rest_offset_m + k.count);
        b.max_distance_m.assign(k.max_distance_m, k.max_distance_m + k.count);
        b.backstop_m.assign(k.backstop_m, k.backstop_m + k.count);
    }
}

// Step 1: stretch/shear on every edge, bend across every interior edge (caller indices).
std::vector<Spring> derive_springs(const ClothMeshDesc& mesh) {
    struct HalfEdge {
        uint64_t key;  // (min << 32) | max
        uint32_t opposite;
    };
    std::vector<HalfEdge> edges;
    edges.reserve(size_t(mesh.triangle_count) * 3);
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = v[e], b = v[(e + 1) % 3], o = v[(e + 2) % 3];
            edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), o});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const HalfEdge& l, const HalfEdge& r) {
        return l.key != r.key ? l.key < r.key : l.opposite < r.opposite;
    });
    std::vector<Spring> springs;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        springs.push_back({uint32_t(edges[i].key >> 32), uint32_t(edges[i].key), ConstraintKind::stretch, 0.0f});
        for (size_t k = i; k + 1 < j; ++k)  // interior edge: bend between the opposite vertices
            if (edges[k].opposite != edges[k + 1].opposite)
                springs.push_back({std::min(edges[k].opposite, edges[k + 1].opposite),
                                   std::max(edges[k].opposite, edges[k + 1].opposite), ConstraintKind::bend, 0.0f});
        i = j;
    }
    // A bend pair can coincide with an edge or another bend pair on odd meshes: keep one.
    std::sort(springs.begin(), springs.end(), [](const Spring& l, const Spring& r) {
        return l.a != r.a ? l.a < r.a : (l.b != r.b ? l.b < r.b : l.kind < r.kind);
    });
    springs.erase(std::unique(springs.begin(), springs.end(),
                              [](const Spring& l, const Spring& r) { return l.a == r.a && l.b == r.b; }),
                  springs.end());
    return springs;
}

// Rest lengths from ClothMeshDesc::rest_corners, by particle pair key (min << 32 | max): an edge's
// length in its triangles (their mean: the two sides of a gathered seam differ), and a bend pair's
// distance with its two triangles unfolded flat about their shared edge (a sewn seam rests flat).
struct CornerRest {
    std::vector<std::pair<uint64_t, float>> edge, bend;  // sorted by key
    static float find(const std::vector<std::pair<uint64_t, float>>& v, uint64_t key) {
        const auto it = std::lower_bound(v.begin(), v.end(), std::make_pair(key, -1.0f));
        return it != v.end() && it->first == key ? it->second : 0.0f;
    }
};

CornerRest corner_rest(const ClothMeshDesc& mesh) {
    struct HalfEdge {
        uint64_t key;
        uint32_t triangle, corner;  // the edge runs from corner to corner + 1 of the triangle
    };
    std::vector<HalfEdge> edges;
    for (uint32_t t = 0; t < mesh.triangle_count; ++t)
        for (uint32_t e = 0; e < 3; ++e) {
            const uint32_t a = mesh.triangles[3 * t + e], b = mesh.triangles[3 * t + (e + 1) % 3];
            edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, e});
        }
    std::sort(edges.begin(), edges.end(), [](const HalfEdge& l, const HalfEdge& r) {
        return l.key != r.key ? l.key < r.key : l.triangle < r.triangle;
    });
    // The opposite corner of half-edge h in the frame of its edge from particle min to max: the
    // distance along the edge from min and the height above it.
    auto frame = [&](const HalfEdge& h, float* along, float* height, float* length) {
        const Vec3* c = mesh.rest_corners + 3 * h.triangle;
        Vec3 p = c[h.corner], q = c[(h.corner + 1) % 3];
        if (mesh.triangles[3 * h.triangle + h.corner] > mesh.triangles[3 * h.triangle + (h.corner + 1) % 3]) std::swap(p, q);
        const Vec3 o = c[(h.corner + 2) % 3];
        const Vec3 e{q.x - p.x, q.y - p.y, q.z - p.z}, d{o.x - p.x, o.y - p.y, o.z - p.z};
        *length = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
        *along = *length > 0.0f ? (d.x * e.x + d.y * e.y + d.z * e.z) / *length : 0.0f;
        *height = std::sqrt(std::max(0.0f, d.x * d.x + d.y * d.y + d.z * d.z - *along * *along));
    };
    CornerRest out;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        float sum = 0.0f;
        for (; j < edges.size() && edges[j].key == edges[i].key; ++j) {
            float along, height, length;
            frame(edges[j], &along, &height, &length);
            sum += length;
        }
        out.edge.push_back({edges[i].key, sum / float(j - i)});
        for (size_t k = i; k + 1 < j; ++k) {
            const uint32_t o1 = mesh.triangles[3 * edges[k].triangle + (edges[k].corner + 2) % 3];
            const uint32_t o2 = mesh.triangles[3 * edges[k + 1].triangle + (edges[k + 1].corner + 2) % 3];
            if (o1 == o2) continue;
            float u1, h1, l1, u2, h2, l2;
            frame(edges[k], &u1, &h1, &l1);
            frame(edges[k + 1], &u2, &h2, &l2);
            out.bend.push_back({(uint64_t(std::min(o1, o2)) << 32) | std::max(o1, o2),
                                std::sqrt((u1 - u2) * (u1 - u2) + (h1 + h2) * (h1 + h2))});
        }
        i = j;
    }
    std::sort(out.edge.begin(), out.edge.end());
    std::sort(out.bend.begin(), out.bend.end());
    return out;
}

// Step 2: slot of every particle. Lattice particles go to plane (i & 1, j & 1), row-major with a
// common row width, so each spring family of the lattice joins two planes at one constant offset.
LatticeLayout assign_slots(const ClothMeshDesc& mesh, std::vector<uint32_t>& slot_of_particle,
                           uint32_t& slot_count) {
    const uint32_t n = mesh.particle_count;
    slot_of_particle.assign(n, kNoParticle);
    LatticeLayout layout;
    uint32_t next = 0;
    if (mesh.lattice != nullptr) {
        int32_t min_i = std::numeric_limits<int32_t>::max(), min_j = min_i, max_i = -1, max_j = -1;
        for (uint32_t p = 0; p < n; ++p) {
            const int32_t i = mesh.lattice[2 * p], j = mesh.lattice[2 * p + 1];
            if (i < 0 || j < 0) continue;
            min_i = std::min(min_i, i), max_i = std::max(max_i, i);
            min_j = std::min(min_j, j), max_j = std::max(max_j, j);
        }
        if (max_i >= 0) {
            // Keep the parity of the coordinates (a shift by an odd amount would swap planes, which
            // is harmless, but an even shift keeps slots predictable for tests).
            min_i &= ~1, min_j &= ~1;
            const uint64_t rows = uint64_t(max_i - min_i) / 2 + 1, cols = uint64_t(max_j - min_j) / 2 + 1;
            // Plane node (r, c) sits at r * stride + c - first of its plane. The stride is the
            // plane's width (a box) unless the mesh gives a narrower one: then a plane row runs on
            // into the next (a helix), so slanted panels packed side by side leave no holes at the
            // row ends (docs/pattern-format.md); every lattice family still joins two planes at one
            // constant slot offset.
            const uint64_t stride = mesh.lattice_plane_stride != 0 ? mesh.lattice_plane_stride : cols;
            uint64_t first = 0, plane = rows * cols;
            if (stride != cols) {
                first = ~uint64_t(0);
                uint64_t last = 0;
                for (uint32_t p = 0; p < n; ++p) {
                    const int32_t i = mesh.lattice[2 * p], j = mesh.lattice[2 * p + 1];
                    if (i < 0 || j < 0) continue;
                    const uint64_t at = uint64_t(i - min_i) / 2 * stride + uint64_t(j - min_j) / 2;
                    first = std::min(first, at), last = std::max(last, at);
                }
                plane = last - first + 1;
            }
            if (plane <= uint64_t(n) * 2 + 16) {  // a sparse lattice would waste more than it gains
                std::vector<uint8_t> taken(plane * 4, 0);
                uint32_t placed = 0;
                for (uint32_t p = 0; p < n; ++p) {
                    const int32_t i = mesh.lattice[2 * p], j = mesh.lattice[2 * p + 1];
                    if (i < 0 || j < 0) continue;
                    const uint32_t li = uint32_t(i - min_i), lj = uint32_t(j - min_j);
                    const uint64_t slot = ((li & 1) * 2 + (lj & 1)) * plane + (li >> 1) * stride + (lj >> 1) - first;
                    if (taken[slot]) continue;  // a duplicate coordinate: this particle goes last
                    taken[slot] = 1;
                    slot_of_particle[p] = uint32_t(slot);
                    ++placed;
                }
                next = uint32_t(plane * 4);
                layout.plane_rows = uint32_t(rows);
                layout.plane_cols = uint32_t(cols);
                layout.fine_rows = uint32_t(max_i - min_i + 1);
                layout.fine_cols = uint32_t(max_j - min_j + 1);
                layout.full = stride == cols && placed == n &&
                              uint64_t(placed) == uint64_t(layout.fine_rows) * layout.fine_cols;
            }
        }
    }
    for (uint32_t p = 0; p < n; ++p)
        if (slot_of_particle[p] == kNoParticle) slot_of_particle[p] = next++;
    slot_count = next;
    return layout;
}

ConstraintKind classify(const ClothMeshDesc& mesh, uint32_t a, uint32_t b, ConstraintKind kind) {
    if (kind != ConstraintKind::stretch || mesh.lattice == nullptr) return kind;
    const int32_t ai = mesh.lattice[2 * a], aj = mesh.lattice[2 * a + 1];
    const int32_t bi = mesh.lattice[2 * b], bj = mesh.lattice[2 * b + 1];
    if (ai < 0 || aj < 0 || bi < 0 || bj < 0) return kind;
    return (std::abs(ai - bi) == 1 && std::abs(aj - bj) == 1) ? ConstraintKind::shear : kind;
}

// kRunLaneNs and kIndexedLaneNs (weft/cook.h) in hundredths of a ns: integers, so every compiler cuts alike.
constexpr uint64_t kRunLaneCost = uint64_t(kRunLaneNs * 100.0 + 0.5), kIndexedLaneCost = uint64_t(kIndexedLaneNs * 100.0 + 0.5);
static_assert(kRunLaneCost == 71 && kIndexedLaneCost == 540);

// Cuts the maximal run s[i, j) at gaps of two slots or more where the pieces cost less than the
// whole (dynamic programming over those gaps, as build_tethers cuts its batches): a run lane at
// kRunLaneCost, every spring of a piece shorter than min_run_lanes at kIndexedLaneCost. A one-slot
// gap (where a full plane row ends) is never a cut: it seldom pays and would reorder the plain
// grids' runs. A sewn garment's runs bridge the holes its seams leave, and the maximal run padded
// every one of them.
void cut_run(const std::vector<Spring>& s, size_t i, size_t j, const CookOptions& options, std::vector<Unit>& units) {
    std::vector<size_t> edge{i};  // where a stretch without such a gap starts, then j
    for (size_t k = i + 1; k < j; ++k)
        if (s[k].a - s[k - 1].a > 2) edge.push_back(k);
    edge.push_back(j);
    const size_t n = edge.size() - 1;
    // cost[y]: the cheapest cut of s[i, edge[y]); start[y]: where its last piece starts (an edge index).
    std::vector<uint64_t> cost(n + 1, 0);
    std::vector<size_t> start(n + 1, 0);
    auto piece_cost = [&](size_t x, size_t y) {
        const size_t count = edge[y] - edge[x];
        if (count < options.min_run_lanes) return kIndexedLaneCost * count;
        return kRunLaneCost * round_up(s[edge[y] - 1].a - s[edge[x]].a + 1, options.simd_width);
    };
    for (size_t y = 1; y <= n; ++y) {
        cost[y] = ~uint64_t(0);
        for (size_t x = y; x-- > 0;) {
            const uint64_t c = cost[x] + piece_cost(x, y);
            if (c <= cost[y]) cost[y] = c, start[y] = x;  // ties: the longest piece
        }
    }
    std::vector<Unit> pieces;
    for (size_t y = n; y > 0; y = start[y]) {
        const size_t first = edge[start[y]], last = edge[y];
        if (last - first >= options.min_run_lanes) {
            pieces.push_back({uint32_t(first), uint32_t(last - first), s[first].a, s[first].b,
                              round_up(s[last - 1].a - s[first].a + 1, options.simd_width), s[first].kind, 0});
        } else {
            for (size_t k = last; k-- > first;) pieces.push_back({uint32_t(k), 1, s[k].a, s[k].b, 0, s[k].kind, 0});
        }
    }
    units.insert(units.end(), pieces.rbegin(), pieces.rend());
}

// Step 3: maximal runs among springs sorted by (kind, offset, a). A run's lanes (gaps and padding
// included) must not reach from its a side into its b side: round_up(lanes) <= offset. A maximal
// run bridges every gap up to max_run_gap and pads its tail to the SIMD width; cut_run then cuts it
// where that costs less.
std::vector<Unit> find_runs(const std::vector<Spring>& s, const CookOptions& options) {
    std::vector<Unit> units;
    for (size_t i = 0; i < s.size();) {
        const uint32_t offset = s[i].b - s[i].a;
        size_t j = i + 1;
        while (j < s.size() && s[j].kind == s[i].kind && s[j].b - s[j].a == offset &&
               s[j].a - s[j - 1].a <= options.max_run_gap + 1 &&
               round_up(s[j].a - s[i].a + 1, options.simd_width) <= offset)
            ++j;
        const uint32_t count = uint32_t(j - i);
        if (count >= options.min_run_lanes && count >= 1) {
            cut_run(s, i, j, options, units);
        } else {
            for (size_t k = i; k < j; ++k) units.push_back({uint32_t(k), 1, s[k].a, s[k].b, 0, s[k].kind, 0});
        }
        i = j;
    }
    return units;
}

// Step 4: first-fit colouring. Stretch units first, then shear, then bend; long runs before short
// ones. A unit that fits none of kMaxColours goes to the overflow colour.
uint32_t colour_units(std::vector<Unit>& units, const std::vector<Spring>& s, uint32_t slot_count) {
    std::stable_sort(units.begin(), units.end(), [](const Unit& l, const Unit& r) {
        if (l.kind != r.kind) return l.kind < r.kind;
        if (l.count != r.count) return l.count > r.count;
        return l.count == 1 && (l.a0 != r.a0 ? l.a0 < r.a0 : l.b0 < r.b0);
    });
    std::vector<uint64_t> used(slot_count, 0);
    uint32_t colours = 0;
    for (Unit& u : units) {
        uint64_t taken = 0;
        for (uint32_t k = 0; k < u.count; ++k) taken |= used[s[u.first + k].a] | used[s[u.first + k].b];
        if (taken == ~uint64_t(0)) {
            u.colour = kOverflowColour;
            continue;
        }
        uint32_t c = 0;
        while (taken & (uint64_t(1) << c)) ++c;
        u.colour = uint16_t(c);
        colours = std::max(colours, c + 1);
        for (uint32_t k = 0; k < u.count; ++k) {
            used[s[u.first + k].a] |= uint64_t(1) << c;
            used[s[u.first + k].b] |= uint64_t(1) << c;
        }
    }
    return colours;
}

void emit_batches(const std::vector<Unit>& units, const std::vector<Spring>& s, uint32_t colours, LaneArrays out,
                  uint32_t& on_runs) {
    on_runs = 0;
    auto emit_lane = [&](uint32_t a, uint32_t b, float rest, float weight) {
        out.index_a.push_back(a);
        out.index_b.push_back(b);
        out.rest_length.push_back(rest);
        out.lane_weight.push_back(weight);
    };
    for (uint32_t c = 0; c <= colours; ++c) {
        const uint16_t colour = c < colours ? uint16_t(c) : kOverflowColour;
        for (const Unit& u : units) {  // runs of this colour
            if (u.colour != colour || u.lanes == 0) continue;
            ConstraintBatch batch;
            batch.first_lane = uint32_t(out.rest_length.size());
            batch.lane_count = u.lanes;
            batch.a0 = u.a0;
            batch.b0 = u.b0;
            batch.kind = u.kind;
            batch.layout = BatchLayout::run;
            batch.colour = colour;
            uint32_t next = 0;
            for (uint32_t k = 0; k < u.count; ++k) {
                const Spring& sp = s[u.first + k];
                for (; u.a0 + next < sp.a; ++next) emit_lane(u.a0 + next, u.b0 + next, 0.0f, 0.0f);  // gap
                emit_lane(sp.a, sp.b, sp.rest, 1.0f);
                ++next;
            }
            for (; next < u.lanes; ++next) emit_lane(u.a0 + next, u.b0 + next, 0.0f, 0.0f);  // padding
            on_runs += u.count;
            out.batches.push_back(batch);
        }
        for (uint32_t kind = 0; kind < kConstraintKindCount; ++kind) {  // singles of this colour
            ConstraintBatch batch;
            batch.first_lane = uint32_t(out.rest_length.size());
            batch.kind = ConstraintKind(kind);
            batch.layout = BatchLayout::indexed;
            batch.colour = colour;
            for (const Unit& u : units) {
                if (u.colour != colour || u.lanes != 0 || uint32_t(u.kind) != kind) continue;
                const Spring& sp = s[u.first];
                emit_lane(sp.a, sp.b, sp.rest, 1.0f);
            }
            batch.lane_count = uint32_t(out.rest_length.size()) - batch.first_lane;
            if (batch.lane_count > 0) out.batches.push_back(batch);
        }
    }
}

}  // namespace

uint32_t cook_lanes(std::vector<Spring> springs, uint32_t slot_count, const CookOptions& options, LaneArrays out,
                    uint32_t* on_runs) {
    std::sort(springs.begin(), springs.end(), [](const Spring& l, const Spring& r) {
        if (l.kind != r.kind) return l.kind < r.kind;
        if (l.b - l.a != r.b - r.a) return l.b - l.a < r.b - r.a;
        return l.a < r.a;
    });
    std::vector<Unit> units = find_runs(springs, options);
    const uint32_t colours = colour_units(units, springs, slot_count);
    emit_batches(units, springs, colours, out, *on_runs);
    return colours;
}

uint32_t slots_touched(const std::vector<ConstraintBatch>& batches, uint32_t slot_count) {
    uint32_t touched = slot_count;
    for (const ConstraintBatch& b : batches)
        if (b.layout == BatchLayout::run) touched = std::max({touched, b.a0 + b.lane_count, b.b0 + b.lane_count});
    return touched;
}

namespace {

// Distances along the flat panels of a mesh that has no rest pose of its own (a sewn garment: a
// seam particle has one flat position per panel), for its tethers. A path along the surface is
// never shorter than the straight line between its ends in any pose, so a tether this long never
// pulls a garment at rest (Kim, Chentanez, Mueller 2012, geodesic LRA); every bit it is longer is
// sag the tether lets through. So the distances come from fast marching (Kimmel and Sethian 1998)
// on each triangle's flat corners: a particle's distance also follows a straight front across a
// triangle from its two other corners, not only the mesh's edges and bend pairs (two triangles
// unfolded about their edge), whose zigzag paths ran up to 6% long. A front crosses a triangle
// only from corners reached from the same source: fronts of two pins joined measure the distance
// to the row of pins, shorter than to either anchor (the sample skirt's waist pulled to 9x).
class RestGeodesics {
public:
    RestGeodesics(const ClothMeshDesc& mesh, const CornerRest& corners)
        : mesh_(mesh), first_(mesh.particle_count + 1, 0), first_triangle_(mesh.particle_count + 1, 0) {
        const uint32_t n = mesh.particle_count;
        for (const auto* pairs : {&corners.edge, &corners.bend})
            for (const auto& [key, length] : *pairs) ++first_[(key >> 32) + 1], ++first_[uint32_t(key) + 1];
        for (uint32_t p = 0; p < n; ++p) first_[p + 1] += first_[p];
        next_.resize(first_[n]);
        std::vector<uint32_t> fill(first_.begin(), first_.end() - 1);
        for (const auto* pairs : {&corners.edge, &corners.bend})
            for (const auto& [key, length] : *pairs) {
                const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
                next_[fill[a]++] = {b, length}, next_[fill[b]++] = {a, length};
            }
        for (uint32_t k = 0; k < 3 * mesh.triangle_count; ++k) ++first_triangle_[mesh.triangles[k] + 1];
        for (uint32_t p = 0; p < n; ++p) first_triangle_[p + 1] += first_triangle_[p];
        corner_of_.resize(first_triangle_[n]);
        fill.assign(first_triangle_.begin(), first_triangle_.end() - 1);
        for (uint32_t k = 0; k < 3 * mesh.triangle_count; ++k) corner_of_[fill[mesh.triangles[k]]++] = k;
    }
    // Distance of every particle from the nearest of `sources` (infinity where none is reachable),
    // and which source that is (ties to the lower source index).
    void from(const std::vector<uint32_t>& sources, std::vector<float>* distance, std::vector<uint32_t>* nearest) const {
        const uint32_t n = uint32_t(first_.size() - 1);
        distance->assign(n, std::numeric_limits<float>::infinity());
        nearest->assign(n, ~0u);
        std::vector<char> done(n, 0);
        using Entry = std::pair<float, uint32_t>;  // (distance, particle): ordered, so the result is deterministic
        std::vector<Entry> heap;
        const auto offer = [&](uint32_t q, float dq, uint32_t from_source) {
            if (dq < (*distance)[q] || (dq == (*distance)[q] && from_source < (*nearest)[q])) {
                if (dq < (*distance)[q]) heap.push_back({dq, q}), std::push_heap(heap.begin(), heap.end(), std::greater<>());
                (*distance)[q] = dq, (*nearest)[q] = from_source;
            }
        };
        for (uint32_t s : sources) (*distance)[s] = 0.0f, (*nearest)[s] = std::min((*nearest)[s], s), heap.push_back({0.0f, s});
        std::make_heap(heap.begin(), heap.end(), std::greater<>());
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), std::greater<>());
            const auto [d, p] = heap.back();
            heap.pop_back();
            if (d > (*distance)[p] || done[p]) continue;
            done[p] = 1;
            for (uint32_t k = first_[p]; k < first_[p + 1]; ++k) offer(next_[k].first, d + next_[k].second, (*nearest)[p]);
            // Each triangle around p with one other corner done: a front through both reaches the third.
            for (uint32_t k = first_triangle_[p]; k < first_triangle_[p + 1]; ++k) {
                const uint32_t t = corner_of_[k] / 3, c = corner_of_[k] % 3;
                for (uint32_t side = 1; side <= 2; ++side) {
                    const uint32_t cq = (c + side) % 3, cr = (c + 3 - side) % 3;
                    const uint32_t q = mesh_.triangles[3 * t + cq], r = mesh_.triangles[3 * t + cr];
                    if (!done[q] || done[r] || (*nearest)[q] != (*nearest)[p]) continue;
                    const Vec3* corner = mesh_.rest_corners + 3 * t;
                    const float dr = front_across(corner[c], corner[cq], corner[cr], d, (*distance)[q]);
                    offer(r, dr, (*nearest)[p]);
                }
            }
        }
    }

private:
    // The distance at C of a straight front that has reached A at tA and B at tB (fast marching's
    // update in triangle ABC), or infinity when the front's ray to C does not cross the edge AB
    // (the edges' paths then serve).
    static float front_across(Vec3 a, Vec3 b, Vec3 c, float ta, float tb) {
        const double ex = double(b.x) - a.x, ey = double(b.y) - a.y, ez = double(b.z) - a.z;
        const double cx = double(c.x) - a.x, cy = double(c.y) - a.y, cz = double(c.z) - a.z;
        const double length = std::sqrt(ex * ex + ey * ey + ez * ez);
        if (!(length > 0.0)) return std::numeric_limits<float>::infinity();
        const double along = (cx * ex + cy * ey + cz * ez) / length;  // C's foot on AB, from A
        const double height = std::sqrt(std::max(0.0, cx * cx + cy * cy + cz * cz - along * along));
        const double slope = (double(tb) - ta) / length;  // the front's direction: cosine along AB
        if (!(height > 0.0) || !(std::fabs(slope) < 1.0)) return std::numeric_limits<float>::infinity();
        const double across = std::sqrt(1.0 - slope * slope);
        const double foot = along - height * slope / across;  // where the ray to C crosses AB
        if (foot < 0.0 || foot > length) return std::numeric_limits<float>::infinity();
        return float(ta + slope * along + across * height);
    }

    const ClothMeshDesc& mesh_;
    std::vector<uint32_t> first_;                       // CSR over particles: edges and bend pairs
    std::vector<std::pair<uint32_t, float>> next_;      // (neighbour, rest length)
    std::vector<uint32_t> first_triangle_, corner_of_;  // CSR over particles: 3 * triangle + corner
};

// Step 5: tethers from every free particle to its nearest pinned particle and (with two per
// particle) its farthest, in runs of consecutive slots. How far: the straight line on the rest mesh,
// or, for a mesh with rest_corners (sewn), the path along its flat panels (RestGeodesics).
Result build_tethers(const ClothMeshDesc& mesh, const CornerRest& corners, const std::vector<uint32_t>& slot_of_particle,
                     const std::vector<float>& inverse_mass, const CookOptions& options, CookedCloth& out,
                     uint32_t* tethered) {
    *tethered = 0;
    if (options.tethers_per_particle > 2)
        return make_error(ErrorCode::out_of_range, "tethers_per_particle is %u, at most 2", options.tethers_per_particle);
    const Vec3* rest = mesh.rest_positions ? mesh.rest_positions : mesh.positions;
    std::vector<uint32_t> pinned;
    for (uint32_t p = 0; p < mesh.particle_count; ++p)
        if (inverse_mass[p] == 0.0f) pinned.push_back(p);
    if (pinned.empty() || options.tethers_per_particle == 0) return {};
    const bool two = options.tethers_per_particle == 2 && pinned.size() >= 2;
    // Sewn: geodesic distances from the nearest pin (one search from all of them), and from each
    // pin chosen as a farthest anchor (one search each, kept).
    const bool geodesic = mesh.rest_corners != nullptr;
    std::optional<RestGeodesics> geodesics;
    std::vector<float> nearest_distance;
    std::vector<uint32_t> nearest_pin;
    std::vector<std::pair<uint32_t, std::vector<float>>> from_pin;  // (pin, distances), sorted by pin
    if (geodesic) {
        geodesics.emplace(mesh, corners);
        geodesics->from(pinned, &nearest_distance, &nearest_pin);
    }
    const auto distance_from_pin = [&](uint32_t pin) -> const std::vector<float>& {
        auto it = std::lower_bound(from_pin.begin(), from_pin.end(), pin, [](const auto& e, uint32_t q) { return e.first < q; });
        if (it == from_pin.end() || it->first != pin) {
            std::vector<float> d;
            std::vector<uint32_t> unused;
            geodesics->from({pin}, &d, &unused);
            it = from_pin.insert(it, {pin, std::move(d)});
        }
        return it->second;
    };

    struct Tether {
        uint32_t anchor[2], slot;
        float rest[2];
    };
    std::vector<Tether> tethers;
    for (uint32_t p = 0; p < mesh.particle_count; ++p) {
        if (inverse_mass[p] == 0.0f) continue;
        if (geodesic && nearest_pin[p] == ~0u) continue;  // a piece no pin holds
        // The nearest pinned particle, and the farthest: two anchors far apart bound a particle in
        // two directions (a cloth hung along an edge cannot swing below its top pin's reach),
        // where the two nearest of a row of pins would be almost the same ball.
        float best[2] = {std::numeric_limits<float>::infinity(), -1.0f};
        uint32_t anchor[2] = {0, 0};
        for (uint32_t q : pinned) {  // ties to the lower index
            const float d = distance(rest[p], rest[q]);
            if (d < best[0]) best[0] = d, anchor[0] = q;
        }
        for (uint32_t q : pinned) {  // another pin, even where two are equally far (odd grids)
            const float d = distance(rest[p], rest[q]);
            if (q != anchor[0] && d > best[1]) best[1] = d, anchor[1] = q;
        }
        if (geodesic) {  // the nearest along the panels; the farthest in the pose, at its distance along them
            best[0] = nearest_distance[p], anchor[0] = nearest_pin[p];
            if (two && anchor[1] == anchor[0]) anchor[1] = pinned[pinned[0] == anchor[0] ? 1 : 0];
            if (two) best[1] = distance_from_pin(anchor[1])[p];
            if (two && !std::isfinite(best[1])) anchor[1] = anchor[0], best[1] = best[0];
        }
        if (!two) best[1] = best[0], anchor[1] = anchor[0];
        Tether t{{slot_of_particle[anchor[0]], slot_of_particle[anchor[1]]}, slot_of_particle[p], {best[0], best[1]}};
        if (t.anchor[1] < t.anchor[0]) std::swap(t.anchor[0], t.anchor[1]), std::swap(t.rest[0], t.rest[1]);
        tethers.push_back(t);
    }
    // Batches: runs of tethered slots at most simd_width apart, the gaps padded. A batch whose lanes
    // share one anchor pair holds it (the axis once per batch); grouped by pair alone, a dressed
    // garment's few attachment anchors, each holding particles side by side, left its batches 79%
    // padding. So a run whose pair groups would pad it more than twice over gives each lane its own
    // anchors (kTetherLaneAnchors): such a lane costs about twice one of a shared pair (gathers, its
    // own axis; the flag pinned along its pole: 18.3 us a step per lane against 9.3 by pairs, 6% padded).
    const float padding = std::numeric_limits<float>::infinity();
    const uint32_t width = options.simd_width;
    bool any_per_lane = false;
    auto emit = [&](float a, float b, const uint32_t anchor[2]) {
        out.tether_rest[0].push_back(a);
        out.tether_rest[1].push_back(b);
        out.tether_anchor[0].push_back(anchor[0]);
        out.tether_anchor[1].push_back(anchor[1]);
    };
    // One batch of tethers [first, last), in slot order, at most `width` slots apart.
    auto emit_batch = [&](const Tether* first, const Tether* last, bool per_lane) {
        TetherBatch batch;
        batch.first_lane = uint32_t(out.tether_rest[0].size());
        batch.particle0 = first->slot;
        batch.anchor[0] = per_lane ? kTetherLaneAnchors : first->anchor[0];
        batch.anchor[1] = per_lane ? kTetherLaneAnchors : first->anchor[1];
        any_per_lane = any_per_lane || per_lane;
        uint32_t next = 0;
        for (const Tether* t = first; t != last; ++t) {
            for (; batch.particle0 + next < t->slot; ++next) emit(padding, padding, t->anchor);
            emit(t->rest[0], t->rest[1], t->anchor);
            ++next;
        }
        batch.lane_count = round_up(next, width);
        for (; next < batch.lane_count; ++next) emit(padding, padding, last[-1].anchor);
        out.tether_batches.push_back(batch);
    };
    // Tethers [first, last) cut into batches with the fewest lanes: a batch pads every hole in its
    // slot span and its tail to `width`, so bridging a hole of g slots costs g lanes and cutting
    // there costs a tail; the cheapest cuts by dynamic programming over batches of at most
    // kMaxSpan slots (a longer batch can always be cut on a multiple of `width` for free).
    auto emit_batches = [&](const Tether* first, const Tether* last, bool per_lane) {
        constexpr uint32_t kMaxSpan = 512;
        const size_t n = size_t(last - first);
        std::vector<uint32_t> lanes(n + 1, 0), start(n + 1, 0);  // best lanes for first[0..j), its last batch's start
        for (size_t j = 1; j <= n; ++j) {
            lanes[j] = ~0u;
            for (size_t i = j; i-- > 0 && first[j - 1].slot - first[i].slot < kMaxSpan;) {
                const uint32_t cost = lanes[i] + round_up(first[j - 1].slot - first[i].slot + 1, width);
                if (cost <= lanes[j]) lanes[j] = cost, start[j] = uint32_t(i);  // ties: the longest batch
            }
        }
        std::vector<size_t> cuts;
        for (size_t j = n; j > 0; j = start[j]) cuts.push_back(start[j]);
        std::reverse(cuts.begin(), cuts.end());
        cuts.push_back(n);
        for (size_t k = 0; k + 1 < cuts.size(); ++k) emit_batch(first + cuts[k], first + cuts[k + 1], per_lane);
    };
    // The run's tethers grouped by anchor pair (then slot, at most `width` apart): f(first, last).
    auto by_pair = [&](std::vector<Tether>& run, auto&& f) {
        std::sort(run.begin(), run.end(), [](const Tether& l, const Tether& r) {
            if (l.anchor[0] != r.anchor[0]) return l.anchor[0] < r.anchor[0];
            if (l.anchor[1] != r.anchor[1]) return l.anchor[1] < r.anchor[1];
            return l.slot < r.slot;
        });
        for (size_t i = 0; i < run.size();) {
            size_t j = i + 1;
            while (j < run.size() && run[j].anchor[0] == run[i].anchor[0] && run[j].anchor[1] == run[i].anchor[1] &&
                   run[j].slot - run[j - 1].slot <= width)
                ++j;
            f(run.data() + i, run.data() + j);
            i = j;
        }
    };
    std::sort(tethers.begin(), tethers.end(), [](const Tether& l, const Tether& r) { return l.slot < r.slot; });
    for (size_t i = 0; i < tethers.size();) {
        size_t j = i + 1;
        while (j < tethers.size() && tethers[j].slot - tethers[j - 1].slot <= width) ++j;
        std::vector<Tether> run(tethers.begin() + ptrdiff_t(i), tethers.begin() + ptrdiff_t(j));
        uint32_t pair_lanes = 0;
        by_pair(run, [&](const Tether* a, const Tether* b) { pair_lanes += round_up(b[-1].slot - a->slot + 1, width); });
        if (pair_lanes > 2 * round_up(tethers[j - 1].slot - tethers[i].slot + 1, width))
            emit_batches(tethers.data() + i, tethers.data() + j, true);
        else
            by_pair(run, [&](const Tether* a, const Tether* b) { emit_batches(a, b, false); });
        i = j;
    }
    if (!any_per_lane) out.tether_anchor[0].clear(), out.tether_anchor[1].clear();
    *tethered = uint32_t(tethers.size());
    return {};
}

// Triangles in slots for the wind pass (and rendering): first the runs, whole SIMD groups of
// triangles with the same corner offsets (b - a, c - a) and consecutive a (no padding lanes), so
// the SIMD pass loads their corners as vectors; then the rest (gathered by the SIMD pass), grouped
// by first-fit colour so that consecutive triangles share no vertex (the pass adds each triangle's
// force to its three vertices and would otherwise wait for the store of the triangle before).
void order_triangles(const ClothMeshDesc& mesh, const std::vector<uint32_t>& slot_of_particle, uint32_t slot_count,
                     const CookOptions& options, CookedCloth& out) {
    struct Tri {
        uint32_t a, b, c;  // slots, caller winding
        float rest_area_m2;
    };
    const Vec3* rest = mesh.rest_positions ? mesh.rest_positions : mesh.positions;
    std::vector<Tri> tris(mesh.triangle_count);
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        tris[t] = {slot_of_particle[v[0]], slot_of_particle[v[1]], slot_of_particle[v[2]],
                   triangle_area(rest[v[0]], rest[v[1]], rest[v[2]])};
        // The lowest slot first (winding kept): a lattice triangle of one shape then has the same
        // corner offsets whichever corner the mesh lists first, so all of them share one run.
        while (tris[t].a > tris[t].b || tris[t].a > tris[t].c) tris[t] = {tris[t].b, tris[t].c, tris[t].a, tris[t].rest_area_m2};
    }
    auto offsets = [](const Tri& t) { return std::pair<int64_t, int64_t>{int64_t(t.b) - t.a, int64_t(t.c) - t.a}; };
    std::sort(tris.begin(), tris.end(), [&](const Tri& l, const Tri& r) {
        return offsets(l) != offsets(r) ? offsets(l) < offsets(r) : l.a < r.a;
    });
    // A run's three corner ranges must not overlap (each is loaded and stored as one vector).
    auto fits = [&](const Tri& first, uint32_t lanes) {
        const int64_t ob = int64_t(first.b) - first.a, oc = int64_t(first.c) - first.a;
        const int64_t len = lanes;
        return std::llabs(ob) >= len && std::llabs(oc) >= len && std::llabs(oc - ob) >= len &&
               std::max({first.a, first.b, first.c}) + lanes <= slot_count;
    };
    std::vector<Tri> singles;
    out.triangles.clear();
    out.wind_runs.clear();
    out.wind_lane_weight.clear();
    out.wind_rest_area.clear();
    out.wind_run_triangles = 0;
    for (size_t i = 0; i < tris.size();) {
        size_t j = i + 1;
        while (j < tris.size() && offsets(tris[j]) == offsets(tris[i]) && tris[j].a == tris[j - 1].a + 1 &&
               fits(tris[i], uint32_t(j + 1 - i)))
            ++j;
        // Whole SIMD groups of consecutive triangles only, so a run has no padding lanes; the rest
        // go to the gathered path, which packs them densely.
        const uint32_t lanes = uint32_t(j - i) / options.simd_width * options.simd_width;
        if (lanes > 0) {
            TriangleRun run;
            run.first_lane = uint32_t(out.wind_lane_weight.size());
            run.lane_count = lanes;
            run.a0 = tris[i].a, run.b0 = tris[i].b, run.c0 = tris[i].c;
            for (size_t k = i; k < i + lanes; ++k) {
                out.wind_lane_weight.push_back(1.0f);
                out.wind_rest_area.push_back(tris[k].rest_area_m2);
                out.triangles.insert(out.triangles.end(), {tris[k].a, tris[k].b, tris[k].c});
            }
            out.wind_run_triangles += lanes;
            out.wind_runs.push_back(run);
        }
        singles.insert(singles.end(), tris.begin() + i + lanes, tris.begin() + j);
        i = j;
    }
    std::vector<uint64_t> used(slot_count, 0);
    std::vector<std::pair<uint32_t, uint32_t>> coloured;  // (colour, single)
    for (uint32_t t = 0; t < singles.size(); ++t) {
        const uint64_t taken = used[singles[t].a] | used[singles[t].b] | used[singles[t].c];
        uint32_t colour = 0;
        while (colour < 63 && (taken & (uint64_t(1) << colour))) ++colour;
        for (uint32_t s : {singles[t].a, singles[t].b, singles[t].c}) used[s] |= uint64_t(1) << colour;
        coloured.push_back({colour, t});
    }
    std::stable_sort(coloured.begin(), coloured.end());
    for (const auto& [colour, t] : coloured) {
        out.triangles.insert(out.triangles.end(), {singles[t].a, singles[t].b, singles[t].c});
        out.wind_rest_area.push_back(singles[t].rest_area_m2);
    }
}

}  // namespace

Result cook_cloth(const ClothMeshDesc& mesh, const CookOptions& options, CookedCloth* out) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (Result r = check_options(options); !r.ok()) return r;
    if (Result r = check_mesh(mesh); !r.ok()) return r;
    const uint32_t n = mesh.particle_count;
    const Vec3* rest = mesh.rest_positions ? mesh.rest_positions : mesh.positions;

    std::vector<float> inverse_mass(n);
    for (uint32_t p = 0; p < n; ++p)
        inverse_mass[p] = mesh.masses ? (mesh.masses[p] > 0.0f ? 1.0f / mesh.masses[p] : 0.0f) : mesh.inverse_masses[p];

    CookedCloth cooked;
    cooked.simd_width = options.simd_width;
    uint32_t slot_count = 0;
    const LatticeLayout layout = assign_slots(mesh, cooked.slot_of_particle, slot_count);

    // Springs in slots; a spring between two pinned particles never moves anything: dropped.
    std::vector<Spring> springs;
    uint32_t counts[kConstraintKindCount] = {};
    const CornerRest corners = mesh.rest_corners != nullptr ? corner_rest(mesh) : CornerRest{};
    for (const Spring& s : derive_springs(mesh)) {
        if (inverse_mass[s.a] == 0.0f && inverse_mass[s.b] == 0.0f) continue;
        const uint32_t sa = cooked.slot_of_particle[s.a], sb = cooked.slot_of_particle[s.b];
        const ConstraintKind kind = classify(mesh, s.a, s.b, s.kind);
        const uint64_t key = (uint64_t(s.a) << 32) | s.b;
        const float length = mesh.rest_corners == nullptr       ? distance(rest[s.a], rest[s.b])
                             : s.kind == ConstraintKind::bend ? CornerRest::find(corners.bend, key)
                                                              : CornerRest::find(corners.edge, key);
        springs.push_back({std::min(sa, sb), std::max(sa, sb), kind, length});
        counts[uint32_t(kind)] += 1;
    }
    uint32_t on_runs = 0;
    const uint32_t colours =
        cook_lanes(std::move(springs), slot_count, options,
                   {cooked.rest_length, cooked.lane_weight, cooked.index_a, cooked.index_b, cooked.batches}, &on_runs);
    uint32_t tethered = 0;
    if (Result r = build_tethers(mesh, corners, cooked.slot_of_particle, inverse_mass, options, cooked, &tethered); !r.ok())
        return r;

    // Slots: every index a padded lane may touch exists; padding slots are pinned and at the origin.
    uint32_t touched = slots_touched(cooked.batches, slot_count);
    for (const TetherBatch& b : cooked.tether_batches) touched = std::max(touched, b.particle0 + b.lane_count);
    slot_count = round_up(touched, options.simd_width);
    cooked.particle_of_slot.assign(slot_count, kNoParticle);
    cooked.start_x.assign(slot_count, 0.0f);
    cooked.start_y.assign(slot_count, 0.0f);
    cooked.start_z.assign(slot_count, 0.0f);
    cooked.inverse_mass.assign(slot_count, 0.0f);
    for (uint32_t p = 0; p < n; ++p) {
        const uint32_t s = cooked.slot_of_particle[p];
        cooked.particle_of_slot[s] = p;
        cooked.start_x[s] = mesh.positions[p].x;
        cooked.start_y[s] = mesh.positions[p].y;
        cooked.start_z[s] = mesh.positions[p].z;
        cooked.inverse_mass[s] = inverse_mass[p];
    }
    std::vector<float> mass(n);
    for (uint32_t p = 0; p < n; ++p) mass[p] = inverse_mass[p] > 0.0f ? 1.0f / inverse_mass[p] : 0.0f;
    build_coarse_level(mesh, layout, mass, inverse_mass, options, cooked);
    order_triangles(mesh, cooked.slot_of_particle, slot_count, options, cooked);
    copy_garment(mesh, cooked);

    cooked.refresh_asset(n, colours, counts, on_runs, tethered);
    if (Result r = validate_asset(cooked.asset()); !r.ok()) return r;  // cooking bug: never hand it out
    *out = std::move(cooked);
    return {};
}

LanePadding lane_padding(const ClothAsset& a) {
    LanePadding p;
    p.constraints.all_lanes = a.lane_count;
    for (uint32_t l = 0; l < a.lane_count; ++l) p.constraints.padding_lanes += a.lane_weight[l] == 0.0f;
    p.coarse.all_lanes = a.coarse_lane_count;
    for (uint32_t l = 0; l < a.coarse_lane_count; ++l) p.coarse.padding_lanes += a.coarse_lane_weight[l] == 0.0f;
    p.tethers.all_lanes = a.tether_lane_count;
    for (uint32_t l = 0; l < a.tether_lane_count; ++l)
        p.tethers.padding_lanes += std::isinf(a.tether_rest[0][l]) && std::isinf(a.tether_rest[1][l]);
    p.wind.all_lanes = uint64_t(a.wind_lane_count) + (a.triangle_count - a.wind_run_triangles);
    for (uint32_t l = 0; l < a.wind_lane_count; ++l) p.wind.padding_lanes += a.wind_lane_weight[l] == 0.0f;
    for (const LanePadding::Pass* pass : {&p.constraints, &p.coarse, &p.tethers, &p.wind})
        p.padding_lanes += pass->padding_lanes, p.all_lanes += pass->all_lanes;
    return p;
}

}  // namespace weft
