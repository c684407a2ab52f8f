// Self-collision: the spatial hash, the triangles' walk and the point-face contact (self_collision.h).
#include "collide/self_collision.h"

#include "simd/float_w.h"  // WEFT_HAVE_AVX2 and its intrinsics

#include <cmath>
#include <utility>
#include <limits>

namespace weft {
namespace {

// Cell coordinates beyond this are not hashed (a position far from anything, or not finite):
// float -> int conversion of them would be undefined.
constexpr float kMaxCellCoordinate = 1.0e9f;

struct P3 {
    float x, y, z;
};
P3 operator-(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 operator+(P3 a, P3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator*(float s, P3 a) { return {s * a.x, s * a.y, s * a.z}; }
float dot(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
P3 cross(P3 a, P3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

P3 position(const Particles& p, uint32_t s) { return {p.x[s], p.y[s], p.z[s]}; }
P3 previous(const Particles& p, uint32_t s) { return {p.previous_x[s], p.previous_y[s], p.previous_z[s]}; }
void move(Particles& p, uint32_t s, P3 d) {
    p.x[s] += d.x;
    p.y[s] += d.y;
    p.z[s] += d.z;
}

// A cell coordinate, false when it is out of hashing range (or NaN).
bool cell_of(float coordinate_m, float inverse_cell, int32_t* out) {
    const float f = coordinate_m * inverse_cell;
    if (!(f > -kMaxCellCoordinate && f < kMaxCellCoordinate)) return false;
    const int32_t i = int32_t(f);  // towards zero; floor below
    *out = i - int32_t(f < float(i));
    return true;
}

// Cells next to each other along x take buckets next to each other, so a triangle's row of cells
// along x is one range of entries. (y, z) are hashed (Teschner et al. 2003's primes).
uint32_t bucket_of(int32_t ix, int32_t iy, int32_t iz, uint32_t mask) {
    return (((uint32_t(iy) * 19349663u) ^ (uint32_t(iz) * 83492791u)) + uint32_t(ix)) & mask;
}

// 1. The movable particles into their buckets: a counting sort, stable in slot order.
void sort_into_buckets(const Particles& p, SelfCollisionState& st) {
    const uint32_t table = st.table_size, mask = table - 1;
    const float inverse_cell = 1.0f / st.cell_m;
    for (uint32_t b = 0; b <= table; ++b) st.cell_start[b] = 0;
    for (uint32_t s = 0; s < p.slot_count; ++s) {
        int32_t ix, iy, iz;
        st.slot_bucket[s] = ~0u;
        if (!(p.inverse_mass[s] > 0.0f)) continue;  // pinned or padding: never pushed
        if (!cell_of(p.x[s], inverse_cell, &ix) || !cell_of(p.y[s], inverse_cell, &iy) ||
            !cell_of(p.z[s], inverse_cell, &iz))
            continue;
        const uint32_t b = bucket_of(ix, iy, iz, mask);
        st.slot_bucket[s] = b;
        st.cell_start[b] += 1;
    }
    uint32_t end = 0;  // cell_start[b] = the end of bucket b, then each entry placed before it
    for (uint32_t b = 0; b < table; ++b) st.cell_start[b] = end += st.cell_start[b];
    st.cell_start[table] = end;
    for (uint32_t s = p.slot_count; s-- > 0;) {
        const uint32_t b = st.slot_bucket[s];
        if (b == ~0u) continue;
        const uint32_t e = --st.cell_start[b];
        st.entry_slot[e] = s;
        st.entry_x[e] = p.x[s];
        st.entry_y[e] = p.y[s];
        st.entry_z[e] = p.z[s];
    }
    // The blocks of kSelfEntryBlock entries read past the last one: those lanes are never in a box.
    for (uint32_t e = end; e < end + kSelfEntryBlock; ++e) {
        st.entry_slot[e] = ~0u;
        st.entry_x[e] = st.entry_y[e] = st.entry_z[e] = std::numeric_limits<float>::quiet_NaN();
    }
}

struct Box {
    P3 lo, hi;
};
[[maybe_unused]] bool inside(const Box& b, P3 q) {
    return q.x >= b.lo.x && q.x <= b.hi.x && q.y >= b.lo.y && q.y <= b.hi.y && q.z >= b.lo.z && q.z <= b.hi.z;
}

// Entries [begin, end) inside `box` and not a corner of its triangle, kSelfEntryBlock at a time
// (one comparison mask per block, no branch per entry), each handed to `visit`.
template <class Visit>
void for_entries_in_box(const SelfCollisionState& st, uint32_t begin, uint32_t end, const Box& box,
                        const uint32_t corner[3], Visit&& visit) {
    for (uint32_t e = begin; e < end; e += kSelfEntryBlock) {
#if WEFT_HAVE_AVX2  // the same mask as the loop below, in one register (a mask: the same bits either way)
        const __m256 x = _mm256_loadu_ps(st.entry_x + e), y = _mm256_loadu_ps(st.entry_y + e),
                     z = _mm256_loadu_ps(st.entry_z + e);
        __m256 in = _mm256_and_ps(_mm256_cmp_ps(x, _mm256_set1_ps(box.lo.x), _CMP_GE_OQ),
                                  _mm256_cmp_ps(x, _mm256_set1_ps(box.hi.x), _CMP_LE_OQ));
        in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(y, _mm256_set1_ps(box.lo.y), _CMP_GE_OQ),
                                             _mm256_cmp_ps(y, _mm256_set1_ps(box.hi.y), _CMP_LE_OQ)));
        in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(z, _mm256_set1_ps(box.lo.z), _CMP_GE_OQ),
                                             _mm256_cmp_ps(z, _mm256_set1_ps(box.hi.z), _CMP_LE_OQ)));
        // The triangle's own corners are never its contacts: out of the mask too.
        const __m256i slot = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(st.entry_slot + e));
        const __m256i own = _mm256_or_si256(
            _mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(corner[0]))),
            _mm256_or_si256(_mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(corner[1]))),
                            _mm256_cmpeq_epi32(slot, _mm256_set1_epi32(int32_t(corner[2])))));
        in = _mm256_andnot_ps(_mm256_castsi256_ps(own), in);
        uint32_t inside = uint32_t(_mm256_movemask_ps(in));
