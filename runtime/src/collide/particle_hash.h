// A spatial hash of particles, rebuilt each substep, and the point-face arithmetic that cloth-cloth
// contact shares: a cloth against itself (self_collision.h) and against the cloths it is worn over
// (layers.h).
//
// The hash: particles sorted by bucket (a counting sort, stable in slot order) with their positions
// copied beside them; a box's cells are walked row by row along x, where cells next to each other
// take buckets next to each other, and kHashEntryBlock entries are tested against the box at once.
// Nothing allocates: the arrays are carved from the world's block at add_cloth.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "kernels.h"        // Particles
#include "weft/cloth_asset.h"
#include "simd/float_w.h"  // WEFT_HAVE_AVX2 and its intrinsics

namespace weft {

// The box walk tests this many hash entries at once; the entry arrays hold as many more.
inline constexpr uint32_t kHashEntryBlock = 8;
// Cells a box may span along one axis before it is skipped (and counted by the caller).
inline constexpr uint32_t kMaxHashCellsPerAxis = 4;

struct ParticleHash {
    uint32_t* cell_start = nullptr;   // [table_size + 1]: each bucket's first entry (prefix sums)
    uint32_t* entry_slot = nullptr;   // [slots + kHashEntryBlock]: the hashed slots, sorted by bucket
    uint32_t* slot_bucket = nullptr;  // [slots]: each slot's bucket this substep (~0u: none)
    float* entry_x = nullptr;         // [slots + kHashEntryBlock]: their positions at the sort, metres
    float* entry_y = nullptr;
    float* entry_z = nullptr;
    uint32_t table_size = 0;  // a power of two >= 16
    float cell_m = 0.0f;      // the cells' edge, metres
};

// The bucket count for `slot_count` slots: the next power of two, at least 16 (at most twice the slots).
inline uint32_t particle_hash_table_size(uint32_t slot_count) {
    uint32_t size = 16;
    while (size < slot_count) size *= 2;
    return size;
}

struct P3 {
    float x, y, z;
};
inline P3 operator-(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline P3 operator*(float s, P3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline float dot(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline P3 cross(P3 a, P3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

inline P3 position(const Particles& p, uint32_t s) { return {p.x[s], p.y[s], p.z[s]}; }
inline P3 previous(const Particles& p, uint32_t s) { return {p.previous_x[s], p.previous_y[s], p.previous_z[s]}; }
inline void move(Particles& p, uint32_t s, P3 d) {
    p.x[s] += d.x;
    p.y[s] += d.y;
    p.z[s] += d.z;
}

struct Box {
    P3 lo, hi;
};
inline bool inside(const Box& b, P3 q) {
    return q.x >= b.lo.x && q.x <= b.hi.x && q.y >= b.lo.y && q.y <= b.hi.y && q.z >= b.lo.z && q.z <= b.hi.z;
}

// A triangle's box widened by `reach`.
inline Box widened_box(P3 a, P3 b, P3 c, float reach) {
    const auto lower = [](float u, float v, float w) { return u < v ? (u < w ? u : w) : (v < w ? v : w); };
    const auto upper = [](float u, float v, float w) { return u > v ? (u > w ? u : w) : (v > w ? v : w); };
    return {{lower(a.x, b.x, c.x) - reach, lower(a.y, b.y, c.y) - reach, lower(a.z, b.z, c.z) - reach},
            {upper(a.x, b.x, c.x) + reach, upper(a.y, b.y, c.y) + reach, upper(a.z, b.z, c.z) + reach}};
}

// Cell coordinates beyond this are not hashed (a position far from anything, or not finite):
// float -> int conversion of them would be undefined.
inline constexpr float kMaxCellCoordinate = 1.0e9f;

// A cell coordinate, false when it is out of hashing range (or NaN).
inline bool cell_of(float coordinate_m, float inverse_cell, int32_t* out) {
    const float f = coordinate_m * inverse_cell;
    if (!(f > -kMaxCellCoordinate && f < kMaxCellCoordinate)) return false;
    const int32_t i = int32_t(f);  // towards zero; floor below
    *out = i - int32_t(f < float(i));
    return true;
}

// Cells next to each other along x take buckets next to each other, so a box's row of cells along x
// is one range of entries. (y, z) are hashed (Teschner et al. 2003's primes).
inline uint32_t bucket_of(int32_t ix, int32_t iy, int32_t iz, uint32_t mask) {
    return (((uint32_t(iy) * 19349663u) ^ (uint32_t(iz) * 83492791u)) + uint32_t(ix)) & mask;
}

// Slots [0, count) at (x, y, z) into their buckets, those with `inverse_mass` > 0 only (all of them
// when it is null): a counting sort, stable in slot order.
inline void sort_into_buckets(const float* x, const float* y, const float* z, const float* inverse_mass,
                              uint32_t count, ParticleHash& h) {
    const uint32_t table = h.table_size, mask = table - 1;
    const float inverse_cell = 1.0f / h.cell_m;
    for (uint32_t b = 0; b <= table; ++b) h.cell_start[b] = 0;
    for (uint32_t s = 0; s < count; ++s) {
        int32_t ix, iy, iz;
        h.slot_bucket[s] = ~0u;
        if (inverse_mass != nullptr && !(inverse_mass[s] > 0.0f)) continue;  // pinned or padding: never pushed
        if (!cell_of(x[s], inverse_cell, &ix) || !cell_of(y[s], inverse_cell, &iy) || !cell_of(z[s], inverse_cell, &iz))
            continue;
        const uint32_t b = bucket_of(ix, iy, iz, mask);
        h.slot_bucket[s] = b;
        h.cell_start[b] += 1;
    }
    uint32_t end = 0;  // cell_start[b] = the end of bucket b, then each entry placed before it
    for (uint32_t b = 0; b < table; ++b) h.cell_start[b] = end += h.cell_start[b];
    h.cell_start[table] = end;
    for (uint32_t s = count; s-- > 0;) {
        const uint32_t b = h.slot_bucket[s];
        if (b == ~0u) continue;
        const uint32_t e = --h.cell_start[b];
        h.entry_slot[e] = s;
        h.entry_x[e] = x[s];
        h.entry_y[e] = y[s];
        h.entry_z[e] = z[s];
    }
    // The blocks of kHashEntryBlock entries read past the last one: those lanes are never in a box.
    for (uint32_t e = end; e < end + kHashEntryBlock; ++e) {
        h.entry_slot[e] = ~0u;
        h.entry_x[e] = h.entry_y[e] = h.entry_z[e] = std::numeric_limits<float>::quiet_NaN();
    }
}

// Entries [begin, end) inside `box` and not one of `excluded` (a triangle's own corners; ~0u for
// none: padding entries are outside every box), kHashEntryBlock at a time (one comparison mask per
// block, no branch per entry), each handed to `visit`.
template <class Visit>
void for_entries_in_box(const ParticleHash& h, uint32_t begin, uint32_t end, const Box& box,
                        const uint32_t excluded[3], Visit&& visit) {
    for (uint32_t e = begin; e < end; e += kHashEntryBlock) {
#if WEFT_HAVE_AVX2  // the same mask as the loop below, in one register (a mask: the same bits either way)
        const __m256 x = _mm256_loadu_ps(h.entry_x + e), y = _mm256_loadu_ps(h.entry_y + e),
                     z = _mm256_loadu_ps(h.entry_z + e);
        __m256 in = _mm256_and_ps(_mm256_cmp_ps(x, _mm256_set1_ps(box.lo.x), _CMP_GE_OQ),
                                  _mm256_cmp_ps(x, _mm256_set1_ps(box.hi.x), _CMP_LE_OQ));
        in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(y, _mm256_set1_ps(box.lo.y), _CMP_GE_OQ),
                                             _mm256_cmp_ps(y, _mm256_set1_ps(box.hi.y), _CMP_LE_OQ)));
        in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(z, _mm256_set1_ps(box.lo.z), _CMP_GE_OQ),
                                             _mm256_cmp_ps(z, _mm256_set1_ps(box.hi.z), _CMP_LE_OQ)));
        const __m256i slot = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(h.entry_slot + e));
        const __m256i own = _mm256_or_si256(
            _mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(excluded[0]))),
            _mm256_or_si256(_mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(excluded[1]))),
                            _mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(excluded[2])))));
        in = _mm256_andnot_ps(_mm256_castsi256_ps(own), in);
        uint32_t inside = uint32_t(_mm256_movemask_ps(in));
