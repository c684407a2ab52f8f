// The body pass through the step's own two-level hierarchy (collide/body.h: BodyHierarchy), as a
// template over the wide float type, instantiated for the scalar and the AVX2 path
// (body_kernels_scalar.cpp, body_kernels_avx2.cpp). Both paths test the same leaves in the same
// order with the same operations and pick the closest triangle by the same scalar rule, so they give
// bit-identical results (tested).
//
// Per cluster of kClusterSlots slots consecutive in the pass's order (the Morton order of their
// start positions, collide/body.h: order_for_body_pass, so they are neighbours): one walk of the
// hierarchy with the cluster's box widened by the reach collects every leaf whose (motion-widened)
// box the reach of any of its particles can meet; then each particle tests those leaves' boxes
// eight at a time, and the eight triangles of every leaf its reach meets at once (Ericson's closest
// point on a triangle, Real-Time Collision Detection 5.1.5, written branch-free). Conservative: a
// leaf is skipped only when its box lies beyond the reach.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "collide/body.h"
#include "collide/colliders.h"
#include "simd/float_w.h"

namespace weft {
namespace body_query {

inline constexpr uint32_t kClusterSlots = 16;
inline constexpr uint32_t kMaxCandidates = 512;  // leaves per batch of a cluster (more: several batches)

inline uint32_t lane_bits(simd::Mask1 m) { return m.v ? 1u : 0u; }
#if WEFT_HAVE_AVX2
inline uint32_t lane_bits(simd::Mask8 m) { return uint32_t(_mm256_movemask_ps(m.v)); }
#endif

// The first of a leaf's kLeafTriangles lanes with the least value of d2 (the lane a scan in lane
// order keeping only strictly smaller values ends on): one pass, no branch per lane.
inline uint32_t first_least(const float* d2, simd::Float1) {
    float least = d2[0];
    uint32_t lane = 0;
    for (uint32_t k = 1; k < kLeafTriangles; ++k) {
        lane = d2[k] < least ? k : lane;
        least = d2[k] < least ? d2[k] : least;
    }
    return lane;
}
#if WEFT_HAVE_AVX2
inline uint32_t first_least(const float* d2, simd::Float8) {
    static_assert(kLeafTriangles == 8, "one AVX2 register per leaf");
    const __m256 d = _mm256_loadu_ps(d2);
    __m256 m = _mm256_min_ps(d, _mm256_permute_ps(d, _MM_SHUFFLE(2, 3, 0, 1)));
    m = _mm256_min_ps(m, _mm256_permute_ps(m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = _mm256_min_ps(m, _mm256_permute2f128_ps(m, m, 1));
    return uint32_t(__builtin_ctz(uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(d, m, _CMP_EQ_OQ)))));
}
#endif

// Appends the candidates i + k of the set bits k of `bits` (lanes of one eight-wide box test) to
// the hit list, in lane order: their leaf, box distance and squared reach. Branch-free (a data-dependent loop
// over the bits cost a mispredicted branch per group); the AVX2 form writes eight lanes and advances
// by the count, so the lists have 8 entries of slack.
inline uint32_t append_hits(uint32_t bits, const uint32_t* leaf, simd::Float1 box2, simd::Float1 reach2, uint32_t n,
                            uint32_t* leaf_out, float* box2_out, float* reach2_out) {
    leaf_out[n] = leaf[0];
    box2_out[n] = box2.v;
    reach2_out[n] = reach2.v;
    return n + bits;
}
#if WEFT_HAVE_AVX2
// Lane indices of each 8-bit mask's set bits, packed low (three bits each).
struct PackTable {
    uint32_t lanes[256];
    constexpr PackTable() : lanes() {
        for (uint32_t m = 0; m < 256; ++m) {
            uint32_t packed = 0, n = 0;
            for (uint32_t k = 0; k < 8; ++k)
                if (m >> k & 1u) packed |= k << (3 * n++);
            lanes[m] = packed;
        }
    }
};
inline constexpr PackTable kPackTable{};
// The permutation that moves the set lanes of `bits` to the front, in order.
inline __m256i pack_order(uint32_t bits) {
    const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    return _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(int(kPackTable.lanes[bits])), shifts), _mm256_set1_epi32(7));
}
inline uint32_t append_hits(uint32_t bits, const uint32_t* leaf, simd::Float8 box2, simd::Float8 reach2, uint32_t n,
                            uint32_t* leaf_out, float* box2_out, float* reach2_out) {
    const __m256i order = pack_order(bits);
    const __m256i leaves = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(leaf));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(leaf_out + n), _mm256_permutevar8x32_epi32(leaves, order));
    _mm256_storeu_ps(box2_out + n, _mm256_permutevar8x32_ps(box2.v, order));
    _mm256_storeu_ps(reach2_out + n, _mm256_permutevar8x32_ps(reach2.v, order));
    return n + uint32_t(__builtin_popcount(bits));
}
#endif

// The closest point of `p` on a leaf's eight triangles strictly within `limit2`: its lane (the first
// of the closest), squared distance and weights v (of b) and w (of c); false when no triangle is
// within `limit2`. Triangles whose plane lies at `limit2` or further are skipped first (most of a
// cluster's far particles). Ericson's regions, each a mask, applied from the lowest to the highest
// priority so the highest wins, as his early returns do.
struct LeafClosest {
    uint32_t lane;
    float distance2, v, w;
};