#else
        uint32_t inside = 0;
        for (uint32_t k = 0; k < kSelfEntryBlock; ++k) {
            const float x = st.entry_x[e + k], y = st.entry_y[e + k], z = st.entry_z[e + k];
            const uint32_t slot = st.entry_slot[e + k];
            inside |= uint32_t((x >= box.lo.x) & (x <= box.hi.x) & (y >= box.lo.y) & (y <= box.hi.y) &
                               (z >= box.lo.z) & (z <= box.hi.z) & (slot != corner[0]) & (slot != corner[1]) &
                               (slot != corner[2]))
                      << k;
        }
#endif
        if (end - e < kSelfEntryBlock) inside &= (1u << (end - e)) - 1u;
        while (inside != 0) {
            const uint32_t k = uint32_t(__builtin_ctz(inside));
            inside &= inside - 1u;
            visit(st.entry_slot[e + k]);
        }
    }
}

// Coulomb friction on a contact of unit normal n (Macklin et al. 2014, sec. 6.1): the tangential part
// of `relative` (the two sides' motion over the substep) is cancelled up to `limit` (friction times
// the depth); returns the correction, divided by the contact's weight as the push is (zero: none).
P3 friction_slip(P3 relative, P3 n, float limit, float weight) {
    const P3 tangent = relative - dot(relative, n) * n;
    const float tangent2 = dot(tangent, tangent);
    if (!(tangent2 > 0.0f && limit > 0.0f)) return {0.0f, 0.0f, 0.0f};
    const float keep = tangent2 <= limit * limit ? 0.0f : 1.0f - limit / std::sqrt(tangent2);
    return ((keep - 1.0f) / weight) * tangent;  // cancels (1 - keep) of the tangent
}

float larger(float a, float b) { return a > b ? a : b; }  // inline, unlike std::fmax (no NaN here)
float smaller(float a, float b) { return a < b ? a : b; }

// A contact's PBD weight, sum w_i g_i^2 over its particles' inverse masses w_i and barycentric
// gradients g_i, raised where needed to the largest w_i g_i, so that no particle moves further than
// the contact's depth. Without it a closest point near an edge's pinned end (g of the movable end
// near 0) moved that end by depth / g: a garment whose attached waistband met a fold blew up.
// Where it applies the contact is resolved over the sweeps instead of at once.
float bounded_weight(float wg0, float wg1, float wg2, float wg3, float squared) {
    return larger(squared, larger(larger(wg0, wg1), larger(wg2, wg3)));
}

