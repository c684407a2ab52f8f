// Body colliders (seed section 4.2): cloth against the offset hull of a triangle mesh through
// Embree. Procedural bodies (an icosphere, a thin slab) for the core cases; the shared mean_all body,
// blended between its A-pose and T-pose, for the animated ones (skipped with a message when
// ../shared/data is missing).
#include "support/test_support.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <random>

#include "body/body_mesh.h"

using namespace weft;
using namespace weft::test;
using body::BodyMesh;

namespace {

constexpr float kDt = scenes::kSeedTimeStep_s;

// Signed distance from p to the hull by brute force over every triangle (double precision): the
// same rule as the runtime (closest point, inside when behind the interpolated normal), written
// independently. Returns the penetration (> 0 inside) of the closest triangle within `reach`, and
// whether one was found.
struct BruteContact {
    bool found = false;
    double penetration = 0.0, distance = 0.0;
    uint32_t triangle = 0;
    double closest_of_kind[2] = {1e300, 1e300};  // the closest distance among triangles out of / in a crease
};

struct D3 {
    double x, y, z;
};
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(double s, D3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Closest point by projection onto the plane, then the edges when it falls outside (not Ericson's
// region walk, which the runtime uses).
void closest_point(D3 p, D3 a, D3 b, D3 c, double w[3]) {
    w[0] = 1, w[1] = w[2] = 0;
    const D3 ab = b - a, ac = c - a, ap = p - a;
    const double d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac);
    const double det = d00 * d11 - d01 * d01;
    if (det > 1e-30) {
        const double b1 = (d11 * dot(ap, ab) - d01 * dot(ap, ac)) / det;
        const double b2 = (d00 * dot(ap, ac) - d01 * dot(ap, ab)) / det;
        if (b1 >= 0 && b2 >= 0 && b1 + b2 <= 1) {
            w[0] = 1 - b1 - b2, w[1] = b1, w[2] = b2;
            return;
        }
    }
    double best = 1e300;
    const D3 v[3] = {a, b, c};
    for (int e = 0; e < 3; ++e) {
        const D3 s = v[e], d = v[(e + 1) % 3] - v[e];
        const double len2 = dot(d, d);
        const double t = len2 > 0 ? std::clamp(dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
        const D3 q = s + t * d, r = p - q;
        if (dot(r, r) < best) {
            best = dot(r, r);
            w[0] = w[1] = w[2] = 0;
            w[e] = 1 - t;
            w[(e + 1) % 3] = t;
        }
    }
}

// Hull triangle f's corners and vertex normals, in double.
struct HullTriangle {
    D3 corner[3], normal[3];
    D3 normal_at(const double w[3]) const {  // the unit normal interpolated at weights w
        const D3 n = w[0] * normal[0] + w[1] * normal[1] + w[2] * normal[2];
        return (1.0 / std::sqrt(dot(n, n))) * n;
    }
};
HullTriangle hull_triangle(const BodyView& v, uint32_t f) {
    const uint32_t* t = v.triangles + 3 * f;
    HullTriangle h;
    for (int k = 0; k < 3; ++k) {
        h.corner[k] = {v.hull[4 * t[k]], v.hull[4 * t[k] + 1], v.hull[4 * t[k] + 2]};
        h.normal[k] = {v.normals[3 * t[k]], v.normals[3 * t[k] + 1], v.normals[3 * t[k] + 2]};
    }
    return h;
}

// How much further than thickness + margin the step searches each triangle (its leaf's fold).
std::vector<double> triangle_fold(const BodyView& v) {
    std::vector<double> fold(v.triangle_count, 0.0);
    for (uint32_t l = 0; l < v.leaf_count; ++l)
        for (uint32_t k = 0; k < 8; ++k) fold[v.leaf_triangle[8 * l + k]] = v.leaf_fold_m[l];
    return fold;
}

// The closest hull point within `reach` (default: the step's, thickness + margin, and further by
// the fold where the hull folds).
BruteContact brute_force(const BodyView& v, Vec3 point, double reach = -1.0) {
    const D3 p{point.x, point.y, point.z};
    const bool steps_reach = reach < 0.0;
    if (steps_reach) reach = double(v.thickness_m) + v.margin_m;
    const std::vector<double> fold = steps_reach ? triangle_fold(v) : std::vector<double>(v.triangle_count, 0.0);
    BruteContact out;
    double best = std::numeric_limits<double>::infinity();
    for (uint32_t f = 0; f < v.triangle_count; ++f) {
        const HullTriangle h = hull_triangle(v, f);
        const D3* corner = h.corner;
        double w[3];
        closest_point(p, corner[0], corner[1], corner[2], w);
        const D3 q = w[0] * corner[0] + w[1] * corner[1] + w[2] * corner[2];
        const double d2 = dot(p - q, p - q);
        if (v.in_crease != nullptr) {
            double& kind = out.closest_of_kind[v.in_crease[f] != 0];
            kind = std::min(kind, std::sqrt(d2));
        }
        if (!(d2 < best) || !(d2 < (reach + fold[f]) * (reach + fold[f]))) continue;
        best = d2;
        const D3 n = h.normal_at(w);
        out.found = true;
        out.distance = std::sqrt(d2);
        out.penetration = dot(q - p, n);
        out.triangle = f;
    }
    return out;
}

// The step's verdict in double precision: how deep it pushes `point` (<= 0: not at all). Inside by
// the closest triangle (brute_force); or, in front of a triangle in a crease (BodyView::in_crease),
// behind the face of the closest triangle within reach whose closest point lies inside it (not on
// an edge), if that triangle's interpolated normal also has it behind. `ambiguous` when a decision
// is within rounding of going the other way; `second_look` when only the crease rule pushes it.
double brute_force_depth(const BodyView& v, Vec3 point, bool* ambiguous, bool* second_look) {
    const BruteContact c = brute_force(v, point);
    *ambiguous = c.found && std::abs(c.penetration) < 1e-5;
    *second_look = false;
    const D3 p{point.x, point.y, point.z};
    const double reach = double(v.thickness_m) + v.margin_m;
    // A near tie for the closest triangle between one in a crease and one not: float may pick either.
    if (c.found && std::abs(c.closest_of_kind[0] - c.closest_of_kind[1]) < 1e-6) *ambiguous = true;
    if (!c.found || c.penetration > 0.0 || v.in_crease[c.triangle] == 0) return c.found ? c.penetration : -1.0;
    double best = reach * reach, depth = -1.0;
    for (uint32_t f = 0; f < v.triangle_count; ++f) {
        const HullTriangle h = hull_triangle(v, f);
        const D3* corner = h.corner;
        // The point's projection onto the triangle's plane, as weights (inside the face: all > 0).
        const D3 ab = corner[1] - corner[0], ac = corner[2] - corner[0], ap = p - corner[0];
        const double d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac), det = d00 * d11 - d01 * d01;
        if (!(det > 1e-30)) continue;
        const double b1 = (d11 * dot(ap, ab) - d01 * dot(ap, ac)) / det, b2 = (d00 * dot(ap, ac) - d01 * dot(ap, ab)) / det;
        const double w[3] = {1.0 - b1 - b2, b1, b2};
        const D3 q = w[0] * corner[0] + w[1] * corner[1] + w[2] * corner[2];
        const D3 face{ab.y * ac.z - ab.z * ac.y, ab.z * ac.x - ab.x * ac.z, ab.x * ac.y - ab.y * ac.x};
        const double d2 = dot(p - q, p - q), behind = dot(q - p, face) / std::sqrt(dot(face, face));
        const double edge = std::min({w[0], w[1], w[2]});
        if (d2 < best * 1.0001 && behind > -1e-6 && std::abs(edge) < 1e-5) *ambiguous = true;
        if (!(d2 < best) || !(edge > 0.0) || !(behind > 0.0)) continue;
        best = d2;
        const D3 n = h.normal_at(w);
        depth = dot(q - p, n);
    }
    if (std::abs(depth) < 1e-5) *ambiguous = true;
    *second_look = depth > 0.0;
    return depth > 0.0 ? depth : c.penetration;
}

// A world with room for one cloth and one body.
struct BodyWorld {
    OwnedWorld owned;
    ClothId cloth;
    BodyId body;
    uint32_t particle_count = 0;

    // `substeps` > 0: that many substeps a step, one sweep each (explicit split), else the policy's.
    BodyWorld(const ClothAsset& asset, const BodyMesh& mesh, const BodyDesc& settings,
              SimdPath path = SimdPath::automatic, uint32_t substeps = 0, uint32_t max_skin_constraints = ~0u) {
        WorldDesc d = world_for({&asset}, 0, path);
        d.max_bodies = 1;
        d.max_cached_plane_bodies = settings.collision == BodyCollision::cached_planes ? 1 : 0;
        d.max_body_vertices = mesh.vertex_count();
        d.max_body_triangles = mesh.triangle_count();
        // scenes::bind_skin binds at most every particle
        d.max_skin_constraints = max_skin_constraints == ~0u ? asset.particle_count : max_skin_constraints;
        REQUIRE(make_world(d, &owned).ok());
        ClothDesc cd;
        cd.asset = &asset;
        if (substeps > 0) {
            cd.policy = BudgetPolicy::explicit_split;
            cd.substeps = substeps;
            cd.iterations = 1;
        }
        REQUIRE(add_cloth(owned.world, cd, &cloth).ok());
        BodyDesc b = settings;
        b.positions = mesh.positions.data();
        b.vertex_count = mesh.vertex_count();
        b.triangles = mesh.triangles.data();
        b.triangle_count = mesh.triangle_count();
        const Result r = add_body(owned.world, b, &body);
        INFO(r.message);
        REQUIRE(r.ok());
        particle_count = asset.particle_count;
    }
    std::vector<Vec3> positions() const { return read_all(owned.world, cloth, particle_count); }
    // Puts particle k at points[k], free (inverse mass 100 / kg).
    void place(const std::vector<Vec3>& points) const {
        for (uint32_t k = 0; k < uint32_t(points.size()); ++k)
            REQUIRE(set_particle(owned.world, cloth, k, points[k], 100.0f).ok());
    }
    void step_once() const {
        const Result r = step(owned.world, kDt);
        INFO(r.message);
        REQUIRE(r.ok());
    }
    BodyView view() const {
        BodyView v;
        REQUIRE(view_body(owned.world, body, &v).ok());
        return v;
    }
    // Deepest brute-force penetration of any particle into the hull (looking 0.25 m deep: a particle
    // the step lost sight of must not be out of the test's).
    double max_penetration() const {
        const BodyView v = view();
        double worst = 0.0;
        for (const Vec3& p : positions()) {
            const BruteContact c = brute_force(v, p, 0.25);
            if (c.found) worst = std::max(worst, c.penetration);
        }
        return worst;
    }
};

bool have_shared_body() {
    return std::ifstream(body::shared_body_path("mean_all.obj")).good() &&
           std::ifstream(body::shared_body_path("mean_all_tpose.obj")).good();
}

// True (with a message) when ../shared/data is missing: the test is skipped.
bool skip_without_shared_body() {
    if (have_shared_body()) return false;
    MESSAGE("skipped: ", body::shared_body_path("mean_all.obj"), " not found");
    return true;
}

// mean_all in A-pose and T-pose, loaded once.
const BodyMesh* shared_pose(bool tpose) {
    static BodyMesh a, t;
    static bool loaded = false;
    if (!loaded) {
        REQUIRE(body::load_body_mesh(body::shared_body_path("mean_all.obj"), &a).empty());
        REQUIRE(body::load_body_mesh(body::shared_body_path("mean_all_tpose.obj"), &t).empty());
        REQUIRE(a.triangles == t.triangles);
        loaded = true;
    }
    return tpose ? &t : &a;
}

// Six times the enclosed volume: positive when every triangle winds counter-clockwise from outside.
double signed_volume6(const BodyMesh& m) {
    double v = 0.0;
    for (size_t f = 0; f < m.triangles.size(); f += 3) {
        const Vec3 a = m.positions[m.triangles[f]], b = m.positions[m.triangles[f + 1]], c = m.positions[m.triangles[f + 2]];
        v += double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) - double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
             double(a.z) * (double(b.x) * c.y - double(b.y) * c.x);
    }
    return v;
}

}  // namespace

