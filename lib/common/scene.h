// A scene: everything a world holds (cloths, colliders, wind, gravity, the time step), as plain
// data. weft-sim reads it from a scene file (docs/scene-format.md, scene_json.h); weft-bench and
// the tests make the seed paper's experiments as scenes (seed_scenes.h). `build_scene` creates a
// world with exactly what the scene uses: no wind entry, no wind pass; no collider, no collision pass.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/asset_writer.h"
#include "body/mannequin.h"
#include "common/skin_binding.h"
#include "weft/weft.h"
#include "weft/cook.h"

namespace weft::scenes {

inline constexpr float kSeedTimeStep_s = 0.033f;
inline constexpr float kCottonDensity_kg_m2 = 0.150f;  // Penava et al. 2014 (shared/data/README.md)

// An n x n grid (n >= 2) of side `size_m`, one diagonal per quad (the paper's spring counts).
// `vertical` lays it in the x-y plane (a flag, pole along y at x = 0, rows going down from y_m),
// otherwise in the x-z plane at height y_m, centred on the y axis. Masses are area-weighted (seed
// eq. 9).
struct GridMesh {
    uint32_t n = 0;
    std::vector<Vec3> positions;
    std::vector<uint32_t> triangles;
    std::vector<float> masses;
    std::vector<int32_t> lattice;  // (row, column) per particle
    uint32_t index(uint32_t row, uint32_t col) const { return row * n + col; }
    ClothMeshDesc desc() const;
};
GridMesh make_grid(uint32_t n, float width_m, float height_m_or_length, bool vertical, float y_m,
                   float density_kg_m2 = kCottonDensity_kg_m2);

// A grid cloth made in memory (the seed's experiments).
struct GridSource {
    uint32_t n = 100;
    float width_m = 2.0f;
    float length_m = 2.0f;
    bool vertical = false;  // see make_grid
    float y_m = 2.0f;       // height (horizontal) or top edge (vertical)
    float areal_density_kg_m2 = kCottonDensity_kg_m2;
    Vec3 offset_m{};        // added to every particle before cooking
    // Pinned particles: (row, column) pairs, whole rows and whole columns. Negative indices count
    // from the end (-1 = the last row or column).
    std::vector<std::pair<int32_t, int32_t>> pins;
    std::vector<int32_t> pin_rows, pin_columns;
};

struct ClothSpec {
    std::string name;
    std::optional<GridSource> grid;  // exactly one of grid and asset_path
    std::string asset_path;          // a baked .weft file (weft-bake), as the scene names it
    // Baked assets carry their fabric; it gives the compliance and damping unless the scene names them.
    bool compliance_given = false, damping_given = false;
    CookOptions cook;                // grid only
    ClothDesc desc;                  // solver settings; desc.asset is filled by build_scene
    // The cloths it is worn over, by name: cloths listed before it (desc.worn_over is filled by build_scene).
    std::vector<std::string> worn_over;
};

// A body collider (weft/body.h) and how it moves: the project's mannequin or a mesh file, still,
// walking or bending and sitting (the mannequin's procedural clips, lib/body/mannequin.h, entered
// from its rest pose over ramp_s) or blended back and forth between two poses of the same mesh
// (the shared A-pose and T-pose).
enum class BodyAnimation : uint8_t { still, walk, blend, bend_and_sit };
struct BodySpec {
    bool mannequin = false;     // the project's own (lib/body/mannequin.h, default measurements)
    std::string mesh_path;      // or an OBJ/glTF file, relative to the scene file's folder
    BodyAnimation animation = BodyAnimation::still;
    std::string blend_to_path;  // blend: the second pose (same faces)
    float period_s = 2.0f;      // blend: rest -> blend_to -> rest
    float ramp_s = 1.0f;        // walk, bend_and_sit: seconds from the rest pose into the full clip
    float thickness_m = 0.004f, margin_m = 0.002f, friction = 0.5f;  // BodyDesc
    // BodyDesc::collision. A scene names the cheapest model that keeps its garment within 2 mm of
    // the hull (docs/garments.md); without a name, cached_planes, within it on every body measured.
    BodyCollision collision = BodyCollision::cached_planes;
    // Capsule colliders around these bones of the mannequin, moved with them, `limb_capsule_sections`
    // along each (body::fit_limb_capsules); none by default. Under skin_constraints they keep a
    // skirt's free hem off the swinging thighs: its backstops stand at the hips (docs/garments.md).
    std::vector<std::string> limb_capsules;
    uint32_t limb_capsule_sections = 2;
    // A plane collider under the soles (the rest pose's lowest vertex), as thick as the hull and
    // with the body's friction: the floor weft-bake dresses a garment on, so a floor-length hem
    // rests on it in the game as it did when baked.
    bool ground = false;
};

// The scene files' names of the body collision models ("exact", "cached_planes").
const char* body_collision_name(BodyCollision c);
// The model a name stands for; false for an unknown name.
bool body_collision_from_name(const std::string& name, BodyCollision* out);

struct Scene {
    std::string name;
    std::string base_dir = ".";  // relative asset paths are looked up here first
    float dt_s = kSeedTimeStep_s;
    uint32_t frames = 330;  // 10.9 s at the seed's dt: long enough to come to rest
    Vec3 gravity_m_s2{0.0f, -9.81f, 0.0f};
    float air_density_kg_m3 = 1.2f;
    std::optional<Vec3> wind_m_s;  // present: the world has the wind pass
    SimdPath simd = SimdPath::automatic;
    bool profile = false;
    bool normals = false;  // the step ends with vertex normals (WorldDesc::normals): a renderer's cost
    bool tangents = false;       // and tangents (WorldDesc::tangents)
    bool render_meshes = false;  // and drives the assets' render meshes (WorldDesc::render_meshes)
    StepScheduler scheduler;  // not in scene files: the running tool's thread pool (WorldDesc::scheduler)
    std::vector<ClothSpec> cloths;
    std::vector<ColliderDesc> colliders;
    std::optional<BodySpec> body;
};

// How far into the walk at time t: 0 at rest, 1 walking (a smoothstep over spec.ramp_s).
float walk_entry(const BodySpec& spec, float t_s);

// A limb capsule as a collider: inflated by the body's thickness, with the body's friction.
ColliderDesc limb_collider(const BodySpec& spec, const body::LimbCapsule& c);

// A world's block, freed with std::free.
using WorldBlock = std::unique_ptr<unsigned char[], void (*)(void*)>;
// Allocates a block sized for `desc` and creates the world in it. Returns the failure message.
std::string create_world_in_block(const WorldDesc& desc, WorldBlock* memory, World** out);

// One cloth of a built scene: where its asset came from, and its instance.
// The assets sit behind pointers: the world keeps a pointer to its asset, so moving a SceneCloth
// must not move the asset.
struct SceneCloth {
    GridMesh mesh;                         // grid sources
    std::unique_ptr<CookedCloth> cooked;   // grid sources: the cooked asset
    std::unique_ptr<assets::LoadedAsset> loaded;  // baked sources: the file's bytes and the asset in them
    const ClothAsset* asset = nullptr;
    ClothId id{};
    ClothDesc desc;  // what add_cloth was given (the scene's settings, the baked fabric's stiffness)
    // The skin_constraints body model for an asset without baked ones: the binding cooked for it,
    // kept for inspection (the world holds its own copy; null when the asset's own are bound).
    std::unique_ptr<SkinBinding> skin;
};

// A built scene's body: its rest pose, what animates it, its id in the world.
struct SceneBody {
    BodySpec spec;
    std::vector<Vec3> rest, blend_to, pose;
    std::vector<uint32_t> triangles;
    std::shared_ptr<const void> mannequin;  // body::Mannequin for the walk (lib/body)
    BodyId id{};
    std::vector<body::LimbCapsule> limb_capsules, posed_capsules;  // rest pose; at the last animate_body
    std::vector<ColliderId> limb_colliders;
    ColliderId ground{};  // spec.ground
};

struct SceneWorld {
    // Owns its world: destroy_world releases the body's Embree scene and device, `memory` the rest.
    SceneWorld() = default;
    SceneWorld(SceneWorld&& other) noexcept { *this = std::move(other); }
    SceneWorld& operator=(SceneWorld&& other) noexcept;
    ~SceneWorld() { destroy_world(world); }

