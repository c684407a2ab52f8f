// The world: every cloth instance, collider and the wind, in one caller-provided memory block.
//
// Life cycle (all memory is sized up front; stepping never allocates, throws or locks):
//   WorldDesc desc = ...;                                   // capacities and features
//   MemoryRequirements need = world_memory_requirements(desc);
//   void* block = aligned_alloc(need.alignment, need.bytes); // or a game's own pool
//   World* world; create_world(desc, block, need.bytes, &world);
//   add_cloth(world, cloth_desc, &cloth);  add_collider(world, collider_desc, &collider);
//   every frame: set_collider(...), set_body_vertices(...), set_wind(...), step(world, dt),
//                read_positions(...), read_normals(...)
//   remove_cloth(world, cloth), remove_collider(...) between steps give their memory back
//   destroy_world(world) (releases the Embree device of a world with bodies, weft/body.h), then
//   free the block: it is the caller's.
#pragma once

#include "weft/asset_view.h"  // ClothAsset is only pointed to: its layout is weft/cloth_asset.h
#include "weft/types.h"

namespace weft {

struct World;

// Collider shapes (seed section 2.1, plus capsule and plane).
enum class ColliderShape : uint8_t { sphere, capsule, cylinder, plane };

struct ColliderDesc {
    ColliderShape shape = ColliderShape::sphere;
    // sphere: centre p0. capsule/cylinder: axis from p0 to p1. plane: point p0, normal p1 (unit).
    Vec3 p0{};
    Vec3 p1{0.0f, 1.0f, 0.0f};
    float radius_m = 0.5f;     // sphere, capsule, cylinder
    float inflation_m = 0.0f;  // collision skin added to the radius (seed figure 8); plane: offset
    float friction = 0.0f;     // Coulomb coefficient; 0 = the seed's frictionless projection (7)/(8)
};

// --- the step on a game's job system ------------------------------------------------------
//
// A step runs in two stages of independent work items: the bodies (refit of the ones the game
// moved), then the cloths (each cloth's whole step). Items of one stage touch disjoint memory, so
// any thread may run any range of them, and the result is the same bits whatever the split.

// Runs items [begin, end) of one stage; `task_context` is the step's own, passed back untouched.
using StepTaskFn = void (*)(uint32_t begin, uint32_t end, void* task_context);

// The game's job system, as Box2D v3's b2WorldDef::enqueueTask / finishTask: enqueue_task runs
// `task` over items [0, item_count) in ranges of at least `min_range` items, on any threads, and
// returns a handle that finish_task waits on; or it runs them all itself and returns null (then
// finish_task is not called). The step calls finish_task before it enqueues the next stage.
using EnqueueStepTaskFn = void* (*)(StepTaskFn task, uint32_t item_count, uint32_t min_range, void* task_context,
                                    void* user_context);
using FinishStepTaskFn = void (*)(void* user_task, void* user_context);

struct StepScheduler {
    EnqueueStepTaskFn enqueue_task = nullptr;  // null: step() runs every item on the calling thread
    FinishStepTaskFn finish_task = nullptr;
    void* user_context = nullptr;
};

// What a world must hold. Every count is a hard capacity checked when things are added.
struct WorldDesc {
    uint32_t max_cloths = 1;
    uint32_t max_particles = 0;    // summed over cloth instances (their asset's particle slots)
    uint32_t max_constraints = 0;  // summed constraint lanes the step may project per sweep
    uint32_t max_colliders = 0;
    uint32_t max_coarse_nodes = 0;  // summed ClothAsset::coarse_slot_count (node slots) of the cloths
    uint32_t max_bodies = 0;          // body colliders (weft/body.h); > 0 creates an Embree device
    uint32_t max_body_vertices = 0;   // summed over bodies
    uint32_t max_body_triangles = 0;  // summed over bodies
    uint32_t max_cached_plane_bodies = 0;  // bodies that may use BodyCollision::cached_planes
    uint32_t max_skin_constraints = 0;     // summed over the cloths (weft/attachments.h); reserve_cloth adds
    uint32_t max_triangle_lanes = 0;       // summed over the cloths, for `tangents`; reserve_cloth adds
    uint32_t max_render_vertices = 0;      // summed over the cloths, for `render_meshes`; reserve_cloth adds
    uint32_t max_last_good_particles = 0;  // summed slots of cloths with RecoveryPolicy::last_good_state
    uint32_t max_self_collision_particles = 0;  // summed slots of cloths with ClothDesc::self_collision
    uint32_t max_self_collision_triangles = 0;  // and their summed triangles (reserve_cloth adds both)
    // Summed over the cloths worn over others (ClothDesc::worn_over): their own slots plus the slots
    // of the largest cloth each is worn over (reserve_layer adds them).
    uint32_t max_layer_particles = 0;
    uint32_t max_layer_triangles = 0;  // and their own triangles (reserve_layer adds them)