// The plane and ball tests of lanes k.. of a leaf (corners + k) against p within sqrt(limit2):
// the lanes that may hold a point that close (`near`), with p - a and n . (p - a) for n = ab x ac
// (not normalised). Plane: (n.ap)^2 < limit2 |n|^2; a degenerate triangle (n = 0) never passes,
// its neighbours' edges cover it. Ball: the triangle lies within `radius` (the longer of ab, ac)
// of a, so it is out of reach when |ap| >= sqrt(limit2) + radius.
template <class F>
struct LaneCull {
    Vec3W<F> ap;
    F plane, n2;
    decltype(F{} < F{}) near;
};
template <class F>
inline LaneCull<F> cull_lanes(const float* c, const Vec3W<F>& p, F limit2, F limit_m) {
    using namespace simd;
    LaneCull<F> out;
    out.ap = {p.x - load(c, F{}), p.y - load(c + 8, F{}), p.z - load(c + 16, F{})};
    const Vec3W<F> n{load(c + 72, F{}), load(c + 80, F{}), load(c + 88, F{})};
    out.plane = dot(n, out.ap);
    out.n2 = dot(n, n);
    const F ball = limit_m + load(c + 96, F{});
    out.near = (out.plane * out.plane < limit2 * out.n2) & (dot(out.ap, out.ap) < ball * ball);
    return out;
}

template <class F>
inline bool closest_in_leaf(const float* corners, const float* p, float limit2, LeafClosest& out) {
    alignas(32) float d2_out[kLeafTriangles], v_out[kLeafTriangles], w_out[kLeafTriangles];
    const float limit_m = std::sqrt(limit2);
    using namespace simd;
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    const Vec3W<F> point{splat(p[0], F{}), splat(p[1], F{}), splat(p[2], F{})};
    const F limit = splat(limit2, F{}), far = splat(std::numeric_limits<float>::infinity(), F{});
    uint32_t within = 0;
    for (uint32_t k = 0; k < kLeafTriangles; k += F::width) {
        const float* c = corners + k;
        const LaneCull<F> cull = cull_lanes(c, point, limit, splat(limit_m, F{}));
        const Vec3W<F>& ap = cull.ap;
        const auto near = cull.near;
        if (!any(near)) {
            store(d2_out + k, far);
            continue;
        }
        const Vec3W<F> ab{load(c + 24, F{}), load(c + 32, F{}), load(c + 40, F{})};
        const Vec3W<F> ac{load(c + 48, F{}), load(c + 56, F{}), load(c + 64, F{})};
        const F d1 = dot(ab, ap), d2 = dot(ac, ap);
        const F ab_ab = dot(ab, ab), ab_ac = dot(ab, ac), ac_ac = dot(ac, ac);
        const F d3 = d1 - ab_ab, d4 = d2 - ab_ac;  // ab.bp, ac.bp with bp = ap - ab
        const F d5 = d1 - ab_ac, d6 = d2 - ac_ac;  // ab.cp, ac.cp with cp = ap - ac
        const F vc = neg_mul_add(d3, d2, d1 * d4);
        const F vb = neg_mul_add(d1, d6, d5 * d2);
        const F va = neg_mul_add(d5, d4, d3 * d6);
        // The weights as numerators over one denominator per region, so one division serves all
        // regions: face (vb, vc) / sum, a degenerate triangle (sum <= 0) falling back to corner a.
        const F sum = va + vb + vc;
        const auto face = sum > zero;
        F v_num = keep_if(face, vb), w_num = keep_if(face, vc), den = select(face, sum, one);
        // Each region in turn, lowest priority first, where the point is not `outside` it.
        auto region = [&](auto outside, F v_region, F w_region, F den_region) {
            v_num = select(outside, v_num, v_region);
            w_num = select(outside, w_num, w_region);
            den = select(outside, den, den_region);
        };
        const F e43 = d4 - d3, e56 = d5 - d6;
        region((va > zero) | (e43 < zero) | (e56 < zero), e56, e43, e43 + e56);  // edge bc
        region((vb > zero) | (d2 < zero) | (d6 > zero), zero, d2, d2 - d6);     // edge ac
        region((d6 < zero) | (d5 > d6), zero, one, one);                        // corner c
        region((vc > zero) | (d1 < zero) | (d3 > zero), d1, zero, d1 - d3);     // edge ab
        region((d3 < zero) | (d4 > d3), one, zero, one);                        // corner b
        region((d1 > zero) | (d2 > zero), zero, zero, one);                     // corner a
        const F inverse = one / den;
        const F v = v_num * inverse, w = w_num * inverse;
        // p - closest = ap - v ab - w ac.
        const Vec3W<F> r{neg_mul_add(w, ac.x, neg_mul_add(v, ab.x, ap.x)), neg_mul_add(w, ac.y, neg_mul_add(v, ab.y, ap.y)),
                         neg_mul_add(w, ac.z, neg_mul_add(v, ab.z, ap.z))};
        const F distance2 = dot(r, r);
        const auto accepted = near & (distance2 < limit);  // NaN (degenerate) never passes
        store(d2_out + k, select(accepted, distance2, far));
        store(v_out + k, v);
        store(w_out + k, w);
        within |= lane_bits(accepted) << k;
    }
    if (within == 0) return false;
    const uint32_t lane = first_least(d2_out, F{});
    out = {lane, d2_out[lane], v_out[lane], w_out[lane]};
    return true;
}

// The best triangle a particle has found so far.
struct Best {
    float distance2;
    uint32_t triangle;
    float v, w;
};

// Of the hull triangles a particle's tunnelling ray enters (moving against the outward normal), the
// one whose plane its new position lies deepest behind, kNoTriangle when none. A ray that starts
// inside one part's hull (a point resting in a crease, where two parts' hulls overlap) leaves it
// before it enters the other, and that entry counts. The deepest, not the first: under the crotch
// a particle pulled up first grazes into a thigh's hull, whose plane it is hardly behind, and then
// enters the crotch's, which it must go back out of.
// The ray is traced in each triangle's frame (intersect_leaf): from its origin moved with the
// triangle this substep (motion) to the particle's new position.
inline constexpr uint32_t kNoTriangle = 0xffffffffu;
struct RayHit {
    float t;  // along the ray's direction (the whole displacement) from its origin
    uint32_t triangle;
    float u, v;       // weights of the triangle's corners b and c at the hit
    float motion[3];  // the hit triangle's motion this substep (ray_in_body_frame)
};

