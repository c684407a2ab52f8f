// Layered garments (ClothDesc::worn_over): a cloth against the cloths it is worn over, the inner
// layer winning.
//
// Each substep of the outer cloth, after its self-collision and before the colliders and bodies
// (so those win), for each cloth it is worn over:
//   1. the inner cloth's positions at the end of this substep. The inner cloth's step has ended (its
//      stage runs first, world.h StepStage), so they are taken back along its last substep's motion:
//      x(t) = x_end - (x_end - x_previous) * (t_end - t) / h_inner;
//   2. this cloth's movable particles are hashed (collide/particle_hash.h) and every inner triangle
//      finds those in its box widened by the reach. A particle over the face (its projection inside
//      the triangle) that is less than `thickness` in front of it, or less than the capture depth
//      behind it, is pushed out to the thickness. "In front" is where the face's normal points: a
//      baked garment's triangles face away from the body (their winding is the panels' outside), so
//      the outer layer belongs there whatever happened before, and a crossing is undone. Then each
//      edge of such a particle against the triangle's three edges: where their closest points lie
//      inside both, the outer edge's less than `thickness` in front of the inner one's along the
//      face's normal (and not beside it), the edge is pushed out likewise. Without it an outer edge
//      spanning a ridge of the inner cloth (an armhole's gathers) cut through it with both ends
//      outside every face's prism;
//   3. the inner cloth's particles are hashed and every triangle of this cloth finds those in its box:
//      an inner particle less than `thickness` behind the face, or less than the capture depth in
//      front of it, pushes the face's corners out (by its barycentric weights) to the thickness.
// Only this cloth moves: the inner one has finished its step and is an obstacle that moves, as a
// body is. Friction as in self-collision, against the inner cloth's motion over the substep.
//
// Fixed work: two sorts over the slots and one walk over each cloth's triangles per inner cloth; a
// triangle outside the other cloth's box is not walked. Nothing allocates: the arrays are the
// cloth's, carved at add_cloth. The same bits every run on either SIMD path (one plain code path).
#pragma once

#include <cstdint>

#include "collide/particle_hash.h"
#include "kernels.h"
#include "weft/cloth_asset.h"

namespace weft {

// A contact deeper than this many thicknesses on the wrong side is left alone (another part of the
// garment, beyond the other side of a limb).
inline constexpr float kLayerCaptureThicknesses = 2.0f;

// A layered cloth's arrays (in the world's block).
struct LayerState {
    ParticleHash own;    // this cloth's movable particles, walked by the inner cloth's triangles
    ParticleHash inner;  // the inner cloth's particles, walked by this cloth's triangles
    float* inner_x = nullptr;  // [inner slots]: the inner cloth's positions at this substep's end, metres
    float* inner_y = nullptr;
    float* inner_z = nullptr;
    // This cloth's mesh edges by particle (build_mesh_edges, at add_cloth).
    uint32_t* edge_first = nullptr;  // [slot_count + 1]
    uint32_t* edge_other = nullptr;  // [6 * triangle_count]
    uint32_t inner_capacity = 0;  // slots of the largest inner cloth the arrays were carved for
};

// The inner cloth as this substep reads it: its particles after its step, its asset, and how far
// before its step's end this substep ends (seconds) over its last substep (seconds).
struct InnerLayer {
    const Particles* particles = nullptr;
    const ClothAsset* asset = nullptr;
    float time_before_end_s = 0.0f;
    float inner_substep_s = 0.0f;
};

struct LayerArgs {
    float thickness_m = 0.003f;
    float friction = 0.3f;
    float substep_s = 0.0f;  // this cloth's substep, h
};

struct LayerCounts {
    uint64_t contacts = 0;           // particle-face pairs pushed apart, both ways
    uint64_t skipped_triangles = 0;  // triangles stretched over more cells than kMaxHashCellsPerAxis
};

// The cells' edge for hashing one cloth's particles against the other's triangles: the triangles'
// mean longest edge (start pose) plus twice the reach.
float layer_cell_m(const ClothAsset& triangles_of, float thickness_m);

void collide_layer(Particles& p, const ClothAsset& asset, LayerState& state, const InnerLayer& inner,
                   const LayerArgs& args, LayerCounts& counts);

}  // namespace weft