// A contact's thickness: the cloth's, but no more than kSelfThicknessPerEdge times the shortest
// edge (in the start pose) at any of its four particles. Where a garment's mesh is finer than the
// thickness (slivers at a seam, a panel meshed at 1 mm), particles a few edges apart along the
// cloth lie closer than the thickness without any fold, and pushing them apart to it tore the mesh
// (a pooled hem's 0.6 mm edges stretched 25 times their length in a frame).
float contact_thickness(const SelfCollisionState& st, const SelfCollisionArgs& args, uint32_t i, uint32_t j,
                        uint32_t k, uint32_t l) {
    const float* e = st.shortest_edge_m;
    return smaller(args.thickness_m, kSelfThicknessPerEdge * smaller(smaller(e[i], e[j]), smaller(e[k], e[l])));
}

// 3. Particle s against triangle (a, b, c): the push out to the thickness and friction. Returns
// whether they were in contact.
bool contact(Particles& p, uint32_t s, const uint32_t corner[3], const SelfCollisionArgs& args,
             const SelfCollisionState& st) {
    const P3 a = position(p, corner[0]), b = position(p, corner[1]), c = position(p, corner[2]);
    const P3 x = position(p, s);
    const P3 e1 = b - a, e2 = c - a, ax = x - a;
    // The projection's barycentric weights (Ericson 3.4); a point beside the face is left to the
    // triangle it lies over.
    const float d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
    const float d20 = dot(ax, e1), d21 = dot(ax, e2);
    const float denominator = d00 * d11 - d01 * d01;
    if (!(denominator > 1e-20f)) return false;  // degenerate (or NaN)
    const float v_scaled = d11 * d20 - d01 * d21, w_scaled = d00 * d21 - d01 * d20;  // times the denominator
    if (!(v_scaled >= 0.0f && w_scaled >= 0.0f && v_scaled + w_scaled <= denominator)) return false;
    const float v = v_scaled / denominator, w = w_scaled / denominator;
    const float u = 1.0f - v - w;
    const P3 n_raw = cross(e1, e2);
    const P3 n = (1.0f / std::sqrt(dot(n_raw, n_raw))) * n_raw;  // |n_raw|^2 = denominator > 0
    // The side the particle belongs on: where it was at the substep's start (it may have crossed
    // the face since). Near the face the plane's side is the sheet's side, also for a particle that
    // stood over a neighbouring triangle then.
    const P3 pa = previous(p, corner[0]), pb = previous(p, corner[1]), pc = previous(p, corner[2]);
    const P3 px = previous(p, s);
    const float side = dot(px - pa, cross(pb - pa, pc - pa)) < 0.0f ? -1.0f : 1.0f;
    const float distance = side * dot(ax, n);
    if (!(distance < args.thickness_m)) return false;  // beyond any contact's thickness
    const float thickness = contact_thickness(st, args, s, corner[0], corner[1], corner[2]);
    if (!(distance < thickness) || distance < -kSelfCaptureThicknesses * thickness) return false;
    const float wx = p.inverse_mass[s], wa = p.inverse_mass[corner[0]], wb = p.inverse_mass[corner[1]],
                wc = p.inverse_mass[corner[2]];
    const float weight = bounded_weight(wx, wa * u, wb * v, wc * w, wx + wa * u * u + wb * v * v + wc * w * w);  // > 0: s is movable
    // C = distance - thickness < 0; its gradient is side * n at x and -side * n * (u, v, w) at the corners.
    const P3 push = ((thickness - distance) / weight * side) * n;
    move(p, s, wx * push);
    move(p, corner[0], (-wa * u) * push);
    move(p, corner[1], (-wb * v) * push);
    move(p, corner[2], (-wc * w) * push);
    // Friction: the pair's relative tangential motion over the substep, cancelled up to
    // friction * |C| and shared the same way.
    const P3 moved_x = position(p, s) - px;
    const P3 moved_face = u * (position(p, corner[0]) - pa) + v * (position(p, corner[1]) - pb) +
                          w * (position(p, corner[2]) - pc);
    const P3 slip = friction_slip(moved_x - moved_face, n, args.friction * (thickness - distance), weight);
    if (slip.x != 0.0f || slip.y != 0.0f || slip.z != 0.0f) {
        move(p, s, wx * slip);
        move(p, corner[0], (-wa * u) * slip);
        move(p, corner[1], (-wb * v) * slip);
        move(p, corner[2], (-wc * w) * slip);
    }
    return true;
}

