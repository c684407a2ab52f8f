// Stage 4 of the seed's step against body colliders (seed section 4.2): particles against the
// offset hull of a triangle mesh.
//
// Detection: the closest hull triangle within thickness + margin (+ the motion of its vertices
// this step) through Weft's own box hierarchy (BodyHierarchy, collide/body_query.h: one walk per
// cluster of neighbouring slots, eight triangles at a time per particle; closest point on a
// triangle: Ericson, Real-Time Collision Detection, 5.1.5), or, for the plain reference pass
// (add_reference_body), one Embree rtcPointQuery per particle. The barycentric coordinates of that point interpolate the hull's vertex normals into the
// contact normal; the particle is inside when it lies behind the hull along that normal.
// Response: the same projection and friction as the analytic colliders (colliders.h:
// resolve_contact), with the surface's own motion, interpolated from the hull's per-vertex
// displacement, as the collider motion.
// Tunnelling: a particle that moved further than the thickness this substep is also traced by a
// ray from its previous to its new position, entering the hull stops it there. Weft's hierarchy
// traces it in each triangle's frame (the previous position moved with the triangle: the motion
// relative to the surface is what crosses it); the plain reference pass, in world space
// (rtcIntersect1; Embree's BVH is refitted at the first such ray of a step after the body moved).
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>

#include "kernels.h"
#include "memory/regions.h"
#include "weft/body.h"
#include "weft/closest_point.h"
#include "weft/debug.h"