TEST_CASE("body: the procedural bodies wind outward") {
    const double pi = 3.14159265358979;
    CHECK(signed_volume6(body::make_icosphere({0, 0, 0}, 0.3f, 3)) / 6.0 ==
          doctest::Approx(4.0 / 3.0 * pi * 0.027).epsilon(0.02));
    CHECK(signed_volume6(body::make_box({0, 0, 0}, {1, 2, 3})) / 6.0 == doctest::Approx(6.0));
}

TEST_CASE("body: a cloth dropped on an icosphere stays outside its offset hull and comes to rest") {
    const BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 3);
    const scenes::GridMesh grid = scenes::make_grid(20, 0.6f, 0.6f, false, 0.45f);
    const CookedCloth cooked = cook(grid.desc());
    BodyDesc settings;
    settings.thickness_m = 0.005f;
    settings.friction = 0.5f;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        BodyWorld w(cooked.asset(), sphere, settings, path);
        double worst = 0.0;
        for (int i = 0; i < 150; ++i) {
            w.step_once();
            if (i % 10 == 9) worst = std::max(worst, w.max_penetration());
        }
        const std::vector<Vec3> before = w.positions();
        w.step_once();
        const std::vector<Vec3> after = w.positions();
        double speed = 0.0;
        for (size_t i = 0; i < after.size(); ++i) {
            const double dx = after[i].x - before[i].x, dy = after[i].y - before[i].y, dz = after[i].z - before[i].z;
            speed += std::sqrt(dx * dx + dy * dy + dz * dz) / kDt;
        }
        speed /= double(after.size());
        MESSAGE(std::string(simd_path_name(path)), ": max penetration ", worst * 1e3, " mm, mean speed after 5 s ", speed * 1e3,
                " mm/s, contacts last step ", world_stats(w.owned.world).body_contacts);
        CHECK(worst <= 1e-3);
        CHECK(speed < 0.01);
        CHECK(world_stats(w.owned.world).body_contacts > 0);
        // It rests on the sphere, not below it.
        double top = -1.0;
        for (const Vec3& p : after) top = std::max(top, double(p.y));
        CHECK(top > 0.29);
    }
}

TEST_CASE("body: a taut sheet dragged over a swaying ball stays out of it (particles that slid under the hull)") {
    // The seed's drape (2 m, pinned at two corners) falls over a ball that sways under it: pulled
    // taut by its pins, the sheet slides around the ball, a particle resting on the hull moves
    // further than the thickness along it in a substep, and its ray, starting inside the hull, meets
    // no entry. Without the far search such particles cut under the surface, out of reach, and the
    // ball went through the sheet (weft's hello sample, 0.1 m of sway).
    const BodyMesh ball = body::make_icosphere({0.0f, 1.0f, 0.0f}, 0.5f, 3);
    scenes::GridMesh grid = scenes::make_grid(50, 2.0f, 2.0f, false, 2.0f);
    grid.masses[grid.index(0, 0)] = grid.masses[grid.index(0, 49)] = 0.0f;
    const CookedCloth cooked = cook(grid.desc());
    BodyDesc settings;
    settings.thickness_m = 0.005f;
    settings.friction = 0.5f;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        BodyWorld w(cooked.asset(), ball, settings, path);
        std::vector<Vec3> moved(ball.positions.size());
        double worst = 0.0;
        for (int i = 1; i <= 90; ++i) {
            const float x = 0.1f * std::sin(3.0f * float(i) / 60.0f);
            for (size_t v = 0; v < moved.size(); ++v) moved[v] = {ball.positions[v].x + x, ball.positions[v].y, ball.positions[v].z};
            REQUIRE(set_body_vertices(w.owned.world, w.body, moved.data(), uint32_t(moved.size())).ok());
            REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
            if (i % 5 == 0) worst = std::max(worst, w.max_penetration());
        }
        MESSAGE(std::string(simd_path_name(path)), ": deepest particle ", worst * 1e3, " mm into the hull");
        CHECK(worst <= 2e-3);
    }
}

TEST_CASE("body: a fast particle crossing a thin slab is caught by the tunnelling ray") {
    // A 2 cm slab (a thin limb); the particle falls 0.55 m in its first step, right through it.
    const BodyMesh slab = body::make_box({-0.5f, -0.01f, -0.5f}, {0.5f, 0.01f, 0.5f});
    Points pts({{0.0f, 0.3f, 0.0f}, {0.2f, 0.05f, 0.1f}});
    BodyDesc settings;
    settings.thickness_m = 0.005f;
    settings.friction = 0.0f;
    BodyWorld w(pts.cooked.asset(), slab, settings);
    REQUIRE(set_gravity(w.owned.world, {0.0f, -1000.0f, 0.0f}).ok());
    w.step_once();
    const WorldStats stats = world_stats(w.owned.world);
    CHECK(stats.body_rays >= 2);
    CHECK(stats.body_contacts >= 2);
    for (const Vec3& p : w.positions()) {
        CAPTURE(p.y);
        CHECK(p.y >= 0.015f - 1e-4f);  // on top of the hull (slab top + thickness)
        CHECK(p.y <= 0.015f + 1e-4f);
    }
}

TEST_CASE("body: a fast particle that grazes into one part's hull and then enters another goes back out of the one it is deepest behind") {
    // Under the crotch: a wall (a thigh's side) through a ceiling (the crotch), two parts whose
    // hulls overlap. The particle, just outside the wall's hull (a box's corner normals put its sides
    // thickness / sqrt(3) out), is pulled up 13 cm in a step and 1.6 mm toward the wall: in the last
    // substep its ray grazes into the wall's hull and then enters
    // the ceiling's, 3.5 cm behind that one's plane. Pushed out of the first entry's plane (the
    // wall's) it stayed inside the ceiling, beyond the point search's reach. It belongs under it.
    BodyMesh body = body::make_box({-0.5f, 0.1f, -0.5f}, {0.5f, 0.12f, 0.5f});  // the ceiling
    const BodyMesh wall = body::make_box({-0.5f, -0.5f, -0.5f}, {0.0f, 0.3f, 0.5f});
    const uint32_t first = uint32_t(body.positions.size());
    body.positions.insert(body.positions.end(), wall.positions.begin(), wall.positions.end());
    for (uint32_t v : wall.triangles) body.triangles.push_back(first + v);
    Points pts({{0.0039f, 0.0f, 0.0f}});
    BodyDesc settings;
    settings.thickness_m = 0.005f;
    settings.friction = 0.0f;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        BodyWorld w(pts.cooked.asset(), body, settings, path);
        REQUIRE(set_gravity(w.owned.world, {-2.7f, 234.0f, 0.0f}).ok());  // 2 g dt^2 a step: (-1.5 mm, 13 cm)
        w.step_once();
        CHECK(world_stats(w.owned.world).body_rays >= 1);
        const Vec3 p = w.positions()[0];
        CAPTURE(p.x);
        CAPTURE(p.y);
        CHECK(p.y <= 0.095f + 1e-4f);  // under the ceiling's hull, not through it
        CHECK(w.max_penetration() <= 1e-3);
    }
}

