// Body colliders: the offset hull, the closest-point search (Weft's hierarchy, or Embree's
// rtcPointQuery for the reference pass), the tunnelling ray (Embree), the response, and the
// hierarchy's creation and refit (the SIMD templates are in collide/body_query.h).
#include "collide/body.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "collide/body_query.h"
#include "collide/colliders.h"
#include "memory/arena.h"

namespace weft {
namespace {

inline float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void sub3(const float* a, const float* b, float* out) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

// Reach of the step's query: thickness + margin; each leaf adds its own sweep (BodyHierarchy).
float base_reach(const BodyState& body) { return body.desc.thickness_m + body.desc.margin_m; }

// What the point-query callback reads and keeps: the closest hull triangle seen so far.
struct ClosestQuery {
    const BodyState* body;
    float point[3];
    float best_distance2;
    uint32_t best_triangle;
    Barycentric best;
};

// Embree calls this for every triangle whose box meets the query sphere; shrinking the radius to
// the best distance so far prunes the rest of the traversal (Embree docs, rtcPointQuery).
bool closest_triangle_callback(RTCPointQueryFunctionArguments* args) {
    ClosestQuery& q = *static_cast<ClosestQuery*>(args->userPtr);
    const BodyState& body = *q.body;
    const uint32_t* t = body.triangles + 3 * args->primID;
    const float* a = body.hull + 4 * t[0];
    const float* b = body.hull + 4 * t[1];
    const float* c = body.hull + 4 * t[2];
    const Barycentric w = closest_on_triangle(q.point, a, b, c);
    float d[3];
    for (int k = 0; k < 3; ++k) d[k] = q.point[k] - (w.w0 * a[k] + w.w1 * b[k] + w.w2 * c[k]);
    const float distance2 = dot3(d, d);
    // Strictly closer only: ties keep the triangle met first, so the result is deterministic.
    if (!(distance2 < q.best_distance2)) return false;
    q.best_distance2 = distance2;
    q.best_triangle = args->primID;
    q.best = w;
    args->query->radius = std::sqrt(distance2);
    return true;
}

// The closest hull triangle to `point` within `reach` (the plain reference pass: thickness + margin,
// not widened by the body's motion, the rtcPointQuery pass).
bool find_closest(const BodyState& body, const float* point, float reach, uint32_t* triangle, Barycentric* w) {
    ClosestQuery q{&body, {point[0], point[1], point[2]}, reach * reach, 0, {1.0f, 0.0f, 0.0f}};
    RTCPointQuery query;
    query.x = point[0];
    query.y = point[1];
    query.z = point[2];
    query.time = 0.0f;
    query.radius = reach;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(body.scene, &query, &context, closest_triangle_callback, &q);
    if (!(q.best_distance2 < reach * reach)) return false;
    *triangle = q.best_triangle;
    *w = q.best;
    return true;
}

// The hull point and contact normal at barycentric `w` of triangle `triangle`.
void interpolate(const BodyState& body, uint32_t triangle, Barycentric w, float* point, float* normal) {
    const uint32_t* t = body.triangles + 3 * triangle;
    float n[3];
    for (int k = 0; k < 3; ++k) {
        point[k] = w.w0 * body.hull[4 * t[0] + k] + w.w1 * body.hull[4 * t[1] + k] + w.w2 * body.hull[4 * t[2] + k];
        n[k] = w.w0 * body.normals[3 * t[0] + k] + w.w1 * body.normals[3 * t[1] + k] +
               w.w2 * body.normals[3 * t[2] + k];
    }
    const float length2 = dot3(n, n);
    const float inverse = length2 > 1e-24f ? 1.0f / std::sqrt(length2) : 0.0f;
    for (int k = 0; k < 3; ++k) normal[k] = n[k] * inverse;
}

// The surface's displacement at a contact over one substep: the hull's per-vertex motion since the
// previous step, interpolated, times the substep's share of the step.
Vec3 surface_motion(const BodyState& body, uint32_t triangle, Barycentric w, float share) {
    const uint32_t* t = body.triangles + 3 * triangle;
    float m[3];
    for (int k = 0; k < 3; ++k) {
        const float d0 = body.hull[4 * t[0] + k] - body.previous_hull[4 * t[0] + k];
        const float d1 = body.hull[4 * t[1] + k] - body.previous_hull[4 * t[1] + k];
        const float d2 = body.hull[4 * t[2] + k] - body.previous_hull[4 * t[2] + k];
        m[k] = (w.w0 * d0 + w.w1 * d1 + w.w2 * d2) * share;
    }
    return {m[0], m[1], m[2]};
}

// The hull point and normal at a closest-point search's answer, and how deep `x` lies behind that
// tangent plane (> 0: inside), metres.
struct HullPlane {
    Barycentric w;
    float point[3], normal[3];
    float depth;
};
HullPlane hull_plane_at(const BodyState& body, const body_query::Best& best, const float* x) {
    HullPlane h;
    h.w = {1.0f - best.v - best.w, best.v, best.w};
    interpolate(body, best.triangle, h.w, h.point, h.normal);
    float to_hull[3];
    sub3(h.point, x, to_hull);
    h.depth = dot3(to_hull, h.normal);
    return h;
}

// Particle i from x onto h's plane, along its normal (no friction: the crease rounds' projection).
void push_out(const Particles& p, uint32_t i, const float* x, const HullPlane& h) {
    p.x[i] = x[0] + h.normal[0] * h.depth;
    p.y[i] = x[1] + h.normal[1] * h.depth;
    p.z[i] = x[2] + h.normal[2] * h.depth;
}

// The outward normal of hull triangle t, ab x ac (not normalised).
void hull_face_normal(const BodyState& body, uint32_t t, float* n) {
    const uint32_t* v = body.triangles + 3 * t;
    const float *a = body.hull + 4 * v[0], *b = body.hull + 4 * v[1], *c = body.hull + 4 * v[2];
    float ab[3], ac[3];
    sub3(b, a, ab), sub3(c, a, ac);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
}

// The closest hull triangle within `reach` of p that p lies behind, seen from inside its face (the
// closest point inside the triangle, not on an edge or a corner: behind a face p is inside that
// part's hull, while beside an edge of a convex part it is not). Scalar, over the hierarchy's
// leaves (listed in `c`), for the few points that need it; the same code on both paths.
bool behind_open_face(const BodyState& body, const float* p, float reach, body_query::Candidates& c,
                      body_query::Best* out) {
    using namespace body_query;
    const BodyHierarchy& h = body.hierarchy;
    Best best{reach * reach, kNoTriangle, 0.0f, 0.0f};
    const auto test = [&] {
        for (uint32_t i = 0; i < c.count; ++i)
            for (uint32_t k = 0; k < kLeafTriangles; ++k) {  // a last leaf's padding repeats a triangle
                const uint32_t t = h.leaf_triangle[kLeafTriangles * c.leaf[i] + k];
                const uint32_t* v = body.triangles + 3 * t;
                const float *a = body.hull + 4 * v[0], *b = body.hull + 4 * v[1], *e = body.hull + 4 * v[2];
                TriangleRegion region = TriangleRegion::face;
                const Barycentric w = closest_on_triangle(p, a, b, e, &region);
                if (region != TriangleRegion::face) continue;
                float to_face[3], n[3];
                for (int x = 0; x < 3; ++x) to_face[x] = w.w0 * a[x] + w.w1 * b[x] + w.w2 * e[x] - p[x];
                hull_face_normal(body, t, n);
                const float d2 = dot3(to_face, to_face);
                if (d2 < best.distance2 && dot3(to_face, n) > 0.0f) best = {d2, t, w.w1, w.w2};
            }
        c.count = 0;
    };
    const float lo[3] = {p[0] - reach, p[1] - reach, p[2] - reach}, hi[3] = {p[0] + reach, p[1] + reach, p[2] + reach};
    c.count = 0;
    collect_leaves<simd::Float1>(h, reach, lo, hi, c, test);
    test();
    if (best.triangle == kNoTriangle) return false;
    *out = best;
    return true;
}

// A particle that crossed the hull since its previous position: the entry point, or false. The ray
// starts `back` metres behind the previous position: a particle projected onto the hull last
// substep may sit a rounding error inside it, and a ray from there would first meet the hull from
// within (a leaving hit) and miss the entry.
bool trace_entry(const BodyState& body, const float* previous, const float* to, float back, uint32_t* triangle,
                 Barycentric* w, float* hit) {
    float d[3];
    sub3(to, previous, d);
    const float length = std::sqrt(dot3(d, d));
    const float lead = back / length;  // length > thickness > 0: only moving particles get here
    RTCRayHit rh{};
    rh.ray.org_x = previous[0] - lead * d[0];
    rh.ray.org_y = previous[1] - lead * d[1];
    rh.ray.org_z = previous[2] - lead * d[2];
    const float from[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z};
    rh.ray.dir_x = d[0];
    rh.ray.dir_y = d[1];
    rh.ray.dir_z = d[2];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = 1.0f + lead;  // to the new position: dir is the whole displacement
    rh.ray.mask = ~0u;   // Debian's Embree is built with ray masks: 0 would hit nothing
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(body.scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    // Entering means moving against the outward face normal (our winding, not Embree's Ng sign).
    const uint32_t* t = body.triangles + 3 * rh.hit.primID;
    float e1[3], e2[3];
    sub3(body.hull + 4 * t[1], body.hull + 4 * t[0], e1);
    sub3(body.hull + 4 * t[2], body.hull + 4 * t[0], e2);
    const float face[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const float dir[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
    if (!(dot3(dir, face) < 0.0f)) return false;  // leaving the hull: not a crossing into it
    *triangle = rh.hit.primID;
    *w = {1.0f - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v};  // Embree: p = (1-u-v) v0 + u v1 + v v2
    for (int k = 0; k < 3; ++k) hit[k] = from[k] + rh.ray.tfar * dir[k];
    return true;
}

}  // namespace

// Four floats added as one (GCC and Clang vector extension: SSE on x86, NEON on ARM).
using Float4 = float __attribute__((vector_size(16)));

void compute_offset_hull(BodyState& body, const Vec3* positions, const float* previous) {
    // Area-weighted normals: the sum of the unnormalised face normals (each |e1 x e2| = 2 area),
    // summed in the hull's own four-float slots before the hull is written over them: one
    // four-wide add per corner instead of three scalar ones (the fourth lane adds 0; the sums, in
    // the same order, are the same bits). The arrays do not overlap (restrict).
    float* __restrict sum = body.hull;
    const uint32_t* __restrict triangles = body.triangles;
    for (uint32_t i = 0; i < 4 * body.vertex_count; ++i) sum[i] = 0.0f;
    for (uint32_t f = 0; f < body.triangle_count; ++f) {
        const uint32_t* t = triangles + 3 * f;
        const Vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
        const float e1[3] = {b.x - a.x, b.y - a.y, b.z - a.z};
        const float e2[3] = {c.x - a.x, c.y - a.y, c.z - a.z};
        const Float4 face = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0], 0.0f};
        for (int corner = 0; corner < 3; ++corner) {
            float* s = sum + 4 * t[corner];
            Float4 total;
            std::memcpy(&total, s, sizeof(total));
            total += face;
            std::memcpy(s, &total, sizeof(total));
        }
    }
    // The seed's offset hull: every vertex pushed out along its unit normal by the thickness.
    const float thickness = body.desc.thickness_m;
    for (uint32_t v = 0; v < body.vertex_count; ++v) {
        float* h = body.hull + 4 * v;
        float* nv = body.normals + 3 * v;
        const float n[3] = {h[0], h[1], h[2]};
        const float length2 = dot3(n, n);
        const float inverse = length2 > 0.0f ? 1.0f / std::sqrt(length2) : 0.0f;  // isolated vertex: no push
        for (int k = 0; k < 3; ++k) nv[k] = n[k] * inverse;
        h[0] = positions[v].x + thickness * nv[0];
        h[1] = positions[v].y + thickness * nv[1];
        h[2] = positions[v].z + thickness * nv[2];
        h[3] = 0.0f;  // the vertex's motion since `previous`: widens its leaves (BodyHierarchy)
        if (previous == nullptr) continue;
        const float* q = previous + 4 * v;
        const float d2 = (h[0] - q[0]) * (h[0] - q[0]) + (h[1] - q[1]) * (h[1] - q[1]) + (h[2] - q[2]) * (h[2] - q[2]);
        h[3] = std::sqrt(d2);
    }
}

BodyContact closest_hull_point(const BodyState& body, const float* point, float reach) {
    BodyContact contact;
    uint32_t triangle = 0;
    Barycentric w{};
    if (!find_closest(body, point, reach, &triangle, &w)) return contact;
    float hull_point[3], normal[3], to_hull[3];
    interpolate(body, triangle, w, hull_point, normal);
    sub3(hull_point, point, to_hull);
    contact.found = true;
    contact.penetration_m = dot3(to_hull, normal);  // > 0: the point lies behind the hull
    contact.hull_point = {hull_point[0], hull_point[1], hull_point[2]};
    contact.normal = {normal[0], normal[1], normal[2]};
    contact.triangle = triangle;
    return contact;
}

namespace {

// The plain pass (add_reference_body): one rtcPointQuery per particle, radius thickness +
// margin (the plain pass: not widened by the body's motion, so a surface sweeping over resting
// cloth can leave it deeper than Weft's pass). The baseline the step's own hierarchy is measured against.
void collide_body_reference(const Particles& p, const BodyState& body, float share, BodyPassCounts& counts) {
    using F = simd::Float1;
    const float thickness2 = body.desc.thickness_m * body.desc.thickness_m;
    ColliderKernelArgs args{};
    args.friction = body.desc.friction;
    for (uint32_t i = 0; i < p.slot_count; ++i) {
        if (!(p.inverse_mass[i] > 0.0f)) continue;  // pinned and padding slots
        const float x[3] = {p.x[i], p.y[i], p.z[i]};
        const float previous[3] = {p.previous_x[i], p.previous_y[i], p.previous_z[i]};
        float moved[3];
        sub3(x, previous, moved);
        uint32_t triangle = 0;
        Barycentric w{};
        float hull_point[3], normal[3];
        float penetration = 0.0f;
        bool contact = false;
        if (dot3(moved, moved) > thickness2) {
            counts.rays += 1;
            float hit[3];
            if (trace_entry(body, previous, x, body.desc.thickness_m, &triangle, &w, hit)) {
                float unused[3], to_hit[3];
                interpolate(body, triangle, w, unused, normal);
                sub3(hit, x, to_hit);
                penetration = dot3(to_hit, normal);
                contact = penetration > 0.0f;
            }
        }
        if (!contact) {
            counts.queried += 1;
            if (!find_closest(body, x, base_reach(body), &triangle, &w)) continue;
            float to_hull[3];
            interpolate(body, triangle, w, hull_point, normal);
            sub3(hull_point, x, to_hull);
            penetration = dot3(to_hull, normal);
            contact = penetration > 0.0f;
        }
        if (!contact) continue;
        counts.contacts += 1;
        args.motion = surface_motion(body, triangle, w, share);
        const Vec3W<F> xw{{x[0]}, {x[1]}, {x[2]}};
        const Vec3W<F> nw{{normal[0]}, {normal[1]}, {normal[2]}};
        resolve_contact(p, i, xw, nw, F{penetration}, simd::Mask1{true}, args);
    }
}

const body_query::Path& path_for(SimdPath path) {
    if (path == SimdPath::avx2)
        if (const body_query::Path* avx2 = body_query::avx2_path(); avx2 != nullptr) return *avx2;
    return body_query::scalar_path();
}

// Searches of the pushed particles after the first push (the crease rounds in collide_body).
constexpr uint32_t kCreaseRounds = 4;
// A crease round's push shorter than this ends the particle's rounds: most later pushes are the
// rounding of the projection itself (10-100 nm), and a search costs as much as a first one
// (weft-bench body: of 711 particles a frame pushed again in the second round, 48 by more than 1 um).
constexpr float kCreaseTolerance_m = 1e-6f;

// Slot i's contact plane (planes model): the hull point and normal at `w` on `triangle` and the
// surface's motion there, or no plane (kNoTriangle); found where the particle now is, held while
// it stays within sqrt(reach2) of there.
void keep_plane(const ContactPlanes& c, uint32_t i, const Particles& p, const BodyState& body, uint32_t triangle,
                Barycentric w, uint32_t crease_triangle, Barycentric crease_w, float share, float reach2) {
    float point[3] = {p.x[i], p.y[i], p.z[i]}, normal[3] = {0.0f, 0.0f, 0.0f};
    float crease_point[3] = {p.x[i], p.y[i], p.z[i]}, crease_normal[3] = {0.0f, 0.0f, 0.0f};
    Vec3 motion{};
    if (triangle != body_query::kNoTriangle) {
        interpolate(body, triangle, w, point, normal);
        motion = surface_motion(body, triangle, w, share);
    }
    if (crease_triangle != body_query::kNoTriangle) interpolate(body, crease_triangle, crease_w, crease_point, crease_normal);
    const float m[3] = {motion.x, motion.y, motion.z};
    for (int a = 0; a < 3; ++a) {
        c.point[a][i] = point[a];
        c.normal[a][i] = normal[a];
        c.motion[a][i] = m[a];
        c.crease_point[a][i] = crease_point[a];
        c.crease_normal[a][i] = crease_normal[a];
    }
    c.from[0][i] = p.x[i], c.from[1][i] = p.y[i], c.from[2][i] = p.z[i];
    c.reach2[i] = reach2;
}

// The exact pass, per cluster of kClusterSlots slots: one walk of the hierarchy serves the
// tunnelling rays of the particles that moved further than the thickness and the closest-point
// search of all; an entering ray hit wins, else the closest triangle; then the response
// (projection along the interpolated hull normal, friction against the surface's motion:
// colliders.h's resolve_contact). With `planes` it keeps each searched particle's plane; with
// `marked_only` it searches only the particles project_on_planes marked (reach2 < 0).
void collide_clusters(const Particles& particles, const uint32_t* order, const BodyState& body, float share,
                      const ContactPlanes* planes, bool marked_only, const body_query::Path& path,
                      BodyPassCounts& counts) {
    using F = simd::Float1;
    using namespace body_query;
    const Particles p = particles;
    const SearchCluster search = path.search;
    const SearchAgain search_again = path.search_again;
    const float thickness = body.desc.thickness_m;
    const float reach = base_reach(body);
    // The planes model wants every particle's closest point within reach, inside or not (a later
    // substep may bring it behind that plane), so no plane shortcut (in_front_of_every_plane).
    const bool contacts_only = planes == nullptr;
    ColliderKernelArgs args{};
    args.friction = body.desc.friction;
    Candidates candidates;  // on the stack (about 16 kB each): nothing allocates
    Candidates scratch;     // the lost particles' searches and the crease triangles' second look
    Cluster q;
    q.share = share;  // the rays' frame: each triangle's motion this substep (intersect_leaf)
    for (uint32_t c0 = 0; c0 < p.slot_count; c0 += kClusterSlots) {
        const uint32_t n = p.slot_count - c0 < kClusterSlots ? p.slot_count - c0 : kClusterSlots;
        uint32_t slot[kClusterSlots];
        for (uint32_t k = 0; k < n; ++k) slot[k] = order[c0 + k];
        q.active = q.rays = 0;
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t i = slot[k];
            if (!(p.inverse_mass[i] > 0.0f)) continue;  // pinned and padding slots
            if (marked_only && !(planes->reach2[i] < 0.0f)) continue;  // held by its plane
            const float x[3] = {p.x[i], p.y[i], p.z[i]};
            const float previous[3] = {p.previous_x[i], p.previous_y[i], p.previous_z[i]};
            q.point[k][0] = x[0], q.point[k][1] = x[1], q.point[k][2] = x[2];
            q.active |= 1u << k;
            float moved[3];
            sub3(x, previous, moved);
            const float length2 = dot3(moved, moved);
            if (!(length2 > thickness * thickness)) continue;
            // Further than the thickness in one substep: the point search alone could miss a
            // crossing. The ray starts one thickness behind the previous position: a particle
            // projected onto the hull may sit a rounding error inside it, and a ray from there would
            // first meet the hull from within (a leaving hit) and miss the entry.
            const float lead = thickness / std::sqrt(length2);
            for (int a = 0; a < 3; ++a) {
                q.origin[k][a] = previous[a] - lead * moved[a];
                q.dir[k][a] = moved[a];
            }
            q.t_far[k] = 1.0f + lead;  // to the new position: dir is the whole displacement
            q.rays |= 1u << k;
            counts.rays += 1;
        }
        if (q.active == 0) continue;
        const uint32_t met = search(body.hierarchy, reach, q, candidates, contacts_only);
        counts.queried += uint64_t(__builtin_popcount(met));
        uint32_t pushed = 0, pushed_from[kClusterSlots], lost = 0;
        uint32_t entered = 0;            // pushed onto the plane where their ray entered the hull
        float entry[kClusterSlots][3];   // that entry point
        uint32_t plane_triangle[kClusterSlots];  // the contact plane each point keeps (planes model)
        Barycentric plane_at[kClusterSlots];
        // Point k inside the hull at barycentric `w` of `triangle`, by `penetration` along `normal`:
        // the response (seed eq. 7-8 against the hull, with friction).
        const auto respond = [&](uint32_t k, uint32_t triangle, Barycentric w, const float* normal, float penetration) {
            const float* x = q.point[k];
            counts.contacts += 1;
            pushed |= 1u << k;
            pushed_from[k] = triangle;
            args.motion = surface_motion(body, triangle, w, share);
            const Vec3W<F> xw{{x[0]}, {x[1]}, {x[2]}};
            const Vec3W<F> nw{{normal[0]}, {normal[1]}, {normal[2]}};
            resolve_contact(p, slot[k], xw, nw, F{penetration}, simd::Mask1{true}, args);
        };
        for (uint32_t k = 0; k < n; ++k) {
            if (!(q.active >> k & 1u)) continue;
            const float* x = q.point[k];
            plane_triangle[k] = kNoTriangle;
            uint32_t triangle = kNoTriangle;
            Barycentric w{};
            float normal[3], penetration = 0.0f;
            const RayHit& hit = q.hit[k];
            if (hit.triangle != kNoTriangle) {
                w = {1.0f - hit.u - hit.v, hit.u, hit.v};
                float unused[3], at[3], to_hit[3];
                interpolate(body, hit.triangle, w, unused, normal);
                // On the ray in the hit triangle's frame (ray_in_body_frame: the kernel's segment).
                const float inverse_t_far = 1.0f / q.t_far[k];
                for (int a = 0; a < 3; ++a) {
                    float dir;
                    const float origin = ray_in_body_frame(q.origin[k][a], q.dir[k][a], hit.motion[a], inverse_t_far, &dir);
                    at[a] = origin + hit.t * dir;
                }
                sub3(at, x, to_hit);
                penetration = dot3(to_hit, normal);
                if (penetration > 0.0f) {
                    triangle = hit.triangle, entered |= 1u << k;
                    for (int a = 0; a < 3; ++a) entry[k][a] = at[a];
                    plane_triangle[k] = hit.triangle, plane_at[k] = w;
                }
            }
            if (triangle == kNoTriangle) {
                const Best& best = q.best[k];
                if (!(best.distance2 < std::numeric_limits<float>::infinity())) {
                    lost |= (q.rays >> k & 1u) << k;  // moved far and met no hull on the way: below
                    continue;
                }
                HullPlane h = hull_plane_at(body, best, x);
                triangle = best.triangle;
                // In front of a triangle in a crease (the arm's underside in the armpit) the particle
                // may still be inside the other part: behind the face of another triangle within reach.
                Best other;
                if (!(h.depth > 0.0f) && body.hierarchy.in_crease[best.triangle] != 0 &&
                    behind_open_face(body, x, reach, scratch, &other)) {
                    const HullPlane o = hull_plane_at(body, other, x);
                    if (o.depth > 0.0f) h = o, triangle = other.triangle;
                }
                w = h.w, penetration = h.depth;
                for (int a = 0; a < 3; ++a) normal[a] = h.normal[a];
                plane_triangle[k] = triangle, plane_at[k] = w;
                if (!(penetration > 0.0f)) continue;
            }
            respond(k, triangle, w, normal, penetration);
        }
        const uint32_t searched = q.active;  // the crease rounds reuse q.active
        // A particle that moved further than the thickness, met no entering hull on the way and has
        // no hull within reach may have slid along the hull from a contact (its ray then starts
        // inside the hull and meets no entry) and cut under the surface by up to how far it moved:
        // such particles (rare) look that much further, and are pushed out of the closest surface
        // if they were on or in front of it before this substep.
        if (lost != 0) {
            float far = 0.0f;
            for (uint32_t k = 0; k < n; ++k) {
                if (!(lost >> k & 1u)) continue;
                float moved[3];
                sub3(q.point[k], q.origin[k], moved);
                far = std::max(far, std::sqrt(dot3(moved, moved)));
            }
            // Its own cluster and leaf list (scratch): the crease rounds below search the cluster's.
            Cluster lost_q;
            for (uint32_t k = 0; k < n; ++k)
                for (int a = 0; a < 3; ++a) lost_q.point[k][a] = q.point[k][a];
            lost_q.active = lost, lost_q.rays = 0;
            counts.queried +=
                uint64_t(__builtin_popcount(search(body.hierarchy, reach + far, lost_q, scratch, false)));
            for (uint32_t k = 0; k < n; ++k) {
                const Best& best = lost_q.best[k];
                if (!(lost >> k & 1u) || !(best.distance2 < std::numeric_limits<float>::infinity())) continue;
                const HullPlane h = hull_plane_at(body, best, q.point[k]);
                plane_triangle[k] = best.triangle, plane_at[k] = h.w;
                // Only a particle that came from the surface it is now under (within reach of it
                // before this substep): one that was already behind that surface's plane (a point
                // outside in a crease, behind another part's tangent plane) or far in front of it
                // is not taken to have cut under it.
                const uint32_t i = slot[k];
                const float previous[3] = {p.previous_x[i], p.previous_y[i], p.previous_z[i]};
                float to_hull[3];
                sub3(h.point, previous, to_hull);
                const float was = dot3(to_hull, h.normal);  // how deep the particle was behind it
                if (h.depth > 0.0f && was <= thickness && was >= -reach) {
                    respond(k, best.triangle, h.w, h.normal, h.depth);
                    lost &= ~(1u << k);
                }
            }
            // Through a thin part (an arm, a leg) the closest surface is the far side, which the
            // particle never reached (its ray slipped between two triangles, each traced in its own
            // frame): those still lost go back out of the surface closest to where they started
            // the substep, if they are behind it.
            if (lost != 0) {
                for (uint32_t k = 0; k < n; ++k) {
                    if (!(lost >> k & 1u)) continue;
                    const uint32_t i = slot[k];
                    lost_q.point[k][0] = p.previous_x[i], lost_q.point[k][1] = p.previous_y[i], lost_q.point[k][2] = p.previous_z[i];
                }
                lost_q.active = lost;
                counts.queried += uint64_t(__builtin_popcount(search(body.hierarchy, reach, lost_q, scratch, false)));
                for (uint32_t k = 0; k < n; ++k) {
                    const Best& best = lost_q.best[k];
                    if (!(lost >> k & 1u) || !(best.distance2 < std::numeric_limits<float>::infinity())) continue;
                    const HullPlane h = hull_plane_at(body, best, q.point[k]);
                    if (!(h.depth > 0.0f)) continue;
                    plane_triangle[k] = best.triangle, plane_at[k] = h.w;
                    respond(k, best.triangle, h.w, h.normal, h.depth);
                }
            }
        }
        // The plane where a ray entered is the hull's tangent there; a particle that moved far in
        // one substep lands on it up to that move away from the entry, and where the hull bulges
        // out between the two (the buttocks below the back's waist) it lands still inside, deeper
        // than the point search's reach, where no later substep finds it. Such particles are searched
        // again from where they landed, as far as their entry point (which is on the hull), and
        // pushed out of the closest surface if they are behind it; the crease rounds go on from there.
        if (entered != 0) {
            Cluster again;
            float far = 0.0f;
            for (uint32_t k = 0; k < n; ++k) {
                if (!(entered >> k & 1u)) continue;
                const uint32_t i = slot[k];
                again.point[k][0] = p.x[i], again.point[k][1] = p.y[i], again.point[k][2] = p.z[i];
                float slid[3];
                sub3(again.point[k], entry[k], slid);
                far = std::max(far, std::sqrt(dot3(slid, slid)));
            }
            again.active = entered, again.rays = 0;
            counts.queried += uint64_t(__builtin_popcount(search(body.hierarchy, reach + far, again, scratch, false)));
            for (uint32_t k = 0; k < n; ++k) {
                const Best& best = again.best[k];
                if (!(entered >> k & 1u) || !(best.distance2 < std::numeric_limits<float>::infinity())) continue;
                const HullPlane h = hull_plane_at(body, best, again.point[k]);
                if (!(h.depth > 0.0f)) continue;
                push_out(p, slot[k], again.point[k], h);
                pushed_from[k] = best.triangle;
                plane_triangle[k] = best.triangle, plane_at[k] = h.w;
            }
        }
        // In a crease of the hull (between the thighs, in the armpit) the push out of one surface
        // can land inside the other: the pushed particles are searched again from where they
        // landed and projected out of the closest surface again, without friction (alternating
        // projections onto the two sides converge; friction would pull back toward the first).
        // skirt-walk: the hem under the crotch 1.65 mm below the hull before, 0.58 mm after one
        // round. Each later round takes only the particles the round before moved: skirt-walk's
        // deepest particle over 300 frames 0.86 mm with two rounds, 0.48 with three, 0.38 with four
        // (tee-walk 0.12, 0.04, 0.014 mm), for 3.4% more of the pass's instructions than two.
        // Each search starts from the triangle the particle was last pushed out of, at its distance
        // from where the particle landed (about zero): only a strictly closer triangle, the other side
        // of a crease, can change the answer, so every leaf whose box lies further away is skipped.
        uint32_t crease_triangle[kClusterSlots];  // the other side of a crease (planes model)
        Barycentric crease_at[kClusterSlots];
        for (uint32_t k = 0; k < n; ++k) crease_triangle[k] = kNoTriangle;
        for (uint32_t round = 0; round < kCreaseRounds && pushed != 0; ++round) {
            q.active = pushed, q.rays = 0;
            for (uint32_t k = 0; k < n; ++k) {
                if (!(pushed >> k & 1u)) continue;
                float* landed = q.point[k];
                landed[0] = p.x[slot[k]], landed[1] = p.y[slot[k]], landed[2] = p.z[slot[k]];
                const uint32_t* t = body.triangles + 3 * pushed_from[k];
                const float *a = body.hull + 4 * t[0], *b = body.hull + 4 * t[1], *c = body.hull + 4 * t[2];
                const Barycentric on = closest_on_triangle(landed, a, b, c);
                float away[3];
                for (int axis = 0; axis < 3; ++axis)
                    away[axis] = landed[axis] - (on.w0 * a[axis] + on.w1 * b[axis] + on.w2 * c[axis]);
                q.best[k] = {dot3(away, away), pushed_from[k], on.w1, on.w2};
            }
            search_again(body.hierarchy, reach, q, candidates);
            uint32_t moved = 0;
            for (uint32_t k = 0; k < n; ++k) {
                if (!(pushed >> k & 1u)) continue;
                const Best& best = q.best[k];
                if (!(best.distance2 < std::numeric_limits<float>::infinity())) continue;
                const HullPlane h = hull_plane_at(body, best, q.point[k]);
                if (!(h.depth > 0.0f)) continue;
                push_out(p, slot[k], q.point[k], h);
                moved |= h.depth > kCreaseTolerance_m ? 1u << k : 0u;
                pushed_from[k] = best.triangle;
                crease_triangle[k] = best.triangle, crease_at[k] = h.w;
            }
            pushed = moved;
        }
        if (planes == nullptr) continue;
        // Each point's plane holds while it stays within kPlanesBound_m of where it is now.
        for (uint32_t k = 0; k < n; ++k)
            if (searched >> k & 1u)
                keep_plane(*planes, slot[k], p, body, plane_triangle[k], plane_at[k], crease_triangle[k], crease_at[k],
                           share, kPlanesBound_m * kPlanesBound_m);
    }
}

}  // namespace

void collide_body(const Particles& particles, const uint32_t* order, const BodyState& body, uint32_t substep,
                  uint32_t substeps, const ContactPlanes* planes, SimdPath path, BodyPassCounts& counts) {
    const float share = 1.0f / float(substeps);
    if (body.reference_queries) return collide_body_reference(particles, body, share, counts);
    const body_query::Path& kernels = path_for(path);
    if (substeps == 1) planes = nullptr;  // no later substep to keep planes for: the exact pass
    if (planes == nullptr || substep == 0)
        return collide_clusters(particles, order, body, share, planes, false, kernels, counts);
    // Later substeps of the planes model: the kept planes, then the exact search for the particles
    // that moved beyond what their plane holds.
    if (kernels.project_on_planes(particles, *planes, body.desc.friction, counts.contacts) > 0)
        collide_clusters(particles, order, body, share, planes, true, kernels, counts);
}

// Morton code of a point quantised to 10 bits an axis: the bits of x, y and z interleaved.
uint32_t morton3(uint32_t x, uint32_t y, uint32_t z) {
    auto spread = [](uint32_t v) {  // 10 bits -> every third of 30
        v = (v | v << 16) & 0x030000ffu;
        v = (v | v << 8) & 0x0300f00fu;
        v = (v | v << 4) & 0x030c30c3u;
        return (v | v << 2) & 0x09249249u;
    };
    return spread(x) | spread(y) << 1 | spread(z) << 2;
}

void order_for_body_pass(const ClothAsset& asset, uint32_t* key, uint32_t* order) {
    const uint32_t n = asset.slot_count;
    const float* start[3] = {asset.start_x, asset.start_y, asset.start_z};
    float lo[3], extent = 0.0f;
    for (int a = 0; a < 3; ++a) {
        float low = n > 0 ? start[a][0] : 0.0f, high = low;
        for (uint32_t i = 1; i < n; ++i) low = start[a][i] < low ? start[a][i] : low, high = start[a][i] > high ? start[a][i] : high;
        lo[a] = low;
        extent = high - low > extent ? high - low : extent;
    }
    const float scale = extent > 0.0f ? 1023.0f / extent : 0.0f;  // one scale: cells stay cubes
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t cell[3];
        for (int a = 0; a < 3; ++a) {
            const float c = (start[a][i] - lo[a]) * scale;
            cell[a] = c >= 0.0f && c <= 1023.0f ? uint32_t(c) : (c > 1023.0f ? 1023u : 0u);  // NaN: 0
        }
        key[i] = morton3(cell[0], cell[1], cell[2]);
        order[i] = i;
    }
    std::sort(order, order + n, [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
}

ContactPlanes contact_planes_in(float* block, uint32_t slot_count) {
    ContactPlanes c;
    float** arrays[kContactPlaneArrays] = {&c.point[0],        &c.point[1],        &c.point[2],        &c.normal[0],
                                           &c.normal[1],       &c.normal[2],       &c.motion[0],       &c.motion[1],
                                           &c.motion[2],       &c.from[0],         &c.from[1],         &c.from[2],
                                           &c.reach2,          &c.crease_point[0], &c.crease_point[1], &c.crease_point[2],
                                           &c.crease_normal[0], &c.crease_normal[1], &c.crease_normal[2]};
    for (uint32_t a = 0; a < kContactPlaneArrays; ++a) *arrays[a] = block + size_t(a) * slot_count;
    return c;
}

BodyContact closest_hull_point_hierarchy(const BodyState& body, const float* point, float reach, SimdPath path) {
    using namespace body_query;
    BodyContact contact;
    Candidates candidates;
    Cluster q;
    q.point[0][0] = point[0], q.point[0][1] = point[1], q.point[0][2] = point[2];
    q.active = 1u;
    path_for(path).search(body.hierarchy, reach, q, candidates, false);
    const Best& best = q.best[0];
    if (!(best.distance2 < std::numeric_limits<float>::infinity())) return contact;
    const HullPlane h = hull_plane_at(body, best, point);
    contact.found = true;
    contact.penetration_m = h.depth;
    contact.hull_point = {h.point[0], h.point[1], h.point[2]};
    contact.normal = {h.normal[0], h.normal[1], h.normal[2]};
    contact.triangle = best.triangle;
    return contact;
}

// --- the hierarchy: creation and refit ----------------------------------------------------------

namespace {

struct HierarchySizes {
    uint32_t leaves, groups, roots, padded_leaves, padded_groups, padded_roots;
};
HierarchySizes hierarchy_sizes(uint32_t triangles) {
    HierarchySizes s;
    s.leaves = (triangles + kLeafTriangles - 1) / kLeafTriangles;
    s.groups = (s.leaves + kGroupLeaves - 1) / kGroupLeaves;
    s.padded_leaves = s.groups * kGroupLeaves;
    s.roots = (s.groups + kRootGroups - 1) / kRootGroups;
    s.padded_groups = s.roots * kRootGroups;
    s.padded_roots = (s.roots + 7) / 8 * 8;
    return s;
}

bool carve_boxes(Arena& arena, uint32_t count, Boxes* b) {
    float** arrays[6] = {&b->min_x, &b->min_y, &b->min_z, &b->max_x, &b->max_y, &b->max_z};
    for (float** a : arrays) {
        *a = arena.allocate_array<float>(count);
        if (*a == nullptr) return false;
    }
    for (uint32_t i = 0; i < count; ++i) {  // empty boxes: no query ever meets them
        b->min_x[i] = b->min_y[i] = b->min_z[i] = std::numeric_limits<float>::infinity();
        b->max_x[i] = b->max_y[i] = b->max_z[i] = -std::numeric_limits<float>::infinity();
    }
    return true;
}

// Orders `count` triangles so that every run of a root's, a group's, a leaf's triangles is a compact
// patch: split at a multiple of the unit nearest the middle along the centroids' longest axis
// (std::nth_element works in place: nothing allocates; depth about log2(triangles / 8)).
void split_triangles(uint32_t* first, uint32_t count, const float* centroid) {
    if (count <= kLeafTriangles) return;
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = centroid[3 * first[0] + a];
    for (uint32_t i = 1; i < count; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], centroid[3 * first[i] + a]);
            hi[a] = std::max(hi[a], centroid[3 * first[i] + a]);
        }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    constexpr uint32_t group = kGroupLeaves * kLeafTriangles, root = kRootGroups * group;
    const uint32_t unit = count > root ? root : count > group ? group : kLeafTriangles;
    const uint32_t units = (count + unit - 1) / unit;
    const uint32_t half = std::max(1u, units / 2) * unit;
    std::nth_element(first, first + half, first + count, [&](uint32_t a, uint32_t b) {
        const float ca = centroid[3 * a + axis], cb = centroid[3 * b + axis];
        return ca < cb || (ca == cb && a < b);  // a total order: the same split on every machine
    });
    split_triangles(first, half, centroid);
    split_triangles(first + half, count - half, centroid);
}

}  // namespace

