// Self-collision: the spatial hash, the triangles' walk and the point-face contact (self_collision.h).
#include "collide/self_collision.h"

#include <cmath>
#include <utility>
#include <limits>

namespace weft {
namespace {

float smaller(float a, float b) { return a < b ? a : b; }  // inline, unlike std::fmin (no NaN here)

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
    const P3 a = position(p, corner[0]), x = position(p, s);
    FacePoint f;
    if (!project_onto_face(a, position(p, corner[1]), position(p, corner[2]), x, &f)) return false;
    const float u = f.u, v = f.v, w = f.w;
    const P3 n = f.n, ax = x - a;
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
    SegmentPoints c;
    if (!closest_points_inside(position(p, s), position(p, r), position(p, q0), position(p, q1), &c)) return false;
    const float a = c.a, b = c.b;
    const P3 gap = c.gap;
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

// 4a. The screens of edges (s, r) for r = others[0 .. count), count <= kHashEntryBlock: bit k of
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
    alignas(32) uint32_t index[kHashEntryBlock];
    for (uint32_t k = 0; k < kHashEntryBlock; ++k) index[k] = k < count ? others[k] : q.s;  // a readable slot
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
    build_mesh_edges(asset, st.edge_first, st.edge_other, st.hash.slot_bucket);
    const uint32_t* const first = st.edge_first;
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

float self_collision_cell_m(const ClothAsset& a, float thickness_m) {
    const float reach = (1.0f + kSelfCaptureThicknesses) * thickness_m;
    const float edge = mean_longest_edge_m(a.start_x, a.start_y, a.start_z, a.triangles, a.triangle_count);
    return std::fmax(edge + 2.0f * reach, 1e-3f);
}

void collide_self(Particles& p, const ClothAsset& asset, SelfCollisionState& st, const SelfCollisionArgs& args,
                  SelfCollisionCounts& counts) {
    sort_into_buckets(p.x, p.y, p.z, p.inverse_mass, p.slot_count, st.hash);
    const float reach = (1.0f + kSelfCaptureThicknesses) * args.thickness_m;
    for (uint32_t t = 0; t < asset.triangle_count; ++t) {
        const uint32_t corner[3] = {asset.triangles[3 * t], asset.triangles[3 * t + 1], asset.triangles[3 * t + 2]};
        // 2. The triangle's box, widened by the reach, and the particles in it.
        const P3 a = position(p, corner[0]), b = position(p, corner[1]), c = position(p, corner[2]);
        const Box box = widened_box(a, b, c, reach);
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
            for (uint32_t first = st.edge_first[s], end = st.edge_first[s + 1]; first < end; first += kHashEntryBlock) {
                const uint32_t count = end - first < kHashEntryBlock ? end - first : kHashEntryBlock;
                uint32_t inside[3];
                screen_edges(p, screen, st.edge_other + first, count, inside);
                for (uint32_t k = 0; k < count; ++k)
                    for (uint32_t e = 0; e < 3; ++e)
                        if ((inside[e] >> k) & 1u)
                            counts.contacts += uint64_t(edge_contact(p, s, st.edge_other[first + k], corner[e],
                                                                     corner[(e + 1) % 3], args, st));
            }
        };
        // A triangle stretched over more cells than kMaxHashCellsPerAxis is skipped and counted; one
        // that is not finite is the health check's business.
        if (for_particles_in_box(st.hash, box, corner, visit) == BoxWalk::too_large) counts.skipped_triangles += 1;
    }
}

}  // namespace weft
