// The world's private layout. Everything here lives inside the caller's memory block.
#pragma once

#include "asset/validate.h"
#include "collide/body.h"
#include "collide/layers.h"
#include "collide/self_collision.h"
#include "error.h"
#include "kernels.h"
#include "memory/arena.h"
#include "memory/regions.h"
#include "weft/attachments.h"
#include "weft/debug.h"
#include "weft/world.h"

namespace weft {

// A cloth's counters for the step it runs (its own, so cloths can step on different threads);
// end_step adds them into WorldStats in cloth order.
struct ClothStepCounts {
    uint64_t pass_ns[static_cast<int>(Pass::count)] = {};
    uint64_t colliders_skipped = 0;
    BodyPassCounts body;
    SelfCollisionCounts self;
    LayerCounts layers;
    bool skipped = false;  // asleep: the step ran nothing
};

// A cloth's copy of a healthy step (RecoveryPolicy::last_good_state), in the world's block.
struct LastGoodState {
    float* x = nullptr;  // [slot_count] each: positions and previous positions, metres
    float* y = nullptr;
    float* z = nullptr;
    float* previous_x = nullptr;
    float* previous_y = nullptr;
    float* previous_z = nullptr;
    float previous_substep_s = 0.0f;
    bool saved = false;  // false until a healthy step copies the cloth (or after a reset or teleport)
};

// Health (cloth_health): the last step's findings and what the next step compares against.
struct HealthState {
    uint32_t problems = 0;  // HealthProblem bits of the last step
    bool recovered = false;
    float energy_J_per_kg = 0.0f;
    float baseline_J_per_kg = 0.0f;  // running mean of the energy over finite steps
    float start_extent_m = 0.0f;     // the start pose's box diagonal over movable particles
    uint32_t healthy_steps = 0;      // in a row, for the last good copy's refresh
    uint64_t recoveries = 0;
};

// Vertex normals are computed when asked for, or needed by tangents or render meshes.
inline bool has_normals(const WorldDesc& d) { return d.normals || d.tangents || d.render_meshes; }

struct alignas(64) ClothInstance {  // a cache line of its own: cloths step on different threads
    InstanceSlot slot;
    const ClothAsset* asset = nullptr;
    ClothDesc settings;
    SolverSplit split;  // settings after the budget policy: what the step runs
    Particles particles;
    CoarseState coarse;
    RenderOutput render;  // WorldDesc::render_meshes and an asset with a render mesh, else null
    float previous_substep_s = 0.0f;  // h_prev of time-corrected Verlet; 0 before the first step
    uint32_t own_body = ~0u;          // set_cloth_body: the one body it collides with (~0u: every body)
    uint32_t attached_body = ~0u;     // the body the asset's attachments follow (weft/attachments.h)
    // Skin constraints (bind_skin_constraints): the body they follow and their copy.
    uint32_t skin_body = ~0u;
    SkinState skin_state;          // the bound constraints in slot order (constraints/skin.h)
    uint32_t skin_capacity = 0;    // constraints skin_state's arrays hold (a multiple of kSimdWidth)
    Region skin_memory;            // skin_state's arrays in the world's skin pool
    // skin_state.point holds P on the hull that is now the body's previous one (the last step's):
    // the next frames pass takes it as previous_point instead of gathering it again.
    bool skin_points_current = false;
    uint32_t* body_order = nullptr;   // [slot_count] with bodies: the body pass's slot order (collide/body.h)
    // [max_cached_plane_bodies * kContactPlaneArrays * slot_count]: the contact planes of each
    // cached_planes body, at its BodyState::plane_index (collide/body.h: contact_planes_in).
    float* contact_planes = nullptr;
    // Slots of the lattice planes with inverse mass 0 (pinned, or no particle there). While there
    // are none, the integration pass skips the per-lane pinned check (integrate/verlet.h).
    uint32_t held_plane_slots = 0;
    ClothStepCounts counts;  // this step's
    // Sleeping (ClothDesc::sleep_speed_m_s): steps in a row every particle was slower than the
    // sleep speed, and whether the cloth's steps now run nothing. `bounds` is its box of movable
    // particles (metres) as of its last collision pass or its falling asleep (known: one was found).
    uint32_t calm_steps = 0;
    bool sleeping = false;
    bool bounds_known = false;
    ParticleBounds bounds{};
    HealthState health;
    LastGoodState last_good;  // arrays only when added with RecoveryPolicy::last_good_state
    SelfCollisionState self_collision;  // arrays only when added with ClothDesc::self_collision
    // Layered garments (ClothDesc::worn_over): the cloths it is worn over (indices, checked live at
    // add_cloth; they cannot be removed before it), its layer (0: worn over nothing; its StepStage)
    // and its arrays (only with worn_over).
    uint32_t worn_over[kMaxWornOver] = {};
    uint32_t worn_over_count = 0;
    uint32_t layer = 0;
    LayerState layers;
    float priority = 0.0f;  // the frame budget's (set_cloth_priority): higher keeps its sweeps longer
    // Character motion: the root the game gave (set_cloth_root), the root of the last step, and
    // whether a root was given yet.
    Transform root, previous_root;
    bool has_root = false;
    // This substep's carry: x -> carry_rotation (x - carry_pivot) + carry_pivot + carry_shift (carried
    // false: none). Friction subtracts it from the surfaces' motion: the particles already moved so.
    bool carried = false;
    // This step's root moved faster than ClothDesc's jump speeds: begin_step carried the cloth
    // whole, and its colliders stand at their end pose with no motion to drag it by.
    bool root_jumped = false;
    float carry_rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    Vec3 carry_pivot{}, carry_shift{};
};

// How far this step's carry moved a point at `p` (zero without one).
Vec3 carried_motion(const ClothInstance& cloth, Vec3 p);

// Character motion (runtime/src/character_motion.cpp). At each substep's start: carries the cloth
// by the substep's part of the share of its root's motion since the last step that its inertia
// leaves out.
void follow_root(ClothInstance& cloth, float dt_s, uint32_t substep, uint32_t substeps);
// teleport_cloth: carries the cloth rigidly to `root`; with drop_velocity, at rest there.
void jump_to_root(ClothInstance& cloth, const Transform& root, bool drop_velocity);
// Whether the root moved or turned faster than the cloth's jump speeds since the last step.
bool root_jumps(const ClothInstance& cloth, float dt_s);

struct ColliderState {
    InstanceSlot slot;
    ColliderDesc desc;
    Vec3 motion_m{};     // how far p0 moved since the last step (drives friction)
    Vec3 motion_p1_m{};  // how far p1 moved (a capsule's or cylinder's other end)
};

struct World {
    WorldDesc desc;
    const Kernels* kernels = nullptr;
    bool profiling = false;  // set_profiling (weft/debug.h): the passes read the clock
    // The rest of the block: the arrays of the cloths and bodies, each in a region of its own from
    // instance_memory_begin on (memory/regions.h: reserve_instance_memory).
    Arena arena;
    size_t instance_memory_begin = 0;
    Region* regions = nullptr;  // [max_cloths + max_bodies]: scratch for the gap search