// One segment as the edge-edge screen reads it: its start, direction and squared length.
struct Segment {
    P3 start, direction;
    float length2;
};
Segment segment(P3 from, P3 to) {
    const P3 d = to - from;
    return {from, d, dot(d, d)};
}

// Whether the closest points of the lines through two segments lie inside both (Ericson 5.1.9),
// checked without a division: the screen before edge_contact, on positions read once a triangle.
[[maybe_unused]] bool closest_points_inside(const Segment& u, const Segment& v) {
    const P3 r0 = u.start - v.start;
    const float bb = dot(u.direction, v.direction), cc = dot(u.direction, r0), ff = dot(v.direction, r0);
    const float denominator = u.length2 * v.length2 - bb * bb;
    const float a_scaled = bb * ff - cc * v.length2, b_scaled = bb * a_scaled + ff * denominator;
    return denominator > 1e-6f * u.length2 * v.length2 && a_scaled > 0.0f && a_scaled < denominator &&
           b_scaled > 0.0f && b_scaled < denominator * v.length2;
}

// 4. Edge (s, r) against the triangle's edge (q0, q1), none of them shared. Returns whether they were
// in contact.
bool edge_contact(Particles& p, uint32_t s, uint32_t r, uint32_t q0, uint32_t q1, const SelfCollisionArgs& args,
                  const SelfCollisionState& st) {
    const P3 p0 = position(p, s), p1 = position(p, r), e0 = position(p, q0), e1 = position(p, q1);
    // The closest points p0 + a (p1 - p0) and e0 + b (e1 - e0) (Ericson 5.1.9), where both lie
    // inside their segments; an end's closest point is a particle's, which the face tests keep.
    const P3 d1 = p1 - p0, d2 = e1 - e0, r0 = p0 - e0;
    const float aa = dot(d1, d1), ee = dot(d2, d2), bb = dot(d1, d2), cc = dot(d1, r0), ff = dot(d2, r0);
    const float denominator = aa * ee - bb * bb;
    if (!(denominator > 1e-6f * aa * ee)) return false;  // parallel (or degenerate, or NaN)
    // Both parameters inside their segments, checked before any division: a = a_scaled / D and
    // b = b_scaled / (D ee).
    const float a_scaled = bb * ff - cc * ee, b_scaled = bb * a_scaled + ff * denominator;
    if (!(a_scaled > 0.0f && a_scaled < denominator && b_scaled > 0.0f && b_scaled < denominator * ee)) return false;
    const float a = a_scaled / denominator, b = (bb * a + ff) / ee;
    if (!(a > 0.0f && a < 1.0f && b > 0.0f && b < 1.0f)) return false;
    const P3 gap = (p0 + a * d1) - (e0 + b * d2);
    const float gap2 = dot(gap, gap), widest = kSelfCaptureThicknesses * args.thickness_m;
    if (!(gap2 < widest * widest)) return false;  // beyond any contact's capture depth
    const float thickness = contact_thickness(st, args, s, r, q0, q1), capture = kSelfCaptureThicknesses * thickness;
    if (!(gap2 < capture * capture)) return false;
    // Which side edge (s, r) stood on at the substep's start, seen from the other edge.
    const P3 pp0 = previous(p, s), pp1 = previous(p, r), pe0 = previous(p, q0), pe1 = previous(p, q1);
    const P3 before = (pp0 + a * (pp1 - pp0)) - (pe0 + b * (pe1 - pe0));
    const float before2 = dot(before, before);
    P3 n;
    float distance;
    if (dot(gap, before) < 0.0f && before2 > 0.0f) {  // crossed since: back to the former side
        n = (1.0f / std::sqrt(before2)) * before;
        distance = dot(gap, n);
    } else {
        if (!(gap2 < thickness * thickness) || !(gap2 > 0.0f)) return false;
        distance = std::sqrt(gap2);
        n = (1.0f / distance) * gap;
    }
    const float ws = p.inverse_mass[s], wr = p.inverse_mass[r], w0 = p.inverse_mass[q0], w1 = p.inverse_mass[q1];
    const float weight = bounded_weight(ws * (1.0f - a), wr * a, w0 * (1.0f - b), w1 * b,
                                        ws * (1.0f - a) * (1.0f - a) + wr * a * a + w0 * (1.0f - b) * (1.0f - b) + w1 * b * b);
    if (!(weight > 0.0f)) return false;
    const P3 push = ((thickness - distance) / weight) * n;
    move(p, s, (ws * (1.0f - a)) * push);
    move(p, r, (wr * a) * push);
    move(p, q0, (-w0 * (1.0f - b)) * push);
    move(p, q1, (-w1 * b) * push);
    // Friction, as for a face: the closest points' relative tangential motion over the substep,
    // cancelled up to friction * |C|, shared the same way.
    const P3 moved_edge = (1.0f - a) * (position(p, s) - pp0) + a * (position(p, r) - pp1);
    const P3 moved_other = (1.0f - b) * (position(p, q0) - pe0) + b * (position(p, q1) - pe1);
    const P3 slip = friction_slip(moved_edge - moved_other, n, args.friction * (thickness - distance), weight);
    if (slip.x != 0.0f || slip.y != 0.0f || slip.z != 0.0f) {
        move(p, s, (ws * (1.0f - a)) * slip);
        move(p, r, (wr * a) * slip);
        move(p, q0, (-w0 * (1.0f - b)) * slip);
        move(p, q1, (-w1 * b) * slip);
    }
    return true;
}

