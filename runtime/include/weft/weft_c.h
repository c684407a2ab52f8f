/* Weft's C interface: the whole frame loop, for C games and engine bindings (C99 and C++).
 *
 *   WeftMemoryRequirements need;
 *   weft_asset_memory_requirements(file, size, &need);          // file: a .weft, 64-byte aligned
 *   WeftAsset* asset;  weft_load_asset(file, size, asset_block, need.bytes, &asset);
 *   WeftWorldDesc desc = weft_default_world_desc();  weft_reserve_cloth(&desc, asset);
 *   weft_world_memory_requirements(&desc, &need);
 *   WeftWorld* world;  weft_create_world(&desc, world_block, need.bytes, &world);
 *   WeftClothDesc cloth = weft_default_cloth_desc(asset);  weft_add_cloth(world, &cloth, &cloth_id);
 *   every frame: weft_set_body_vertices(...), weft_set_collider(...), weft_set_cloth_root(...),
 *                weft_step(world, dt), weft_read_positions(...), weft_read_normals(...)
 *   weft_destroy_world(world); then free the blocks and the file bytes: they are the caller's.
 *
 * Every fallible call returns a WeftResult: a code (WEFT_OK is 0) and a message; a refused call
 * changes nothing. Nothing allocates: the asset and the world live in blocks the caller provides
 * (a world with bodies also holds an Embree device, released by weft_destroy_world). A handle
 * used after weft_destroy_world, or a block that never held one, gives an error while its memory
 * is still the caller's; a freed block or a wild pointer cannot be detected.
 * The C++ API is weft/world.h; this is a thin layer over it, stepping to the same bits. */
#ifndef WEFT_C_H
#define WEFT_C_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Enums are 32-bit; in C++ they have that fixed type, so any value a C caller passes is well defined
 * (and refused where it names nothing). */
#ifdef __cplusplus
#define WEFT_ENUM(name) enum name : uint32_t
#else
#define WEFT_ENUM(name) enum name
#endif

typedef WEFT_ENUM(WeftErrorCode) {
    WEFT_OK = 0,
    WEFT_INVALID_ARGUMENT = 1,   /* a null pointer, a zero count, a handle that is not live */
    WEFT_NON_FINITE = 2,         /* NaN or infinity where a finite value is needed */
    WEFT_OUT_OF_RANGE = 3,       /* an id or count that does not match, a value outside its range */
    WEFT_CAPACITY_EXCEEDED = 4,  /* the world was created too small for what is added */
    WEFT_MEMORY_TOO_SMALL = 5,   /* the caller's block is smaller or less aligned than required */
    WEFT_UNSUPPORTED = 6,        /* e.g. the AVX2 path on a CPU without it */
    WEFT_CORRUPT_ASSET = 7,      /* the asset file failed validation */
    WEFT_STALE_ID = 8            /* the id of a cloth, body or collider that was removed */
} WeftErrorCode;

typedef struct WeftResult {
    WeftErrorCode code;
    char message[120]; /* NUL-terminated; empty on WEFT_OK */
} WeftResult;

/* The code's name ("ok", "corrupt_asset", ...). */
const char* weft_error_name(WeftErrorCode code);

typedef struct WeftVec3 {
    float x, y, z; /* metres, m/s or m/s^2 */
} WeftVec3;

/* A tangent and its handedness w (+1 or -1): bitangent = w * cross(normal, tangent). */
typedef struct WeftVec4 {
    float x, y, z, w;
} WeftVec4;

typedef struct WeftMemoryRequirements {
    size_t bytes;
    size_t alignment; /* the block's start must be a multiple of this */
} WeftMemoryRequirements;

typedef WEFT_ENUM(WeftSimdPath) { WEFT_SIMD_AUTOMATIC = 0, WEFT_SIMD_SCALAR = 1, WEFT_SIMD_AVX2 = 2 } WeftSimdPath;

typedef struct WeftAsset WeftAsset; /* a loaded .weft asset, in the caller's block */
typedef struct WeftWorld WeftWorld; /* a world, in the caller's block */
/* Ids as the add calls return them: a place in the world (low 16 bits; 0, 1, 2... as first added) and
 * the generation of what holds it (high 16 bits), so the id of a removed instance is refused
 * (WEFT_STALE_ID) even after another took its place. */