namespace {

constexpr double kCarryMoved_m = 0.3 * kDt * 20;  // what carried_along moves the body

// A resting cloth's mean move along x while its body moves at 0.3 m/s along x for 20 steps (after
// 30 steps to settle): the surface's velocity drives friction.
double carried_along(BodyWorld& w, const BodyMesh& body) {
    for (int i = 0; i < 30; ++i) w.step_once();
    const std::vector<Vec3> before = w.positions();
    std::vector<Vec3> moved = body.positions;
    for (int i = 1; i <= 20; ++i) {
        for (size_t v = 0; v < moved.size(); ++v) moved[v].x = body.positions[v].x + 0.3f * kDt * float(i);
        REQUIRE(set_body_vertices(w.owned.world, w.body, moved.data(), uint32_t(moved.size())).ok());
        w.step_once();
    }
    const std::vector<Vec3> after = w.positions();
    double dx = 0.0;
    for (size_t i = 0; i < after.size(); ++i) dx += after[i].x - before[i].x;
    return dx / double(after.size());
}

}  // namespace

TEST_CASE("body: a moving box carries a resting cloth along through friction, not without it") {
    const BodyMesh box = body::make_box({-0.5f, -0.1f, -0.5f}, {0.5f, 0.0f, 0.5f});
    const scenes::GridMesh grid = scenes::make_grid(8, 0.2f, 0.2f, false, 0.006f);
    const CookedCloth cooked = cook(grid.desc());
    auto carried = [&](float friction) {
        BodyDesc settings;
        settings.friction = friction;
        BodyWorld w(cooked.asset(), box, settings);
        const double moved = carried_along(w, box);
        CHECK(w.max_penetration() <= 1e-3);
        return moved;
    };
    const double body_moved = kCarryMoved_m;
    const double sticking = carried(1.0f), frictionless = carried(0.0f);
    MESSAGE("box moved ", body_moved, " m; cloth on top moved ", sticking, " m with friction 1, ", frictionless,
            " m without");
    CHECK(sticking == doctest::Approx(body_moved).epsilon(0.05));
    // Without friction the cloth is left behind; it drifts some because the 12-triangle box's
    // interpolated vertex normals tilt toward its edges (a smooth body has no such tilt).
    CHECK(std::fabs(frictionless) < 0.6 * body_moved);
}

// The same under skin constraints: the backstop's friction (constraints/skin.h) carries a cloth
// bound to a moving floor along with it; without friction the floor slides out from under it.
// Balls of 1 m: only the backstop acts. A flat square of two triangles, so the backstop's normal is
// straight up everywhere (a box's vertex normals tilt towards its edges and push the cloth along).
TEST_CASE("body: skin constraints carry a cloth resting on a moving floor through the backstop's friction, not without it") {
    BodyMesh floor;
    floor.positions = {{-0.5f, 0.0f, -0.5f}, {0.5f, 0.0f, -0.5f}, {0.5f, 0.0f, 0.5f}, {-0.5f, 0.0f, 0.5f}};
    floor.triangles = {0, 2, 1, 0, 3, 2};  // facing +y
    const scenes::GridMesh grid = scenes::make_grid(8, 0.2f, 0.2f, false, 0.006f);
    const CookedCloth cooked = cook(grid.desc());
    auto carried = [&](float friction) {
        BodyDesc settings;
        settings.friction = friction;
        settings.collision = BodyCollision::skin_constraints;
        BodyWorld w(cooked.asset(), floor, settings);
        SkinBindingOptions options;
        options.max_distance_m = 1.0f;
        options.loose_offset_m = 1.0f;  // every particle bound
        options.backstop_m = 0.0f;
        SkinBinding skin;
        const std::string e = scenes::bind_skin(w.owned.world, w.cloth, w.body, options, &skin);
        INFO(e);
        REQUIRE(e.empty());
        return carried_along(w, floor);
    };
    const double sticking = carried(1.0f), frictionless = carried(0.0f);
    MESSAGE("floor moved ", kCarryMoved_m, " m; bound cloth on it: ", sticking, " m with friction 1, ", frictionless, " m without");
    CHECK(sticking == doctest::Approx(kCarryMoved_m).epsilon(0.05));
    CHECK(std::fabs(frictionless) < 0.05 * kCarryMoved_m);
}

TEST_CASE("body: closest-point contacts match a brute-force search (icosphere, moving)") {
    BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 2);
    Points pts({{0.0f, 2.0f, 0.0f}});
    BodyWorld w(pts.cooked.asset(), sphere, BodyDesc{});
    uint32_t checked = 0, missed = 0;
    std::vector<Vec3> moved = sphere.positions;
    for (int frame = 0; frame < 3; ++frame) {
        for (size_t v = 0; v < moved.size(); ++v)  // squash and move: the hull changes shape
            moved[v] = {sphere.positions[v].x * (1.0f + 0.1f * frame), sphere.positions[v].y + 0.01f * frame,
                        sphere.positions[v].z};
        REQUIRE(set_body_vertices(w.owned.world, w.body, moved.data(), uint32_t(moved.size())).ok());
        w.step_once();
        const BodyView v = w.view();
        for (uint32_t i = 0; i < v.vertex_count; ++i) {
            for (float offset : {-0.006f, -0.003f, -0.0005f, 0.001f}) {
                const Vec3 p{v.hull[4 * i] + offset * v.normals[3 * i] + 0.003f,
                             v.hull[4 * i + 1] + offset * v.normals[3 * i + 1],
                             v.hull[4 * i + 2] + offset * v.normals[3 * i + 2] - 0.002f};
                const BruteContact ref = brute_force(v, p);
                BodyContact got;
                REQUIRE(query_body(w.owned.world, w.body, p, &got).ok());
                ++checked;
                if (ref.found && ref.penetration > 1e-4 && (!got.found || got.penetration_m < ref.penetration - 1e-4))
                    ++missed;
            }
            // 5 cm inside, beyond the step's reach: query_body with a wider reach sees it as the brute force does.
            const Vec3 deep{v.hull[4 * i] - 0.05f * v.normals[3 * i], v.hull[4 * i + 1] - 0.05f * v.normals[3 * i + 1],
                            v.hull[4 * i + 2] - 0.05f * v.normals[3 * i + 2]};
            const BruteContact ref = brute_force(v, deep, 0.25);
            BodyContact got, near;
            REQUIRE(query_body(w.owned.world, w.body, deep, &near).ok());
            REQUIRE(query_body(w.owned.world, w.body, deep, &got, 0.25f).ok());
            ++checked;
            if (near.found || !got.found || std::fabs(got.penetration_m - ref.penetration) > 1e-4) ++missed;
        }
    }
    MESSAGE(checked, " points checked, ", missed, " contacts missed");
    CHECK(checked > 1000);
    CHECK(missed == 0);
}