// What a visit's edge screens read: the triangle (its first corner, unit normal, widened box and
// sides, all as read when the triangle's walk began) and the visited particle.
struct EdgeScreen {
    P3 a, normal;
    Box box;
    const Segment* sides;  // [3], corner k to k + 1
    const uint32_t* corner;
    P3 xs;
    float hs;          // xs's height over the triangle's plane
    float capture, flat;
    uint32_t s;
};

// 4a. The screens of edges (s, r) for r = others[0 .. count), count <= kSelfEntryBlock: bit k of
// inside[e] is set when edge k passes them and its closest points to side e lie inside both
// segments (closest_points_inside), the ones edge_contact then tests. Screened: r a corner of the
// triangle; r < s, movable and in the box (the edge is visited from r); both ends beyond the capture
// depth on one side of the plane, or both within `flat` of it. All of an edge list is screened from
// the positions before any of its contacts: those move s, r and the triangle's corners, none of
// which a later edge of the list reads (xs and the sides were read before, as always). Eight lanes
// at a time with AVX2, the same IEEE operations lane by lane as the scalar loop: the same bits.
void screen_edges(const Particles& p, const EdgeScreen& q, const uint32_t* others, uint32_t count,
                  uint32_t inside[3]) {
#if WEFT_HAVE_AVX2
    alignas(32) uint32_t index[kSelfEntryBlock];
    for (uint32_t k = 0; k < kSelfEntryBlock; ++k) index[k] = k < count ? others[k] : q.s;  // a readable slot
    const __m256i r = _mm256_load_si256(reinterpret_cast<const __m256i*>(index));
    // Eight scalar loads a coordinate: faster than vgatherdps here (a handful of edges, latency-bound).
    const auto gather = [&index](const float* base) {
        return _mm256_setr_ps(base[index[0]], base[index[1]], base[index[2]], base[index[3]], base[index[4]],
                              base[index[5]], base[index[6]], base[index[7]]);
    };
    const __m256 xr = gather(p.x), yr = gather(p.y), zr = gather(p.z);
    const auto set = [](float v) { return _mm256_set1_ps(v); };
    const auto add = [](__m256 u, __m256 v) { return _mm256_add_ps(u, v); };
    const auto sub = [](__m256 u, __m256 v) { return _mm256_sub_ps(u, v); };
    const auto mul = [](__m256 u, __m256 v) { return _mm256_mul_ps(u, v); };
    const auto cmp_gt = [](__m256 u, __m256 v) { return _mm256_cmp_ps(u, v, _CMP_GT_OQ); };
    const auto cmp_lt = [](__m256 u, __m256 v) { return _mm256_cmp_ps(u, v, _CMP_LT_OQ); };
    const auto both = [](__m256 u, __m256 v) { return _mm256_and_ps(u, v); };
    const auto either = [](__m256 u, __m256 v) { return _mm256_or_ps(u, v); };
    inside[0] = inside[1] = inside[2] = 0;
    // Heights over the plane first (dot(xr - a, normal), summed as dot() does): in a flat or
    // unfolded neighbourhood they leave no lane, and nothing more is read.
    const __m256 dx = sub(xr, set(q.a.x)), dy = sub(yr, set(q.a.y)), dz = sub(zr, set(q.a.z));
    const __m256 hr = add(add(mul(dx, set(q.normal.x)), mul(dy, set(q.normal.y))), mul(dz, set(q.normal.z)));
    const __m256 cap = set(q.capture), hs = set(q.hs);
    const __m256 above = both(cmp_gt(hs, cap), cmp_gt(hr, cap));
    const __m256 below = both(cmp_lt(hs, set(-q.capture)), cmp_lt(hr, set(-q.capture)));
    const __m256 sign = set(-0.0f);
    const __m256 flat = both(cmp_lt(_mm256_andnot_ps(sign, hs), set(q.flat)), cmp_lt(_mm256_andnot_ps(sign, hr), set(q.flat)));
    const __m256 lane_used = _mm256_castsi256_ps(
        _mm256_cmpgt_epi32(_mm256_set1_epi32(int32_t(count)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)));
    __m256 keep = _mm256_andnot_ps(either(either(above, below), flat), lane_used);
    if (_mm256_movemask_ps(keep) == 0) return;
    // r a corner, or r < s, movable and in the box: not this visit's edge.
    const __m256i corner_hit = _mm256_or_si256(
        _mm256_cmpeq_epi32(r, _mm256_set1_epi32(int32_t(q.corner[0]))),
        _mm256_or_si256(_mm256_cmpeq_epi32(r, _mm256_set1_epi32(int32_t(q.corner[1]))),
                        _mm256_cmpeq_epi32(r, _mm256_set1_epi32(int32_t(q.corner[2])))));
    // r < s as unsigned: flip the sign bits for the signed comparison.
    const __m256i flip = _mm256_set1_epi32(int32_t(0x80000000u));
    const __m256i lower = _mm256_cmpgt_epi32(_mm256_xor_si256(_mm256_set1_epi32(int32_t(q.s)), flip), _mm256_xor_si256(r, flip));
    __m256 in_box = both(_mm256_cmp_ps(xr, set(q.box.lo.x), _CMP_GE_OQ), _mm256_cmp_ps(xr, set(q.box.hi.x), _CMP_LE_OQ));
    in_box = both(in_box, both(_mm256_cmp_ps(yr, set(q.box.lo.y), _CMP_GE_OQ), _mm256_cmp_ps(yr, set(q.box.hi.y), _CMP_LE_OQ)));
    in_box = both(in_box, both(_mm256_cmp_ps(zr, set(q.box.lo.z), _CMP_GE_OQ), _mm256_cmp_ps(zr, set(q.box.hi.z), _CMP_LE_OQ)));
    const __m256 from_r = both(_mm256_castsi256_ps(lower), both(cmp_gt(gather(p.inverse_mass), set(0.0f)), in_box));
    keep = _mm256_andnot_ps(either(_mm256_castsi256_ps(corner_hit), from_r), keep);
    if (_mm256_movemask_ps(keep) == 0) return;
    // closest_points_inside(segment(xs, xr), side e).
    const __m256 ux = sub(xr, set(q.xs.x)), uy = sub(yr, set(q.xs.y)), uz = sub(zr, set(q.xs.z));
    const __m256 ul2 = add(add(mul(ux, ux), mul(uy, uy)), mul(uz, uz));
    for (uint32_t e = 0; e < 3; ++e) {
        const Segment& v = q.sides[e];
        const P3 r0 = q.xs - v.start;
        const __m256 bb = add(add(mul(ux, set(v.direction.x)), mul(uy, set(v.direction.y))), mul(uz, set(v.direction.z)));
        const __m256 cc = add(add(mul(ux, set(r0.x)), mul(uy, set(r0.y))), mul(uz, set(r0.z)));
        const __m256 ff = set(dot(v.direction, r0)), vl2 = set(v.length2);
        const __m256 denominator = sub(mul(ul2, vl2), mul(bb, bb));
        const __m256 a_scaled = sub(mul(bb, ff), mul(cc, vl2));
        const __m256 b_scaled = add(mul(bb, a_scaled), mul(ff, denominator));
        __m256 ok = both(keep, cmp_gt(denominator, mul(mul(set(1e-6f), ul2), vl2)));
        ok = both(ok, both(cmp_gt(a_scaled, set(0.0f)), cmp_lt(a_scaled, denominator)));
        ok = both(ok, both(cmp_gt(b_scaled, set(0.0f)), cmp_lt(b_scaled, mul(denominator, vl2))));
        inside[e] = uint32_t(_mm256_movemask_ps(ok));
    }
#else
    inside[0] = inside[1] = inside[2] = 0;
    for (uint32_t k = 0; k < count; ++k) {
        const uint32_t r = others[k];
        if (r == q.corner[0] || r == q.corner[1] || r == q.corner[2]) continue;
        const P3 xr = position(p, r);
        if (r < q.s && p.inverse_mass[r] > 0.0f && weft::inside(q.box, xr)) continue;
        const float hr = dot(xr - q.a, q.normal);
        if ((q.hs > q.capture && hr > q.capture) || (q.hs < -q.capture && hr < -q.capture) ||
            (std::fabs(q.hs) < q.flat && std::fabs(hr) < q.flat))
            continue;
        const Segment edge = segment(q.xs, xr);
        for (uint32_t e = 0; e < 3; ++e) inside[e] |= uint32_t(closest_points_inside(edge, q.sides[e])) << k;
    }
#endif
}

}  // namespace