// A ray from `origin` along `dir` for t in [0, t_far] (the particle's whole displacement), seen
// from a triangle that moved by `motion` this substep: from origin + motion to the same end,
// origin + t_far dir. The particle's motion relative to the surface is what crosses it: a hull
// swinging into a hem moving towards it crosses it by the sum of both motions while either alone
// stays within reach. With motion 0 (a still body) it adds exact zeros: the world's ray.
inline float ray_in_body_frame(float origin, float dir, float motion, float inverse_t_far, float* body_dir) {
    *body_dir = dir - motion * inverse_t_far;
    return origin + motion;
}

// One cluster's points (kClusterSlots slots consecutive in the pass's order): those to search (bits
// of `active`) and those that also trace a ray (bits of `rays`) from origin[k] along dir[k] for t in
// [0, t_far[k]].
struct Cluster {
    float point[kClusterSlots][3];
    float origin[kClusterSlots][3];
    float dir[kClusterSlots][3];
    float t_far[kClusterSlots];
    float share = 1.0f;  // the substep's share of the step: of each triangle's motion, for the rays
    uint32_t active = 0, rays = 0;
    Best best[kClusterSlots];
    RayHit hit[kClusterSlots];
};

// Moeller-Trumbore against a leaf's eight triangles, each in its own frame (ray_in_body_frame: the
// origin moved by the triangle's motion, `share` of its motion this step, the end kept): the lanes
// the segment org' + t dir', t in [0, t_far], crosses, with t, u (weight of b), v (weight of c),
// det > 0 when entering (det = ab . (dir' x ac) = -dir' . (ab x ac), the outward normal), how far
// the segment's end lies behind the triangle's plane ((t_far - t) det / |ab x ac|) and the lane's
// motion.
template <class F>
inline uint32_t intersect_leaf(const float* corners, const float* org, const float* dir, float t_far, float share,
                               float* t_out, float* u_out, float* v_out, float* det_out, float* depth_out,
                               float* motion_out) {
    using namespace simd;
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    const F portion = splat(share, F{}), inverse_t_far = splat(1.0f / t_far, F{});
    uint32_t hits = 0;
    for (uint32_t k = 0; k < kLeafTriangles; k += F::width) {
        const float* c = corners + k;
        const Vec3W<F> ab{load(c + 24, F{}), load(c + 32, F{}), load(c + 40, F{})};
        const Vec3W<F> ac{load(c + 48, F{}), load(c + 56, F{}), load(c + 64, F{})};
        // The origin moved with the triangle and the direction to the same end (ray_in_body_frame,
        // the same operations lane by lane).
        const Vec3W<F> m{load(c + 104, F{}) * portion, load(c + 112, F{}) * portion, load(c + 120, F{}) * portion};
        const Vec3W<F> d{splat(dir[0], F{}) - m.x * inverse_t_far, splat(dir[1], F{}) - m.y * inverse_t_far,
                         splat(dir[2], F{}) - m.z * inverse_t_far};
        const Vec3W<F> to{(splat(org[0], F{}) + m.x) - load(c, F{}), (splat(org[1], F{}) + m.y) - load(c + 8, F{}),
                          (splat(org[2], F{}) + m.z) - load(c + 16, F{})};
        const Vec3W<F> p{d.y * ac.z - d.z * ac.y, d.z * ac.x - d.x * ac.z, d.x * ac.y - d.y * ac.x};
        const F det = dot(ab, p);
        const F inverse = one / det;
        const Vec3W<F> q{to.y * ab.z - to.z * ab.y, to.z * ab.x - to.x * ab.z, to.x * ab.y - to.y * ab.x};
        const F u = dot(to, p) * inverse, v = dot(d, q) * inverse, t = dot(ac, q) * inverse;
        const auto miss = (u < zero) | (v < zero) | (u + v > one) | (t < zero) | (t > splat(t_far, F{}));
        const uint32_t lanes = lane_bits(abs(det) > zero) & ~lane_bits(miss);  // det 0: parallel, NaN lanes miss
        if (lanes == 0) continue;
        store(t_out + k, t);
        store(u_out + k, u);
        store(v_out + k, v);
        store(det_out + k, det);
        const Vec3W<F> n{load(c + 72, F{}), load(c + 80, F{}), load(c + 88, F{})};  // ab x ac, stored
        store(depth_out + k, (splat(t_far, F{}) - t) * det / sqrt(dot(n, n)));
        store(motion_out + k, m.x);
        store(motion_out + kLeafTriangles + k, m.y);
        store(motion_out + 2 * kLeafTriangles + k, m.z);
        hits |= lanes << k;
    }
    return hits;
}

// The leaves one cluster may touch, with their boxes copied into local arrays (eight-wide tests).
struct Candidates {
    uint32_t count = 0;
    bool whole = false;  // after search_cluster: the list holds every leaf the cluster's walk met
    uint32_t leaf[kMaxCandidates + 8];
    alignas(32) float min_x[kMaxCandidates + 8], min_y[kMaxCandidates + 8], min_z[kMaxCandidates + 8];
    alignas(32) float max_x[kMaxCandidates + 8], max_y[kMaxCandidates + 8], max_z[kMaxCandidates + 8];
    alignas(32) float reach2[kMaxCandidates + 8];  // (base reach + the leaf's sweep)^2
    alignas(32) float sweep[kMaxCandidates + 8];   // the leaf's sweep (its rays' origins move up to that)
};