    // Features: a pass that is not enabled is not in the step at all (and costs nothing).
    bool wind = false;
    bool normals = false;        // vertex normals at the end of each step (read_normals)
    bool tangents = false;       // and tangents from the uv (read_tangents; needs assets with uv)
    bool render_meshes = false;  // and each asset's render mesh driven (read_render_mesh)

    Vec3 gravity_m_s2{0.0f, -9.81f, 0.0f};
    float air_density_kg_m3 = 1.2f;  // rho in equations (2) and (3)

    SimdPath simd = SimdPath::automatic;
    StepScheduler scheduler;  // how step() hands out its work items (above)

    // The frame budget's cost model (set_frame_budget_us; docs/architecture.md, "Frame budget"):
    float budget_ns_per_lane = 1.25f;      // ns a constraint lane costs per sweep (fine and coarse)
    float budget_ns_per_particle = 15.0f;  // ns a particle slot costs per substep (integration, collision)
};

// How a spring's length correction is evaluated (runtime/src/constraints/distance.h).
enum class SpringProjection : uint8_t {
    exact,      // C = |x_b - x_a| - l0: one square root and one division per spring
    sqrt_free,  // Jakobsen's square-root approximation: same rest state, no square root
};

// The explicit split's accepted range (docs/solver.md, "Splits the API refuses"): outside it a
// configuration measured jittering or blowing up on the drape or the sphere.
inline constexpr float kMinRelaxation = 0.5f;
inline constexpr float kMaxRelaxation = 1.0f;
inline constexpr uint32_t kMaxCoarseSubsteps = 8;  // substeps of an explicit split with coarse_level

// What the step does with a cloth it finds unhealthy (docs/architecture.md, "Health and recovery"),
// at the end of that step: the cloth is healthy after it.
enum class RecoveryPolicy : uint8_t {
    none,             // report only (cloth_health); the cloth goes on as it is
    last_good_state,  // back to its copy of a recent healthy step (needs max_last_good_particles)
    rest_pose,        // back to the asset's start pose, at rest (as reset_cloth)
    dressed_pose,     // the dressed pose on its body as posed now (reset_to_pose); else rest_pose
};

// How a cloth spends its solver budget.
enum class BudgetPolicy : uint8_t {
    // Pinned cloth: 1 substep of `sweeps` iterations with tethers; collider-held: 2-3 substeps,
    // relaxation 0.8, the coarse level (docs/solver.md, "The policy").
    automatic,
    // substeps, iterations, relaxation and coarse_level exactly as given below.
    explicit_split,
};

// Whether an explicit split runs the asset's coarse level. automatic: as the automatic policy
// would for this cloth: off for a cloth its tethers hold (the two fight: docs/solver.md), on for
// one held by colliders.
enum class CoarseLevel : uint8_t { automatic, off, on };

// Ids name a place in the world's instance array and the generation of what holds it: removing an
// instance bumps the generation, so its old id is refused (ErrorCode::stale_id) even after another
// instance took the place.
struct ColliderId {
    uint32_t index = 0;
    uint32_t generation = 0;
};
struct ClothId {
    uint32_t index = 0;
    uint32_t generation = 0;
};

// Layered garments: a cloth is worn over at most kMaxWornOver cloths, and a cloth worn over others is
// at most in the kMaxClothLayers-th layer (next to the skin is the first).
inline constexpr uint32_t kMaxWornOver = 4;
inline constexpr uint32_t kMaxClothLayers = 3;

// ClothDesc::self_thickness_m's accepted range, metres.
inline constexpr float kMinSelfThickness_m = 0.0005f;
inline constexpr float kMaxSelfThickness_m = 0.05f;

// Per-instance solver settings. Defaults reproduce the seed experiments at the paper's budget
// (3 sweeps at the caller's dt of 0.033 s, hard constraints, tethers on).
struct ClothDesc {
    const ClothAsset* asset = nullptr;  // must outlive the world; never copied
    Vec3 translation_m{};               // added to the asset's start positions

