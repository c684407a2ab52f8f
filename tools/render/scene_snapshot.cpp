#include "render/scene_snapshot.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace weft::render {

namespace {

glm::vec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_weft(const glm::vec3& v) { return {v.x, v.y, v.z}; }

constexpr int kRoundSegments = 96;  // around a collider's axis: the sphere's facets stay under 1 mm deep at 0.5 m

}  // namespace

namespace {

// A surface of revolution around the axis through `origin` along unit `axis`: each profile point
// is a ring at `along` metres up the axis with `radius`, its normal `radial` outwards and `axial`
// along the axis. Sphere, capsule and cylinder are all such surfaces.
struct ProfilePoint {
    float along, radius, radial, axial;
};

void add_lathe(const glm::vec3& origin, const glm::vec3& axis, const std::vector<ProfilePoint>& profile,
               SurfaceMesh* mesh) {
    // u, v, axis right-handed, so that (around, up the profile) triangles face outwards.
    const glm::vec3 helper = std::abs(axis.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 u = glm::normalize(glm::cross(axis, helper)), v = glm::cross(axis, u);
    const uint32_t first = uint32_t(mesh->positions.size()), ring = kRoundSegments + 1;
    for (const ProfilePoint& p : profile) {
        for (int j = 0; j <= kRoundSegments; ++j) {
            const float angle = 2.0f * std::numbers::pi_v<float> * float(j) / float(kRoundSegments);
            const glm::vec3 out = std::cos(angle) * u + std::sin(angle) * v;
            mesh->positions.push_back(to_weft(origin + p.along * axis + p.radius * out));
            mesh->normals.push_back(to_weft(p.radial * out + p.axial * axis));
        }
    }
    for (uint32_t i = 0; i + 1 < profile.size(); ++i) {
        for (uint32_t j = 0; j < uint32_t(kRoundSegments); ++j) {
            const uint32_t a = first + i * ring + j, b = a + 1, c = a + ring, d = c + 1;
            for (uint32_t k : {a, b, c, c, b, d}) mesh->indices.push_back(k);
        }
    }
}

// Half a circle of `radius` from angle `from` to `to` (radians from the equator), its centre
// `along` up the axis.
void add_arc(float along, float radius, float from, float to, std::vector<ProfilePoint>* profile) {
    constexpr int kSteps = kRoundSegments / 4;
    for (int k = 0; k <= kSteps; ++k) {
        const float phi = from + (to - from) * float(k) / float(kSteps);
        profile->push_back({along + radius * std::sin(phi), radius * std::cos(phi), std::cos(phi), std::sin(phi)});
    }
}

}  // namespace

bool is_floor(const ColliderDesc& c) {
    return c.shape == ColliderShape::plane && c.p1.y > 0.999f * glm::length(to_glm(c.p1));
}

SurfaceMesh collider_surface(const ColliderDesc& c, const Box& scene) {
    SurfaceMesh mesh;
    constexpr float kHalfPi = 0.5f * std::numbers::pi_v<float>;
    const glm::vec3 p0 = to_glm(c.p0), p1 = to_glm(c.p1);
    std::vector<ProfilePoint> profile;
    switch (c.shape) {
        case ColliderShape::sphere:
            add_arc(0.0f, c.radius_m, -kHalfPi, kHalfPi, &profile);
            add_lathe(p0, {0.0f, 1.0f, 0.0f}, profile, &mesh);
            break;
        case ColliderShape::capsule:
        case ColliderShape::cylinder: {
            const float length = glm::length(p1 - p0);
            const glm::vec3 axis = length > 0.0f ? (p1 - p0) / length : glm::vec3(0.0f, 1.0f, 0.0f);
            if (c.shape == ColliderShape::capsule) {
                add_arc(0.0f, c.radius_m, -kHalfPi, 0.0f, &profile);
                add_arc(length, c.radius_m, 0.0f, kHalfPi, &profile);
            } else {  // the seed's finite cylinder has no caps (eq. 6)
                profile = {{0.0f, c.radius_m, 1.0f, 0.0f}, {length, c.radius_m, 1.0f, 0.0f}};
            }
            add_lathe(p0, axis, profile, &mesh);
            break;
        }
        case ColliderShape::plane: {
            // A square around the point nearest the scene's centre, three scene sizes wide.
            const glm::vec3 n = glm::normalize(p1);
            const glm::vec3 u = glm::normalize(glm::cross(n, std::abs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0)));
            const glm::vec3 v = glm::cross(n, u);
            const glm::vec3 centre = scene.centre() - glm::dot(scene.centre() - p0, n) * n;
            const float half = 1.5f * std::max(scene.diagonal(), 1.0f);
            for (glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(-1, 1), glm::vec2(1, 1)}) {
                mesh.positions.push_back(to_weft(centre + half * (corner.x * u + corner.y * v)));
                mesh.normals.push_back(to_weft(n));
            }
            mesh.indices = {0, 1, 2, 2, 1, 3};
            break;
        }
    }
    return mesh;
}