typedef uint32_t WeftClothId;
typedef uint32_t WeftBodyId;
typedef uint32_t WeftColliderId;
#define WEFT_EVERY_BODY 0xFFFFFFFFu /* weft_set_cloth_body: the cloth collides with every body again */

/* --- assets (weft-bake's files) ---------------------------------------------------------------- */

/* The block weft_load_asset needs for this file (checks the header and checksum first). */
WeftResult weft_asset_memory_requirements(const void* file, size_t size, WeftMemoryRequirements* out);

/* Loads the asset in place: `file` (64-byte aligned) must stay alive and unchanged while the asset
 * is used; `memory` holds the handle and the loader's scratch. Every byte is validated first. */
WeftResult weft_load_asset(const void* file, size_t size, void* memory, size_t memory_bytes, WeftAsset** out_asset);

/* What a game reads of an asset (weft/asset_view.h): pointers into the loaded file, null when absent. */
typedef struct WeftAssetInfo {
    uint32_t particle_count; /* positions and normals are read in this count, the caller's order */
    uint32_t triangle_count;
    const float* uv;         /* [2 * particle_count] texture coordinates, metres on the flat panel */
    /* Sewn seams: particle sewn_particle[k] splits into one render vertex per source, at
     * sewn_uv[2j..2j+1] for j in [sewn_uv_first[k], sewn_uv_first[k + 1]). */
    uint32_t sewn_point_count;
    const uint32_t* sewn_particle;
    const uint32_t* sewn_uv_first;
    const float* sewn_uv;
    int has_fabric;                 /* 0: the fabric fields hold the defaults */
    float damping_per_s;            /* the fabric's, for WeftClothDesc */
    float compliance_m_per_n[3];    /* stretch, shear, bend */
    uint32_t attachment_count;      /* particles bound to the body the garment was dressed on */
    uint32_t skin_constraint_count; /* baked skin constraints */
    uint32_t render_vertex_count;   /* the render mesh (weft-bake --render-mesh); 0: none */
    uint32_t render_triangle_count;
} WeftAssetInfo;
WeftResult weft_asset_info(const WeftAsset* asset, WeftAssetInfo* out);

/* The triangles as particle indices (caller order, the asset's winding): 3 * triangle_count values. */
WeftResult weft_asset_triangles(const WeftAsset* asset, uint32_t* out_indices, uint32_t index_count);
/* The render mesh's triangles (3 * render_triangle_count render vertex indices) and texture
 * coordinates (2 * render_vertex_count floats); either output may be null. */
WeftResult weft_asset_render_mesh(const WeftAsset* asset, uint32_t* out_indices, uint32_t index_count, float* out_uv,
                                  uint32_t uv_count);
/* The start pose, metres, caller order: particle_count values. */
WeftResult weft_asset_start_positions(const WeftAsset* asset, WeftVec3* out, uint32_t count);

/* --- the world ----------------------------------------------------------------------------------- */

typedef struct WeftWorldDesc {
    uint32_t max_cloths;         /* weft_reserve_cloth adds 1 and the next three per cloth */
    uint32_t max_particles;
    uint32_t max_constraints;
    uint32_t max_coarse_nodes;
    uint32_t max_colliders;
    uint32_t max_bodies;         /* > 0: the world creates an Embree device */
    uint32_t max_body_vertices;  /* summed over bodies */
    uint32_t max_body_triangles; /* summed over bodies */
    int wind;                    /* non-zero: the wind pass exists (weft_set_wind) */
    int normals;                 /* non-zero: each step ends with vertex normals (weft_read_normals) */
    WeftVec3 gravity_m_s2;
    float air_density_kg_m3;     /* for the wind's drag and lift */
    WeftSimdPath simd;
    int tangents;                /* non-zero: also unit tangents from the uv (weft_read_tangents); implies normals */
    uint32_t max_triangle_lanes; /* weft_reserve_cloth adds the asset's; carved only with tangents */
    int render_meshes;           /* non-zero: each step drives the cloths' render meshes (weft_read_render_mesh) */
    uint32_t max_render_vertices; /* weft_reserve_cloth adds the asset's */
    uint32_t max_last_good_particles; /* weft_reserve_cloth_recovering adds the asset's for WEFT_RECOVER_LAST_GOOD */
    float budget_ns_per_lane;     /* the frame budget's cost model (weft/world.h): ns a constraint lane per sweep */
    float budget_ns_per_particle; /* ns a particle slot per substep */
    uint32_t max_self_collision_particles; /* weft_reserve_cloth_desc adds the asset's for a self-colliding cloth */
    uint32_t max_self_collision_triangles;
    uint32_t max_layer_particles; /* weft_reserve_layer adds what a cloth worn over others needs */
    uint32_t max_layer_triangles;
    uint32_t max_skin_constraints;    /* weft_reserve_cloth adds the asset's (a garment dressed by weft-bake --body) */
    uint32_t max_cached_plane_bodies; /* bodies that may use WEFT_BODY_CACHED_PLANES */
} WeftWorldDesc;