void build_self_collision_edges(const ClothAsset& asset, SelfCollisionState& st) {
    const uint32_t slots = asset.slot_count;
    uint32_t* const first = st.edge_first;
    uint32_t* const cursor = st.slot_bucket;  // scratch
    for (uint32_t s = 0; s <= slots; ++s) first[s] = 0;
    for (uint32_t k = 0; k < 3 * asset.triangle_count; ++k) first[asset.triangles[k] + 1] += 2;
    for (uint32_t s = 0; s < slots; ++s) first[s + 1] += first[s];
    for (uint32_t s = 0; s < slots; ++s) cursor[s] = first[s];
    for (uint32_t t = 0; t < asset.triangle_count; ++t)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t a = asset.triangles[3 * t + k];
            st.edge_other[cursor[a]++] = asset.triangles[3 * t + (k + 1) % 3];
            st.edge_other[cursor[a]++] = asset.triangles[3 * t + (k + 2) % 3];
        }
    // Each slot's list sorted (insertion: a handful each) and its repeats dropped, packed down.
    uint32_t packed = 0;
    for (uint32_t s = 0; s < slots; ++s) {
        const uint32_t begin = first[s], end = first[s + 1];
        uint32_t* list = st.edge_other + begin;
        for (uint32_t i = 1; i < end - begin; ++i)
            for (uint32_t j = i; j > 0 && list[j - 1] > list[j]; --j) std::swap(list[j - 1], list[j]);
        first[s] = packed;
        for (uint32_t i = 0; i < end - begin; ++i)
            if (i == 0 || list[i] != list[i - 1]) st.edge_other[packed++] = list[i];
    }
    first[slots] = packed;
    for (uint32_t s = 0; s < slots; ++s) {
        float shortest = std::numeric_limits<float>::infinity();
        for (uint32_t k = first[s]; k < first[s + 1]; ++k) {
            const uint32_t r = st.edge_other[k];
            const float dx = asset.start_x[r] - asset.start_x[s], dy = asset.start_y[r] - asset.start_y[s],
                        dz = asset.start_z[r] - asset.start_z[s];
            shortest = std::fmin(shortest, std::sqrt(dx * dx + dy * dy + dz * dz));
        }
        st.shortest_edge_m[s] = shortest;  // +inf for a slot on no triangle
    }
}