#else
        uint32_t inside = 0;
        for (uint32_t k = 0; k < kHashEntryBlock; ++k) {
            const float x = h.entry_x[e + k], y = h.entry_y[e + k], z = h.entry_z[e + k];
            const uint32_t slot = h.entry_slot[e + k];
            inside |= uint32_t((x >= box.lo.x) & (x <= box.hi.x) & (y >= box.lo.y) & (y <= box.hi.y) &
                               (z >= box.lo.z) & (z <= box.hi.z) & (slot != excluded[0]) & (slot != excluded[1]) &
                               (slot != excluded[2]))
                      << k;
        }
#endif
        if (end - e < kHashEntryBlock) inside &= (1u << (end - e)) - 1u;
        while (inside != 0) {
            const uint32_t k = uint32_t(__builtin_ctz(inside));
            inside &= inside - 1u;
            visit(h.entry_slot[e + k]);
        }
    }
}

// What for_particles_in_box found of a box.
enum class BoxWalk : uint8_t { walked, not_finite, too_large };

// Every hashed particle inside `box` (but `excluded`), in bucket order, handed to `visit`. A box
// over more than kMaxHashCellsPerAxis cells along an axis, or not finite, is not walked.
template <class Visit>
BoxWalk for_particles_in_box(const ParticleHash& h, const Box& box, const uint32_t excluded[3], Visit&& visit) {
    const uint32_t mask = h.table_size - 1;
    const float inverse_cell = 1.0f / h.cell_m;
    int32_t c0[3], c1[3];
    if (!cell_of(box.lo.x, inverse_cell, &c0[0]) || !cell_of(box.lo.y, inverse_cell, &c0[1]) ||
        !cell_of(box.lo.z, inverse_cell, &c0[2]) || !cell_of(box.hi.x, inverse_cell, &c1[0]) ||
        !cell_of(box.hi.y, inverse_cell, &c1[1]) || !cell_of(box.hi.z, inverse_cell, &c1[2]))
        return BoxWalk::not_finite;
    if (uint32_t(c1[0] - c0[0]) >= kMaxHashCellsPerAxis || uint32_t(c1[1] - c0[1]) >= kMaxHashCellsPerAxis ||
        uint32_t(c1[2] - c0[2]) >= kMaxHashCellsPerAxis)
        return BoxWalk::too_large;
    for (int32_t iy = c0[1]; iy <= c1[1]; ++iy)
        for (int32_t iz = c0[2]; iz <= c1[2]; ++iz) {
            // The row of cells c0[0]..c1[0] along x: consecutive buckets, maybe wrapping round.
            const uint32_t first = bucket_of(c0[0], iy, iz, mask), last = bucket_of(c1[0], iy, iz, mask);
            if (first <= last) {
                for_entries_in_box(h, h.cell_start[first], h.cell_start[last + 1], box, excluded, visit);
            } else {
                for_entries_in_box(h, h.cell_start[first], h.cell_start[mask + 1], box, excluded, visit);
                for_entries_in_box(h, h.cell_start[0], h.cell_start[last + 1], box, excluded, visit);
            }
        }
    return BoxWalk::walked;
}