/* No capacity, gravity (0, -9.81, 0) m/s^2, air 1.2 kg/m^3, no wind, the widest SIMD path, the
   frame budget's default cost model. */
WeftWorldDesc weft_default_world_desc(void);

/* Adds one instance of `asset` to the capacities. */
WeftResult weft_reserve_cloth(WeftWorldDesc* desc, const WeftAsset* asset);

/* What a step does with a cloth it finds unhealthy (weft/world.h, RecoveryPolicy). */
typedef WEFT_ENUM(WeftRecoveryPolicy) {
    WEFT_RECOVER_NONE = 0,       /* report only */
    WEFT_RECOVER_LAST_GOOD = 1,  /* back to its copy of a recent healthy step */
    WEFT_RECOVER_REST_POSE = 2,  /* back to the asset's start pose, at rest */
    WEFT_RECOVER_DRESSED_POSE = 3 /* the dressed pose on its body as posed now; else the rest pose */
} WeftRecoveryPolicy;

/* weft_reserve_cloth for a cloth added with `recovery` (WEFT_RECOVER_LAST_GOOD: room for its copy). */
WeftResult weft_reserve_cloth_recovering(WeftWorldDesc* desc, const WeftAsset* asset, WeftRecoveryPolicy recovery);

WeftResult weft_world_memory_requirements(const WeftWorldDesc* desc, WeftMemoryRequirements* out);

/* Creates a world in `memory` (at least weft_world_memory_requirements, suitably aligned). */
WeftResult weft_create_world(const WeftWorldDesc* desc, void* memory, size_t bytes, WeftWorld** out_world);

/* Releases the world's Embree device (if it has bodies); the handle is dead afterwards. Null: nothing. */
void weft_destroy_world(WeftWorld* world);

typedef struct WeftClothDesc {
    const WeftAsset* asset;        /* must outlive the world */
    WeftVec3 translation_m;        /* added to the asset's start positions */
    uint32_t sweeps;               /* the solver budget: passes over every constraint per step (1..1000) */
    float compliance_m_per_n[3];   /* stretch, shear, bend; 0 = hard */
    float damping_per_s;           /* dv/dt = -damping * v */
    float drag_coefficient;        /* wind, with the world's wind feature */
    float lift_coefficient;
    float sleep_speed_m_s;         /* every particle slower than this (m/s) for 30 steps: it sleeps; 0 = never */
    WeftRecoveryPolicy recovery;   /* what a step does with it when unhealthy; WEFT_RECOVER_NONE: report only */
    int self_collision;            /* non-zero: it collides with itself (chosen at weft_add_cloth) */
    float self_thickness_m;        /* the distance kept between a particle and the cloth's faces, m */
    float self_friction;           /* Coulomb coefficient between its layers */
    WeftClothId worn_over[4];      /* layered garments: the cloths it is worn over (added before it), */
    uint32_t worn_over_count;      /* 0..4; they win: it stays layer_thickness_m outside their faces */
    float layer_thickness_m;       /* m */
    float layer_friction;          /* Coulomb coefficient between the layers */
    /* Character motion (weft_set_cloth_root; weft/world.h, ClothDesc): */
    float linear_inertia;          /* share of the root's motion the cloth feels, 0..1 (0: carried rigidly) */
    float angular_inertia;         /* the same for its rotation */
    float max_inertial_speed_m_s;  /* root motion beyond this speed carries the cloth rigidly */
    float jump_speed_m_s;          /* a root faster than this, or turning faster than */
    float jump_turn_rad_s;         /*   this, is a jump: carried whole, as weft_teleport_cloth; 0: never */
    float max_step_growth;         /* a dt more than this times the last one is stepped as the last; 0: off */
    float max_step_s;              /* no step is longer than this for the cloth, s; 0: no limit */
} WeftClothDesc;