// BodyView::in_crease by its definition, over every pair of hull triangles: a triangle is in a crease
// when another whose normal points against its own (cosine below -0.3) comes within the body's reach
// (thickness + margin) of its middle. Two overlapping balls (a limb against a torso), at the default
// margin and at one wide enough that the hierarchy walk's candidate list fills and is searched
// several times. A pair within rounding of either threshold may go either way.
TEST_CASE("body: crease marks are those of a pass over every pair of hull triangles") {
    BodyMesh balls = body::make_icosphere({0.0f, 1.0f, 0.0f}, 0.3f, 4);
    const BodyMesh other = body::make_icosphere({0.42f, 1.05f, 0.0f}, 0.2f, 3);
    const uint32_t first = balls.vertex_count();
    balls.positions.insert(balls.positions.end(), other.positions.begin(), other.positions.end());
    for (uint32_t i : other.triangles) balls.triangles.push_back(first + i);
    Points pts({{0.0f, 2.0f, 0.0f}});
    for (const float margin_m : {0.002f, 0.3f}) {
        CAPTURE(margin_m);
        BodyDesc settings;
        settings.margin_m = margin_m;
        BodyWorld w(pts.cooked.asset(), balls, settings);
        const BodyView v = w.view();
        const double reach = double(settings.thickness_m) + margin_m;
        const auto corner = [&](uint32_t t, int k) {
            const float* h = v.hull + 4 * v.triangles[3 * t + k];
            return D3{h[0], h[1], h[2]};
        };
        std::vector<D3> normal(v.triangle_count), middle(v.triangle_count);
        for (uint32_t t = 0; t < v.triangle_count; ++t) {
            const D3 a = corner(t, 0), b = corner(t, 1), c = corner(t, 2), e1 = b - a, e2 = c - a;
            const D3 n{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
            normal[t] = (1.0 / std::sqrt(dot(n, n))) * n;
            middle[t] = (1.0 / 3.0) * (a + b + c);
        }
        uint32_t marked = 0, differ = 0, borderline = 0;
        for (uint32_t t = 0; t < v.triangle_count; ++t) {
            bool facing = false, close_call = false;
            for (uint32_t u = 0; u < v.triangle_count; ++u) {
                const double cosine = dot(normal[t], normal[u]);
                if (cosine > -0.3 + 1e-5) continue;
                double w3[3];
                closest_point(middle[t], corner(u, 0), corner(u, 1), corner(u, 2), w3);
                const D3 d = w3[0] * corner(u, 0) + w3[1] * corner(u, 1) + w3[2] * corner(u, 2) - middle[t];
                const double distance = std::sqrt(dot(d, d));
                if (cosine > -0.3 - 1e-5 || std::fabs(distance - reach) < 1e-6) close_call = close_call || distance < reach + 1e-6;
                else facing = facing || distance < reach;
            }
            marked += v.in_crease[t] != 0;
            if (!facing && close_call) ++borderline;
            else if (facing != (v.in_crease[t] != 0)) ++differ;
        }
        MESSAGE(margin_m, " m margin: ", marked, " of ", v.triangle_count, " triangles marked, ", borderline, " borderline");
        CHECK(marked > 20);                   // the balls' overlap is a crease
        CHECK(marked < v.triangle_count / 2);  // and only there
        CHECK(differ == 0);
    }
}

TEST_CASE("body: contacts on the animated mean_all body match a brute-force search over every triangle") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    Points pts({{0.0f, 3.0f, 0.0f}});
    for (SimdPath path : available_paths()) {
    CAPTURE(simd_path_name(path));
    BodyWorld w(pts.cooked.asset(), a, BodyDesc{}, path);
    std::vector<Vec3> pose;
    uint32_t checked = 0, missed = 0, deep = 0;
    uint32_t seed = 12345;
    auto uniform = [&] {
        seed = seed * 1664525u + 1013904223u;
        return float(seed >> 8) / float(1u << 24);
    };
    for (float blend : {0.0f, 0.35f, 0.7f, 1.0f}) {
        body::blend(a, t, blend, &pose);
        REQUIRE(set_body_vertices(w.owned.world, w.body, pose.data(), uint32_t(pose.size())).ok());
        w.step_once();
        const BodyView v = w.view();
        for (int k = 0; k < 150; ++k) {
            const uint32_t i = uint32_t(uniform() * float(v.vertex_count)) % v.vertex_count;
            const float offset = -0.007f + 0.009f * uniform();
            const Vec3 p{v.hull[4 * i] + offset * v.normals[3 * i] + 0.004f * (uniform() - 0.5f),
                         v.hull[4 * i + 1] + offset * v.normals[3 * i + 1] + 0.004f * (uniform() - 0.5f),
                         v.hull[4 * i + 2] + offset * v.normals[3 * i + 2] + 0.004f * (uniform() - 0.5f)};
            const BruteContact ref = brute_force(v, p);
            BodyContact got;
            REQUIRE(query_body(w.owned.world, w.body, p, &got).ok());
            ++checked;
            if (ref.found && ref.penetration > 1e-4) {
                ++deep;
                if (!got.found || got.penetration_m < ref.penetration - 1e-4) ++missed;
            }
        }
    }
    MESSAGE(std::string(simd_path_name(path)), ": ", checked, " points on 4 poses, ", deep, " deeper than 0.1 mm by brute force, ",
            missed, " missed");
    CHECK(deep > 100);
    CHECK(missed == 0);
    }
}

TEST_CASE("body: the animated mean_all (A-pose to T-pose) carries particles on its upper arms, outside") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    // Particles 1 mm outside the offset hull where the skin faces the way it moves from A to T by
    // 5 to 30 cm: the leading side of the upper arms, which must push them along.
    OwnedWorld probe;
    std::vector<Vec3> start, skin_motion;
    {
        WorldDesc d;
        d.max_bodies = 1;
        d.max_body_vertices = a.vertex_count();
        d.max_body_triangles = a.triangle_count();
        REQUIRE(make_world(d, &probe).ok());
        BodyDesc b;
        b.positions = a.positions.data();
        b.vertex_count = a.vertex_count();
        b.triangles = a.triangles.data();
        b.triangle_count = a.triangle_count();
        BodyId id;
        REQUIRE(add_body(probe.world, b, &id).ok());
        BodyView v;
        REQUIRE(view_body(probe.world, id, &v).ok());
        for (uint32_t i = 0; i < v.vertex_count; i += 7) {
            const float* h = v.hull + 4 * i;
            const float* n = v.normals + 3 * i;
            const Vec3 m{t.positions[i].x - a.positions[i].x, t.positions[i].y - a.positions[i].y,
                         t.positions[i].z - a.positions[i].z};
            const float length = std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z);
            if (length > 0.05f && length < 0.3f && n[0] * m.x + n[1] * m.y + n[2] * m.z > 0.7f * length) {
                start.push_back({h[0] + 0.001f * n[0], h[1] + 0.001f * n[1], h[2] + 0.001f * n[2]});
                skin_motion.push_back(m);
            }
        }
    }
    REQUIRE(start.size() > 20);
    Points pts(start);
    BodyDesc settings;
    settings.friction = 1.0f;
    BodyWorld w(pts.cooked.asset(), a, settings);
    std::vector<Vec3> pose;
    double worst = 0.0;
    for (int frame = 1; frame <= 30; ++frame) {  // one second from A to T
        body::blend(a, t, float(frame) / 30.0f, &pose);
        REQUIRE(set_body_vertices(w.owned.world, w.body, pose.data(), uint32_t(pose.size())).ok());
        w.step_once();
        worst = std::max(worst, w.max_penetration());
    }
    // How far each particle went along its skin's motion, relative to that motion.
    double followed = 0.0;
    const std::vector<Vec3> end = w.positions();
    for (size_t i = 0; i < end.size(); ++i) {
        const Vec3 m = skin_motion[i];
        const double d = (end[i].x - start[i].x) * m.x + (end[i].y - start[i].y) * m.y + (end[i].z - start[i].z) * m.z;
        followed += d / (double(m.x) * m.x + double(m.y) * m.y + double(m.z) * m.z);
    }
    followed /= double(end.size());
    MESSAGE(start.size(), " particles on the moving skin followed it ", followed * 100.0,
            "% on average; max penetration ", worst * 1e3, " mm");
    CHECK(worst <= 1e-3);
    // Known limitation (not yet fixed): the hull jumps to the frame's pose at the first substep, so
    // a pushed particle leaves with up to 3x the skin's speed and, in this A-to-T motion, slides
    // off the arm and falls (measured: followed -1100%). Kept as a warning until the contact
    // response limits the normal velocity to the surface's (or the pose is interpolated per substep).
    WARN(followed > 0.7);
}

// Points near the skin of mean_all (every `stride`-th vertex, offsets along the normal from
// `deepest` to `highest` metres off the hull, a lateral jitter), in the order of the vertices.
std::vector<Vec3> points_near_skin(const BodyView& v, uint32_t stride, float deepest, float highest, uint32_t seed) {
    auto uniform = [&] {
        seed = seed * 1664525u + 1013904223u;
        return float(seed >> 8) / float(1u << 24);
    };
    std::vector<Vec3> out;
    for (uint32_t i = 0; i < v.vertex_count; i += stride) {
        const float offset = deepest + (highest - deepest) * uniform();
        out.push_back({v.hull[4 * i] + offset * v.normals[3 * i] + 0.004f * (uniform() - 0.5f),
                       v.hull[4 * i + 1] + offset * v.normals[3 * i + 1] + 0.004f * (uniform() - 0.5f),
                       v.hull[4 * i + 2] + offset * v.normals[3 * i + 2] + 0.004f * (uniform() - 0.5f)});
    }
    return out;
}

// points_near_skin on the shared A-pose's offset hull.
std::vector<Vec3> points_near_a_pose(uint32_t stride, float deepest, float highest, uint32_t seed) {
    Points probe_points({{0.0f, 3.0f, 0.0f}});
    BodyWorld probe(probe_points.cooked.asset(), *shared_pose(false), BodyDesc{});
    return points_near_skin(probe.view(), stride, deepest, highest, seed);
}

// Calls check(world, count) on every SIMD path with a weightless world of the shared A-pose body and
// one point (far above it until placed) for every `stride`-th vertex, as points_near_skin places them.
template <class Check>
void on_every_path_with_skin_points(uint32_t stride, Check&& check) {
    const BodyMesh& a = *shared_pose(false);
    const uint32_t count = uint32_t(points_near_a_pose(stride, 0.0f, 0.0f, 1).size());
    Points pts(std::vector<Vec3>(count, Vec3{0.0f, 3.0f, 0.0f}));
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        BodyWorld w(pts.cooked.asset(), a, BodyDesc{}, path);
        REQUIRE(set_gravity(w.owned.world, {0, 0, 0}).ok());
        check(w, count, std::string(simd_path_name(path)));
    }
}