    uint32_t sweeps = 3;  // the budget: passes over every constraint per step (1..1000)
    BudgetPolicy policy = BudgetPolicy::automatic;
    // Used with BudgetPolicy::explicit_split (sweeps is then substeps * iterations):
    uint32_t substeps = 1;     // Verlet steps per step() call (1..64)
    uint32_t iterations = 3;   // constraint sweeps per substep (0..1000)
    float relaxation = 1.0f;   // scales every correction, kMinRelaxation..kMaxRelaxation; 1 = the seed's
    CoarseLevel coarse_level = CoarseLevel::automatic;  // when the asset has one
    uint32_t coarse_iterations = 1;  // coarse-level sweeps per substep (1..16; the policy uses 1)
    SpringProjection projection = SpringProjection::exact;

    // XPBD compliance (inverse stiffness) per constraint kind, m/N. 0 = hard (the seed's method).
    float compliance_m_per_n[kConstraintKindCount] = {0.0f, 0.0f, 0.0f};

    float damping_per_s = 1.0f;  // velocity damping, 1/s: dv/dt = -damping v (the seed's F_damp)

    bool tethers = true;                 // the asset's long-range attachments (either policy)
    bool tethers_before_sweeps = false;  // also project them before the sweeps (docs/solver.md)
    float tether_slack = 0.0f;           // extension before a tether acts, fraction of its length
    bool contact_tethers = true;         // coarse nodes held near a node in contact (docs/solver.md)

    // Wind (only when the world has the wind feature): drag and lift coefficients of (2), (3).
    float drag_coefficient = 0.1f;
    float lift_coefficient = 0.1f;

    // Character motion (set_cloth_root; docs/architecture.md, "Character motion").
    float linear_inertia = 1.0f;              // share of the root's motion felt, 0..1 (0: carried rigidly)
    float angular_inertia = 1.0f;             // the same for its rotation
    float max_inertial_speed_m_s = 1000.0f;   // root motion beyond this speed carries the cloth rigidly
    // A root faster than either in one step is a jump, as teleport_cloth (Chaos's teleport
    // thresholds): the cloth is carried rigidly by the whole step's root motion, its velocity turned
    // with it, and its bodies' motion that step counts as done. 0: never.
    float jump_speed_m_s = 100.0f;
    float jump_turn_rad_s = 30.0f;            // about 5 revolutions a second
    // A step more than max_step_growth times the last one (a hitch, a loading frame) simulates the
    // cloth as long as the last one: the solver's rest sag grows with the step, so a longer step
    // sets a hanging garment swinging. Any step simulates it at most max_step_s (Chaos's
    // MaxPhysicsDelta): in one substep of 0.25 s gravity alone moves a particle 0.6 m. 0: off.
    float max_step_growth = 1.5f;
    float max_step_s = 1.0f / 30.0f;