/* world.h's ClothDesc defaults, with the compliance and damping of the asset's fabric if it has one. */
WeftClothDesc weft_default_cloth_desc(const WeftAsset* asset);

/* Adds to the capacities what the cloth `cloth` describes needs: weft_reserve_cloth, and the room
   for its last good copy (WEFT_RECOVER_LAST_GOOD) and its self-collision. */
WeftResult weft_reserve_cloth_desc(WeftWorldDesc* desc, const WeftClothDesc* cloth);
/* Adds the room a cloth of `outer` worn over cloths of which `largest_inner` has the most particles
   needs for its layers (weft/world.h: reserve_layer); weft_reserve_cloth_desc still adds the cloth. */
WeftResult weft_reserve_layer(WeftWorldDesc* desc, const WeftAsset* outer, const WeftAsset* largest_inner);

WeftResult weft_add_cloth(WeftWorld* world, const WeftClothDesc* desc, WeftClothId* out_cloth);

/* --- bodies and colliders -------------------------------------------------------------------------- */

/* How cloths collide with a body (weft/body.h, BodyCollision). */
typedef WEFT_ENUM(WeftBodyCollision) {
    WEFT_BODY_EXACT = 0,            /* every substep, every particle: the closest hull point */
    WEFT_BODY_CACHED_PLANES = 1,    /* exact at the first substep, then its contact plane (max_cached_plane_bodies) */
    WEFT_BODY_SKIN_CONSTRAINTS = 2  /* cloths bound by skin constraints (weft_bind_asset_skin_constraints) only */
} WeftBodyCollision;

typedef struct WeftBodyDesc {
    const WeftVec3* positions;  /* rest pose, metres; copied */
    uint32_t vertex_count;
    const uint32_t* triangles;  /* 3 per triangle, counter-clockwise seen from outside; copied */
    uint32_t triangle_count;
    float thickness_m;          /* the collision hull's offset from the skin */
    float margin_m;             /* query reach beyond the thickness */
    float friction;             /* Coulomb coefficient against the moving surface */
    WeftBodyCollision collision;
} WeftBodyDesc;

/* body.h's defaults: thickness 5 mm, margin 2 mm, friction 0.5, the exact model; no mesh. */
WeftBodyDesc weft_default_body_desc(void);

/* A triangle-mesh body the cloth collides with (weft/body.h). */
WeftResult weft_add_body(WeftWorld* world, const WeftBodyDesc* desc, WeftBodyId* out_body);

/* The body's new pose (vertex_count positions, metres); the next step moves the hull there. */
WeftResult weft_set_body_vertices(WeftWorld* world, WeftBodyId body, const WeftVec3* positions, uint32_t count);

/* Binds the asset's body attachments (a dressed garment's waistband) to the body it was dressed on. */
WeftResult weft_attach_cloth_to_body(WeftWorld* world, WeftClothId cloth, WeftBodyId body);
/* Binds the skin constraints weft-bake --body baked into the asset (weft/attachments.h) to that body:
   the game-cost collision of a dressed garment, with WEFT_BODY_SKIN_CONSTRAINTS. */
WeftResult weft_bind_asset_skin_constraints(WeftWorld* world, WeftClothId cloth, WeftBodyId body);
typedef WEFT_ENUM(WeftColliderShape) {
    WEFT_COLLIDER_SPHERE = 0,  /* centre p0 */
    WEFT_COLLIDER_CAPSULE = 1, /* axis p0 to p1 */
    WEFT_COLLIDER_CYLINDER = 2,
    WEFT_COLLIDER_PLANE = 3    /* point p0, unit normal p1 */
} WeftColliderShape;