TEST_CASE("body: one step pushes particles placed inside the moving mean_all out (every SIMD path)") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    on_every_path_with_skin_points(41, [&](BodyWorld& w, uint32_t count, const std::string& path) {
        std::vector<Vec3> pose;
        uint32_t deep_before = 0;
        double worst_after = 0.0;
        uint32_t seed = 99;
        for (float blend : {0.2f, 0.25f, 0.6f}) {  // moving: the arms move up to 1.5 cm between the first two
            body::blend(a, t, blend, &pose);
            REQUIRE(set_body_vertices(w.owned.world, w.body, pose.data(), uint32_t(pose.size())).ok());
            // Placed on this pose's hull (set_body_vertices has computed it), up to 6 mm inside.
            const std::vector<Vec3> placed = points_near_skin(w.view(), 41, -0.006f, 0.002f, seed++);
            for (uint32_t k = 0; k < count; ++k)
                REQUIRE(set_particle(w.owned.world, w.cloth, k, placed[k], 100.0f).ok());
            w.step_once();
            const BodyView v = w.view();
            const std::vector<Vec3> after = w.positions();
            for (uint32_t k = 0; k < count; ++k) {
                const BruteContact c = brute_force(v, placed[k]);
                deep_before += c.found && c.penetration > 1e-4;
                // What the step must push out: a particle within its reach of the nearest hull (a
                // vertex of the arm buried in the torso places its points deeper in the body than
                // any surface's reach). Measured 0.25 m deep after the step.
                if (c.found) worst_after = std::max(worst_after, brute_force(v, after[k], 0.25).penetration);
            }
        }
        MESSAGE(path, ": ", deep_before, " of ", 3 * count, " placements deeper than 0.1 mm; deepest after the step ",
                worst_after * 1e3, " mm");
        CHECK(deep_before > 100);
        CHECK(worst_after <= 1e-3);
    });
}

// The step's pass does not compute a closest point for a particle in front of every nearby
// triangle's plane (body_query.h: in_front_of_every_plane). It must still move exactly the
// particles that are inside the hull by the closest-triangle rule, or in front of a crease
// triangle and behind another's face (a brute-force search in double precision), and leave every
// other one where it was, bit for bit, armpit and crotch included.
TEST_CASE("body: the step moves exactly the particles a brute-force search finds inside (every SIMD path)") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    // The brute-force verdicts per pose, found on the first path (the placements are the same on each).
    std::vector<std::vector<double>> depth_of_pose(3);
    std::vector<std::vector<char>> ambiguous_of_pose(3), crease_of_pose(3);  // crease: inside only by the second look
    on_every_path_with_skin_points(9, [&](BodyWorld& w, uint32_t count, const std::string& path) {
        std::vector<Vec3> pose;
        uint32_t inside = 0, outside = 0, wrong = 0, in_crease = 0;
        uint32_t seed = 5;
        for (int p = 0; p < 3; ++p) {
            body::blend(a, t, 0.5f * float(p), &pose);
            REQUIRE(set_body_vertices(w.owned.world, w.body, pose.data(), uint32_t(pose.size())).ok());
            // One step for the body to arrive (the particles far above it): then it stands still and
            // the pass reaches as far as the brute-force search, thickness + margin (+ the fold).
            for (uint32_t k = 0; k < count; ++k)
                REQUIRE(set_particle(w.owned.world, w.cloth, k, {0.0f, 3.0f, 0.0f}, 100.0f).ok());
            w.step_once();
            const std::vector<Vec3> placed = points_near_skin(w.view(), 9, -0.006f, 0.006f, seed++);
            for (uint32_t k = 0; k < count; ++k)
                REQUIRE(set_particle(w.owned.world, w.cloth, k, placed[k], 100.0f).ok());
            w.step_once();
            const std::vector<Vec3> after = w.positions();
            std::vector<double>& depth = depth_of_pose[p];
            std::vector<char>& ambiguous = ambiguous_of_pose[p];
            std::vector<char>& crease = crease_of_pose[p];
            for (uint32_t k = uint32_t(depth.size()); k < count; ++k) {
                bool close_call = false, second_look = false;
                depth.push_back(brute_force_depth(w.view(), placed[k], &close_call, &second_look));
                ambiguous.push_back(close_call);
                crease.push_back(second_look);
            }
            for (uint32_t k = 0; k < count; ++k) {
                if (ambiguous[k]) continue;  // within rounding of a decision: either verdict
                const bool moved = std::memcmp(&after[k], &placed[k], sizeof(Vec3)) != 0;
                in_crease += crease[k];
                inside += depth[k] > 0.0;
                outside += depth[k] < 0.0;
                if (moved != (depth[k] > 0.0)) {
                    if (wrong < 5) MESSAGE("particle ", k, " at depth ", depth[k] * 1e3, " mm, moved ", moved);
                    ++wrong;
                }
            }
        }
        MESSAGE(path, ": ", inside, " inside (", in_crease, " of them in front of a crease triangle), ", outside,
                " outside, ", wrong, " wrong");
        CHECK(inside > 2000);
        CHECK(in_crease > 10);
        CHECK(outside > 2000);
        CHECK(wrong == 0);
    });
}

namespace {

// Steps the same points through the scalar and the AVX2 body pass on the animated mean_all (falling
// under gravity while the arms rise: rays too) and checks that both give the same bits, `frames`
// frames. `scattered`: the points placed in a shuffled order of the start positions the pass orders
// its clusters by, so every cluster of 16 spans the body, its walk meets thousands of leaves and the
// candidate list is searched and emptied many times per cluster (and the crease search walks again).
void check_same_bits_on_mean_all(bool scattered, int frames, BodyCollision model = BodyCollision::exact,
                                 uint32_t substeps = 0) {
    if (skip_without_shared_body()) return;
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("skipped: no AVX2 on this machine or build");
        return;
    }
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    std::vector<Vec3> start = points_near_a_pose(7, -0.006f, 0.02f, 5);
    Points pts(start);
    if (scattered) {
        uint32_t seed = 77;
        for (size_t k = start.size() - 1; k > 0; --k) {
            seed = seed * 1664525u + 1013904223u;
            std::swap(start[k], start[seed % (k + 1)]);
        }
    }
    BodyDesc settings;
    settings.collision = model;
    BodyWorld scalar(pts.cooked.asset(), a, settings, SimdPath::scalar, substeps);
    BodyWorld avx2(pts.cooked.asset(), a, settings, SimdPath::avx2, substeps);
    for (BodyWorld* w : {&scalar, &avx2}) w->place(start);
    std::vector<Vec3> pose;
    uint64_t contacts = 0, rays = 0;
    bool same = true;
    for (int frame = 1; frame <= frames; ++frame) {
        body::blend(a, t, float(frame) / float(frames), &pose);
        for (BodyWorld* w : {&scalar, &avx2}) {
            REQUIRE(set_body_vertices(w->owned.world, w->body, pose.data(), uint32_t(pose.size())).ok());
            w->step_once();
        }
        contacts += world_stats(avx2.owned.world).body_contacts;
        rays += world_stats(avx2.owned.world).body_rays;
        same = same && same_bits(scalar.positions(), avx2.positions());
        for (size_t k = 0; k < start.size(); k += 13) {
            BodyContact cs, ca;
            REQUIRE(query_body(scalar.owned.world, scalar.body, start[k], &cs).ok());
            REQUIRE(query_body(avx2.owned.world, avx2.body, start[k], &ca).ok());
            same = same && cs.found == ca.found && cs.triangle == ca.triangle &&
                   std::memcmp(&cs.penetration_m, &ca.penetration_m, sizeof(float)) == 0;
        }
    }
    MESSAGE(start.size(), " particles, ", frames, " frames: ", contacts, " contacts, ", rays, " rays");
    CHECK(contacts > 1000);
    CHECK(rays > 100);
    CHECK(same);
}

}  // namespace

TEST_CASE("body: the scalar and AVX2 body passes give the same bits on the animated mean_all") {
    check_same_bits_on_mean_all(false, 12);
}

TEST_CASE("body: the scalar and AVX2 body passes give the same bits when every cluster spans the body") {
    check_same_bits_on_mean_all(true, 6);
}

TEST_CASE("body: the scalar and AVX2 cached-planes passes give the same bits on the animated mean_all") {
    check_same_bits_on_mean_all(false, 12, BodyCollision::cached_planes, 3);
}

TEST_CASE("body: cached planes keep the particles on the moving mean_all within 2 mm of the hull, searching fewer") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    const std::vector<Vec3> start = points_near_a_pose(5, -0.003f, 0.015f, 21);
    Points pts(start);
    constexpr int kFrames = 12;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        // The same points through both models at 3 substeps a step, while the arms rise (A to T)
        // and gravity pulls them down and toward the body's front, so later substeps bring them
        // against the hull and across it (the fastest faster than the thickness a substep).
        BodyDesc exact_desc, planes_desc;
        planes_desc.collision = BodyCollision::cached_planes;
        BodyWorld exact(pts.cooked.asset(), a, exact_desc, path, 3);
        BodyWorld planes(pts.cooked.asset(), a, planes_desc, path, 3);
        for (BodyWorld* w : {&exact, &planes}) {
            REQUIRE(set_gravity(w->owned.world, {0.0f, -9.81f, -6.0f}).ok());
            w->place(start);
        }
        std::vector<Vec3> pose;
        double deepest[2] = {0.0, 0.0};
        uint64_t searched[2] = {0, 0}, contacts[2] = {0, 0};
        for (int frame = 1; frame <= kFrames; ++frame) {
            body::blend(a, t, float(frame) / float(kFrames), &pose);
            int m = 0;
            for (BodyWorld* w : {&exact, &planes}) {
                REQUIRE(set_body_vertices(w->owned.world, w->body, pose.data(), uint32_t(pose.size())).ok());
                w->step_once();
                searched[m] += world_stats(w->owned.world).body_queried;
                contacts[m] += world_stats(w->owned.world).body_contacts;
                for (const Vec3& p : w->positions()) {  // the exact hull query (tested against brute force above)
                    BodyContact c;
                    REQUIRE(query_body(w->owned.world, w->body, p, &c).ok());
                    if (c.found) deepest[m] = std::max(deepest[m], double(c.penetration_m));
                }
                ++m;
            }
        }
        // And by brute force over every triangle, every 4th particle, at the last pose.
        double brute = 0.0;
        const BodyView v = planes.view();
        const std::vector<Vec3> last = planes.positions();
        for (size_t k = 0; k < last.size(); k += 4) {
            const BruteContact c = brute_force(v, last[k]);
            if (c.found) brute = std::max(brute, c.penetration);
        }
        MESSAGE(std::string(simd_path_name(path)), ": ", start.size(), " particles, ", kFrames, " frames: deepest exact ",
                deepest[0] * 1e3, " mm, planes ", deepest[1] * 1e3, " mm (brute force at the end ", brute * 1e3,
                " mm); searched ", searched[0], " / ", searched[1], ", contacts ", contacts[0], " / ", contacts[1]);
        CHECK(contacts[1] > 10000);
        CHECK(deepest[1] <= 0.002);
        CHECK(brute <= 0.002);
        CHECK(searched[1] < searched[0]);
    }
}