// Appends the leaves first + k of the set bits k of `bits` with their boxes and squared reaches
// (lanes of one walk test) to `c`, branch-free as append_hits (the AVX2 form writes eight lanes: the
// arrays' slack).
inline void append_candidates(uint32_t bits, uint32_t first, const simd::Float1* box, simd::Float1 reach2,
                              simd::Float1 sweep, Candidates& c) {
    const uint32_t n = c.count;
    c.leaf[n] = first;
    c.min_x[n] = box[0].v, c.min_y[n] = box[1].v, c.min_z[n] = box[2].v;
    c.max_x[n] = box[3].v, c.max_y[n] = box[4].v, c.max_z[n] = box[5].v;
    c.reach2[n] = reach2.v;
    c.sweep[n] = sweep.v;
    c.count = n + bits;
}
#if WEFT_HAVE_AVX2
inline void append_candidates(uint32_t bits, uint32_t first, const simd::Float8* box, simd::Float8 reach2,
                              simd::Float8 sweep, Candidates& c) {
    const __m256i order = pack_order(bits);
    const uint32_t n = c.count;
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(c.leaf + n), _mm256_add_epi32(_mm256_set1_epi32(int(first)), order));
    float* out[6] = {c.min_x + n, c.min_y + n, c.min_z + n, c.max_x + n, c.max_y + n, c.max_z + n};
    for (int a = 0; a < 6; ++a) _mm256_storeu_ps(out[a], _mm256_permutevar8x32_ps(box[a].v, order));
    _mm256_storeu_ps(c.reach2 + n, _mm256_permutevar8x32_ps(reach2.v, order));
    _mm256_storeu_ps(c.sweep + n, _mm256_permutevar8x32_ps(sweep.v, order));
    c.count = n + uint32_t(__builtin_popcount(bits));
}
#endif

// Traces a cluster point's ray against every candidate leaf whose box meets the segment's box
// widened by the leaf's sweep (in a triangle's frame the origin moves by up to that,
// intersect_leaf), keeping the entry its end lies deepest behind (RayHit; equal depths the smaller
// t, then the first leaf and lane: deterministic).
template <class F>
inline void trace_candidates(const BodyHierarchy& h, const Candidates& c, const float* org, const float* dir,
                             float t_far, float share, RayHit& hit) {
    using namespace simd;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        const float end = org[a] + t_far * dir[a];
        lo[a] = org[a] < end ? org[a] : end;
        hi[a] = org[a] < end ? end : org[a];
    }
    const F lx = splat(lo[0], F{}), ly = splat(lo[1], F{}), lz = splat(lo[2], F{});
    const F hx = splat(hi[0], F{}), hy = splat(hi[1], F{}), hz = splat(hi[2], F{});
    alignas(32) float t[kLeafTriangles], u[kLeafTriangles], v[kLeafTriangles], det[kLeafTriangles];
    alignas(32) float depth[kLeafTriangles], motion[3 * kLeafTriangles];
    float deepest = -std::numeric_limits<float>::infinity();
    for (uint32_t i = 0; i < c.count; i += F::width) {
        const F sweep = load(c.sweep + i, F{});
        const auto apart = (load(c.min_x + i, F{}) - sweep > hx) | (load(c.max_x + i, F{}) + sweep < lx) |
                           (load(c.min_y + i, F{}) - sweep > hy) | (load(c.max_y + i, F{}) + sweep < ly) |
                           (load(c.min_z + i, F{}) - sweep > hz) | (load(c.max_z + i, F{}) + sweep < lz);
        uint32_t bits = ~lane_bits(apart) & ((1u << F::width) - 1u);
        while (bits != 0) {
            const uint32_t lane = uint32_t(__builtin_ctz(bits));
            bits &= bits - 1;
            if (i + lane >= c.count) break;
            const uint32_t leaf = c.leaf[i + lane];
            uint32_t lanes = intersect_leaf<F>(h.leaf_corners + size_t(kLeafCorners) * leaf, org, dir, t_far, share, t, u,
                                               v, det, depth, motion);
            while (lanes != 0) {
                const uint32_t k = uint32_t(__builtin_ctz(lanes));
                lanes &= lanes - 1;
                if (!(det[k] > 0.0f)) continue;  // entries only (RayHit)
                if (!(depth[k] > deepest || (depth[k] == deepest && t[k] < hit.t))) continue;
                deepest = depth[k];
                hit = {t[k], h.leaf_triangle[kLeafTriangles * leaf + k], u[k], v[k],
                       {motion[k], motion[kLeafTriangles + k], motion[2 * kLeafTriangles + k]}};
            }
        }
    }
}

// Whether `p` lies in front of the plane of every triangle of the listed leaves that the plane and
// ball tests of closest_in_leaf let through at the leaf's reach, by more than kFrontMargin_m: then
// its closest triangle leaves it outside the hull (no contact; vertex normals within 90 degrees of
// their faces' normals), and the step needs no closest point.
inline constexpr float kFrontMargin_m = 1e-6f;
template <class F>
inline bool in_front_of_every_plane(const BodyHierarchy& h, const float* p, const uint32_t* leaf, const float* reach2,
                                    uint32_t count) {
    using namespace simd;
    const Vec3W<F> point{splat(p[0], F{}), splat(p[1], F{}), splat(p[2], F{})};
    const F zero = splat(0.0f, F{}), margin2 = splat(kFrontMargin_m * kFrontMargin_m, F{});
    for (uint32_t j = 0; j < count; ++j) {
        const float* corners = h.leaf_corners + size_t(kLeafCorners) * leaf[j];
        const F limit = splat(reach2[j], F{}), limit_m = splat(std::sqrt(reach2[j]), F{});
        for (uint32_t k = 0; k < kLeafTriangles; k += F::width) {
            const LaneCull<F> cull = cull_lanes(corners + k, point, limit, limit_m);
            const auto behind = (cull.plane < zero) | (cull.plane * cull.plane < margin2 * cull.n2);
            if (any(cull.near & behind)) return false;
        }
    }
    return true;
}