typedef struct WeftColliderDesc {
    WeftColliderShape shape;
    WeftVec3 p0, p1;    /* metres (a plane's p1: its unit normal) */
    float radius_m;     /* sphere, capsule, cylinder */
    float inflation_m;  /* collision skin added to the radius; a plane's offset */
    float friction;     /* Coulomb coefficient; 0 = frictionless */
} WeftColliderDesc;

/* world.h's defaults: a sphere of radius 0.5 m at the origin, no inflation, no friction. */
WeftColliderDesc weft_default_collider_desc(void);

WeftResult weft_add_collider(WeftWorld* world, const WeftColliderDesc* desc, WeftColliderId* out_collider);

/* Moves or reshapes a collider; the next step sees it (its motion drives friction). */
WeftResult weft_set_collider(WeftWorld* world, WeftColliderId collider, const WeftColliderDesc* desc);

/* --- character motion (weft/world.h: set_cloth_root, teleport_cloth) ----------------------------------- */

typedef struct WeftQuat {
    float x, y, z, w; /* unit */
} WeftQuat;
typedef struct WeftTransform {
    WeftVec3 translation_m;
    WeftQuat rotation;
} WeftTransform;

/* The character's root this frame: the next step carries the cloth by the share of the root's
   motion its inertia leaves out (WeftClothDesc). */
WeftResult weft_set_cloth_root(WeftWorld* world, WeftClothId cloth, const WeftTransform* root);
/* A jump (a camera cut, a respawn): the cloth carried rigidly to `root` now; with drop_velocity
   non-zero it starts from rest. Teleport its body and colliders too. */
WeftResult weft_teleport_cloth(WeftWorld* world, WeftClothId cloth, const WeftTransform* root, int drop_velocity);
/* The body's new pose with no motion (the hull does not sweep from the old pose). */
WeftResult weft_teleport_body(WeftWorld* world, WeftBodyId body, const WeftVec3* positions, uint32_t count);
/* A collider moved with no motion (friction carries nothing). */
WeftResult weft_teleport_collider(WeftWorld* world, WeftColliderId collider, const WeftColliderDesc* desc);
/* The dressed cloth back at its dressed pose on its body as the body is now, at rest. */
WeftResult weft_reset_to_pose(WeftWorld* world, WeftClothId cloth);

/* --- every frame ------------------------------------------------------------------------------------ */

/* Wind velocity, m/s (needs WeftWorldDesc::wind). */
WeftResult weft_set_wind(WeftWorld* world, WeftVec3 velocity_m_s);
WeftResult weft_set_gravity(WeftWorld* world, WeftVec3 gravity_m_s2);

/* Advances every cloth by dt seconds (0 < dt <= 1): a fixed amount of work, no allocation. */
WeftResult weft_step(WeftWorld* world, float dt_s);

/* The same step stage by stage, for an engine's job system (weft/world.h): weft_begin_step, then for
 * each stage in order (WEFT_STAGE_BODIES, WEFT_STAGE_CLOTHS, then the layers worn over those:
 * WEFT_STAGE_SECOND_LAYER, WEFT_STAGE_THIRD_LAYER, empty without layered cloths) weft_run_step_items over
 * [0, weft_step_stage_items) in any ranges on any threads, all before the next stage, then
 * weft_end_step. Any split gives the same bits as weft_step. */
typedef WEFT_ENUM(WeftStepStage) {
    WEFT_STAGE_BODIES = 0,
    WEFT_STAGE_CLOTHS = 1,
    WEFT_STAGE_SECOND_LAYER = 2,
    WEFT_STAGE_THIRD_LAYER = 3
} WeftStepStage;
WeftResult weft_begin_step(WeftWorld* world, float dt_s);
uint32_t weft_step_stage_items(const WeftWorld* world, WeftStepStage stage);
WeftResult weft_run_step_items(WeftWorld* world, WeftStepStage stage, uint32_t begin, uint32_t end);
WeftResult weft_end_step(WeftWorld* world);

/* The cloth collides with this body only (its character's), not every body of the world. */
WeftResult weft_set_cloth_body(WeftWorld* world, WeftClothId cloth, WeftBodyId body);

/* Removes an instance between steps: its memory goes back to the world (the next add may take it)
 * and its id goes stale. A body a cloth still uses (weft_set_cloth_body, attachments) is refused:
 * remove the cloth first. */