uint32_t self_collision_table_size(uint32_t slot_count) {
    uint32_t size = 16;
    while (size < slot_count) size *= 2;
    return size;
}

float self_collision_cell_m(const ClothAsset& a, float thickness_m) {
    double sum = 0.0;
    uint32_t counted = 0;
    for (uint32_t t = 0; t < a.triangle_count; ++t) {
        float longest2 = 0.0f;
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t i = a.triangles[3 * t + k], j = a.triangles[3 * t + (k + 1) % 3];
            const float dx = a.start_x[j] - a.start_x[i], dy = a.start_y[j] - a.start_y[i],
                        dz = a.start_z[j] - a.start_z[i];
            longest2 = std::fmax(longest2, dx * dx + dy * dy + dz * dz);
        }
        if (!std::isfinite(longest2)) continue;
        sum += std::sqrt(double(longest2));
        counted += 1;
    }
    const float reach = (1.0f + kSelfCaptureThicknesses) * thickness_m;
    const float edge = counted > 0 ? float(sum / counted) : 0.0f;
    return std::fmax(edge + 2.0f * reach, 1e-3f);
}

void collide_self(Particles& p, const ClothAsset& asset, SelfCollisionState& st, const SelfCollisionArgs& args,
                  SelfCollisionCounts& counts) {
    sort_into_buckets(p, st);
    const uint32_t mask = st.table_size - 1;
    const float inverse_cell = 1.0f / st.cell_m;
    const float reach = (1.0f + kSelfCaptureThicknesses) * args.thickness_m;
    for (uint32_t t = 0; t < asset.triangle_count; ++t) {
        const uint32_t corner[3] = {asset.triangles[3 * t], asset.triangles[3 * t + 1], asset.triangles[3 * t + 2]};
        // 2. The triangle's box, widened by the reach, and the cells it meets.
        const P3 a = position(p, corner[0]), b = position(p, corner[1]), c = position(p, corner[2]);
        const auto lower = [](float u, float v, float w) { return u < v ? (u < w ? u : w) : (v < w ? v : w); };
        const auto upper = [](float u, float v, float w) { return u > v ? (u > w ? u : w) : (v > w ? v : w); };
        const Box box{{lower(a.x, b.x, c.x) - reach, lower(a.y, b.y, c.y) - reach, lower(a.z, b.z, c.z) - reach},
                      {upper(a.x, b.x, c.x) + reach, upper(a.y, b.y, c.y) + reach, upper(a.z, b.z, c.z) + reach}};
        int32_t c0[3], c1[3];
        if (!cell_of(box.lo.x, inverse_cell, &c0[0]) || !cell_of(box.lo.y, inverse_cell, &c0[1]) ||
            !cell_of(box.lo.z, inverse_cell, &c0[2]) || !cell_of(box.hi.x, inverse_cell, &c1[0]) ||
            !cell_of(box.hi.y, inverse_cell, &c1[1]) || !cell_of(box.hi.z, inverse_cell, &c1[2]))
            continue;  // not finite: the health check's business
        if (uint32_t(c1[0] - c0[0]) >= kMaxSelfCellsPerAxis || uint32_t(c1[1] - c0[1]) >= kMaxSelfCellsPerAxis ||
            uint32_t(c1[2] - c0[2]) >= kMaxSelfCellsPerAxis) {
            counts.skipped_triangles += 1;
            continue;
        }
        const Segment sides[3] = {segment(a, b), segment(b, c), segment(c, a)};  // corner k to k + 1
        // The triangle's unit normal, found for its first candidate (most triangles have none).
        P3 normal{0.0f, 0.0f, 0.0f};
        bool normal_found = false;
        const float flat = kSelfFlatThicknesses * args.thickness_m, capture = kSelfCaptureThicknesses * args.thickness_m;
        const auto visit = [&](uint32_t s) {
            if (!normal_found) {
                const P3 n = cross(b - a, c - a);
                const float n2 = dot(n, n);
                normal = n2 > 0.0f ? (1.0f / std::sqrt(n2)) * n : P3{0.0f, 0.0f, 0.0f};
                normal_found = true;
            }
            counts.contacts += uint64_t(contact(p, s, corner, args, st));
            // 4. Its edges against the triangle's, those the screens leave (screen_edges).
            const P3 xs = position(p, s);
            const EdgeScreen screen{a, normal, box, sides, corner, xs, dot(xs - a, normal), capture, flat, s};
            for (uint32_t first = st.edge_first[s], end = st.edge_first[s + 1]; first < end; first += kSelfEntryBlock) {
                const uint32_t count = end - first < kSelfEntryBlock ? end - first : kSelfEntryBlock;
                uint32_t inside[3];
                screen_edges(p, screen, st.edge_other + first, count, inside);
                for (uint32_t k = 0; k < count; ++k)
                    for (uint32_t e = 0; e < 3; ++e)
                        if ((inside[e] >> k) & 1u)
                            counts.contacts += uint64_t(edge_contact(p, s, st.edge_other[first + k], corner[e],
                                                                     corner[(e + 1) % 3], args, st));
            }
        };
        for (int32_t iy = c0[1]; iy <= c1[1]; ++iy)
            for (int32_t iz = c0[2]; iz <= c1[2]; ++iz) {
                // The row of cells c0[0]..c1[0] along x: consecutive buckets, maybe wrapping round.
                const uint32_t first = bucket_of(c0[0], iy, iz, mask), last = bucket_of(c1[0], iy, iz, mask);
                if (first <= last) {
                    for_entries_in_box(st, st.cell_start[first], st.cell_start[last + 1], box, corner, visit);
                } else {
                    for_entries_in_box(st, st.cell_start[first], st.cell_start[mask + 1], box, corner, visit);
                    for_entries_in_box(st, st.cell_start[0], st.cell_start[last + 1], box, corner, visit);
                }
            }
    }
}

}  // namespace weft