    // Instance arrays: slots [0, *_slots) have been used; a removed instance's slot is free
    // (slot.live false) until the next add takes the lowest free one.
    ClothInstance* cloths = nullptr;  // [desc.max_cloths]
    uint32_t cloth_slots = 0;
    ColliderState* colliders = nullptr;  // [desc.max_colliders]
    uint32_t collider_slots = 0;
    // Body colliders. One Embree device, created with the world only when desc.max_bodies > 0; a
    // reference body (add_reference_body) has its own Embree scene on it (a still body needs no commit).
    RTCDevice embree_device = nullptr;
    BodyState* bodies = nullptr;  // [desc.max_bodies]
    uint32_t body_slots = 0;
    uint32_t body_vertices_used = 0;
    uint32_t body_triangles_used = 0;
    uint32_t cached_plane_bodies = 0;  // live bodies with BodyCollision::cached_planes
    EmbreeCommitHook commit_hook = nullptr;
    void* commit_hook_user = nullptr;
    uint32_t* validation_scratch = nullptr;  // [max(max_particles, max_coarse_nodes)], for validate_asset
    Arena skin_pool;  // WorldDesc::max_skin_constraints: carved by bind_skin_constraints
    uint32_t cloths_live = 0, bodies_live = 0, colliders_live = 0;
    uint32_t particles_used = 0;
    uint32_t constraints_used = 0;
    uint32_t coarse_nodes_used = 0;
    uint32_t triangle_lanes_used = 0;
    uint32_t render_vertices_used = 0;  // by the cloths' tangent uv gradients (WorldDesc::tangents)
    uint32_t last_good_used = 0;        // slots of the cloths' last good copies
    uint32_t self_collision_used = 0;   // slots of the cloths with self-collision
    uint32_t self_collision_triangles_used = 0;  // and their triangles
    uint32_t layer_particles_used = 0;  // the layered cloths' own and largest inner slots
    uint32_t layer_triangles_used = 0;  // and their own triangles

