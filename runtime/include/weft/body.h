// Body colliders: a triangle mesh (a mannequin, a game character's skin) the cloth rests on, moved
// every frame by the game (seed section 4.2: the garment half of the paper).
//
//   WorldDesc desc; desc.max_bodies = 1; desc.max_body_vertices = V; desc.max_body_triangles = T;
//   ... create_world(desc, block, bytes, &world);          // creates the Embree device
//   BodyDesc body; body.positions = ...; body.triangles = ...; add_body(world, body, &id);
//   every frame: set_body_vertices(world, id, skinned, V); step(world, dt);
//   at the end: destroy_world(world) (releases Embree's device), then free the block.
//
// The collision surface is the seed's offset hull (every vertex pushed out `thickness_m` along its
// normal); how each collision model searches and answers it, and what it costs in memory and time:
// docs/garments.md, "Body colliders" and "Collision models".
#pragma once

#include "weft/types.h"
#include "weft/world.h"  // ClothId

namespace weft {

struct World;

// How the step finds and answers contacts with a body (docs/garments.md, "Collision models").
enum class BodyCollision : uint8_t {
    exact,             // every substep, every particle: the closest hull point, tunnelling ray, creases
    cached_planes,     // exact at the first substep, then its contact plane (needs max_cached_plane_bodies)
    skin_constraints,  // a cloth bound by skin constraints: their ball and backstop only, no search
};

struct BodyDesc {
    const Vec3* positions = nullptr;      // [vertex_count] rest pose, metres; copied by add_body
    uint32_t vertex_count = 0;
    const uint32_t* triangles = nullptr;  // [3 * triangle_count], counter-clockwise seen from outside
    uint32_t triangle_count = 0;

    float thickness_m = 0.005f;  // offset of the hull from the skin: the cloth's thickness
    float margin_m = 0.002f;     // query reach beyond the thickness (deeper particles go by the ray)
    float friction = 0.5f;       // Coulomb coefficient against the moving surface; 0 = frictionless
    BodyCollision collision = BodyCollision::exact;  // scene files choose per garment (docs/scene-format.md)
};

struct BodyId {  // as ClothId (weft/world.h): a place and its generation
    uint32_t index = 0;
    uint32_t generation = 0;
};

// Adds a body (validated: finite positions, indices in range, capacities) and builds its hierarchy.
Result add_body(World* world, const BodyDesc& desc, BodyId* out_body);

// Removes a body between steps (its memory goes back to the world's pools, its id goes stale).
// Refused while a cloth still uses it: its own body (set_cloth_body), its skin constraints or its
// attachments. Remove those cloths first.
Result remove_body(World* world, BodyId body);

// The body's new vertex positions (the game's skinned pose), `count` = its vertex count. The next
// step refits the BVH and uses (new - previous) hull positions as the surface velocity for
// friction. Refuses non-finite or absurd positions without changing anything.
Result set_body_vertices(World* world, BodyId body, const Vec3* positions, uint32_t count);
// The same, for a jump (a camera cut, a respawn): the body is at the new pose with no motion, so
// friction and the search see a still surface there.
Result teleport_body(World* world, BodyId body, const Vec3* positions, uint32_t count);

// A cloth collides with every body of the world unless it is given its own: then with that one
// only (its character's), so a crowd's cloths do not look at each other's bodies.
// kEveryBody gives it every body again.
inline constexpr BodyId kEveryBody{~0u};
Result set_cloth_body(World* world, ClothId cloth, BodyId body);

// The closest offset-hull point to `point` within thickness + margin (+ how far the nearby body
// vertices moved at the last step): what the step's query sees.
struct BodyContact {
    bool found = false;       // a hull triangle lies within reach
    float penetration_m = 0;  // > 0: the point is inside the hull by this much
    Vec3 hull_point{};        // closest point on the offset hull
    Vec3 normal{};            // contact normal: the interpolated hull normal there (unit, outward)
    uint32_t triangle = 0;
};
// `reach_m` > 0 looks that far instead (a metric's depth of particles deeper than the step reaches).
Result query_body(const World* world, BodyId body, Vec3 point, BodyContact* out, float reach_m = 0.0f);

}  // namespace weft