    float sleep_speed_m_s = 0.0f;  // at rest below this, m/s, it skips its steps until woken; 0: never

    RecoveryPolicy recovery = RecoveryPolicy::none;  // what an unhealthy step does (cloth_health)

    // Self-collision (docs/architecture.md, "Self-collision"): each substep, every particle is kept
    // self_thickness_m from the faces of the cloth's own triangles, with friction. Chosen at
    // add_cloth (its memory: WorldDesc::max_self_collision_particles and _triangles); off, it costs nothing.
    bool self_collision = false;
    // The distance kept between a particle and a face, m (0.5 mm..5 cm). The hash's cells are sized for
    // the value at add_cloth: a much larger one set later can stretch a triangle's box over too many
    // cells, and such triangles are skipped (WorldStats::self_skipped_triangles).
    float self_thickness_m = 0.004f;
    float self_friction = 0.2f;       // Coulomb coefficient between layers of the cloth

    // Layered garments (docs/architecture.md, "Layered garments"): the cloths this one is worn over
    // (a jacket over a tee, a skirt over leggings), added before it. Each substep its particles are
    // kept layer_thickness_m in front of their faces (the side a baked garment's faces point to, away
    // from the body) and theirs behind its own; the inner cloth wins: only this one moves. Its step
    // runs in a later stage than theirs (StepStage). Chosen at add_cloth (its memory:
    // WorldDesc::max_layer_particles); a cloth worn over cannot be removed before this one.
    ClothId worn_over[kMaxWornOver] = {};
    uint32_t worn_over_count = 0;
    float layer_thickness_m = 0.003f;  // 0.5 mm..5 cm, as self_thickness_m
    float layer_friction = 0.3f;       // Coulomb coefficient between the layers
};

// The frame budget never cuts a cloth below this many sweeps a step (nor below its own ClothDesc::sweeps).
inline constexpr uint32_t kBudgetFloorSweeps = 2;

// Steps in a row a cloth must be calm (every particle slower than ClothDesc::sleep_speed_m_s) to sleep.
inline constexpr uint32_t kCalmStepsBeforeSleep = 30;

// Health (cloth_health), checked at the end of every step of an awake cloth over its movable particles;
// kinetic energy per kg is the mean |v|^2 / 2 over the last substep (particles weighed alike).
inline constexpr float kOverstretchRatio = 4.0f;  // box diagonal beyond this times the start pose's
inline constexpr float kEnergySpikeRatio = 10.0f;  // kinetic energy per kg beyond this times the baseline
inline constexpr float kEnergyFloor_J_per_kg = 50.0f;  // the baseline is at least this (10 m/s)
inline constexpr uint32_t kLastGoodRefreshSteps = 15;  // healthy steps in a row between copies

// --- creation -------------------------------------------------------------------------------

// Adds to `desc` the capacity one instance of `asset` needs (a cloth, its particle slots, constraint
// lanes and coarse nodes; with RecoveryPolicy::last_good_state, the slots of its copy).
void reserve_cloth(WorldDesc& desc, const ClothAsset& asset, RecoveryPolicy recovery = RecoveryPolicy::none);
// The same for the cloth `cloth` describes (its asset, its recovery policy and self-collision).
void reserve_cloth(WorldDesc& desc, const ClothDesc& cloth);
// Adds what a cloth of `outer` worn over cloths of which `largest_inner` has the most slots needs
// for its layers (WorldDesc::max_layer_particles and _triangles); reserve_cloth still adds the cloth
// itself.
void reserve_layer(WorldDesc& desc, const ClothAsset& outer, const ClothAsset& largest_inner);

MemoryRequirements world_memory_requirements(const WorldDesc& desc);

// Creates a world inside `memory` (at least `world_memory_requirements(desc)`). Nothing else is
// allocated, now or later.
Result create_world(const WorldDesc& desc, void* memory, size_t bytes, World** out_world);

// Releases what a world holds outside its block (the Embree device and scenes of its bodies); the
// world is unusable afterwards. Does nothing for a null world or one without bodies.
void destroy_world(World* world);

// Adds a cloth instance; validates the asset and the settings first. Fails without changing the
// world when a capacity would be exceeded.
Result add_cloth(World* world, const ClothDesc& desc, ClothId* out_cloth);

Result add_collider(World* world, const ColliderDesc& desc, ColliderId* out_collider);

// Removes an instance between steps: its memory goes back to the world's pools (the next add may
// take it) and its id goes stale. A body that a cloth still uses (set_cloth_body, skin constraints,
// attachments: weft/body.h) is refused; remove the cloth first.
Result remove_cloth(World* world, ClothId cloth);
Result remove_collider(World* world, ColliderId collider);

// --- every frame ----------------------------------------------------------------------------

// Advances every cloth by dt seconds (0 < dt <= 1). Runs a fixed amount of work: substeps x
// iterations sweeps per cloth. Refuses bad input without changing anything. Its stages' items go
// through WorldDesc::scheduler when it has one.
Result step(World* world, float dt_s);

// The same step, stage by stage, for a game that runs the work items itself:
//   begin_step(world, dt);
//   for each stage in order (bodies, cloths, second_layer, third_layer): run_step_items(world, stage,
//       begin, end) over [0, step_stage_items(world, stage)), in any ranges, on any threads, all
//       before the next stage;
//   end_step(world);   // sums the counters; the step is done
// Nothing else may be called on the world between begin_step and end_step.
// The cloths stage steps every cloth worn over nothing; second_layer those worn over a cloth of the
// cloths stage, third_layer those worn over one of the second (ClothDesc::worn_over). A layer stage
// has no items while no cloth is in it.
enum class StepStage : uint8_t { bodies, cloths, second_layer, third_layer };
Result begin_step(World* world, float dt_s);
uint32_t step_stage_items(const World* world, StepStage stage);
Result run_step_items(World* world, StepStage stage, uint32_t begin, uint32_t end);
Result end_step(World* world);

// Moves a collider; the next step sees it (its motion over the step drives friction).
Result set_collider(World* world, ColliderId collider, const ColliderDesc& desc);
// The same for a jump (a camera cut, a respawn): no motion, so friction carries nothing.
Result teleport_collider(World* world, ColliderId collider, const ColliderDesc& desc);

// Wind velocity u in equations (2) and (3), m/s. Needs the wind feature.
Result set_wind(World* world, Vec3 velocity_m_s);
Result set_gravity(World* world, Vec3 gravity_m_s2);

// Changes a cloth's solver budget or stiffness between steps.
Result set_cloth_settings(World* world, ClothId cloth, const ClothDesc& desc);

// How a cloth's budget is being spent (after the policy).
struct SolverSplit {
    uint32_t substeps = 0, iterations = 0;
    float relaxation = 0.0f;
    bool coarse_level = false, tethers = false;
    uint32_t coarse_iterations = 0;  // coarse-level sweeps per substep
};
Result cloth_solver_split(const World* world, ClothId cloth, SolverSplit* out);

// Particle access, in the caller's particle order (the asset's permutation is applied here).
Result read_positions(const World* world, ClothId cloth, Vec3* out, uint32_t count);
// Unit vertex normals (area-weighted over each particle's triangles, the asset's winding) as of the
// last step, add_cloth or reset_cloth; (0, 0, 0) for a particle with no triangle of non-zero area.
// Needs WorldDesc::normals.
Result read_normals(const World* world, ClothId cloth, Vec3* out, uint32_t count);
// Unit vertex tangents as of the last step, add_cloth or reset_cloth: dP/du (u: the asset's first
// texture coordinate) summed over each particle's triangles weighted by their uv area, made
// orthogonal to the normal; w = +1, or -1 where dP/dv points against cross(normal, tangent) (a
// mirrored panel): bitangent = w * cross(normal, tangent). (0, 0, 0, 1) where no triangle gives
// one. A seam particle takes each triangle's own panel's uv. Needs WorldDesc::tangents.
Result read_tangents(const World* world, ClothId cloth, Vec4* out, uint32_t count);
// The render mesh's vertices (ClothAsset::render, in its vertex order) as of the last step,
// add_cloth or reset_cloth: each its bound point of the cloth's surface moved its offset along the
// interpolated normal, and that unit normal. count = asset.render.vertex_count; `normals` may be
// null. Needs WorldDesc::render_meshes and an asset with a render mesh.
Result read_render_mesh(const World* world, ClothId cloth, Vec3* positions, Vec3* normals, uint32_t count);
Result set_particle(World* world, ClothId cloth, uint32_t particle, Vec3 position_m,
                    float inverse_mass_per_kg);
// Puts the cloth back at its start pose, at rest.
Result reset_cloth(World* world, ClothId cloth);

// The character that carries the cloth: its root transform this frame. The next step carries the
// cloth by the share of the root's motion since the last root that ClothDesc's inertia leaves out
// (particles and their velocities rotate with it); the first root only sets where the root is.
Result set_cloth_root(World* world, ClothId cloth, const Transform& root);
// A jump of the root (a camera cut, a respawn): the cloth is carried rigidly from its last root to
// `root` now, keeping its shape; the jump adds no velocity. Its own motion goes on, turned with the
// root (a cut in a running scene), or with `drop_velocity` it starts from rest (a respawn).
// Teleport its body (teleport_body) and colliders (teleport_collider) too.
Result teleport_cloth(World* world, ClothId cloth, const Transform& root, bool drop_velocity = false);

// Sleeping cloths (ClothDesc::sleep_speed_m_s): whether the cloth skips its steps now, and a wake
// that makes it step again (with zero velocity) and count its calm steps afresh.
Result cloth_is_sleeping(const World* world, ClothId cloth, bool* out_sleeping);
Result wake_cloth(World* world, ClothId cloth);

// A cloth's health as of its last step: what was wrong (HealthProblem bits; 0: healthy) and
// whether its RecoveryPolicy put it back at the end of that step.
enum HealthProblem : uint32_t {
    kNonFinite = 1u << 0,      // a position is NaN or infinite
    kOverstretched = 1u << 1,  // its box's diagonal is beyond kOverstretchRatio times the start pose's
    kEnergySpike = 1u << 2,    // kinetic energy per kg beyond kEnergySpikeRatio times its baseline
};
struct ClothHealth {
    uint32_t problems = 0;     // HealthProblem bits found by the last step
    bool recovered = false;    // the last step recovered it (problems says why)
    float energy_J_per_kg = 0.0f;  // mean |v|^2 / 2 of its movable particles over the last substep
    uint64_t recoveries = 0;   // recoveries since add_cloth
};
Result cloth_health(const World* world, ClothId cloth, ClothHealth* out);

// The frame budget (docs/architecture.md, "Frame budget"): each step, the cloths' estimated cost
// (WorldDesc::budget_ns_per_lane, budget_ns_per_particle: no clock is read, so the bits stay the
// same) is fitted to `budget_us` by cutting the sweeps of the lowest-priority cloths on the automatic
// policy, lowest first, down to kBudgetFloorSweeps. 0: off, the default (every cloth its own sweeps).
Result set_frame_budget_us(World* world, float budget_us);
// A cloth's priority for the budget (the game's: e.g. nearness to the camera); higher keeps its
// sweeps longer, equal ones are cut from the highest slot down. 0 at add_cloth.
Result set_cloth_priority(World* world, ClothId cloth, float priority);

SimdPath world_simd_path(const World* world);

}  // namespace weft