// Tests particle `p` against every candidate leaf whose box lies within the leaf's reach (base + the
// leaf's sweep), keeping the closest triangle within that reach that is strictly closer than `best`;
// with `contacts_only`, none when p lies in front of every plane there (in_front_of_every_plane:
// it is outside the hull, the step's only question; the contacts stay exactly the same, tested).
template <class F>
inline bool search_candidates(const BodyHierarchy& h, const Candidates& c, const float* p, Best& best,
                              bool contacts_only = false) {
    using namespace simd;
    const F px = splat(p[0], F{}), py = splat(p[1], F{}), pz = splat(p[2], F{});
    const F zero = splat(0.0f, F{});
    // First the leaves whose box the reach meets and lies closer than the best so far (a crease
    // search starts from about zero: few leaves), packed in candidate order (the padding past the last
    // candidate has empty boxes, which never pass).
    const F best2 = splat(best.distance2, F{});
    uint32_t hits = 0;
    uint32_t hit_leaf[kMaxCandidates + 8];
    alignas(32) float hit_box2[kMaxCandidates + 8], hit_reach2[kMaxCandidates + 8];
    for (uint32_t i = 0; i < c.count; i += F::width) {
        // Distance from p to each box (zero inside).
        const F dx = max(zero, max(load(c.min_x + i, F{}) - px, px - load(c.max_x + i, F{})));
        const F dy = max(zero, max(load(c.min_y + i, F{}) - py, py - load(c.max_y + i, F{})));
        const F dz = max(zero, max(load(c.min_z + i, F{}) - pz, pz - load(c.max_z + i, F{})));
        const F box2 = mul_add(dx, dx, mul_add(dy, dy, dz * dz));
        const F reach2 = load(c.reach2 + i, F{});
        hits = append_hits(lane_bits(box2 < min(reach2, best2)), c.leaf + i, box2, reach2, hits, hit_leaf, hit_box2,
                           hit_reach2);
    }
    if (contacts_only && in_front_of_every_plane<F>(h, p, hit_leaf, hit_reach2, hits)) return hits != 0;
    // Then their triangles, in that order.
    for (uint32_t j = 0; j < hits; ++j) {
        // Beyond the best so far: no triangle of this leaf can be strictly closer (the boxes are
        // widened by kBoxSlack_m, so the box distance stays below any triangle's despite rounding).
        if (!(hit_box2[j] < best.distance2)) continue;
        const uint32_t leaf = hit_leaf[j];
        // Within the leaf's reach and closer than the best so far (equal lanes lose: d2 < limit).
        const float limit2 = best.distance2 < hit_reach2[j] ? best.distance2 : hit_reach2[j];
        LeafClosest closest;
        if (!closest_in_leaf<F>(h.leaf_corners + size_t(kLeafCorners) * leaf, p, limit2, closest)) continue;
        // Strictly closer (limit2 <= best): ties keep the first, deterministic.
        best = {closest.distance2, h.leaf_triangle[kLeafTriangles * leaf + closest.lane], closest.v, closest.w};
    }
    // A first search starts with no best, so its hits are the leaves within reach; a seeded one (the
    // crease search) does not use the answer.
    return hits != 0;
}

// Appends every leaf whose box meets [lo, hi] to `c`, root by root, group by group; calls `flush` when the list
// is full (the caller searches it and empties it).
template <class F, class Flush>
inline void collect_leaves(const BodyHierarchy& h, float base_reach, const float* lo, const float* hi, Candidates& c,
                           Flush&& flush) {
    using namespace simd;
    const F reach = splat(base_reach, F{});
    const F lx = splat(lo[0], F{}), ly = splat(lo[1], F{}), lz = splat(lo[2], F{});
    const F hx = splat(hi[0], F{}), hy = splat(hi[1], F{}), hz = splat(hi[2], F{});
    // Calls visit(i) for every box i in [first, first + count) below `end` that meets [lo, hi]
    // (apart on some axis: box min above the query's max, or box max below its min).
    auto for_each_meeting = [&](const Boxes& b, uint32_t first, uint32_t count, uint32_t end, auto&& visit) {
        for (uint32_t i0 = first; i0 < first + count; i0 += F::width) {
            const auto apart = (load(b.min_x + i0, F{}) > hx) | (load(b.max_x + i0, F{}) < lx) |
                               (load(b.min_y + i0, F{}) > hy) | (load(b.max_y + i0, F{}) < ly) |
                               (load(b.min_z + i0, F{}) > hz) | (load(b.max_z + i0, F{}) < lz);
            uint32_t bits = ~lane_bits(apart) & ((1u << F::width) - 1u);
            while (bits != 0) {
                const uint32_t i = i0 + uint32_t(__builtin_ctz(bits));
                bits &= bits - 1;
                if (i >= end) return;  // padding boxes are empty, but be explicit
                visit(i);
            }
        }
    };
    const uint32_t padded_roots = (h.root_count + 7) / 8 * 8;
    for_each_meeting(h.roots, 0, padded_roots, h.root_count, [&](uint32_t r) {
        for_each_meeting(h.groups, r * kRootGroups, kRootGroups, h.group_count, [&](uint32_t g) {
            // The leaves, packed branch-free (the padding leaves past leaf_count are empty boxes,
            // which meet nothing); the list is searched and emptied when it may not hold another eight.
            // Each particle then tests the leaf's own box (the walk's shrunk back by the sweep: still
            // holding the triangles, by the slack) within the base reach plus the sweep: the widened
            // box within the base reach let 13% more leaves through to the triangle tests (measured).
            const Boxes& b = h.leaves;
            for (uint32_t i0 = g * kGroupLeaves; i0 < (g + 1) * kGroupLeaves; i0 += F::width) {
                F box[6] = {load(b.min_x + i0, F{}), load(b.min_y + i0, F{}), load(b.min_z + i0, F{}),
                            load(b.max_x + i0, F{}), load(b.max_y + i0, F{}), load(b.max_z + i0, F{})};
                const auto apart = (box[0] > hx) | (box[3] < lx) | (box[1] > hy) | (box[4] < ly) | (box[2] > hz) | (box[5] < lz);
                const F sweep = load(h.leaf_sweep + i0, F{});
                for (int a = 0; a < 3; ++a) box[a] = box[a] + sweep, box[3 + a] = box[3 + a] - sweep;
                const F leaf_reach = reach + sweep;
                append_candidates(~lane_bits(apart) & ((1u << F::width) - 1u), i0, box, leaf_reach * leaf_reach, sweep, c);
                if (c.count + 8 > kMaxCandidates) flush();
            }
        });
    });
}

