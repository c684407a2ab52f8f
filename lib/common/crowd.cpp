#include "common/crowd.h"

#include <cmath>

#include "body/mannequin.h"
#include "common/scene_json.h"

namespace weft::scenes {

namespace {

std::string load_sample(const std::string& path, const CrowdOptions& options, SceneWorld* out) {
    Scene scene;
    if (std::string e = load_scene_file(path, &scene); !e.empty()) return path + ": " + e;
    if (scene.cloths.size() != 1 || !scene.body || !scene.body->mannequin)
        return path + ": a crowd's scene dresses the mannequin in one garment";
    scene.profile = false;
    if (std::string e = build_scene(scene, out, options.asset_dirs); !e.empty()) return path + ": " + e;
    return {};
}

const body::Mannequin& mannequin(const Crowd& crowd) {
    return *static_cast<const body::Mannequin*>(crowd.skirt.body->mannequin.get());
}

Vec3 plus(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }

// One garment of a character: the sample scene's cloth, moved to where the character stands, on
// its body under the scene's body model.
std::string add_garment(Crowd& c, const SceneWorld& sample, const CrowdCharacter& who, float inertia, ClothId* out) {
    const SceneCloth& garment = sample.cloths[0];
    ClothDesc desc = garment.desc;
    desc.translation_m = who.offset_m;
    desc.linear_inertia = desc.angular_inertia = inertia;
    desc.sleep_speed_m_s = c.sleep_speed_m_s;
    desc.recovery = c.recovery;
    if (Result r = add_cloth(c.world, desc, out); !r.ok()) return r.message;
    if (Result r = set_cloth_body(c.world, *out, who.body); !r.ok()) return r.message;
    if (garment.asset->attachment_count > 0)
        if (Result r = attach_cloth_to_body(c.world, *out, who.body); !r.ok()) return r.message;
    if (sample.body->spec.collision == BodyCollision::skin_constraints) {
        if (garment.asset->skin.count == 0) return "the crowd's garments carry their skin constraints (weft-bake --body)";
        if (Result r = bind_asset_skin_constraints(c.world, *out, who.body); !r.ok()) return r.message;
    }
    return {};
}

}  // namespace

Crowd::~Crowd() { destroy_world(world); }

std::string spawn_character(Crowd& c, uint32_t k) {
    if (k >= c.characters.size()) return "no character " + std::to_string(k);
    CrowdCharacter& who = c.characters[k];
    const SceneBody& body = *c.skirt.body;
    const BodySpec& spec = body.spec;
    // At rest where it stands (c.pose is the scratch: spawning allocates nothing).
    for (size_t v = 0; v < body.rest.size(); ++v) c.pose[v] = plus(body.rest[v], who.offset_m);
    BodyDesc bd;
    bd.positions = c.pose.data();
    bd.vertex_count = uint32_t(body.rest.size());
    bd.triangles = body.triangles.data();
    bd.triangle_count = uint32_t(body.triangles.size() / 3);
    bd.thickness_m = spec.thickness_m;
    bd.margin_m = spec.margin_m;
    bd.friction = spec.friction;
    bd.collision = spec.collision;
    if (Result r = add_body(c.world, bd, &who.body); !r.ok()) return std::string("body: ") + r.message;
    who.limb_colliders.resize(body.limb_capsules.size());
    for (size_t i = 0; i < body.limb_capsules.size(); ++i) {
        body::LimbCapsule capsule = body.limb_capsules[i];
        capsule.p0 = plus(capsule.p0, who.offset_m), capsule.p1 = plus(capsule.p1, who.offset_m);
        if (Result r = add_collider(c.world, limb_collider(spec, capsule), &who.limb_colliders[i]); !r.ok())
            return std::string("limb capsule: ") + r.message;
    }
    who.root = {};
    if (std::string e = add_garment(c, c.skirt, who, c.inertia, &who.skirt); !e.empty()) return "skirt: " + e;
    if (std::string e = add_garment(c, c.tee, who, c.inertia, &who.tee); !e.empty()) return "tee: " + e;
    return {};
}

std::string despawn_character(Crowd& c, uint32_t k) {
    if (k >= c.characters.size()) return "no character " + std::to_string(k);
    CrowdCharacter& who = c.characters[k];
    for (ClothId cloth : {who.skirt, who.tee})  // the cloths first: they use the body
        if (Result r = remove_cloth(c.world, cloth); !r.ok()) return r.message;
    for (ColliderId collider : who.limb_colliders)
        if (Result r = remove_collider(c.world, collider); !r.ok()) return r.message;
    if (Result r = remove_body(c.world, who.body); !r.ok()) return r.message;
    return {};
}

std::string build_crowd(const CrowdOptions& options, Crowd* out) {
    Crowd& c = *out;
    if (options.characters == 0) return "a crowd of no one";
    if (std::string e = load_sample(options.skirt_scene, options, &c.skirt); !e.empty()) return e;
    if (std::string e = load_sample(options.tee_scene, options, &c.tee); !e.empty()) return e;
    const SceneBody& body = *c.skirt.body;
    const BodySpec& spec = body.spec;  // the skirt scene's body (the tee's is the same mannequin)
    if (c.tee.body->rest.size() != body.rest.size()) return "the two scenes dress different bodies";
    c.dt_s = c.skirt.dt_s;

    WorldDesc wd;
    wd.max_cloths = 0;
    for (uint32_t k = 0; k < options.characters; ++k) {
        for (const SceneWorld* sample : {&c.skirt, &c.tee}) {
            const ClothAsset& asset = *sample->cloths[0].asset;
            reserve_cloth(wd, asset, options.recovery);
            if (sample->body->spec.collision == BodyCollision::skin_constraints) wd.max_skin_constraints += asset.skin.count;
            if (sample->body->spec.collision == BodyCollision::cached_planes) wd.max_cached_plane_bodies = options.characters;
        }
    }
    if (spec.collision != c.tee.body->spec.collision) return "the two scenes name different body models";
    if (spec.collision != BodyCollision::skin_constraints) wd.max_skin_constraints = 0;
    wd.max_bodies = options.characters;
    wd.max_body_vertices = options.characters * uint32_t(body.rest.size());
    wd.max_body_triangles = options.characters * uint32_t(body.triangles.size() / 3);
    wd.max_colliders = options.characters * uint32_t(body.limb_capsules.size());
    wd.gravity_m_s2 = {0.0f, -9.81f, 0.0f};
    wd.simd = options.simd;
    wd.scheduler = options.scheduler;
    if (std::string e = create_world_in_block(wd, &c.memory, &c.world); !e.empty()) return e;
    if (options.profile) set_profiling(c.world, true);

    // A square grid; each character its own phase in the stride and its own pace (0.8 to 1.2),
    // from a fixed sequence so every run builds the same crowd.
    const uint32_t side = uint32_t(std::ceil(std::sqrt(double(options.characters))));
    c.pose.resize(body.rest.size());
    c.inertia = options.inertia;
    c.sleep_speed_m_s = options.sleep_speed_m_s;
    c.recovery = options.recovery;
    c.characters.resize(options.characters);
    for (uint32_t k = 0; k < options.characters; ++k) {
        CrowdCharacter& who = c.characters[k];
        who.offset_m = {options.spacing_m * float(k % side), 0.0f, options.spacing_m * float(k / side)};
        who.phase_s = 1.1f * float((k * 7) % 16) / 16.0f;  // the walk's stride is 1.1 s
        who.pace = 0.8f + 0.4f * float((k * 5) % 9) / 8.0f;
        who.standing = k < options.standing;
        if (std::string e = spawn_character(c, k); !e.empty()) return e;
        c.particles += c.skirt.cloths[0].asset->particle_count + c.tee.cloths[0].asset->particle_count;
    }
    return {};
}

namespace {

// The character's root in the world: its own root, then its place on the grid.
Transform world_root(const CrowdCharacter& who) {
    return {plus(who.root.translation_m, who.offset_m), who.root.rotation};
}

Vec3 apply(const Transform& t, Vec3 v) {
    const Quat& q = t.rotation;  // v + 2 w (u x v) + 2 u x (u x v), u the vector part
    const Vec3 u{q.x, q.y, q.z};
    const auto cross = [](Vec3 a, Vec3 b) { return Vec3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
    const Vec3 c = cross(u, v), d = cross(u, c);
    return {v.x + 2 * (q.w * c.x + d.x) + t.translation_m.x, v.y + 2 * (q.w * c.y + d.y) + t.translation_m.y,
            v.z + 2 * (q.w * c.z + d.z) + t.translation_m.z};
}

// Poses character `who` at time t into c.pose and c.posed_capsules (world space).
void pose_character(Crowd& c, const CrowdCharacter& who, float t_s) {
    const SceneBody& body = *c.skirt.body;
    const body::Mannequin& m = mannequin(c);
    // Every character enters the walk together; a standing one stays in the rest pose (entry 0).
    const float entry = who.standing ? 0.0f : walk_entry(body.spec, t_s);
    const float walk_t = who.phase_s + who.pace * t_s;
    const Transform root = world_root(who);
    const auto enter = [entry, &root](Vec3 rest, Vec3 walk) {  // from the rest pose, as the scenes do
        return apply(root, {rest.x + (walk.x - rest.x) * entry, rest.y + (walk.y - rest.y) * entry,
                            rest.z + (walk.z - rest.z) * entry});
    };
    body::walk_pose(m, walk_t, &c.pose);
    for (size_t v = 0; v < c.pose.size(); ++v) c.pose[v] = enter(body.rest[v], c.pose[v]);
    c.posed_capsules.clear();
    if (body.limb_capsules.empty()) return;
    body::walk_capsules(m, body.limb_capsules, walk_t, &c.posed_capsules);
    for (size_t i = 0; i < c.posed_capsules.size(); ++i) {
        c.posed_capsules[i].p0 = enter(body.limb_capsules[i].p0, c.posed_capsules[i].p0);
        c.posed_capsules[i].p1 = enter(body.limb_capsules[i].p1, c.posed_capsules[i].p1);
    }
}

}  // namespace

std::string animate_crowd(Crowd& c, float t_s) {
    const BodySpec& spec = c.skirt.body->spec;
    for (CrowdCharacter& who : c.characters) {
        pose_character(c, who, t_s);
        if (Result r = set_body_vertices(c.world, who.body, c.pose.data(), uint32_t(c.pose.size())); !r.ok())
            return r.message;
        for (size_t i = 0; i < c.posed_capsules.size(); ++i)
            if (Result r = set_collider(c.world, who.limb_colliders[i], limb_collider(spec, c.posed_capsules[i])); !r.ok())
                return r.message;
        for (ClothId cloth : {who.skirt, who.tee})
            if (Result r = set_cloth_root(c.world, cloth, world_root(who)); !r.ok()) return r.message;
    }
    return {};
}

std::string teleport_character(Crowd& c, uint32_t k, const Transform& root, float t_s, bool drop_velocity) {
    if (k >= c.characters.size()) return "no such character";
    CrowdCharacter& who = c.characters[k];
    who.root = root;
    pose_character(c, who, t_s);
    if (Result r = teleport_body(c.world, who.body, c.pose.data(), uint32_t(c.pose.size())); !r.ok()) return r.message;
    for (size_t i = 0; i < c.posed_capsules.size(); ++i)
        if (Result r = teleport_collider(c.world, who.limb_colliders[i], limb_collider(c.skirt.body->spec, c.posed_capsules[i]));
            !r.ok())
            return r.message;
    for (ClothId cloth : {who.skirt, who.tee})
        if (Result r = teleport_cloth(c.world, cloth, world_root(who), drop_velocity); !r.ok()) return r.message;
    return {};
}

}  // namespace weft::scenes
