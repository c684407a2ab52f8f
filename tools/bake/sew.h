// Virtual sewing (seed section 4.2): the flat panels, placed around a body, are sewn into a garment
// and draped on it; weft-bake --body stores the dressed garment as the asset's start state.
//
//   1. sewing: the unsewn garment (every seam point's sources still separate particles) steps in a
//      world with the body as a frictionless collider under a small gravity; before every step each
//      open seam point's sources move geometrically (held kinematic, sliding over the body's hull)
//      toward their target, the mean of the sources as placed (eq. 10), by at most sewing_speed *
//      dt; a seam point whose sources have met is merged into the sewing cloth (every
//      merge_every_frames at most) and follows it from then on; the cloth follows by physics and
//      settles for settle_frames once every seam is closed and merged;
//   1b. attaching: once the seams are closed, the pattern's body attachments slide onto the body's
//      offset hull while the cloth settles (pulled toward the closest hull point every frame, left
//      dynamic), then are bound where they are and pinned;
//   2. merging (as in step 1, then for the asset): each seam point becomes one particle with the
//      summed mass; its sources' texture coordinates are all kept (ClothAsset::sewn_*); triangles
//      keep their flat corners (ClothMeshDesc::rest_corners) so rest lengths still come from the
//      flat panels;
//   3. draping: the sewn garment steps under full gravity until its mean speed stays below
//      rest_speed (or max_drape_frames), and that pose is the start state; particles found inside
//      the skin at rest go out to the closest hull point outside it and are kept outside;
//   4. skin constraints: every free particle of that pose bound to the closest triangle of the whole
//      body's offset hull at rest (cook_skin_binding), stored in the asset (ClothAsset::skin).
// The runtime does the stepping (weft/body.h: Embree offset-hull collisions), so what the baker
// dresses is exactly what a game's world will step.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "bake/pattern.h"
#include "weft/attachments.h"
#include "weft/body.h"
#include "weft/world.h"
#include "weft/cook.h"