// The closest hull triangle to each active point of the cluster within reach (best[k].distance2
// stays infinite when none is), and the first triangle each ray point's segment meets (hit[k]).
// The walk's box holds the points widened by the reach and the rays' segments. Returns the bits of
// the points whose reach met at least one leaf box.
template <class F>
inline uint32_t search_cluster(const BodyHierarchy& h, float reach, Cluster& q, Candidates& c, bool contacts_only = false) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (uint32_t k = 0; k < kClusterSlots; ++k) {
        q.best[k] = {inf, 0, 0.0f, 0.0f};
        q.hit[k] = {inf, kNoTriangle, 0.0f, 0.0f, {0.0f, 0.0f, 0.0f}};
        if (!(q.active >> k & 1u)) continue;
        for (int a = 0; a < 3; ++a) {
            lo[a] = q.point[k][a] - reach < lo[a] ? q.point[k][a] - reach : lo[a];
            hi[a] = q.point[k][a] + reach > hi[a] ? q.point[k][a] + reach : hi[a];
        }
        if (!(q.rays >> k & 1u)) continue;
        for (int a = 0; a < 3; ++a) {  // the point is the segment's far end; its start is the origin
            lo[a] = q.origin[k][a] < lo[a] ? q.origin[k][a] : lo[a];
            hi[a] = q.origin[k][a] > hi[a] ? q.origin[k][a] : hi[a];
        }
    }
    c.whole = false;
    if (q.active == 0) return 0;
    uint32_t met = 0, flushes = 0;
    auto flush = [&] {
        ++flushes;
        // The plane shortcut needs every leaf within reach at once: a walk that fills the list and
        // flushes it on the way (the scalar and AVX2 paths at different points) searches exactly.
        if (c.count + 8 > kMaxCandidates) contacts_only = false;
        // Pad the copy so eight-wide loads past the end read empty boxes.
        for (uint32_t n = c.count; n < c.count + 8; ++n) {
            c.min_x[n] = c.min_y[n] = c.min_z[n] = inf;
            c.max_x[n] = c.max_y[n] = c.max_z[n] = -inf;
            c.reach2[n] = 0.0f;
            c.sweep[n] = 0.0f;
            c.leaf[n] = 0;
        }
        for (uint32_t k = 0; k < kClusterSlots; ++k) {
            if (!(q.active >> k & 1u)) continue;
            if (q.rays >> k & 1u) trace_candidates<F>(h, c, q.origin[k], q.dir[k], q.t_far[k], q.share, q.hit[k]);
            if (search_candidates<F>(h, c, q.point[k], q.best[k], contacts_only)) met |= 1u << k;
        }
        c.count = 0;
    };
    c.count = 0;
    collect_leaves<F>(h, reach, lo, hi, c, flush);
    const uint32_t last = c.count;
    if (last > 0) flush();
    // Kept for search_again unless the walk filled the list and flushed it on the way.
    if (flushes == (last > 0 ? 1u : 0u)) c.count = last, c.whole = true;
    return met;
}

// The closest triangles of the cluster's active points again, after the response moved them (the
// crease pass, collide/body.cpp), each starting from the best the caller seeded (only a strictly
// closer triangle replaces it): against the leaves the last search_cluster collected when it kept
// them all (no second walk; a leaf beyond the reach of every point before the push is not looked
// at, which only leaves a second correction undone), else through a new walk from scratch.
template <class F>
inline void search_again(const BodyHierarchy& h, float reach, Cluster& q, Candidates& c) {
    if (!c.whole) {
        search_cluster<F>(h, reach, q, c);
        return;
    }
    for (uint32_t k = 0; k < kClusterSlots; ++k)
        if (q.active >> k & 1u) search_candidates<F>(h, c, q.point[k], q.best[k]);
}

// Each lane's vertex (x, y, z, motion) from the hull, at hull[offset[k]], as four wide values: on
// AVX2 eight 16-byte loads and a transpose (four vgatherdps per corner measured slower).
inline void load_vertices(const float* hull, const uint32_t* offset, simd::Float1 out[4]) {
    for (int a = 0; a < 4; ++a) out[a] = {hull[offset[0] + a]};
}
#if WEFT_HAVE_AVX2
inline void load_vertices(const float* hull, const uint32_t* offset, simd::Float8 out[4]) {
    auto pair = [&](int k) {  // lanes k and k + 4: vertex k in the low half, k + 4 in the high half
        return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(hull + offset[k])), _mm_loadu_ps(hull + offset[k + 4]), 1);
    };
    const __m256 a0 = pair(0), a1 = pair(1), a2 = pair(2), a3 = pair(3);
    const __m256 t0 = _mm256_unpacklo_ps(a0, a1), t1 = _mm256_unpackhi_ps(a0, a1);  // x0 x1 y0 y1, z0 z1 m0 m1
    const __m256 t2 = _mm256_unpacklo_ps(a2, a3), t3 = _mm256_unpackhi_ps(a2, a3);  // x2 x3 y2 y3, z2 z3 m2 m3
    out[0] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0))};
    out[1] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2))};
    out[2] = {_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0))};
    out[3] = {_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2))};
}
#endif