// Where q projects onto triangle (a, b, c): barycentric weights (u, v, w) and the unit normal of the
// winding (Ericson 3.4). False beside the face (a point there is left to the triangle it lies over)
// or for a degenerate triangle.
struct FacePoint {
    float u, v, w;
    P3 n;
};
inline bool project_onto_face(P3 a, P3 b, P3 c, P3 q, FacePoint* out) {
    const P3 e1 = b - a, e2 = c - a, aq = q - a;
    const float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
    const float d20 = dot(aq, e1), d21 = dot(aq, e2);
    const float denominator = d00 * d11 - d01 * d01;
    if (!(denominator > 1e-20f)) return false;  // degenerate (or NaN)
    const float v_scaled = d11 * d20 - d01 * d21, w_scaled = d00 * d21 - d01 * d20;  // times the denominator
    if (!(v_scaled >= 0.0f && w_scaled >= 0.0f && v_scaled + w_scaled <= denominator)) return false;
    out->v = v_scaled / denominator;
    out->w = w_scaled / denominator;
    out->u = 1.0f - out->v - out->w;
    const P3 n = cross(e1, e2);
    out->n = (1.0f / std::sqrt(dot(n, n))) * n;  // |n|^2 = denominator > 0
    return true;
}

// The closest points p0 + a (p1 - p0) and e0 + b (e1 - e0) of two segments (Ericson 5.1.9), where
// both lie inside their segments (0 < a, b < 1), and gap = the first minus the second; false for
// parallel or degenerate segments and closest points at or beyond an end (an end's closest point is
// a particle's, which the point-face tests keep). Both parameters are checked before any division.
struct SegmentPoints {
    float a, b;
    P3 gap;
};
inline bool closest_points_inside(P3 p0, P3 p1, P3 e0, P3 e1, SegmentPoints* out) {
    const P3 d1 = p1 - p0, d2 = e1 - e0, r0 = p0 - e0;
    const float aa = dot(d1, d1), ee = dot(d2, d2), bb = dot(d1, d2), cc = dot(d1, r0), ff = dot(d2, r0);
    const float denominator = aa * ee - bb * bb;
    if (!(denominator > 1e-6f * aa * ee)) return false;  // parallel (or degenerate, or NaN)
    // a = a_scaled / D and b = b_scaled / (D ee).
    const float a_scaled = bb * ff - cc * ee, b_scaled = bb * a_scaled + ff * denominator;
    if (!(a_scaled > 0.0f && a_scaled < denominator && b_scaled > 0.0f && b_scaled < denominator * ee)) return false;
    const float a = a_scaled / denominator, b = (bb * a + ff) / ee;
    if (!(a > 0.0f && a < 1.0f && b > 0.0f && b < 1.0f)) return false;
    *out = {a, b, (p0 + a * d1) - (e0 + b * d2)};
    return true;
}