    std::vector<SceneCloth> cloths;
    std::unique_ptr<SceneBody> body;
    WorldBlock memory{nullptr, nullptr};
    size_t memory_bytes = 0;  // world_memory_requirements of the scene's world
    World* world = nullptr;
    std::vector<ColliderId> colliders;
    float dt_s = kSeedTimeStep_s;
};

// Cooks or loads every cloth, creates the world with exactly the scene's features and adds
// everything. A relative asset path is looked up in scene.base_dir, then in each of `asset_dirs`
// (where a build put its baked assets). Returns the failure message (empty on success).
std::string build_scene(const Scene& scene, SceneWorld* out, const std::vector<std::string>& asset_dirs = {});

// One baked garment (`asset_path`, looked up as build_scene does) on a body mesh that blends from
// its pose to `blend_to_path` over `blend_s` seconds and back, at 60 frames a second: a garment on a
// moving body (weft-bench corpus --blend-to).
Scene garment_on_blending_body(const std::string& asset_path, const std::string& body_path,
                               const std::string& blend_to_path, float blend_s);

// Moves the scene's body to its pose at time t (seconds since the start) through
// set_body_vertices; nothing for a still body or a scene without one. Call before step().
std::string animate_body(SceneWorld& world, float t_s);

// The triangles of a built cloth in caller particle order (for OBJ and glTF writers).
std::vector<uint32_t> caller_triangles(const ClothAsset& asset);

// Every cloth's current positions, in caller particle order (OBJ frames, pictures).
std::vector<std::vector<Vec3>> cloth_positions(const SceneWorld& world);

}  // namespace weft::scenes