inline float lowest(simd::Float1 a) { return a.v; }
inline float highest(simd::Float1 a) { return a.v; }
#if WEFT_HAVE_AVX2
inline float lowest(simd::Float8 a) {
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(a.v), _mm256_extractf128_ps(a.v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_movehdup_ps(m)));
}
inline float highest(simd::Float8 a) {
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(a.v), _mm256_extractf128_ps(a.v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_movehdup_ps(m)));
}
#endif

// to[index] = the union of from[first, first + count), cut at `end`.
inline void unite(const Boxes& from, uint32_t first, uint32_t end, uint32_t count, Boxes& to, uint32_t index) {
    end = first + count < end ? first + count : end;
    float lo[3] = {from.min_x[first], from.min_y[first], from.min_z[first]};
    float hi[3] = {from.max_x[first], from.max_y[first], from.max_z[first]};
    for (uint32_t i = first + 1; i < end; ++i) {
        lo[0] = from.min_x[i] < lo[0] ? from.min_x[i] : lo[0];
        lo[1] = from.min_y[i] < lo[1] ? from.min_y[i] : lo[1];
        lo[2] = from.min_z[i] < lo[2] ? from.min_z[i] : lo[2];
        hi[0] = from.max_x[i] > hi[0] ? from.max_x[i] : hi[0];
        hi[1] = from.max_y[i] > hi[1] ? from.max_y[i] : hi[1];
        hi[2] = from.max_z[i] > hi[2] ? from.max_z[i] : hi[2];
    }
    to.min_x[index] = lo[0], to.min_y[index] = lo[1], to.min_z[index] = lo[2];
    to.max_x[index] = hi[0], to.max_y[index] = hi[1], to.max_z[index] = hi[2];
}

// Refits every leaf to the hull (BodyState::hull: x, y, z and the vertex's motion this step):
// corners, edges, normals and radii of its triangles, its box widened by the largest motion of its
// vertices and kBoxSlack_m, then the group boxes. Min, max and IEEE arithmetic: both paths agree.
template <class F>
inline void refit_leaves(BodyHierarchy& h, const float* hull, const float* previous_hull) {
    using namespace simd;
    const F slack = splat(kBoxSlack_m, F{});
    for (uint32_t l = 0; l < h.leaf_count; ++l) {
        float* c = h.leaf_corners + size_t(kLeafCorners) * l;
        const uint32_t* offset = h.leaf_vertex + 3 * kLeafTriangles * l;  // 4 * vertex: a[8], b[8], c[8]
        F lo[3], hi[3], sweep;
        for (uint32_t k = 0; k < kLeafTriangles; k += F::width) {
            Vec3W<F> a, ab, ac;
            F* pa[3] = {&a.x, &a.y, &a.z};
            F* pab[3] = {&ab.x, &ab.y, &ab.z};
            F* pac[3] = {&ac.x, &ac.y, &ac.z};
            F corner_a[4], corner_b[4], corner_c[4];  // x, y, z, motion
            load_vertices(hull, offset + k, corner_a);
            load_vertices(hull, offset + kLeafTriangles + k, corner_b);
            load_vertices(hull, offset + 2 * kLeafTriangles + k, corner_c);
            for (int axis = 0; axis < 3; ++axis) {
                const F va = corner_a[axis], vb = corner_b[axis], vc = corner_c[axis];
                *pa[axis] = va;
                *pab[axis] = vb - va;
                *pac[axis] = vc - va;
                const F low = min(va, min(vb, vc)), high = max(va, max(vb, vc));
                lo[axis] = k == 0 ? low : min(lo[axis], low);
                hi[axis] = k == 0 ? high : max(hi[axis], high);
                store(c + 8 * axis + k, va);
                store(c + 24 + 8 * axis + k, vb - va);
                store(c + 48 + 8 * axis + k, vc - va);
            }
            store(c + 72 + k, ab.y * ac.z - ab.z * ac.y);
            store(c + 80 + k, ab.z * ac.x - ab.x * ac.z);
            store(c + 88 + k, ab.x * ac.y - ab.y * ac.x);
            // Rounded up by the slack: the ball test must never cut a triangle that is in reach.
            store(c + 96 + k, sqrt(max(dot(ab, ab), dot(ac, ac))) + slack);
            const F motion = max(corner_a[3], max(corner_b[3], corner_c[3]));
            sweep = k == 0 ? motion : max(sweep, motion);
            // The triangle's motion this step: its corners' mean (the rays' frame, intersect_leaf).
            F before_a[4], before_b[4], before_c[4];
            load_vertices(previous_hull, offset + k, before_a);
            load_vertices(previous_hull, offset + kLeafTriangles + k, before_b);
            load_vertices(previous_hull, offset + 2 * kLeafTriangles + k, before_c);
            const F third = splat(1.0f / 3.0f, F{});
            for (int axis = 0; axis < 3; ++axis)
                store(c + 104 + 8 * axis + k, ((corner_a[axis] - before_a[axis]) + (corner_b[axis] - before_b[axis]) +
                                               (corner_c[axis] - before_c[axis])) * third);
        }
        // Widened by the leaf's motion (a surface sweeping over resting cloth: the particle lies up
        // to that much deeper), by its fold (BodyHierarchy::leaf_fold) and by a slack that absorbs
        // the box test's rounding.
        const float leaf_sweep = highest(sweep) + h.leaf_fold[l];
        const float widen = leaf_sweep + kBoxSlack_m;
        h.leaf_sweep[l] = leaf_sweep;
        h.leaves.min_x[l] = lowest(lo[0]) - widen;
        h.leaves.min_y[l] = lowest(lo[1]) - widen;
        h.leaves.min_z[l] = lowest(lo[2]) - widen;
        h.leaves.max_x[l] = highest(hi[0]) + widen;
        h.leaves.max_y[l] = highest(hi[1]) + widen;
        h.leaves.max_z[l] = highest(hi[2]) + widen;
    }
    for (uint32_t g = 0; g < h.group_count; ++g) unite(h.leaves, g * kGroupLeaves, h.leaf_count, kGroupLeaves, h.groups, g);
    for (uint32_t r = 0; r < h.root_count; ++r) unite(h.groups, r * kRootGroups, h.group_count, kRootGroups, h.roots, r);
}