inline float larger(float a, float b) { return a > b ? a : b; }  // inline, unlike std::fmax (no NaN here)

// A contact's PBD weight, sum w_i g_i^2 over its particles' inverse masses w_i and barycentric
// gradients g_i, raised where needed to the largest w_i g_i, so that no particle moves further than
// the contact's depth. Without it a closest point near an edge's pinned end (g of the movable end
// near 0) moved that end by depth / g: a garment whose attached waistband met a fold blew up.
// Where it applies the contact is resolved over the sweeps instead of at once.
inline float bounded_weight(float wg0, float wg1, float wg2, float wg3, float squared) {
    return larger(squared, larger(larger(wg0, wg1), larger(wg2, wg3)));
}

// Coulomb friction on a contact of unit normal n (Macklin et al. 2014, sec. 6.1): the tangential part
// of `relative` (the two sides' motion over the substep) is cancelled up to `limit` (friction times
// the depth); returns the correction, divided by the contact's weight as the push is (zero: none).
inline P3 friction_slip(P3 relative, P3 n, float limit, float weight) {
    const P3 tangent = relative - dot(relative, n) * n;
    const float tangent2 = dot(tangent, tangent);
    if (!(tangent2 > 0.0f && limit > 0.0f)) return {0.0f, 0.0f, 0.0f};
    const float keep = tangent2 <= limit * limit ? 0.0f : 1.0f - limit / std::sqrt(tangent2);
    return ((keep - 1.0f) / weight) * tangent;  // cancels (1 - keep) of the tangent
}

// The mean longest triangle edge of a mesh at (x, y, z), metres (0 without a finite triangle): the
// hash's cells are this plus twice a contact's reach, so a triangle's widened box spans about two
// cells per axis.
inline float mean_longest_edge_m(const float* x, const float* y, const float* z, const uint32_t* triangles,
                                 uint32_t triangle_count) {
    double sum = 0.0;
    uint32_t counted = 0;
    for (uint32_t t = 0; t < triangle_count; ++t) {
        float longest2 = 0.0f;
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t i = triangles[3 * t + k], j = triangles[3 * t + (k + 1) % 3];
            const float dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
            longest2 = std::fmax(longest2, dx * dx + dy * dy + dz * dz);
        }
        if (!std::isfinite(longest2)) continue;
        sum += std::sqrt(double(longest2));
        counted += 1;
    }
    return counted > 0 ? float(sum / counted) : 0.0f;
}

// A mesh's edges by particle: slot s's neighbours are edge_other[edge_first[s] .. edge_first[s + 1]),
// each once, sorted. edge_first holds slot_count + 1 entries, edge_other 6 per triangle (room for
// every triangle's corners' two edges), `scratch` slot_count.
inline void build_mesh_edges(const ClothAsset& asset, uint32_t* edge_first, uint32_t* edge_other, uint32_t* scratch) {
    const uint32_t slots = asset.slot_count;
    uint32_t* const first = edge_first;
    uint32_t* const cursor = scratch;
    for (uint32_t s = 0; s <= slots; ++s) first[s] = 0;
    for (uint32_t k = 0; k < 3 * asset.triangle_count; ++k) first[asset.triangles[k] + 1] += 2;
    for (uint32_t s = 0; s < slots; ++s) first[s + 1] += first[s];
    for (uint32_t s = 0; s < slots; ++s) cursor[s] = first[s];
    for (uint32_t t = 0; t < asset.triangle_count; ++t)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t a = asset.triangles[3 * t + k];
            edge_other[cursor[a]++] = asset.triangles[3 * t + (k + 1) % 3];
            edge_other[cursor[a]++] = asset.triangles[3 * t + (k + 2) % 3];
        }
    // Each slot's list sorted (insertion: a handful each) and its repeats dropped, packed down.
    uint32_t packed = 0;
    for (uint32_t s = 0; s < slots; ++s) {
        const uint32_t begin = first[s], end = first[s + 1];
        uint32_t* list = edge_other + begin;
        for (uint32_t i = 1; i < end - begin; ++i)
            for (uint32_t j = i; j > 0 && list[j - 1] > list[j]; --j) std::swap(list[j - 1], list[j]);
        first[s] = packed;
        for (uint32_t i = 0; i < end - begin; ++i)
            if (i == 0 || list[i] != list[i - 1]) edge_other[packed++] = list[i];
    }
    first[slots] = packed;
}

}  // namespace weft