TEST_CASE("body: with one substep a step cached planes are the exact pass, bit for bit") {
    if (skip_without_shared_body()) return;
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    const std::vector<Vec3> start = points_near_a_pose(11, -0.003f, 0.015f, 4);
    Points pts(start);
    BodyDesc planes_desc;
    planes_desc.collision = BodyCollision::cached_planes;
    BodyWorld exact(pts.cooked.asset(), a, BodyDesc{}, SimdPath::automatic, 1);
    BodyWorld planes(pts.cooked.asset(), a, planes_desc, SimdPath::automatic, 1);
    std::vector<Vec3> pose;
    uint64_t contacts = 0;
    for (BodyWorld* w : {&exact, &planes}) w->place(start);
    for (int frame = 1; frame <= 6; ++frame) {
        body::blend(a, t, float(frame) / 6.0f, &pose);
        for (BodyWorld* w : {&exact, &planes}) {
            REQUIRE(set_body_vertices(w->owned.world, w->body, pose.data(), uint32_t(pose.size())).ok());
            w->step_once();
        }
        contacts += world_stats(planes.owned.world).body_contacts;
    }
    CHECK(contacts > 1000);
    CHECK(same_bits(exact.positions(), planes.positions()));
}

// A world pays for the cached planes only when it reserves them (WorldDesc::max_cached_plane_bodies).
TEST_CASE("body: the cached planes take memory only in a world that reserves them") {
    const scenes::GridMesh grid = scenes::make_grid(20, 0.5f, 0.5f, false, 0.4f);
    const CookedCloth cooked = cook(grid.desc());
    const ClothAsset& asset = cooked.asset();
    // The world's bytes for `planes` cached-plane bodies of `bodies`, with `extra` particle slots.
    auto bytes = [&](uint32_t bodies, uint32_t planes, uint32_t extra) {
        WorldDesc d = world_for({&asset});
        d.max_particles += extra;
        d.max_bodies = bodies;
        d.max_cached_plane_bodies = planes;
        d.max_body_vertices = bodies > 0 ? 1000 : 0;
        d.max_body_triangles = bodies > 0 ? 2000 : 0;
        return world_memory_requirements(d).bytes;
    };
    constexpr uint32_t kSlots = 1024;
    auto per_slots = [&](uint32_t bodies, uint32_t planes) {
        const size_t small = bytes(bodies, planes, 0), large = bytes(bodies, planes, kSlots);
        REQUIRE(small > 0);
        return large - small;
    };
    // With bodies but no cached-plane body, a slot costs only the body pass's order (4 bytes) more
    // than in a world without bodies, however many bodies; each reserved body adds 76 bytes a slot.
    const size_t plain = per_slots(0, 0);
    for (uint32_t bodies : {1u, 2u, 4u}) {
        CAPTURE(bodies);
        CHECK(per_slots(bodies, 0) == plain + 4 * kSlots);
        CHECK(per_slots(bodies, 1) == plain + (4 + 76) * kSlots);
    }
    CHECK(per_slots(4, 3) == plain + (4 + 3 * 76) * kSlots);
    CHECK(bytes(2, 0, 0) + 76 * asset.slot_count <= bytes(2, 1, 0));
    // More cached-plane bodies than bodies makes no sense.
    CHECK(bytes(1, 2, 0) == 0);
    WorldDesc too_many = world_for({&asset});
    too_many.max_bodies = 1;
    too_many.max_cached_plane_bodies = 2;
    too_many.max_body_vertices = 1000;
    too_many.max_body_triangles = 2000;
    World* refused = nullptr;
    const Result r = create_world(too_many, nullptr, 0, &refused);  // checked before the memory
    INFO(r.message);
    CHECK(r.code == ErrorCode::invalid_argument);
    CHECK(std::strstr(r.message, "max_cached_plane_bodies") != nullptr);
}

TEST_CASE("body: add_body refuses a cached_planes body beyond the world's reserved planes, changing nothing") {
    const BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 3);
    const BodyMesh far_sphere = body::make_icosphere({0, 5, 0}, 0.3f, 2);
    const scenes::GridMesh grid = scenes::make_grid(16, 0.8f, 0.8f, false, 0.35f);
    const CookedCloth cooked = cook(grid.desc());
    auto desc_of = [](const BodyMesh& m, BodyCollision model) {
        BodyDesc b;
        b.positions = m.positions.data();
        b.vertex_count = m.vertex_count();
        b.triangles = m.triangles.data();
        b.triangle_count = m.triangle_count();
        b.collision = model;
        return b;
    };
    // `planes` cached-plane bodies reserved of 2; the cloth runs 3 substeps a step.
    auto world_with = [&](uint32_t planes, OwnedWorld* out, ClothId* cloth) {
        WorldDesc d = world_for({&cooked.asset()});
        d.max_bodies = 2;
        d.max_cached_plane_bodies = planes;
        d.max_body_vertices = sphere.vertex_count() + far_sphere.vertex_count();
        d.max_body_triangles = sphere.triangle_count() + far_sphere.triangle_count();
        REQUIRE(make_world(d, out).ok());
        ClothDesc cd;
        cd.asset = &cooked.asset();
        cd.policy = BudgetPolicy::explicit_split;
        cd.substeps = 3;
        cd.iterations = 1;
        REQUIRE(add_cloth(out->world, cd, cloth).ok());
    };
    BodyId id;
    {  // None reserved: exact bodies only.
        OwnedWorld w;
        ClothId cloth;
        world_with(0, &w, &cloth);
        const Result r = add_body(w.world, desc_of(sphere, BodyCollision::cached_planes), &id);
        INFO(r.message);
        CHECK(r.code == ErrorCode::capacity_exceeded);
        CHECK(std::strstr(r.message, "max_cached_plane_bodies") != nullptr);
        BodyView none;
        CHECK(view_body(w.world, BodyId{0}, &none).code == ErrorCode::out_of_range);  // nothing was added
        REQUIRE(add_body(w.world, desc_of(sphere, BodyCollision::exact), &id).ok());
        CHECK(id.index == 0);
        REQUIRE(step(w.world, kDt).ok());
    }
    // One reserved: the second cached-plane body is refused, an exact one is not; the planes sit at
    // the cached body's own place, so an exact body before it (far away, never touched) changes no bit.
    OwnedWorld both, alone;
    ClothId both_cloth, alone_cloth;
    world_with(1, &both, &both_cloth);
    world_with(1, &alone, &alone_cloth);
    REQUIRE(add_body(both.world, desc_of(far_sphere, BodyCollision::exact), &id).ok());
    REQUIRE(add_body(both.world, desc_of(sphere, BodyCollision::cached_planes), &id).ok());
    CHECK(id.index == 1);
    REQUIRE(add_body(alone.world, desc_of(sphere, BodyCollision::cached_planes), &id).ok());
    CHECK(add_body(alone.world, desc_of(far_sphere, BodyCollision::cached_planes), &id).code ==
          ErrorCode::capacity_exceeded);
    std::vector<Vec3> moved = sphere.positions;
    uint64_t contacts = 0;
    for (int i = 0; i < 30; ++i) {
        for (size_t v = 0; v < moved.size(); ++v) moved[v].y = sphere.positions[v].y + 0.004f * float(i);
        REQUIRE(set_body_vertices(both.world, BodyId{1}, moved.data(), uint32_t(moved.size())).ok());
        REQUIRE(set_body_vertices(alone.world, BodyId{0}, moved.data(), uint32_t(moved.size())).ok());
        REQUIRE(step(both.world, kDt).ok());
        REQUIRE(step(alone.world, kDt).ok());
        contacts += world_stats(both.world).body_contacts;
    }
    const uint32_t n = cooked.asset().particle_count;
    CHECK(contacts > 1000);
    CHECK(same_bits(read_all(both.world, both_cloth, n), read_all(alone.world, alone_cloth, n)));
}