WeftResult weft_remove_cloth(WeftWorld* world, WeftClothId cloth);
WeftResult weft_remove_body(WeftWorld* world, WeftBodyId body);
WeftResult weft_remove_collider(WeftWorld* world, WeftColliderId collider);

/* The cloth's positions in the caller's particle order, metres; count = the asset's particle_count. */
WeftResult weft_read_positions(const WeftWorld* world, WeftClothId cloth, WeftVec3* out, uint32_t count);

/* Unit vertex normals as of the last step (area-weighted, the asset's winding; (0, 0, 0) on no
 * triangle of non-zero area), caller order; needs WeftWorldDesc::normals. */
WeftResult weft_read_normals(const WeftWorld* world, WeftClothId cloth, WeftVec3* out, uint32_t count);
/* Unit tangents from the asset's uv as of the last step, w the handedness ((0, 0, 0, 1) where no
 * triangle gives one), caller order; needs WeftWorldDesc::tangents. */
WeftResult weft_read_tangents(const WeftWorld* world, WeftClothId cloth, WeftVec4* out, uint32_t count);
/* The render mesh's vertices and unit normals as of the last step (render_vertex_count each, the
 * asset's render vertex order; `normals` may be null); needs WeftWorldDesc::render_meshes. */
WeftResult weft_read_render_mesh(const WeftWorld* world, WeftClothId cloth, WeftVec3* positions, WeftVec3* normals,
                                 uint32_t count);

/* Sleeping cloths (WeftClothDesc::sleep_speed_m_s): *out_sleeping is 1 while the cloth's steps run
 * nothing, else 0. Anything that may move it wakes it (weft/world.h); weft_wake_cloth does so
 * explicitly (it steps again from rest). */
WeftResult weft_cloth_is_sleeping(const WeftWorld* world, WeftClothId cloth, int* out_sleeping);
WeftResult weft_wake_cloth(WeftWorld* world, WeftClothId cloth);

/* Health (weft/world.h, cloth_health): the HealthProblem bits the last step found (WEFT_HEALTH_*; 0:
 * healthy), whether its recovery policy put it back at the end of that step, and counts. */
enum { WEFT_HEALTH_NON_FINITE = 1, WEFT_HEALTH_OVERSTRETCHED = 2, WEFT_HEALTH_ENERGY_SPIKE = 4 };
typedef struct WeftClothHealth {
    uint32_t problems;       /* WEFT_HEALTH_* bits */
    int recovered;           /* 1: the last step recovered it */
    float energy_J_per_kg;   /* mean |v|^2 / 2 of its movable particles over the last substep */
    uint64_t recoveries;     /* since it was added */
} WeftClothHealth;
WeftResult weft_cloth_health(const WeftWorld* world, WeftClothId cloth, WeftClothHealth* out);

/* The world's health counts (weft/debug.h, WorldStats): the last step's unhealthy and recovered
 * cloths, and recoveries over all steps. */
typedef struct WeftWorldHealth {
    uint64_t unhealthy_cloths;
    uint64_t recovered_cloths;
    uint64_t total_recoveries;
} WeftWorldHealth;
WeftResult weft_world_health(const WeftWorld* world, WeftWorldHealth* out);

/* The frame budget (weft/world.h: set_frame_budget_us): microseconds a step's cloths may cost by
 * the world's cost model (no clock is read); the lowest priorities lose sweeps first, down to 2.
 * 0 = off, the default. A priority (0 at add) is the game's: higher keeps its sweeps longer. */
WeftResult weft_set_frame_budget_us(WeftWorld* world, float budget_us);
WeftResult weft_set_cloth_priority(WeftWorld* world, WeftClothId cloth, float priority);
/* What the budget did last step (weft/debug.h: WorldStats::budget_*). */
typedef struct WeftFrameBudgetStats {
    double estimate_us;   /* the awake cloths' estimated cost (also with the budget off) */
    uint64_t cloths_cut;  /* cloths that ran fewer sweeps than their own */
    uint64_t sweeps;      /* substeps x iterations, summed over the awake cloths */
} WeftFrameBudgetStats;
WeftResult weft_frame_budget_stats(const WeftWorld* world, WeftFrameBudgetStats* out);

#ifdef __cplusplus
}
#endif

#endif /* WEFT_C_H */