    Vec3 gravity_m_s2{};
    Vec3 wind_m_s{};
    float frame_budget_us = 0.0f;      // set_frame_budget_us; 0: off
    uint32_t* budget_order = nullptr;  // [max_cloths]: scratch, the cloths the budget may cut by priority
    WorldStats stats;
    bool step_open = false;  // between begin_step and end_step
    float step_dt_s = 0.0f;  // the open step's dt
    float last_dt_s = 0.0f;  // the dt of the step before it (0: none yet): what a hitch is measured against
};

// The cloth exists (its id is not stale) and no step is open.
Result find_cloth(const World* world, ClothId id);
// The same for a body.
Result find_body(const World* world, BodyId id);
// An id names a live instance: out_of_range for a place that never held one, stale_id for one
// removed since (a removal bumps its place's generation).
template <class Instance>
Result check_id(const Instance* instances, uint32_t capacity, uint32_t index, uint32_t generation, const char* what) {
    if (index >= capacity || (!instances[index].slot.live && generation == instances[index].slot.generation))
        return make_error(ErrorCode::out_of_range, "%s %u does not exist", what, index);
    if (!instances[index].slot.live || generation != instances[index].slot.generation)
        return make_error(ErrorCode::stale_id, "%s %u (generation %u) was removed", what, index, generation);
    return {};
}
// The slot an add takes: the lowest free one (slots is the array's *_slots, grown when all are
// taken), or `capacity` when the array is full.
template <class Instance>
uint32_t free_slot(const Instance* instances, uint32_t slots, uint32_t capacity) {
    for (uint32_t i = 0; i < slots; ++i)
        if (!instances[i].slot.live) return i;
    return slots < capacity ? slots : capacity;
}
// Marks a slot free and bumps its generation; lowers *slots past free slots at the end.
template <class Instance>
void release_slot(Instance* instances, uint32_t index, uint32_t* slots) {
    instances[index].slot.live = false;
    instances[index].slot.generation = (instances[index].slot.generation + 1) % kGenerations;
    instances[index].slot.memory = {};
    while (*slots > 0 && !instances[*slots - 1].slot.live) --*slots;
}

// Room for `bytes` of a new cloth's or body's arrays in the world's block: the first gap between
// the live instances' regions that fits, after compacting them when none does. Returns an arena
// over that room (`*out_region` its region), or capacity_exceeded.
Result reserve_instance_memory(World& world, size_t bytes, Arena* out_arena, Region* out_region);
// A body's arrays moved by `delta` bytes (compaction): its pointers follow (bodies.cpp).
void rebase_body(World& world, BodyState& body, ptrdiff_t delta);

// Refused while a step is open (begin_step .. end_step): anything that changes the world.
Result refuse_while_stepping(const World* world);

// Commits a body's scene (a refit once built), telling the diagnostics hook.
void commit_body(World& world, BodyState& body);
// Bytes of the world's block a body with these counts takes (its region).
size_t body_region_bytes(uint32_t vertex_count, uint32_t triangle_count);

// Refits a body's Embree BVH to its current hull (a commit).
void refit_embree(World& world, BodyState& body);

// Puts a cloth at its asset's start pose (plus its translation), at rest (add_cloth, reset_cloth).
void place_at_start(const Kernels& kernels, ClothInstance& cloth);
// After positions jumped: contact anchors and wind cleared, the render output found again.
void start_from_new_positions(const Kernels& kernels, ClothInstance& cloth);
// The last good copy (RecoveryPolicy::last_good_state): positions, previous positions and h_prev.
void save_last_good(ClothInstance& cloth);
void restore_last_good(const Kernels& kernels, ClothInstance& cloth);

// Sleeping cloths. wake: a sleeping cloth steps again from rest (previous positions = positions);
// any cloth counts its calm steps afresh. The others wake the cloths a change may move: every
// cloth, those whose box meets a collider's (or whose box is not known), those that may touch a
// body (collide with it, are bound or attached to it).
void wake(ClothInstance& cloth);
void wake_every_cloth(World& world);
void wake_cloths_near(World& world, const ColliderDesc& collider);
void wake_cloths_of_body(World& world, uint32_t body);
// A body whose motion this step counts as done (teleport_body, a jumped root in begin_step): no
// vertex motion, the previous hull is this one, and skin constraints bound to it take their previous
// points from it.
void hold_body_still(World& world, uint32_t body);
bool same_vec3(Vec3 a, Vec3 b);
bool same_transform(const Transform& a, const Transform& b);
bool same_collider(const ColliderDesc& a, const ColliderDesc& b);
// A collider's shape in the kernels' form (no motion).
ColliderKernelArgs collider_shape_args(const ColliderDesc& desc);

// Health: the start pose's extent (add_cloth), and the dressed pose on the body as posed now
// (reset_to_pose and RecoveryPolicy::dressed_pose; the cloth has skin constraints or attachments).
float start_extent_m(const ClothAsset& asset);
void place_on_body(const World& world, ClothInstance& cloth);
// A reset or teleport: the last good copy is of elsewhere, so the next healthy step copies afresh.
inline void forget_last_good(ClothInstance& cloth) { cloth.last_good.saved = false; cloth.health.healthy_steps = 0; }

// The frame budget (budget.cpp), at begin_step: sets each cloth's split for this step from its
// settings, cutting the sweeps of the lowest priorities until the estimate fits the budget, and
// writes the budget's WorldStats. Reads no clock: the same inputs give the same splits.
void spend_frame_budget(World& world);

// Checks a finite vector (no NaN or infinity).
bool is_finite(Vec3 v);

// Applies the budget policy (ClothDesc::policy) to a cloth's settings.
SolverSplit resolve_split(const ClothDesc& desc, const ClothAsset& asset);

}  // namespace weft
