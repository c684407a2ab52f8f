// A crowd: many walking mannequins, each its own body, each in the sample skirt and tee dressed by
// weft-bake (skirt-dressed.weft, tee-dressed.weft), with the sample scenes' solver budgets and
// collision models (samples/scenes/skirt-walk.json, tee-walk.json). What `weft-bench crowd` runs
// and the threading tests step: every cloth collides with its own character's body only
// (set_cloth_body) and the characters stand on a grid, so they never meet.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/scene.h"
#include "weft/body.h"
#include "weft/world.h"

namespace weft::scenes {

struct CrowdOptions {
    uint32_t characters = 32;
    float spacing_m = 1.5f;  // between neighbours on the grid
    // The sample scenes (their garment, solver budget and body model); relative asset paths are
    // looked up in asset_dirs.
    std::string skirt_scene, tee_scene;
    std::vector<std::string> asset_dirs;
    StepScheduler scheduler;
    float inertia = 1.0f;  // the cloths' linear and angular inertia (ClothDesc; 1: world space)
    uint32_t standing = 0;        // the first this many characters stand still in the dressed pose
    float sleep_speed_m_s = 0.0f;  // the cloths' ClothDesc::sleep_speed_m_s (0: they never sleep)
    RecoveryPolicy recovery = RecoveryPolicy::none;  // the cloths' ClothDesc::recovery
    SimdPath simd = SimdPath::automatic;
    bool profile = false;
};

struct CrowdCharacter {
    BodyId body;
    ClothId skirt, tee;
    Vec3 offset_m{};       // where it stands
    float phase_s = 0.0f;  // how far into the walk cycle it starts
    float pace = 1.0f;     // its walking speed relative to the mannequin's walk
    bool standing = false;  // stands still in the dressed (rest) pose: never enters the walk
    std::vector<ColliderId> limb_colliders;  // the skirt scene's limb capsules, moved with its bones
    // Where the character's root is (about its grid place): animate_crowd poses the body there and
    // hands it to its cloths (set_cloth_root). Identity: walking in place.
    Transform root;
};

struct Crowd {
    World* world = nullptr;
    WorldBlock memory{nullptr, nullptr};
    SceneWorld skirt, tee;  // the sample scenes as built (their assets and mannequin; worlds unused)
    std::vector<CrowdCharacter> characters;
    std::vector<Vec3> pose;  // scratch for one character's skinned vertices
    std::vector<body::LimbCapsule> posed_capsules;
    float dt_s = 0.0f;
    float inertia = 1.0f;    // CrowdOptions::inertia
    float sleep_speed_m_s = 0.0f;  // CrowdOptions::sleep_speed_m_s
    RecoveryPolicy recovery = RecoveryPolicy::none;  // CrowdOptions::recovery
    uint32_t particles = 0;  // summed over the cloths

    Crowd() = default;
    Crowd(Crowd&&) = delete;
    ~Crowd();
};

// Builds the crowd's world. Returns the failure message (empty on success).
std::string build_crowd(const CrowdOptions& options, Crowd* out);

// A character leaves the world (its cloths, limb capsules and body removed: their ids go stale)
// and comes back where it stands, at rest, dressed (its new ids in characters[k]). Neither
// allocates, and the world's pools are as they were after a despawn and a spawn.
std::string despawn_character(Crowd& crowd, uint32_t k);
std::string spawn_character(Crowd& crowd, uint32_t k);

// Poses every character at time t (entering the walk from the rest pose over the first second, as
// the sample scenes do) and moves its limb capsules.
std::string animate_crowd(Crowd& crowd, float t_s);

// Moves character `k`'s root to `root` at once (a camera cut), posed at time t: its body, capsules
// and cloths teleport (teleport_body, teleport_collider, teleport_cloth).
std::string teleport_character(Crowd& crowd, uint32_t k, const Transform& root, float t_s, bool drop_velocity = false);

}  // namespace weft::scenes
