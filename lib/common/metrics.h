// Measurements of a cloth's state that tests and benchmarks share. Defined in docs/accuracy.md.
#pragma once

#include <cstdint>
#include <vector>

#include "weft/body.h"
#include "weft/weft.h"
#include "weft/debug.h"

namespace weft::metrics {

struct Strain {
    double mean = 0.0;  // mean |l / l0 - 1| over stretch and shear springs
    double max = 0.0;
    Vec3 max_at{};  // the midpoint of the most strained spring (where to look)
};
Strain stretch_strain(const ClothView& cloth);
// The same over positions in caller order (a peer solver's output, a stored frame).
Strain stretch_strain(const ClothAsset& asset, const std::vector<Vec3>& positions);
// The same over the asset's start state (a dressed garment's stored pose: weft-bake reports it).
Strain start_strain(const ClothAsset& asset);

// Mean particle speed over the last substep, m/s (real, free particles only).
double mean_speed(const ClothView& cloth);

struct Bounds {
    Vec3 min{}, max{};
    bool finite = true;
};
Bounds bounds(const ClothView& cloth);

// Largest distance of a tethered particle beyond its tether length, as a fraction of that length.
double max_tether_excess(const ClothView& cloth);

// Deepest a particle lies inside any collider's collision surface (the shape grown by its
// inflation: the surface the solver enforces), metres; 0 when none is inside.
double max_penetration_m(const ClothView& cloth, const ColliderDesc* colliders, uint32_t count);
// The same over positions in caller order; pinned particles (asset inverse mass 0) are skipped.
double max_penetration_m(const ClothAsset& asset, const std::vector<Vec3>& positions,
                         const ColliderDesc* colliders, uint32_t count);

// Deepest a cloth's free particle lies below a body's offset hull (weft/body.h: what the body
// pass enforces), metres, by query_body: within the step's reach, and 0.25 m deep for a particle
// beyond it; 0 when none is.
double max_body_penetration_m(const World* world, BodyId body, const ClothView& cloth);
// The same, and where that particle is (world metres; untouched when none is inside).
double max_body_penetration_m(const World* world, BodyId body, const ClothView& cloth, Vec3* deepest_at);
// The same over positions in caller order (a peer solver's output); particles pinned in the asset
// (attached) are skipped.
double max_body_penetration_m(const World* world, BodyId body, const ClothAsset& asset,
                              const std::vector<Vec3>& positions);

// Edge-triangle crossings of a cloth with itself (issue 25's measure of self-intersection): the
// mesh edges, each counted with every triangle that shares no particle with it and that its
// segment passes through. 0 for a cloth that does not pass through itself (a fold or a heap that
// only touches counts nothing); two triangles pierced through each other count 2. `triangles` index
// `positions` ([3 * triangle_count]).
uint64_t self_crossings(const uint32_t* triangles, uint32_t triangle_count, const std::vector<Vec3>& positions);
// The same over a cloth's current positions.
uint64_t self_crossings(const ClothView& cloth);
// Edge-triangle crossings between two cloths (issue 25's measure of layers swapping): the edges of
// each through the triangles of the other, at their current positions.
uint64_t layer_crossings(const ClothView& a, const ClothView& b);
// The same between two assets' start poses (a garment dressed over another: weft-bake --over).
uint64_t layer_crossings(const ClothAsset& a, const ClothAsset& b);

// --- errors against a reference run (docs/accuracy.md) ------------------------------------------

// A run's particle positions (caller order) at its sampled frames.
using Frames = std::vector<std::vector<Vec3>>;

// Root-mean-square distance between corresponding particles, metres: sqrt(sum |a_i - b_i|^2 / N).
double rms_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// Trajectory error: RMS particle distance to the reference over every sampled frame, divided by the
// cloth's diagonal: sqrt(sum_f sum_i |x_i(f) - r_i(f)|^2 / (F N)) / D. Infinite when the runs do not
// match in shape or a position is not finite.
double trajectory_error(const Frames& run, const Frames& reference, double diagonal_m);

// Rest-state error: the same on the last sampled frame only (for scenes that come to rest).
double rest_state_error(const Frames& run, const Frames& reference, double diagonal_m);

// Diagonal of the axis-aligned box around the positions, metres (the cloth's size for the errors).
double diagonal_m(const std::vector<Vec3>& positions);

// Position of the real particle with this caller index.
Vec3 particle_position(const ClothView& cloth, uint32_t particle);

}  // namespace weft::metrics