TEST_CASE("body: the same inputs give the same bits") {
    const BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 3);
    const scenes::GridMesh grid = scenes::make_grid(12, 0.5f, 0.5f, false, 0.4f);
    const CookedCloth cooked = cook(grid.desc());
    auto run = [&] {
        BodyWorld w(cooked.asset(), sphere, BodyDesc{});
        std::vector<Vec3> moved = sphere.positions;
        for (int i = 0; i < 40; ++i) {
            for (size_t v = 0; v < moved.size(); ++v) moved[v].z = sphere.positions[v].z + 0.002f * float(i);
            REQUIRE(set_body_vertices(w.owned.world, w.body, moved.data(), uint32_t(moved.size())).ok());
            w.step_once();
        }
        return w.positions();
    };
    CHECK(same_bits(run(), run()));
}

TEST_CASE("body: bad input is refused with a message and the world unchanged") {
    const BodyMesh box = body::make_box({-0.1f, -0.1f, -0.1f}, {0.1f, 0.1f, 0.1f});
    Points pts({{0.0f, 1.0f, 0.0f}});
    BodyWorld w(pts.cooked.asset(), box, BodyDesc{});
    World* world = w.owned.world;
    const BodyView before = w.view();
    const std::vector<float> hull(before.hull, before.hull + 4 * before.vertex_count);
    auto refused = [&](Result r, ErrorCode code) {
        INFO(r.message);
        CHECK(r.code == code);
        CHECK(r.message[0] != '\0');
    };
    // set_body_vertices: NaN, infinity, absurd coordinates, wrong count, unknown body, null.
    std::vector<Vec3> bad = box.positions;
    bad[5].y = std::nanf("");
    refused(set_body_vertices(world, w.body, bad.data(), 8), ErrorCode::non_finite);
    bad[5].y = INFINITY;
    refused(set_body_vertices(world, w.body, bad.data(), 8), ErrorCode::non_finite);
    bad[5].y = 1e9f;
    refused(set_body_vertices(world, w.body, bad.data(), 8), ErrorCode::out_of_range);
    refused(set_body_vertices(world, w.body, box.positions.data(), 7), ErrorCode::out_of_range);
    refused(set_body_vertices(world, BodyId{3}, box.positions.data(), 8), ErrorCode::out_of_range);
    refused(set_body_vertices(world, w.body, nullptr, 8), ErrorCode::invalid_argument);
    CHECK(std::memcmp(hull.data(), w.view().hull, hull.size() * sizeof(float)) == 0);

    // add_body: the world is full; and in a roomier world, each broken description.
    BodyDesc d;
    d.positions = box.positions.data();
    d.vertex_count = 8;
    d.triangles = box.triangles.data();
    d.triangle_count = 12;
    BodyId id;
    refused(add_body(world, d, &id), ErrorCode::capacity_exceeded);
    OwnedWorld roomy;
    WorldDesc wd;
    wd.max_bodies = 2;
    wd.max_body_vertices = 16;
    wd.max_body_triangles = 24;
    REQUIRE(make_world(wd, &roomy).ok());
    std::vector<uint32_t> bad_triangles = box.triangles;
    bad_triangles[7] = 8;
    BodyDesc e = d;
    e.triangles = bad_triangles.data();
    refused(add_body(roomy.world, e, &id), ErrorCode::out_of_range);
    e = d;
    e.positions = bad.data();
    refused(add_body(roomy.world, e, &id), ErrorCode::out_of_range);
    e = d;
    e.thickness_m = -0.01f;
    refused(add_body(roomy.world, e, &id), ErrorCode::out_of_range);
    e = d;
    e.friction = std::nanf("");
    refused(add_body(roomy.world, e, &id), ErrorCode::non_finite);
    e = d;
    e.collision = static_cast<BodyCollision>(7);  // not a model
    refused(add_body(roomy.world, e, &id), ErrorCode::invalid_argument);
    e = d;
    e.vertex_count = 20;  // more than the world holds
    refused(add_body(roomy.world, e, &id), ErrorCode::capacity_exceeded);
    e = d;
    e.triangles = nullptr;
    refused(add_body(roomy.world, e, &id), ErrorCode::invalid_argument);
    refused(add_body(roomy.world, d, nullptr), ErrorCode::invalid_argument);
    BodyView none;
    refused(view_body(roomy.world, BodyId{0}, &none), ErrorCode::out_of_range);  // nothing was added
    REQUIRE(add_body(roomy.world, d, &id).ok());
    CHECK(id.index == 0);

    // A world without bodies refuses them; query and view refuse what does not exist.
    OwnedWorld plain;
    REQUIRE(make_world(WorldDesc{}, &plain).ok());
    refused(add_body(plain.world, d, &id), ErrorCode::invalid_argument);
    BodyContact c;
    refused(query_body(world, w.body, {NAN, 0, 0}, &c), ErrorCode::non_finite);
    refused(query_body(world, w.body, {0, 0, 0}, &c, NAN), ErrorCode::out_of_range);
    refused(query_body(world, w.body, {0, 0, 0}, &c, -1.0f), ErrorCode::out_of_range);
    refused(query_body(world, w.body, {0, 0, 0}, &c, 1e30f), ErrorCode::out_of_range);
    REQUIRE(set_body_vertices(world, w.body, box.positions.data(), 8).ok());
    refused(query_body(world, w.body, {0, 0, 0}, &c), ErrorCode::invalid_argument);  // not refitted yet
    // Capacities that make no sense.
    WorldDesc nonsense;
    nonsense.max_bodies = 1;
    OwnedWorld unused;
    CHECK(world_memory_requirements(nonsense).bytes == 0);
}

// Skin constraints (weft/attachments.h: bind_skin_constraints) and BodyCollision::skin_constraints.
namespace {

// Points near the A-pose skin, bound by scenes::bind_skin (every one with a max distance), stepped
// 12 frames from A to T under gravity pulling them into the body, 3 substeps; after every step each
// constraint is checked against this step's hull. Returns the final positions.
// With `rebind_every_frame`, the binding is bound again before every step, so each step gathers
// the skinned points on the previous hull instead of keeping the last step's.
std::vector<Vec3> run_skin_points(SimdPath path, double* worst_ball_m, double* worst_backstop_m, uint64_t* queried,
                                  bool rebind_every_frame = false) {
    const BodyMesh& a = *shared_pose(false);
    const BodyMesh& t = *shared_pose(true);
    const std::vector<Vec3> start = points_near_a_pose(7, 0.0f, 0.02f, 3);
    Points pts(start);
    BodyDesc settings;
    settings.collision = BodyCollision::skin_constraints;
    BodyWorld w(pts.cooked.asset(), a, settings, path, 3);
    w.place(start);
    REQUIRE(set_gravity(w.owned.world, {0.0f, -9.81f, -6.0f}).ok());
    SkinBindingOptions options;
    options.max_distance_m = 0.01f;
    options.loose_offset_m = 1.0f;  // every particle has its ball
    options.backstop_m = 0.0f;
    SkinBinding skin;
    const std::string e = scenes::bind_skin(w.owned.world, w.cloth, w.body, options, &skin);
    INFO(e);
    REQUIRE(e.empty());
    REQUIRE(skin.particle.size() == start.size());
    std::vector<Vec3> pose;
    *worst_ball_m = *worst_backstop_m = 0.0;
    *queried = 0;
    for (int frame = 1; frame <= 12; ++frame) {
        body::blend(a, t, float(frame) / 12.0f, &pose);
        REQUIRE(set_body_vertices(w.owned.world, w.body, pose.data(), uint32_t(pose.size())).ok());
        if (rebind_every_frame) REQUIRE(bind_skin_constraints(w.owned.world, w.cloth, w.body, skin.constraints()).ok());
        w.step_once();
        *queried += world_stats(w.owned.world).body_queried;
        const BodyView v = w.view();
        const std::vector<Vec3> x = w.positions();
        for (size_t k = 0; k < skin.particle.size(); ++k) {
            const uint32_t* tri = v.triangles + 3 * skin.triangle[k];
            D3 p{0, 0, 0}, n{0, 0, 0};
            for (int c = 0; c < 3; ++c) {
                const double wc = skin.weight[3 * k + c];
                p = p + wc * D3{v.hull[4 * tri[c]], v.hull[4 * tri[c] + 1], v.hull[4 * tri[c] + 2]};
                n = n + wc * D3{v.normals[3 * tri[c]], v.normals[3 * tri[c] + 1], v.normals[3 * tri[c] + 2]};
            }
            n = (1.0 / std::sqrt(dot(n, n))) * n;
            const Vec3 q = x[skin.particle[k]];
            const D3 d = D3{q.x, q.y, q.z} - p;
            const D3 from_centre = d - double(skin.rest_offset_m[k]) * n;
            // A point placed off one surface but inside another part of the hull (the armpit) has its
            // ball wholly behind the backstop: no point meets both, and the backstop wins.
            if (skin.rest_offset_m[k] + skin.backstop_m[k] >= -skin.max_distance_m[k])
                *worst_ball_m = std::max(*worst_ball_m, std::sqrt(dot(from_centre, from_centre)) - skin.max_distance_m[k]);
            *worst_backstop_m = std::max(*worst_backstop_m, -dot(d, n) - skin.backstop_m[k]);
        }
    }
    return w.positions();
}

}  // namespace

TEST_CASE("body: skin constraints keep particles within their max distance and in front of the backstop on the moving mean_all") {
    if (skip_without_shared_body()) return;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        double ball = 0, backstop = 0;
        uint64_t queried = 0;
        run_skin_points(path, &ball, &backstop, &queried);
        MESSAGE(std::string(simd_path_name(path)), ": worst excess over the max distance ", ball * 1e6, " um, behind the backstop ",
                backstop * 1e6, " um");
        CHECK(ball <= 1e-5);      // float rounding of a 1 cm ball on a body a metre from the origin
        CHECK(backstop <= 1e-5);
        CHECK(queried == 0);      // the skin_constraints model searches no hierarchy for a bound cloth
    }
}