// BodyCollision::cached_planes after a step's first substep: every free particle that stayed within
// its plane's reach of where the plane was found is projected onto the plane (the hull is the same
// within a step, so the plane's point, normal and motion are still the exact search's), with the
// same friction as the exact pass against the surface's motion there; a particle that moved further
// gets reach2 = -1 (searched exactly by the caller). Returns how many were marked; adds the
// particles it pushed to `contacts`.
template <class F>
inline uint32_t project_on_planes(const Particles& particles, const ContactPlanes& planes, float friction,
                                  uint64_t& contacts) {
    using namespace simd;
    const Particles p = particles;  // local copies: the stores cannot alias them
    const ContactPlanes c = planes;
    ColliderKernelArgs args{};
    args.friction = friction;
    const F zero = splat(0.0f, F{}), marked = splat(-1.0f, F{});
    uint32_t stale = 0;
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const Vec3W<F> x{load(p.x + i, F{}), load(p.y + i, F{}), load(p.z + i, F{})};
        const Vec3W<F> moved{x.x - load(c.from[0] + i, F{}), x.y - load(c.from[1] + i, F{}), x.z - load(c.from[2] + i, F{})};
        const F reach2 = load(c.reach2 + i, F{});
        const auto free = load(p.inverse_mass + i, F{}) > zero;
        const auto held = free & (dot(moved, moved) < reach2);
        const Vec3W<F> n{load(c.normal[0] + i, F{}), load(c.normal[1] + i, F{}), load(c.normal[2] + i, F{})};
        const Vec3W<F> to_hull{load(c.point[0] + i, F{}) - x.x, load(c.point[1] + i, F{}) - x.y,
                               load(c.point[2] + i, F{}) - x.z};
        const F penetration = dot(to_hull, n);  // > 0: behind the plane; 0 where there is no plane
        const auto contact = held & (penetration > zero);
        if (any(contact)) {
            contacts += uint64_t(__builtin_popcount(lane_bits(contact)));
            if (friction > 0.0f) {
                const Vec3W<F> motion{load(c.motion[0] + i, F{}), load(c.motion[1] + i, F{}), load(c.motion[2] + i, F{})};
                const RelativeMotion<F> m = relative_motion(p, i, x, motion);
                respond_with_friction(p, i, x, n, penetration, m, dot(n, m.e), contact, args);
            } else {
                resolve_contact(p, i, x, n, penetration, contact, args);
            }
        }
        // In a crease: out of the other side too, then the first again, without friction (as the
        // exact pass's crease rounds).
        const Vec3W<F> n2{load(c.crease_normal[0] + i, F{}), load(c.crease_normal[1] + i, F{}),
                          load(c.crease_normal[2] + i, F{})};
        const auto creased = held & (dot(n2, n2) > zero);
        if (any(creased)) {
            const Vec3W<F> q2{load(c.crease_point[0] + i, F{}), load(c.crease_point[1] + i, F{}),
                              load(c.crease_point[2] + i, F{})};
            const Vec3W<F> q1{load(c.point[0] + i, F{}), load(c.point[1] + i, F{}), load(c.point[2] + i, F{})};
            Vec3W<F> y{load(p.x + i, F{}), load(p.y + i, F{}), load(p.z + i, F{})};
            auto project = [&](const Vec3W<F>& q, const Vec3W<F>& nq) {
                const F depth = dot(Vec3W<F>{q.x - y.x, q.y - y.y, q.z - y.z}, nq);
                const auto in = creased & (depth > zero);
                y = {select(in, mul_add(nq.x, depth, y.x), y.x), select(in, mul_add(nq.y, depth, y.y), y.y),
                     select(in, mul_add(nq.z, depth, y.z), y.z)};
            };
            project(q2, n2);
            project(q1, n);
            store(p.x + i, y.x);
            store(p.y + i, y.y);
            store(p.z + i, y.z);
        }
        // Still held where the projections left it? Friction can carry a particle along the plane by
        // the surface's motion (centimetres a substep on a rising arm), further than the plane holds:
        // then the exact search takes it from there in this substep, as the exact pass's crease
        // rounds do (a fixed hold measured 6.9 mm deep without this).
        const Vec3W<F> at{load(p.x + i, F{}) - load(c.from[0] + i, F{}), load(p.y + i, F{}) - load(c.from[1] + i, F{}),
                          load(p.z + i, F{}) - load(c.from[2] + i, F{})};
        const auto kept = held & (dot(at, at) < reach2);
        const uint32_t out = lane_bits(free) & ~lane_bits(kept);
        if (out == 0) continue;
        store(c.reach2 + i, select(kept, reach2, select(free, marked, reach2)));
        stale += uint32_t(__builtin_popcount(out));
    }
    return stale;
}

// One path's search and refit: the templates for the scalar or the AVX2 path (null when unavailable).
// contacts_only (the step's pass): a point in front of every nearby triangle's plane is not searched
// further (in_front_of_every_plane); query_body wants its closest point all the same.
using SearchCluster = uint32_t (*)(const BodyHierarchy&, float, Cluster&, Candidates&, bool contacts_only);
using SearchAgain = void (*)(const BodyHierarchy&, float, Cluster&, Candidates&);
using RefitLeaves = void (*)(BodyHierarchy&, const float* hull, const float* previous_hull);
using ProjectOnPlanes = uint32_t (*)(const Particles&, const ContactPlanes&, float friction, uint64_t& contacts);
struct Path {
    SearchCluster search;
    SearchAgain search_again;
    RefitLeaves refit;
    ProjectOnPlanes project_on_planes;
};
const Path& scalar_path();
const Path* avx2_path();

}  // namespace body_query
}  // namespace weft
