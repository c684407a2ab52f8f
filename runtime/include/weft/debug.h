// What a debugger, a profiler or a test reads: per-pass timings and counters, the cloth's and the
// body's internal arrays without a copy, and a hook around Embree's commits. A game's frame needs
// none of it (weft/weft.h does not include this header).
#pragma once

#include "weft/body.h"
#include "weft/world.h"

namespace weft {

// --- the step's passes and counters -----------------------------------------------------------

// The passes of a step (seed section 2.3), as WorldStats times them. They run in this order except
// `coarse`, which runs before `integrate` on the nodes' own prediction (runtime/src/step.cpp).
// `body`: the body colliders (refit of moved bodies, closest-point queries, tunnelling rays).
// `normals`: the vertex normals the step ends with (WorldDesc::normals).
// normals: the vertex normals (and tangents, WorldDesc::tangents); render_mesh: the render meshes.
// health: the end of step health check and any recovery (cloth_health).
enum class Pass : uint8_t { wind = 0, integrate, coarse, constraints, tethers, collide, body, normals, render_mesh, health, self_collision, layers, count };
const char* pass_name(Pass pass);

struct WorldStats {
    uint64_t steps = 0;
    // Nanoseconds spent in each pass over all steps (only while set_profiling is on).
    uint64_t pass_ns[static_cast<int>(Pass::count)] = {};
    // Projections the last step ran on runs and on the indexed path (padding lanes excluded).
    uint64_t run_projections = 0;
    uint64_t indexed_projections = 0;
    // Colliders skipped for a cloth in a substep because their box missed the cloth's, last step.
    uint64_t colliders_skipped = 0;
    // Body colliders, last step: particle contacts found, tunnelling rays cast, bodies refitted.
    uint64_t body_contacts = 0;
    uint64_t body_rays = 0;
    uint64_t body_refits = 0;
    // Last step: particles whose reach met a box of the body's hierarchy (needed triangle tests;
    // on a reference body (add_reference_body), every particle queried), and Embree refits (made only for
    // the reference pass).
    uint64_t body_queried = 0;
    uint64_t body_embree_refits = 0;
    // Self-collision (ClothDesc::self_collision), last step: particle-face pairs pushed apart, and
    // triangles skipped because they were stretched over more cells than the hash looks at.
    uint64_t self_contacts = 0;
    uint64_t self_skipped_triangles = 0;
    // Layered garments (ClothDesc::worn_over), last step: particle-face pairs pushed apart between a
    // cloth and those it is worn over (both ways), and triangles skipped as self-collision's are.
    uint64_t layer_contacts = 0;
    uint64_t layer_skipped_triangles = 0;
    // Nanoseconds (all steps, while profiling) of pass_ns[body] spent refitting moved
    // bodies (Weft's hierarchy, or Embree's BVH for the reference pass).
    uint64_t body_refit_ns = 0;
    // Embree's heap as its memory monitor reports it (rtcSetDeviceMemoryMonitorFunction): bytes
    // held now, and how many times it grew since creation.
    int64_t embree_bytes = 0;
    uint64_t embree_allocations = 0;
    // Times an add found no gap for its arrays and compacted the live instances (memory/regions.h).
    uint64_t memory_compactions = 0;
    // Cloths asleep after the last step (ClothDesc::sleep_speed_m_s): the next runs nothing for them.
    uint64_t sleeping_cloths = 0;
    // Health (cloth_health): cloths found unhealthy by the last step, those recovered at its end,
    // and recoveries over all steps.
    uint64_t unhealthy_cloths = 0;
    uint64_t recovered_cloths = 0;
    uint64_t total_recoveries = 0;
    // The frame budget (set_frame_budget_us), last step: the cloths' estimated cost in microseconds
    // (also with the budget off), the cloths it ran with fewer sweeps than their own, and the
    // sweeps (substeps x iterations) the awake cloths ran, summed.
    double budget_estimate_us = 0.0;
    uint64_t budget_cloths_cut = 0;
    uint64_t budget_sweeps = 0;
};

WorldStats world_stats(const World* world);

// Times every pass from the next step on (WorldStats::pass_ns; one clock read a pass). Off at creation.
Result set_profiling(World* world, bool on);

// What a world holds now (remove_cloth, remove_body and remove_collider give it back).
struct WorldUsage {
    uint32_t cloths = 0, bodies = 0, colliders = 0;
    uint32_t particle_slots = 0, constraint_lanes = 0, coarse_nodes = 0;
    uint32_t body_vertices = 0, body_triangles = 0;
    size_t instance_bytes = 0;  // the live cloths' and bodies' arrays in the world's block
    size_t skin_bytes = 0;      // the skin constraints' arrays in the world's skin pool
    bool operator==(const WorldUsage&) const = default;
};
WorldUsage world_usage(const World* world);

// --- internal arrays ----------------------------------------------------------------------------

// The cloth's arrays in the asset's slot order (ClothAsset::particle_of_slot maps them to the
// caller's particles), without a copy, for metrics and debug drawing; valid until the next step.
struct ClothView {
    const ClothAsset* asset = nullptr;
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
    const float* previous_x = nullptr;
    const float* previous_y = nullptr;
    const float* previous_z = nullptr;
    const float* inverse_mass = nullptr;
    const float* normal_x = nullptr;  // unit vertex normals (null without WorldDesc::normals)
    const float* normal_y = nullptr;
    const float* normal_z = nullptr;
    float last_substep_s = 0.0f;  // duration of the last substep (velocity = (x - previous) / it)
};
Result view_cloth(const World* world, ClothId cloth, ClothView* out);

// The offset hull as the step sees it, for tests, debugging views and brute-force references.
struct BodyView {
    uint32_t vertex_count = 0, triangle_count = 0;
    const float* hull = nullptr;     // [4 * vertex_count]: x, y, z, the vertex's motion this step (m)
    const float* normals = nullptr;  // [3 * vertex_count]: unit area-weighted vertex normals
    const uint32_t* triangles = nullptr;
    // [triangle_count]: 1 where another part's hull faced the triangle within the reach in the pose
    // add_body was given (the armpit, the inner thighs); a particle in front of such a triangle is
    // checked against the other faces within reach.
    const uint8_t* in_crease = nullptr;
    // The step's leaves: kLeafTriangles (8) triangles each ([8 * leaf_count], a last leaf's padding
    // repeats a triangle), and how much further than thickness + margin the step searches a leaf's
    // triangles because the hull folds there ([leaf_count], metres: 2 x thickness at a crease).
    uint32_t leaf_count = 0;
    const uint32_t* leaf_triangle = nullptr;
    const float* leaf_fold_m = nullptr;
    float thickness_m = 0, margin_m = 0;
};
Result view_body(const World* world, BodyId body, BodyView* out);

// A body searched by the plain reference pass instead of the step's hierarchy: one Embree
// rtcPointQuery a particle (reach thickness + margin, not widened by the body's motion) and an
// Embree refit every moving step. The baseline the body pass is measured against (docs/garments.md).
Result add_reference_body(World* world, const BodyDesc& desc, BodyId* out_body);

// Diagnostics: called with `entering` true just before and false just after every rtcCommitScene
// the world makes (creation and steps), so a test can tell Embree's allocations from Weft's.
using EmbreeCommitHook = void (*)(void* user, bool entering);
Result set_embree_commit_hook(World* world, EmbreeCommitHook hook, void* user);

}  // namespace weft