Box cloth_bounds(const Snapshot& snapshot) {
    Box box;
    for (const ClothSurface& cloth : snapshot.cloths)
        for (const Vec3& p : cloth.positions) box.add(to_glm(p));
    return box;
}

Box bounds(const Snapshot& snapshot) {
    const Box cloths = cloth_bounds(snapshot);
    Box box = cloths;
    for (const BodySurface& body : snapshot.bodies)
        for (const Vec3& p : body.positions) box.add(to_glm(p));
    for (const ColliderDesc& c : snapshot.colliders) {
        const glm::vec3 r(c.radius_m);
        if (c.shape == ColliderShape::plane) {
            // Planes are infinite; the floor's point under the cloths is in (where they will land).
            if (is_floor(c) && !cloths.empty()) box.add({cloths.centre().x, c.p0.y, cloths.centre().z});
            continue;
        }
        box.add(to_glm(c.p0) - r);
        box.add(to_glm(c.p0) + r);
        if (c.shape != ColliderShape::sphere) box.add(to_glm(c.p1) - r), box.add(to_glm(c.p1) + r);
    }
    return box;
}

std::vector<float> planar_uv(const std::vector<Vec3>& rest_positions) {
    Box box;
    for (const Vec3& p : rest_positions) box.add(to_glm(p));
    const glm::vec3 extent = box.empty() ? glm::vec3(0.0f) : box.max - box.min;
    // The two axes the cloth spreads most along; the third is the one it is thinnest in.
    int thin = 0;
    for (int axis = 1; axis < 3; ++axis)
        if (extent[axis] < extent[thin]) thin = axis;
    const int s = thin == 0 ? 1 : 0, t = thin == 2 ? 1 : 2;
    std::vector<float> uv;
    uv.reserve(2 * rest_positions.size());
    for (const Vec3& p : rest_positions) {
        const glm::vec3 q = to_glm(p) - box.min;
        uv.push_back(q[s]);
        uv.push_back(q[t]);
    }
    return uv;
}


Snapshot snapshot_of_scene(const scenes::Scene& scene, const scenes::SceneWorld& world) {
    Snapshot s;
    s.colliders = scene.colliders;
    std::vector<std::vector<Vec3>> positions = scenes::cloth_positions(world);
    for (size_t i = 0; i < world.cloths.size(); ++i) {
        const ClothAsset& asset = *world.cloths[i].asset;
        ClothSurface& cloth = s.cloths.emplace_back();
        cloth.positions = std::move(positions[i]);
        cloth.triangles = scenes::caller_triangles(asset);
        if (asset.uv) {
            cloth.uv.assign(asset.uv, asset.uv + 2 * size_t(asset.particle_count));
        } else {
            std::vector<Vec3> rest(asset.particle_count);
            for (uint32_t p = 0; p < asset.particle_count; ++p) {
                const uint32_t slot = asset.slot_of_particle[p];
                rest[p] = {asset.start_x[slot], asset.start_y[slot], asset.start_z[slot]};
            }
            cloth.uv = planar_uv(rest);
        }
    }
    if (world.body) {  // in its pose now (animate_body), else at rest
        const scenes::SceneBody& b = *world.body;
        s.bodies.push_back({b.pose.empty() ? b.rest : b.pose, b.triangles});
    }
    return s;
}

}  // namespace weft::render