namespace weft {

// The step's own box hierarchy over the offset hull (issue 13, point 3): triangles ordered by
// median splits of their rest-pose centroids, kLeafTriangles to a leaf, kGroupLeaves leaves to a
// group, kRootGroups groups to a root box. Refitted without allocation whenever the body moves; boxes are widened by their vertices'
// motion this step (a moving surface sweeps over resting cloth) and by kBoxSlack_m for rounding.
inline constexpr uint32_t kLeafTriangles = 8;
inline constexpr uint32_t kGroupLeaves = 16;
inline constexpr uint32_t kRootGroups = 8;
inline constexpr float kBoxSlack_m = 1e-5f;

// Axis-aligned boxes, structure of arrays (SIMD tests eight at a time), padded to a multiple of 8
// with empty boxes (min > max).
struct Boxes {
    float* min_x = nullptr;
    float* min_y = nullptr;
    float* min_z = nullptr;
    float* max_x = nullptr;
    float* max_y = nullptr;
    float* max_z = nullptr;
};

struct BodyHierarchy {
    uint32_t leaf_count = 0, group_count = 0, root_count = 0;
    uint32_t* leaf_triangle = nullptr;  // [kLeafTriangles * leaf_count]: body triangle per leaf lane
    uint32_t* leaf_vertex = nullptr;    // [3 * kLeafTriangles * leaf_count]: per leaf a[8], b[8], c[8] as 4 * vertex
    // [kLeafCorners * leaf_count]: per leaf the corner a, edges ab, ac, normal ab x ac (not
    // normalised), radius max(|ab|, |ac|) and motion this step (the mean of its corners' hull -
    // previous_hull: the tunnelling rays' frame) of its triangles, each component an array of
    // kLeafTriangles floats (ax[8], ay[8], az[8], abx[8], ... nz[8], radius[8], mx[8], my[8], mz[8]).
    float* leaf_corners = nullptr;
    // [leaf_count rounded up as `leaves`]: how much further than the base reach the leaf's triangles
    // are searched: the largest motion of its vertices this step plus its leaf_fold.
    float* leaf_sweep = nullptr;
    // [the same]: 2 x thickness for a leaf holding a crease triangle, else 0. Where the hull folds
    // (the armpit, the crotch) a hull vertex lies up to 2 x thickness from where its face's offset
    // would put it (|n_face - n_vertex| <= 2), so a particle within the thickness of the skin may be
    // that far from the closest hull point, beyond the base reach.
    float* leaf_fold = nullptr;
    // [triangle_count]: 1 where another part's hull faced the triangle within the reach in the pose
    // add_body was given (the arm's underside and the torso's side in the armpit, the inner thighs:
    // mark_crease_triangles). Such a triangle can be a particle's closest while the particle is
    // inside the other part, so its "in front" is checked again (collide_clusters).
    uint8_t* in_crease = nullptr;
    Boxes leaves;                 // [leaf_count rounded up to groups * kGroupLeaves]
    Boxes groups;                 // [root_count * kRootGroups]
    Boxes roots;                  // [root_count rounded up to 8]
};
inline constexpr uint32_t kLeafCorners = 16 * kLeafTriangles;

struct BodyState {
    InstanceSlot slot;
    BodyDesc desc;  // thickness, margin, friction (the array pointers are not kept)
    bool reference_queries = false;  // add_reference_body: the plain Embree pass (scene below)
    uint32_t vertex_count = 0, triangle_count = 0;
    // [4 * vertex_count + 4]: the offset hull, Embree's shared vertex buffer: x, y, z and, where
    // Embree does not look, |hull - previous_hull| of the vertex this step (metres). A particle the
    // surface swept over lies up to that much deeper, so the hierarchy widens each leaf's box and
    // reach by its vertices' largest motion (arms move up to 15 mm a frame; widening every query by
    // the whole body's largest motion, the hands', made the first cut's pass 16 ms).
    float* hull = nullptr;
    float* previous_hull = nullptr;  // [4 * vertex_count]: the hull the previous step used
    float* normals = nullptr;        // [3 * vertex_count]: unit area-weighted vertex normals
    uint32_t* triangles = nullptr;   // [3 * triangle_count + 4]: Embree's shared index buffer
    RTCScene scene = nullptr;        // reference bodies only (the plain pass's BVH)
    RTCGeometry geometry = nullptr;
    BodyHierarchy hierarchy;
    bool refit_pending = false;  // new vertices since the last step
    bool moving = false;         // hull and previous_hull differ (the body moved at the last step)
    uint32_t plane_index = ~0u;  // cached_planes: its planes' place in each cloth's contact_planes
    // skin_constraints: the hull moved but the hierarchy was not refitted (refresh_body_hierarchy).
    bool hierarchy_stale = false;
    // This step's refits and their time (the bodies stage; end_step adds them into WorldStats).
    uint32_t refits = 0, embree_refits = 0;
    uint64_t refit_ns = 0, pass_ns = 0;
};

// A point on a hull triangle as barycentric weights (w0 + w1 + w2 = 1); closest_on_triangle
// (weft/closest_point.h) finds the closest one.
using Barycentric = BarycentricWeights<float>;

// Offset hull of `positions`: area-weighted vertex normals, hull = position + thickness * normal, and
// each vertex's motion |hull - previous| (0 without `previous`, the hull before this pose).
void compute_offset_hull(BodyState& body, const Vec3* positions, const float* previous = nullptr);

// The closest hull point within `reach` (BodyContact::found false when none is), by
// Embree's rtcPointQuery (the reference; the step uses its own hierarchy unless
// add_reference_body).
BodyContact closest_hull_point(const BodyState& body, const float* point, float reach);

// Arena bytes for the hierarchies of bodies with these totals (world sizing).
size_t body_hierarchy_bytes(uint32_t triangles, uint32_t bodies);
// Carves the hierarchy from `arena` and orders the triangles (at add_body); false when out of memory.
struct Arena;
bool build_body_hierarchy(BodyState& body, Arena& arena, SimdPath path);
// Refits the hierarchy to the current hull and its vertices' motion since previous_hull (every step
// after the body moved).
void refit_body_hierarchy(BodyState& body, SimdPath path);
// Refits a skin_constraints body's hierarchy if the hull moved since its last refit.
inline void refresh_body_hierarchy(BodyState& body, SimdPath path) {
    if (!body.hierarchy_stale) return;
    refit_body_hierarchy(body, path);
    body.hierarchy_stale = false;
}

// Counts of the pass's work for WorldStats.
struct BodyPassCounts {
    uint64_t contacts = 0, rays = 0;
    uint64_t queried = 0;  // particles whose cluster met at least one leaf (needed a closer look)
};

// BodyCollision::cached_planes: each slot's contact plane from the step's first substep, one array
// per component (structure of arrays, indexed by slot), carved per cloth and body at add_cloth.
// A slot with no hull within reach has a zero normal (no contact) and may move `reach2` from `from`.
struct ContactPlanes {
    float* point[3];   // the closest hull point (m)
    float* normal[3];  // the unit contact normal there (interpolated hull normal), 0 when none
    float* motion[3];  // the surface's displacement there over one substep (m): friction's reference
    float* from[3];    // where the particle was when the plane was found (after its response)
    // Squared distance the particle may move from `from` before it is searched exactly again (m^2);
    // negative: marked for that search this substep.
    float* reach2;
    // The other side of a crease (the hull point and normal the crease rounds last pushed the
    // particle out of, collide/body.cpp), projected onto after the first plane; 0 normal when none.
    float* crease_point[3];
    float* crease_normal[3];
};
inline constexpr uint32_t kContactPlaneArrays = 19;
// The cached planes' bound: a particle is searched exactly again once it is further than this
// from where it was last searched (where its plane was found), before or after the projection
// onto its plane. Where the hull is one consistent surface, getting deeper than this behind any
// triangle (the plane's own, a neighbour curving up, the other side of a crease, a surface it was
// far from) takes moving further. Holds measured and not kept (docs/decisions/): the clearance
// from the hull + 2 mm let particles near overlapping offset hulls (the armpit, fingers, lips) end
// 2.2-14 mm deep; a fixed 5 mm, 5.1-6.9 mm.
inline constexpr float kPlanesBound_m = 0.002f;
// The planes of `slot_count` slots in a block of kContactPlaneArrays * slot_count floats.
ContactPlanes contact_planes_in(float* block, uint32_t slot_count);

// One cloth's particles against one body, for substep `substep` of `substeps`, in clusters of
// consecutive entries of `order` (order_for_body_pass). `planes`: the cloth's contact planes for
// this body (BodyCollision::cached_planes), else null.
void collide_body(const Particles& particles, const uint32_t* order, const BodyState& body, uint32_t substep,
                  uint32_t substeps, const ContactPlanes* planes, SimdPath path, BodyPassCounts& counts);

// The body pass's order of a cloth's slots (at add_cloth): by the Morton code of their start
// positions, so every run of 16 is a compact patch of cloth whatever the slot layout (a garment's
// lattice rows run 16 slots along a panel: 16-32 cm, a box that meets hundreds of leaves). `key`
// is scratch, [slot_count].
void order_for_body_pass(const ClothAsset& asset, uint32_t* key, uint32_t* order);

// The step's contact query for one point through the hierarchy (query_body): at the step's reach
// (thickness + margin), the same result as the pass sees.
BodyContact closest_hull_point_hierarchy(const BodyState& body, const float* point, float reach, SimdPath path);


}  // namespace weft