size_t body_hierarchy_bytes(uint32_t triangles, uint32_t bodies) {
    // Every body rounds its leaves and groups up; bound the sums, plus a cache line per array.
    const size_t leaves = size_t(triangles) / kLeafTriangles + bodies;
    const size_t padded_leaves = leaves + size_t(kGroupLeaves) * bodies;
    const size_t padded_groups = padded_leaves / kGroupLeaves + kRootGroups * size_t(bodies);
    const size_t padded_roots = padded_groups / kRootGroups + 8 * size_t(bodies);
    const size_t floats = kLeafCorners * leaves + 8 * padded_leaves + 6 * (padded_groups + padded_roots);
    return sizeof(float) * floats + sizeof(uint32_t) * 4 * kLeafTriangles * leaves + size_t(triangles) +
           24 * kCacheLine * size_t(bodies);
}

namespace {

// BodyHierarchy::in_crease: a hull triangle is in a crease when another part's surface faces it
// within the reach of its middle (a triangle whose normal points against its own, |cos| > 0.3:
// the arm's underside and the torso's side in the armpit, the inner thighs). There two parts' hulls
// overlap, and a particle in front of one may be behind the other. Leaf by leaf: one walk finds the
// leaves near any of a leaf's eight triangles, and a near leaf's normals are found once for all.
void mark_crease_triangles(BodyState& body) {
    using namespace body_query;
    const float reach = base_reach(body);
    BodyHierarchy& h = body.hierarchy;
    Candidates c;  // on the stack (about 16 kB)
    auto normal_of = [&](uint32_t t, float* out) {  // unit, or zero for a degenerate triangle
        hull_face_normal(body, t, out);
        const float length = std::sqrt(dot3(out, out));
        for (int x = 0; x < 3; ++x) out[x] = length > 0.0f ? out[x] / length : 0.0f;
    };
    for (uint32_t l = 0; l < h.leaf_count; ++l) {
        const uint32_t* own = h.leaf_triangle + kLeafTriangles * l;
        float own_normal[kLeafTriangles][3], middle[kLeafTriangles][3];
        bool facing[kLeafTriangles] = {};
        float lo[3], hi[3];
        for (int x = 0; x < 3; ++x) lo[x] = std::numeric_limits<float>::infinity(), hi[x] = -lo[x];
        for (uint32_t k = 0; k < kLeafTriangles; ++k) {
            const uint32_t* v = body.triangles + 3 * own[k];
            const float *a = body.hull + 4 * v[0], *b = body.hull + 4 * v[1], *e = body.hull + 4 * v[2];
            normal_of(own[k], own_normal[k]);
            for (int x = 0; x < 3; ++x) {
                middle[k][x] = (a[x] + b[x] + e[x]) / 3.0f;
                lo[x] = std::min(lo[x], middle[k][x] - reach), hi[x] = std::max(hi[x], middle[k][x] + reach);
            }
        }
        const auto test = [&] {
            for (uint32_t i = 0; i < c.count; ++i) {
                // The own triangles whose reach meets this leaf's box (it holds its triangles).
                uint32_t near = 0;
                for (uint32_t k = 0; k < kLeafTriangles; ++k)
                    near |= uint32_t(!facing[k] && c.min_x[i] <= middle[k][0] + reach && c.max_x[i] >= middle[k][0] - reach &&
                                     c.min_y[i] <= middle[k][1] + reach && c.max_y[i] >= middle[k][1] - reach &&
                                     c.min_z[i] <= middle[k][2] + reach && c.max_z[i] >= middle[k][2] - reach) << k;
                if (near == 0) continue;
                const uint32_t* theirs = h.leaf_triangle + kLeafTriangles * c.leaf[i];
                float other[kLeafTriangles][3];
                for (uint32_t j = 0; j < kLeafTriangles; ++j) normal_of(theirs[j], other[j]);
                for (uint32_t k = 0; k < kLeafTriangles; ++k)
                    for (uint32_t j = 0; j < kLeafTriangles && (near >> k & 1u) != 0 && !facing[k]; ++j) {
                        if (!(dot3(own_normal[k], other[j]) < -0.3f)) continue;
                        const uint32_t* w = body.triangles + 3 * theirs[j];
                        const Barycentric on = closest_on_triangle(middle[k], body.hull + 4 * w[0], body.hull + 4 * w[1], body.hull + 4 * w[2]);
                        float d[3];
                        for (int x = 0; x < 3; ++x)
                            d[x] = on.w0 * body.hull[4 * w[0] + x] + on.w1 * body.hull[4 * w[1] + x] + on.w2 * body.hull[4 * w[2] + x] - middle[k][x];
                        facing[k] = dot3(d, d) < reach * reach;
                    }
            }
            c.count = 0;
        };
        c.count = 0;
        collect_leaves<simd::Float1>(h, reach, lo, hi, c, test);
        test();
        for (uint32_t k = 0; k < kLeafTriangles; ++k) h.in_crease[own[k]] = facing[k] ? 1 : 0;
    }
}

}  // namespace

