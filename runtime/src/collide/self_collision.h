// Self-collision (ClothDesc::self_collision): a cloth's particles against its own triangles.
//
// Each substep, after the skin constraints and before the colliders and bodies (so those win):
//   1. broad phase: the movable particles are sorted into a spatial hash of cubic cells (a counting
//      sort, stable in slot order), their positions copied beside them in that order;
//   2. every triangle looks up the cells its box meets, widened by the thickness and the capture
//      depth, and tests the particles there that are not its own corners;
//   3. a particle within `thickness` of the triangle's face (its projection inside the triangle)
//      is pushed out to the thickness along the normal, on the side where it was at the substep's
//      start (the previous positions): a particle that crossed the face during this substep, by
//      less than the capture depth, is brought back. The push is a position constraint
//      C = s - thickness >= 0 on the particle and the triangle's point at its barycentric weights
//      (u, v, w), shared by inverse mass (PBD); friction then cancels the pair's relative
//      tangential motion over the substep up to friction * |C| (Macklin et al. 2014, sec. 6.1),
//      shared the same way.
//   4. each edge of such a particle that shares no corner with the triangle, against the triangle's
//      three edges: where the closest points of the two segments lie inside both and closer than
//      the thickness, or have swapped sides since the substep's start (by less than the capture
//      depth), the two edges are pushed apart to the thickness on their former side (Bridson et al.
//      2002's edge-edge proximity, as a PBD constraint shared by the four particles' inverse masses),
//      with the same friction.
//      An edge whose ends are both beyond the capture depth on one side of the triangle's plane, or
//      both within kSelfFlatThicknesses of it (one flat layer), cannot reach its edges: not tested.
//      A particle's edges go through these screens eight at a time (screen_edges).
// Only a triangle's own corners are excluded: the default thickness (4 mm) is a fifth of a baked
// garment's edge, so a neighbour comes that close to a triangle's face only where the cloth lies
// folded on itself, which is self-contact.
//
// Fixed work: the sort is two passes over the slots; a triangle looks at no more than
// kMaxHashCellsPerAxis cells along each axis (a triangle stretched beyond that is skipped and
// counted, the health check's business). Nothing allocates: the arrays are the cloth's, carved at
// add_cloth. Triangles go in asset order and each contact is applied at once (Gauss-Seidel): the
// same bits every run, on either SIMD path (this is one plain code path for both).
#pragma once

#include <cstdint>

#include "collide/particle_hash.h"
#include "kernels.h"
#include "weft/cloth_asset.h"

namespace weft {

// An edge with both ends within this many thicknesses of a triangle's plane lies in it: no edge-edge
// test against that triangle (two layers are kept a thickness apart, so it is one layer).
inline constexpr float kSelfFlatThicknesses = 0.5f;
// A contact deeper than this many thicknesses on the wrong side is left alone (an old crossing).
inline constexpr float kSelfCaptureThicknesses = 2.0f;
// A contact's thickness (and capture depth) is at most this many times the shortest start-pose
// edge at any of its particles (self_collision.cpp, contact_thickness): a mesh finer than the
// thickness.
inline constexpr float kSelfThicknessPerEdge = 0.5f;

// A cloth's self-collision arrays (in the world's block): its particles' hash and its mesh's edges.
struct SelfCollisionState {
    ParticleHash hash;  // the movable particles; its slot_bucket is also build_self_collision_edges' scratch
    // The mesh's edges by particle (built at add_cloth): slot s's neighbours are
    // edge_other[edge_first[s] .. edge_first[s + 1]), each once.
    uint32_t* edge_first = nullptr;  // [slot_count + 1]
    uint32_t* edge_other = nullptr;  // [6 * triangle_count]: room for every triangle's corners' two edges
    float* shortest_edge_m = nullptr;  // [slot_count]: each slot's shortest edge in the start pose (contact_thickness)
};

// The cells' edge for an asset: its triangles' mean longest edge in the start pose plus twice the
// reach (thickness and capture), so a triangle's widened box usually spans two cells per axis.
float self_collision_cell_m(const ClothAsset& asset, float thickness_m);

// Fills state.edge_first, edge_other and shortest_edge_m from the asset's triangles (add_cloth;
// hash.slot_bucket is its scratch).
void build_self_collision_edges(const ClothAsset& asset, SelfCollisionState& state);

struct SelfCollisionArgs {
    float thickness_m = 0.004f;
    float friction = 0.2f;
};

struct SelfCollisionCounts {
    uint64_t contacts = 0;           // particle-triangle and edge-edge pairs pushed apart
    uint64_t skipped_triangles = 0;  // triangles stretched over more cells than kMaxHashCellsPerAxis
};

void collide_self(Particles& p, const ClothAsset& asset, SelfCollisionState& state, const SelfCollisionArgs& args,
                  SelfCollisionCounts& counts);

}  // namespace weft