namespace weft::bake {

// The body to sew on: plain arrays (lib/body loads files or makes the mannequin).
struct SewBody {
    std::vector<Vec3> positions;      // metres, Y up
    std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise seen from outside
};

// One frame of the sewing world as it steps (seed figure 13): the garment, caller order.
struct SewFrame {
    const char* stage = "";          // "sewing": the unsewn panels, seams closing; "drape": merged, under gravity
    uint32_t frame = 0;              // steps taken in this stage (0: before its first)
    bool last = false;               // the stage's final frame (the drape's is the asset's start state)
    const Vec3* positions = nullptr;
    uint32_t particle_count = 0;
    const uint32_t* triangles = nullptr;  // 3 per triangle, counter-clockwise seen from the front
    uint32_t triangle_count = 0;
    const float* uv = nullptr;            // 2 per particle (metres on the flat panel), or null
    float max_seam_gap_m = 0.0f;          // sewing: the largest source-to-target distance now; 0 after merging
};

struct SewOptions {
    float dt_s = 1.0f / 60.0f;
    float sewing_gravity_m_s2 = 1.0f;   // small gravity while the seams close (seed 4.2)
    float sewing_speed_m_s = 0.3f;      // how fast a source moves toward its target
    uint32_t settle_frames = 60;        // frames with every seam closed before merging
    uint32_t merge_every_frames = 5;    // closed seam points join the sewing cloth at most this often
    uint32_t max_sewing_frames = 900;   // a seam still open after this fails the bake
    float gravity_m_s2 = 9.81f;         // the drape after merging
    float rest_speed_m_s = 0.001f;      // the drape is at rest below this mean speed...
    uint32_t rest_frames = 30;          // ...held for this many frames in a row
    uint32_t max_drape_frames = 900;
    // At rest, particles inside the body (ray parity) go out to the closest hull point outside the
    // skin, this often at most, and are kept outside after every step from then on.
    uint32_t untangle_rounds = 3;
    uint32_t sweeps = 8;                // the solver's budget per step (ClothDesc::sweeps): the game's for this garment
    // The body's friction while the seams close: the panels are dragged around the body then, and
    // friction caught the pencil dress's back on mean_all's shoulders (start strain, draped at 16
    // sweeps: 375% at 0.5, 143% at 0.3, 51% frictionless; docs/garments.md).
    float sewing_friction = 0.0f;
    float sewing_damping_per_s = 4.0f;  // extra calm while sewing (ClothDesc::damping_per_s)
    // The drape looks for the rest pose, so it may be calmer than the game's cloth: at 1/s the
    // pencil dress's hem swung with a 5 s period through all 900 frames for one particle order.
    float drape_damping_per_s = 2.0f;
    // Sew and drape without the body's hands and forearms (arm_tip_triangles): a garment without
    // sleeves does not touch them on a body standing in an A-pose, but a skirt placed flat around it
    // wrapped around the hands as its side seams closed (GarmentCode's simulator filters the arms
    // out of a skirt's collisions likewise). Bindings still name the whole body's triangles.
    bool ignore_arm_tips = false;
    // A floor under the body's soles (its lowest vertex), with the body's friction: a garment longer
    // than the legs (GarmentCode samples maxi skirts) lies on it instead of hanging below the feet.
    bool floor = true;
    float body_thickness_m = 0.004f;    // the body's offset hull (BodyDesc::thickness_m)
    float body_friction = 0.5f;
    // Watching (weft-bake --sewing-frames): called with frame 0, every frame_every-th and the last
    // frame of each stage. It only reads, so the bake is the same with it or without it.
    std::function<void(const SewFrame&)> on_frame;
    // How the sewn garment is cooked for its drape. bake_pattern cooks it as its asset will be (the
    // same run shapes, so the same projection order): the stored pose is then at rest for the
    // asset's own solver, not another order's. Empty: cook_cloth with sewn_cook_options.
    std::function<Result(const ClothMeshDesc&, CookedCloth*)> cook_sewn;
    uint32_t frame_every = 10;
    // 4. skin constraints of the dressed garment (weft/attachments.h: cook_skin_binding), and each
    // panel's factor on their max distance (the pattern's "skin" max_distance_scale; empty, or a
    // panel's absent: the default, 1 for a garment the body holds up, 0 for one hung from attachments).
    SkinBindingOptions skin;
    std::vector<std::optional<float>> skin_max_distance_scale;
    // Layered garments (weft-bake --over): garments already dressed on this body, innermost first,
    // that this one is sewn and draped over (ClothDesc::worn_over, layer_thickness_m): its dressed pose
    // and its skin constraints lie outside them. They must outlive the sewing.
    std::vector<const ClothAsset*> worn_over;
    float layer_thickness_m = ClothDesc{}.layer_thickness_m;
};

struct SewReport {
    double sewing_s = 0.0;           // wall time of the whole sewing and drape, seconds
    uint32_t sewing_frames = 0, drape_frames = 0;
    uint32_t seam_points = 0;        // merged
    uint32_t attached = 0;           // particles bound to the body
    uint32_t skin_constraints = 0;   // free particles with a skin constraint (all of them)
    double skin_binding_s = 0.0;     // wall time of step 4 (cook_skin_binding), seconds
    uint32_t particles_before = 0, particles_after = 0;
    double max_seam_gap_m = 0.0;     // largest source-to-target distance when the sources merge
    double max_penetration_m = 0.0;  // deepest particle below the body's offset hull, dressed pose
    uint32_t particles_inside_body = 0;   // inside the skin (ray parity against the body)
    uint32_t untangled_particles = 0;     // moved out of the body to its hull at rest during the drape (per round)
    double max_skin_penetration_m = 0.0;  // of those within the hull's reach: how deep below the skin
    double mean_speed_m_s = 0.0;     // over the last drape frame
    uint32_t body_triangles = 0;
    // Edge-triangle crossings between the dressed garment and those it is worn over (SewOptions::
    // worn_over), dressed poses against dressed poses: 0 when it lies outside them (bake.cpp).
    uint64_t layer_crossings = 0;
    // Whether the garment stays where it was sewn: the height (m, +Y up) of its highest attachment
    // (or without any, of its highest opening: waist, neckline) when the seams have closed and the
    // attachments are on the body (before the drape) and in the dressed pose, its lowest particle's in the dressed pose, and the
    // body's lowest vertex (the soles: a garment that fell off ends below them, there is no floor).
    double top_at_closed_m = 0.0, top_at_rest_m = 0.0, lowest_at_rest_m = 0.0, body_lowest_m = 0.0;
};

// The sewn garment: owns what `desc` points into.
struct SewnGarment {
    std::vector<Vec3> positions;       // the dressed pose
    std::vector<Vec3> rest_corners;    // 3 per triangle: the flat panels' corners
    std::vector<float> masses, uv, sewn_uv;
    std::vector<int32_t> lattice;
    std::vector<uint16_t> panel;
    std::vector<uint32_t> triangles, sewn_particle, sewn_uv_first;
    std::vector<uint32_t> attached_particle, attached_triangle;
    std::vector<float> attached_weight;
    SkinBinding skin;                  // every free particle bound to the whole body at rest
    std::vector<uint32_t> new_of_old;  // the sewn particle of every unsewn one
    ClothMeshDesc desc;                // cook_cloth's input (fabric as the unsewn input's)
};

// Sews `unsewn` (a garment as cook_cloth takes it, with seam points, uv and flat rest positions)
// onto `body`. The `attached` particles (the pattern's bound body attachments) slide onto the
// body's offset hull once the seams are closed and are bound there: pinned, stored as attachments.
// The `held` ones (every attachment, bound or not) keep their height while the seams close. Fails
// with a message when the body is empty or a seam does not close.
Status sew_garment(const ClothMeshDesc& unsewn, const std::vector<uint32_t>& attached, const std::vector<uint32_t>& held,
                   const SewBody& body,
                   const SewOptions& options, SewnGarment* out, SewReport* report);

// A world holding one cloth and the body (as the sewing steps it), released on scope exit.
struct BodyWorld {
    std::unique_ptr<void, decltype(&std::free)> block{nullptr, &std::free};
    World* world = nullptr;
    ClothId cloth;
    BodyId body;
    std::vector<ClothId> inner;  // SewOptions::worn_over's garments, in their order
    BodyWorld() = default;
    BodyWorld(const BodyWorld&) = delete;
    BodyWorld& operator=(const BodyWorld&) = delete;
    ~BodyWorld();
};
// `asset` (which must outlive the world) on `body` with options' hull, friction and sweeps, gravity
// in m/s^2 downward, the given damping (1/s) and the body's query margin (m).
Status open_body_world(const ClothAsset& asset, const SewBody& body, const SewOptions& options, float gravity_m_s2,
                       float damping_per_s, BodyWorld* out, float margin_m = 0.002f);

// How a sewn garment is cooked: as `options` without the coarse level, whose constraints take
// their rest lengths as straight distances on a per-particle rest pose, which a sewn garment does
// not have (a seam particle has one flat position per panel; the dressed pose is not at rest).
inline CookOptions sewn_cook_options(CookOptions options) {
    options.coarse_spacing_m = 0.0f;
    return options;
}

// The triangles of the body's hands and forearms: those with a vertex within kArmTipReach of the
// body's height, along its surface, from its leftmost or rightmost vertex (the fingertips of a
// body standing in an A- or T-pose facing +Z).
inline constexpr float kArmTipReach = 0.26f;  // of the height: the hand and the forearm (mean_all: 45 cm)
std::vector<bool> arm_tip_triangles(const SewBody& body);

// The triangles of the body's offset hull (every vertex out by thickness_m along its area-weighted
// normal, as add_body makes it) that lie inside the hull itself: a triangle whose outside, 1 mm in
// front of its middle, is inside the hull by ray parity is buried under another part of the body
// (the arm's underside in the armpit, the torso's side under the arm, fingers against fingers).
// The sewing and the drape collide without them: a particle in the crease found a buried triangle
// closest, in front of it, and stayed inside the skin.
std::vector<bool> buried_hull_triangles(const SewBody& body, float thickness_m);

// Whether `point` lies inside the body's skin (ray parity against every triangle: a reference for
// reports and tests, not for stepping).
bool inside_body(const SewBody& body, Vec3 point);

// The same answer as inside_body, bit for bit, from the few triangles whose shadow along the ray
// covers the point's: the triangles binned in a grid on the plane across the ray. The sewing asks
// it for every particle after each drape (inside_body took 63% of a dress's bake).
class BodyInsideTest {
public:
    explicit BodyInsideTest(const SewBody& body);
    bool contains(Vec3 point) const;

private:
    const SewBody& body_;
    float origin_[2] = {0, 0}, cell_ = 1;  // the grid on the plane across the ray, metres
    uint32_t cells_ = 1;                   // per side
    std::vector<uint32_t> first_, triangle_;  // CSR: the triangles each cell's shadow meets
};

}  // namespace weft::bake
