// The project's own mannequin (the body garments are dressed on when ../shared is not there): a
// smooth, closed, manifold surface meshed by CGAL's implicit surface mesher from an implicit body
// built of smoothly joined parts sized by body measurements, with a skeleton of bone segments and
// linear-blend skinning weights so that tools and samples can animate it (a procedural walk).
// Y up, feet at y = 0, facing +Z, metres (the conventions of ../shared/data/bodies).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "weft/types.h"

namespace weft::body {

// Circumferences are girths around the body at their height (as in ../shared/data/bodies/*.yaml).
struct Measurements {
    float height_m = 1.72f;
    float bust_m = 0.998f;
    float waist_m = 0.843f;
    float hips_m = 1.035f;
};

// Heights of the landmarks as fractions of the height (a standard adult figure).
inline constexpr float kHipHeight = 0.52f, kWaistHeight = 0.62f, kBustHeight = 0.72f;

struct Bone {
    std::string name;
    int parent = -1;  // index into Mannequin::bones, -1 for the root
    Vec3 head{}, tail{};  // rest-pose joint positions, metres
};

inline constexpr int kBoneInfluences = 2;

struct Mannequin {
    std::vector<Vec3> positions;      // rest pose (A-pose), metres
    std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise seen from outside
    std::vector<Bone> bones;
    std::vector<std::array<uint16_t, kBoneInfluences>> bone;  // per vertex: its bones
    std::vector<std::array<float, kBoneInfluences>> weight;   // per vertex: their weights, sum 1
};

struct MannequinOptions {
    float edge_m = 0.025f;  // about the triangles' size (the mesher's radius bound)
};

// Meshes the mannequin. Returns the failure message (empty on success).
std::string make_mannequin(const Measurements& m, const MannequinOptions& options, Mannequin* out);

// The mannequin's procedural motions, each starting from the rest pose (A-pose) it is dressed in:
//   walk:         walking in place: legs and arms swing about their joints, the torso sways (one
//                 stride every 1.1 s);
//   bend_and_sit: the harder case for a skirt (kBendAndSitPeriod_s, then again): it bends forward at
//                 the waist and hips and straightens, then sits down (thighs forward to near
//                 horizontal, the knees bent, the pelvis lowered so the feet stay level), sits, and
//                 stands up. There is no chair: the body holds the seated pose.
enum class Clip : uint8_t { walk, bend_and_sit };
inline constexpr float kBendAndSitPeriod_s = 7.0f;

// The mannequin in `clip` at time t: the skinned positions (linear blend skinning).
void clip_pose(const Mannequin& body, Clip clip, float t_s, std::vector<Vec3>* out);
inline void walk_pose(const Mannequin& body, float t_s, std::vector<Vec3>* out) { clip_pose(body, Clip::walk, t_s, out); }

// A capsule around one section of a limb bone: the collision proxy a game builds from its
// skeleton (as Chaos's and NvCloth's per-bone capsules), moved by the bone alone.
struct LimbCapsule {
    int bone = -1;       // index into Mannequin::bones
    Vec3 p0{}, p1{};     // axis ends, rest pose, metres
    float radius_m = 0;  // 3 in 4 of the section's own vertices lie within it (see fit_limb_capsules)
};

// Capsules around the named bones, `sections` along each (a limb tapers, so more sections fit
// closer). A section's radius is the 75th percentile of its vertices' distances from the bone's
// axis, over the vertices that follow that bone alone (weight >= 0.9): the limb's own surface, not
// the blends into the torso. Empty message on success; an unknown bone name fails.
std::string fit_limb_capsules(const Mannequin& body, const std::vector<std::string>& bones, int sections,
                              std::vector<LimbCapsule>* out);

// The capsules moved with their bones in `clip` at time t (the motion clip_pose skins with).
void clip_capsules(const Mannequin& body, Clip clip, const std::vector<LimbCapsule>& rest, float t_s,
                   std::vector<LimbCapsule>* out);
inline void walk_capsules(const Mannequin& body, const std::vector<LimbCapsule>& rest, float t_s,
                          std::vector<LimbCapsule>* out) {
    clip_capsules(body, Clip::walk, rest, t_s, out);
}

}  // namespace weft::body