bool build_body_hierarchy(BodyState& body, Arena& arena, SimdPath path) {
    BodyHierarchy& h = body.hierarchy;
    const HierarchySizes s = hierarchy_sizes(body.triangle_count);
    h.leaf_count = s.leaves;
    h.group_count = s.groups;
    h.root_count = s.roots;
    h.leaf_triangle = arena.allocate_array<uint32_t>(size_t(kLeafTriangles) * s.leaves);
    h.leaf_vertex = arena.allocate_array<uint32_t>(3 * size_t(kLeafTriangles) * s.leaves);
    h.leaf_corners = arena.allocate_array<float>(size_t(kLeafCorners) * s.leaves);
    h.leaf_sweep = arena.allocate_array<float>(s.padded_leaves);
    h.leaf_fold = arena.allocate_array<float>(s.padded_leaves);
    h.in_crease = arena.allocate_array<uint8_t>(body.triangle_count);
    if (h.leaf_triangle == nullptr || h.leaf_vertex == nullptr || h.leaf_corners == nullptr ||
        h.leaf_sweep == nullptr || h.leaf_fold == nullptr || h.in_crease == nullptr || !carve_boxes(arena, s.padded_leaves, &h.leaves) ||
        !carve_boxes(arena, s.padded_groups, &h.groups) || !carve_boxes(arena, s.padded_roots, &h.roots))
        return false;
    for (uint32_t l = 0; l < s.padded_leaves; ++l) h.leaf_sweep[l] = h.leaf_fold[l] = 0.0f;  // the padding leaves' stay 0
    // Triangles ordered by recursive median splits of their centroids along the longest axis, at
    // multiples of a group (then of a leaf) near the middle: each leaf is a compact patch and each
    // group a subtree (Morton order gave leaves 2-3 times larger, measured: 3.5 x 5 x 1.4 cm boxes).
    // The centroids live in the corner array's memory until the first refit (16 floats a triangle >= 3).
    float* centroid = h.leaf_corners;
    for (uint32_t f = 0; f < body.triangle_count; ++f) {
        const uint32_t* t = body.triangles + 3 * f;
        for (int a = 0; a < 3; ++a)
            centroid[3 * f + a] = (body.hull[4 * t[0] + a] + body.hull[4 * t[1] + a] + body.hull[4 * t[2] + a]) / 3.0f;
        h.leaf_triangle[f] = f;
    }
    split_triangles(h.leaf_triangle, body.triangle_count, centroid);
    // The last leaf's empty lanes repeat its last triangle (a duplicate never wins a strict test).
    for (uint32_t f = body.triangle_count; f < kLeafTriangles * s.leaves; ++f)
        h.leaf_triangle[f] = h.leaf_triangle[body.triangle_count - 1];
    for (uint32_t l = 0; l < s.leaves; ++l)
        for (uint32_t k = 0; k < kLeafTriangles; ++k)
            for (uint32_t corner = 0; corner < 3; ++corner)
                h.leaf_vertex[3 * kLeafTriangles * l + kLeafTriangles * corner + k] =
                    4 * body.triangles[3 * h.leaf_triangle[kLeafTriangles * l + k] + corner];
    refit_body_hierarchy(body, path);
    mark_crease_triangles(body);
    for (uint32_t l = 0; l < s.leaves; ++l)
        for (uint32_t k = 0; k < kLeafTriangles; ++k)
            if (h.in_crease[h.leaf_triangle[kLeafTriangles * l + k]] != 0) h.leaf_fold[l] = 2.0f * body.desc.thickness_m;
    refit_body_hierarchy(body, path);  // the crease leaves widened by their fold
    return true;
}

void refit_body_hierarchy(BodyState& body, SimdPath path) {
    path_for(path).refit(body.hierarchy, body.hull, body.previous_hull);
}

}  // namespace weft
