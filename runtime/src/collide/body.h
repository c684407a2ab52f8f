// Stage 4 of the seed's step against body colliders (seed section 4.2): particles against the
// offset hull of a triangle mesh, through Embree's BVH.
//
// Detection: one rtcPointQuery per particle, radius thickness + margin, whose callback keeps the
// closest hull triangle (closest point on a triangle: Ericson, Real-Time Collision Detection,
// 5.1.5). The barycentric coordinates of that point interpolate the hull's vertex normals into the
// contact normal; the particle is inside when it lies behind the hull along that normal.
// Response: the same projection and friction as the analytic colliders (colliders.h:
// resolve_contact), with the surface's own motion, interpolated from the hull's per-vertex
// displacement, as the collider motion.
// Tunnelling: a particle that moved further than the thickness this substep is also traced by a
// ray from its previous to its new position (rtcIntersect1); entering the hull stops it there.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>

#include "kernels.h"
#include "weft/body.h"

namespace weft {

struct BodyState {
    BodyDesc desc;  // thickness, margin, friction (the array pointers are not kept)
    uint32_t vertex_count = 0, triangle_count = 0;
    float* hull = nullptr;           // [4 * vertex_count + 4]: the offset hull, Embree's shared vertex buffer
    float* previous_hull = nullptr;  // [4 * vertex_count]: the hull the previous step used
    float* normals = nullptr;        // [3 * vertex_count]: unit area-weighted vertex normals
    uint32_t* triangles = nullptr;   // [3 * triangle_count + 4]: Embree's shared index buffer
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;
    // How far any hull vertex moved at this step: a particle the surface swept over lies up to this
    // much deeper, so the query reaches thickness + margin + sweep (arms move up to 15 mm a frame).
    float sweep_m = 0.0f;
    bool refit_pending = false;  // new vertices since the last step
    bool moving = false;         // hull and previous_hull differ (the body moved at the last step)
};

// Closest point on triangle (a, b, c) to p as barycentric weights (w0 + w1 + w2 = 1).
struct Barycentric {
    float w0, w1, w2;
};
Barycentric closest_on_triangle(const float* p, const float* a, const float* b, const float* c);

// Offset hull of `positions`: area-weighted vertex normals, hull = position + thickness * normal.
void compute_offset_hull(BodyState& body, const Vec3* positions);

// The closest hull point within thickness + margin (BodyContact::found false when none is).
BodyContact closest_hull_point(const BodyState& body, const float* point);

// Counts of the pass's work for WorldStats.
struct BodyPassCounts {
    uint64_t contacts = 0, rays = 0;
};

// One cloth's particles against one body, for one of `substeps` substeps of the step.
void collide_body(const Particles& particles, const BodyState& body, uint32_t substeps, BodyPassCounts& counts);

}  // namespace weft