TEST_CASE("body: the scalar and AVX2 skin constraints give the same bits on the animated mean_all") {
    if (skip_without_shared_body()) return;
    if (!simd_path_available(SimdPath::avx2)) {
        MESSAGE("skipped: no AVX2 on this machine or build");
        return;
    }
    double ball = 0, backstop = 0;
    uint64_t queried = 0;
    const std::vector<Vec3> scalar = run_skin_points(SimdPath::scalar, &ball, &backstop, &queried);
    const std::vector<Vec3> avx2 = run_skin_points(SimdPath::avx2, &ball, &backstop, &queried);
    CHECK(same_bits(scalar, avx2));
}

// The frames pass keeps each step's skinned point for the next step's previous one: the same bits
// as gathering it again from the previous hull (a rebinding forces that).
TEST_CASE("body: skin constraints keep the last step's skinned points, to the bit of gathering them again") {
    if (skip_without_shared_body()) return;
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        double ball = 0, backstop = 0;
        uint64_t queried = 0;
        const std::vector<Vec3> kept = run_skin_points(path, &ball, &backstop, &queried);
        const std::vector<Vec3> gathered = run_skin_points(path, &ball, &backstop, &queried, true);
        CHECK(same_bits(kept, gathered));
    }
}

TEST_CASE("body: bind_skin_constraints refuses bad bindings with a message") {
    const BodyMesh sphere = body::make_icosphere({0, 0, 0}, 0.3f, 2);
    Points pts({{0.0f, 0.31f, 0.0f}, {0.0f, -0.31f, 0.0f}, {0.31f, 0.0f, 0.0f}});
    BodyDesc settings;
    settings.collision = BodyCollision::skin_constraints;
    BodyWorld w(pts.cooked.asset(), sphere, settings);
    w.place({{0.0f, 0.31f, 0.0f}, {0.0f, -0.31f, 0.0f}, {0.31f, 0.0f, 0.0f}});
    REQUIRE(set_particle(w.owned.world, w.cloth, 2, {0.31f, 0.0f, 0.0f}, 0.0f).ok());  // pinned
    uint32_t particle[2] = {0, 1}, triangle[2] = {0, 1};
    float weight[6] = {1, 0, 0, 0, 1, 0}, offset[2] = {0.01f, 0.01f}, max_distance[2] = {0.02f, 0.02f},
          backstop[2] = {0, 0};
    SkinConstraints s{2, particle, triangle, weight, offset, max_distance, backstop};
    CHECK(bind_skin_constraints(w.owned.world, w.cloth, w.body, s).ok());
    auto refused = [&](ErrorCode code, const char* words) {
        const Result r = bind_skin_constraints(w.owned.world, w.cloth, w.body, s);
        INFO(r.message);
        CHECK(r.code == code);
        CHECK(std::string(r.message).find(words) != std::string::npos);
    };
    particle[1] = 0;
    refused(ErrorCode::invalid_argument, "two skin constraints");
    particle[1] = 2;
    refused(ErrorCode::invalid_argument, "pinned");
    particle[1] = 7;
    refused(ErrorCode::out_of_range, "particle 7");
    particle[1] = 1;
    triangle[1] = 100000;
    refused(ErrorCode::out_of_range, "body triangle");
    triangle[1] = 1;
    weight[4] = std::nanf("");
    refused(ErrorCode::invalid_argument, "weights");
    weight[4] = 1;
    max_distance[0] = -1;
    refused(ErrorCode::out_of_range, "max distance");
    max_distance[0] = 0.02f;
    offset[1] = INFINITY;
    refused(ErrorCode::non_finite, "not finite");
    offset[1] = 0.01f;
    CHECK(bind_skin_constraints(w.owned.world, w.cloth, BodyId{4}, s).code == ErrorCode::out_of_range);
    CHECK(bind_skin_constraints(nullptr, w.cloth, w.body, s).code == ErrorCode::invalid_argument);
    CHECK(bind_skin_constraints(w.owned.world, w.cloth, w.body, SkinConstraints{}).ok());  // count 0: unbound
    // A world that reserved no skin constraints (WorldDesc::max_skin_constraints) refuses them by
    // name and steps on unbound.
    BodyWorld none(pts.cooked.asset(), sphere, settings, SimdPath::automatic, 0, 0);
    none.place({{0.0f, 0.31f, 0.0f}, {0.0f, -0.31f, 0.0f}, {0.31f, 0.0f, 0.0f}});
    REQUIRE(set_particle(none.owned.world, none.cloth, 2, {0.31f, 0.0f, 0.0f}, 0.0f).ok());
    const Result r = bind_skin_constraints(none.owned.world, none.cloth, none.body, s);
    CHECK(r.code == ErrorCode::capacity_exceeded);
    CHECK(std::string(r.message).find("max_skin_constraints") != std::string::npos);
    CHECK(step(none.owned.world, 1.0f / 60.0f).ok());
}

namespace {

// Distance from p to triangle (a, b, c), found independently of cook_skin_binding's region test:
// the plane when p projects inside, else the nearest of the three edges.
double distance_to_triangle(const double p[3], const double a[3], const double b[3], const double c[3]) {
    const auto sub = [](const double* u, const double* v, double* out) { for (int i = 0; i < 3; ++i) out[i] = u[i] - v[i]; };
    const auto dot3 = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    const auto to_segment = [&](const double* s, const double* e) {
        double d[3], q[3];
        sub(e, s, d);
        sub(p, s, q);
        const double t = std::clamp(dot3(q, d) / dot3(d, d), 0.0, 1.0);
        for (int i = 0; i < 3; ++i) q[i] -= t * d[i];
        return std::sqrt(dot3(q, q));
    };
    double ab[3], ac[3], ap[3];
    sub(b, a, ab), sub(c, a, ac), sub(p, a, ap);
    const double n[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
    const double* corner[3] = {a, b, c};
    bool inside = true;  // p's projection on the same side of every edge as the triangle
    for (int k = 0; k < 3; ++k) {
        double e[3], q[3], x[3];
        sub(corner[(k + 1) % 3], corner[k], e);
        sub(p, corner[k], q);
        x[0] = e[1] * q[2] - e[2] * q[1], x[1] = e[2] * q[0] - e[0] * q[2], x[2] = e[0] * q[1] - e[1] * q[0];
        inside &= dot3(x, n) >= 0.0;
    }
    if (inside) return std::fabs(dot3(ap, n)) / std::sqrt(dot3(n, n));
    return std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
}

}  // namespace

// cook_skin_binding searches a grid of the triangles: it must find the closest one wherever the
// particle is, near the surface, far off it, and outside the grid's box altogether.
TEST_CASE("body: cook_skin_binding binds each particle to its closest hull triangle, as a brute-force search finds it") {
    const BodyMesh sphere = body::make_icosphere({0.1f, 1.0f, 0.0f}, 0.3f, 3);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> box(-1.5f, 1.5f), unit(-1.0f, 1.0f);
    std::vector<Vec3> points;
    for (int k = 0; k < 200; ++k) points.push_back({box(random), 1.0f + box(random), box(random)});  // most outside the grid
    for (int k = 0; k < 200; ++k) {  // near the surface, inside and out
        Vec3 d{unit(random), unit(random), unit(random)};
        const float r = (0.28f + 0.04f * (unit(random) + 1.0f)) / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        points.push_back({0.1f + r * d.x, 1.0f + r * d.y, r * d.z});
    }
    Points pts(points);
    BodyWorld w(pts.cooked.asset(), sphere, BodyDesc{});
    BodyView view;
    REQUIRE(view_body(w.owned.world, w.body, &view).ok());
    const std::vector<float> inverse_masses(points.size(), 1.0f);
    SkinBindingDesc desc;
    desc.particle_count = uint32_t(points.size());
    desc.positions = points.data();
    desc.inverse_masses = inverse_masses.data();
    SkinBinding skin;
    REQUIRE(cook_skin_binding(view, desc, &skin).ok());
    REQUIRE(skin.particle.size() == points.size());
    double worst = 0.0;
    for (size_t k = 0; k < points.size(); ++k) {
        const double p[3] = {points[k].x, points[k].y, points[k].z};
        const auto corner = [&](uint32_t t, int c, double out[3]) {
            for (int i = 0; i < 3; ++i) out[i] = view.hull[4 * view.triangles[3 * t + c] + i];
        };
        double nearest = HUGE_VAL;
        for (uint32_t t = 0; t < view.triangle_count; ++t) {
            double a[3], b[3], c[3];
            corner(t, 0, a), corner(t, 1, b), corner(t, 2, c);
            nearest = std::min(nearest, distance_to_triangle(p, a, b, c));
        }
        double q[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            double v[3];
            corner(skin.triangle[k], c, v);
            CHECK(skin.weight[3 * k + c] >= -1e-6f);
            for (int i = 0; i < 3; ++i) q[i] += skin.weight[3 * k + c] * v[i];
        }
        const double bound = std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
        worst = std::max(worst, bound - nearest);
    }
    CHECK(worst <= 1e-6);  // the float weights round the bound point by less than a micrometre
}
