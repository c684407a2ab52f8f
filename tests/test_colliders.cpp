// Colliders (seed section 2): plane, capsule and finite cylinder keep particles outside their
// inflated shape; a cylinder has no contact beyond its axis ends (eq. 6); Coulomb friction holds a
// cloth on an incline steeper than friction 0 allows.
#include "support/test_support.h"

#include <algorithm>

using namespace weft;
using namespace weft::test;

namespace {

constexpr float kDt = scenes::kSeedTimeStep_s;

// A world with one cloth and the given colliders.
struct ColliderWorld {
    OwnedWorld owned;
    ClothId cloth;
    uint32_t particle_count = 0;

    ColliderWorld(const ClothAsset& asset, const std::vector<ColliderDesc>& colliders,
                  SimdPath path = SimdPath::automatic) {
        REQUIRE(make_world(world_for({&asset}, uint32_t(colliders.size()), path), &owned).ok());
        ClothDesc cd;
        cd.asset = &asset;
        REQUIRE(add_cloth(owned.world, cd, &cloth).ok());
        for (const ColliderDesc& c : colliders) {
            ColliderId id;
            const Result r = add_collider(owned.world, c, &id);
            INFO(r.message);
            REQUIRE(r.ok());
        }
        particle_count = asset.particle_count;
    }
    std::vector<Vec3> positions() const { return read_all(owned.world, cloth, particle_count); }
    void step_once() const { REQUIRE(step(owned.world, kDt).ok()); }
};

// Distance from x to the segment p0-p1, and the segment parameter (unclamped).
double segment_distance(Vec3 x, Vec3 p0, Vec3 p1, bool clamp, double* t_out = nullptr) {
    const double ax = double(p1.x) - p0.x, ay = double(p1.y) - p0.y, az = double(p1.z) - p0.z;
    const double rx = double(x.x) - p0.x, ry = double(x.y) - p0.y, rz = double(x.z) - p0.z;
    double t = (rx * ax + ry * ay + rz * az) / (ax * ax + ay * ay + az * az);
    if (t_out) *t_out = t;
    if (clamp) t = std::clamp(t, 0.0, 1.0);
    const double dx = rx - t * ax, dy = ry - t * ay, dz = rz - t * az;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

ColliderDesc horizontal_segment(ColliderShape shape) {
    ColliderDesc c;
    c.shape = shape;
    c.p0 = {-1.0f, 0.0f, 0.0f};
    c.p1 = {1.0f, 0.0f, 0.0f};
    c.radius_m = 0.2f;
    c.inflation_m = 0.01f;
    return c;
}

// A small cloth (n x n, `size` m) flat at height y, centred over the origin, nothing pinned.
scenes::GridMesh small_cloth(uint32_t n, float size, float y) { return scenes::make_grid(n, size, size, false, y); }

}  // namespace

TEST_CASE("plane: a particle comes to rest on the inflated plane, never below it") {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        Points pts({{0.0f, 0.5f, 0.0f}, {0.3f, 0.02f, -0.2f}});
        ColliderDesc plane;
        plane.shape = ColliderShape::plane;
        plane.p0 = {0.0f, 0.0f, 0.0f};
        plane.p1 = {0.0f, 1.0f, 0.0f};
        plane.inflation_m = 0.02f;
        ColliderWorld w(pts.cooked.asset(), {plane}, path);
        for (int i = 0; i < 100; ++i) {
            w.step_once();
            for (const Vec3& p : w.positions()) REQUIRE(p.y >= 0.02f - 1e-6f);
        }
        for (const Vec3& p : w.positions()) CHECK(p.y == doctest::Approx(0.02f).epsilon(1e-4));
        const std::vector<Vec3> p = w.positions();
        CHECK(p[0].x == 0.0f);  // straight down, no sideways push
        CHECK(p[0].z == 0.0f);
    }
}

TEST_CASE("plane: a cloth lands on a tilted plane and stays on its positive side") {
    const scenes::GridMesh grid = small_cloth(15, 0.8f, 0.6f);
    const CookedCloth cooked = cook(grid.desc());
    ColliderDesc plane;
    plane.shape = ColliderShape::plane;
    plane.p0 = {0.0f, 0.0f, 0.0f};
    const float s = std::sin(0.3f), c = std::cos(0.3f);
    plane.p1 = {s, c, 0.0f};
    plane.inflation_m = 0.01f;
    ColliderWorld w(cooked.asset(), {plane});
    double lowest = 1e9;
    for (int i = 0; i < 80; ++i) {
        w.step_once();
        for (const Vec3& p : w.positions()) lowest = std::min(lowest, double(p.x) * s + double(p.y) * c);
    }
    CHECK(lowest >= 0.01 - 1e-5);
    CHECK(lowest <= 0.011);  // it did land
}

TEST_CASE("capsule: particles rest on top and slide off the end cap, never inside") {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        const ColliderDesc capsule = horizontal_segment(ColliderShape::capsule);
        const float r = capsule.radius_m + capsule.inflation_m;
        // On top of the middle, above the end cap (beyond p1), and just inside the axis end.
        Points pts({{0.0f, 0.5f, 0.0f}, {1.1f, 0.5f, 0.0f}, {0.95f, 0.5f, 0.0f}});
        ColliderWorld w(pts.cooked.asset(), {capsule}, path);
        double closest_cap = 1e9;
        for (int i = 0; i < 100; ++i) {
            w.step_once();
            const std::vector<Vec3> p = w.positions();
            for (const Vec3& x : p) REQUIRE(segment_distance(x, capsule.p0, capsule.p1, true) >= r - 1e-5);
            closest_cap = std::min(closest_cap, segment_distance(p[1], capsule.p0, capsule.p1, true));
        }
        const std::vector<Vec3> p = w.positions();
        CHECK(p[0].y == doctest::Approx(r).epsilon(1e-4));  // resting on top
        CHECK(p[0].x == 0.0f);
        CHECK(p[2].y == doctest::Approx(r).epsilon(1e-4));
        CHECK(closest_cap < r + 1e-3);  // the end cap caught the particle beyond the axis end ...
        CHECK(p[1].x > 1.1f);           // ... and it slid off outwards
    }
}

TEST_CASE("cylinder: no contact beyond the axis ends (eq. 6), contact along the axis") {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        const ColliderDesc cylinder = horizontal_segment(ColliderShape::cylinder);
        const float r = cylinder.radius_m + cylinder.inflation_m;
        Points pts({{0.0f, 0.5f, 0.0f}, {1.1f, 0.5f, 0.0f}, {0.95f, 0.5f, 0.0f}, {-1.05f, 0.5f, 0.1f}});
        ColliderWorld w(pts.cooked.asset(), {cylinder}, path);
        for (int i = 0; i < 100; ++i) {
            w.step_once();
            for (const Vec3& x : w.positions()) {
                double t = 0.0;
                const double d = segment_distance(x, cylinder.p0, cylinder.p1, false, &t);
                if (t > 0.0 && t < 1.0) REQUIRE(d >= r - 1e-5);
            }
        }
        const std::vector<Vec3> p = w.positions();
        CHECK(p[0].y == doctest::Approx(r).epsilon(1e-4));  // on top of the middle
        CHECK(p[2].y == doctest::Approx(r).epsilon(1e-4));  // on top, near the end
        // Beyond either end: free fall, untouched (x and z exactly as they started).
        CHECK(p[1].x == 1.1f);
        CHECK(p[1].z == 0.0f);
        CHECK(p[1].y < -1.0f);
        CHECK(p[3].x == -1.05f);
        CHECK(p[3].z == 0.1f);
        CHECK(p[3].y < -1.0f);
    }
}

TEST_CASE("capsule and cylinder: a draped cloth stays outside the inflated shape") {
    const scenes::GridMesh grid = small_cloth(20, 1.0f, 0.6f);
    const CookedCloth cooked = cook(grid.desc());
    for (ColliderShape shape : {ColliderShape::capsule, ColliderShape::cylinder}) {
        for (SimdPath path : available_paths()) {
            CAPTURE(int(shape));
            const std::string path_name = simd_path_name(path);
            CAPTURE(path_name);
            ColliderDesc c = horizontal_segment(shape);
            c.p0 = {-1.5f, 0.0f, 0.0f};  // longer than the cloth is wide
            c.p1 = {1.5f, 0.0f, 0.0f};
            const float r = c.radius_m + c.inflation_m;
            ColliderWorld w(cooked.asset(), {c}, path);
            double closest = 1e9;
            for (int i = 0; i < 100; ++i) {
                w.step_once();
                const std::vector<Vec3> p = w.positions();
                REQUIRE(all_finite(p));
                for (const Vec3& x : p) closest = std::min(closest, segment_distance(x, c.p0, c.p1, true));
            }
            CHECK(closest >= r - 1e-5);
            CHECK(closest < r + 2e-3);  // draped over it
        }
    }
}

TEST_CASE("sphere collider: a particle dropped off-centre ends outside, a centred one rests on top") {
    Points pts({{0.0f, 1.0f, 0.0f}, {0.1f, 1.0f, 0.05f}});
    ColliderDesc sphere;
    sphere.p0 = {0.0f, 0.0f, 0.0f};
    sphere.radius_m = 0.5f;
    sphere.inflation_m = 0.01f;
    ColliderWorld w(pts.cooked.asset(), {sphere});
    for (int i = 0; i < 100; ++i) {
        w.step_once();
        for (const Vec3& x : w.positions())
            REQUIRE(std::sqrt(double(x.x) * x.x + double(x.y) * x.y + double(x.z) * x.z) >= 0.51 - 1e-5);
    }
    const std::vector<Vec3> p = w.positions();
    CHECK(p[0].y == doctest::Approx(0.51f).epsilon(1e-4));
    CHECK(p[1].y < 0.0f);  // slid off (frictionless) and fell
}

namespace {

// A cloth lying on a plane tilted by `degrees` about z, with friction `mu`. Returns how far its
// centroid moves over `steps` steps after `settle` steps of settling.
double incline_slide(float degrees, float mu, uint32_t settle, uint32_t steps, SimdPath path = SimdPath::automatic) {
    const float a = degrees * 3.14159265f / 180.0f;
    const float s = std::sin(a), c = std::cos(a);
    scenes::GridMesh grid = small_cloth(10, 0.5f, 0.0f);
    const float lift = 0.005f;  // the plane's inflation: the cloth starts on the skin
    for (Vec3& p : grid.positions) {
        const float x = p.x;
        p.x = x * c - s * lift;  // rotate about z, then lift along the normal (-sin, cos, 0)
        p.y = x * s + c * lift;
    }
    const CookedCloth cooked = cook(grid.desc());
    ColliderDesc plane;
    plane.shape = ColliderShape::plane;
    plane.p0 = {0.0f, 0.0f, 0.0f};
    plane.p1 = {-s, c, 0.0f};
    plane.inflation_m = lift;
    plane.friction = mu;
    ColliderWorld w(cooked.asset(), {plane}, path);
    auto centroid = [&] {
        double x = 0, y = 0, z = 0;
        const std::vector<Vec3> p = w.positions();
        for (const Vec3& v : p) x += v.x, y += v.y, z += v.z;
        return Vec3{float(x / p.size()), float(y / p.size()), float(z / p.size())};
    };
    for (uint32_t i = 0; i < settle; ++i) w.step_once();
    const Vec3 c0 = centroid();
    for (uint32_t i = 0; i < steps; ++i) {
        w.step_once();
        for (const Vec3& v : w.positions()) REQUIRE(double(v.y) * c - double(v.x) * s >= lift - 1e-5);
    }
    const Vec3 c1 = centroid();
    return std::sqrt(double(c1.x - c0.x) * (c1.x - c0.x) + double(c1.y - c0.y) * (c1.y - c0.y) +
                     double(c1.z - c0.z) * (c1.z - c0.z));
}

}  // namespace

TEST_CASE("friction: a cloth on a 30 degree incline sticks with friction 1 and slides with friction 0") {
    for (SimdPath path : available_paths()) {
        const std::string path_name = simd_path_name(path);
        CAPTURE(path_name);
        const double sticking = incline_slide(30.0f, 1.0f, 20, 100, path);
        const double sliding = incline_slide(30.0f, 0.0f, 20, 100, path);
        MESSAGE(path_name, ": centroid moved over 100 steps on a 30 degree incline: friction 1 ",
                sticking, " m, friction 0 ", sliding, " m");
        CHECK(sticking < 0.01);  // tan 30 = 0.577 < 1: static friction holds
        CHECK(sliding > 1.0);    // frictionless: a = g sin 30 = 4.9 m/s^2 for 3.3 s
    }
}

TEST_CASE("friction: the Coulomb threshold sits at tan(angle)") {
    // 30 degrees: tan = 0.577. Friction 0.7 holds, 0.4 lets it slide (slower than frictionless).
    const double holds = incline_slide(30.0f, 0.7f, 20, 100);
    const double slides = incline_slide(30.0f, 0.4f, 20, 100);
    const double free = incline_slide(30.0f, 0.0f, 20, 100);
    MESSAGE("30 degree incline, centroid moved over 100 steps: friction 0.7 ", holds, " m, 0.4 ", slides,
            " m, 0 ", free, " m");
    CHECK(holds < 0.01);
    CHECK(slides > 0.1);
    CHECK(slides < free);
}

TEST_CASE("friction: a moving plane carries a sticking cloth along") {
    // set_collider's motion drives friction relative to the collider.
    scenes::GridMesh grid = small_cloth(8, 0.4f, 0.005f);
    const CookedCloth cooked = cook(grid.desc());
    ColliderDesc plane;
    plane.shape = ColliderShape::plane;
    plane.p0 = {0.0f, 0.0f, 0.0f};
    plane.p1 = {0.0f, 1.0f, 0.0f};
    plane.inflation_m = 0.005f;
    plane.friction = 1.0f;
    ColliderWorld w(cooked.asset(), {plane});
    for (int i = 0; i < 10; ++i) w.step_once();
    const std::vector<Vec3> before = w.positions();
    // Slide the plane along x at 0.5 m/s for 20 steps.
    for (int i = 1; i <= 20; ++i) {
        plane.p0.x = 0.5f * kDt * float(i);
        REQUIRE(set_collider(w.owned.world, ColliderId{0}, plane).ok());
        w.step_once();
    }
    const std::vector<Vec3> after = w.positions();
    double moved = 0.0;
    for (size_t i = 0; i < after.size(); ++i) moved += double(after[i].x - before[i].x) / after.size();
    MESSAGE("plane moved ", plane.p0.x, " m; cloth moved ", moved, " m");
    CHECK(moved > 0.5 * plane.p0.x);
    CHECK(moved < 1.5 * plane.p0.x);
}

// A collider whose box misses the cloth's is skipped for that cloth and substep: the same bits as
// a world without it, while one the cloth falls onto is skipped only until the cloth reaches it.
TEST_CASE("colliders: one out of the cloth's reach is skipped, to the bit of not having it") {
    const scenes::GridMesh grid = small_cloth(12, 0.6f, 0.5f);
    const CookedCloth cooked = cook(grid.desc());
    ColliderDesc sphere;  // under the cloth: it falls onto it
    sphere.p0 = {0.0f, 0.0f, 0.0f};
    sphere.radius_m = 0.3f;
    ColliderDesc far_capsule = horizontal_segment(ColliderShape::capsule);
    far_capsule.p0 = {3.0f, 0.5f, 0.0f};  // beside the cloth, 2.4 m off its edge
    far_capsule.p1 = {3.0f, 1.5f, 0.0f};
    ColliderDesc far_plane;
    far_plane.shape = ColliderShape::plane;
    far_plane.p0 = {0.0f, -2.0f, 0.0f};  // a floor 2 m below
    far_plane.p1 = {0.0f, 1.0f, 0.0f};
    for (SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        ColliderWorld with(cooked.asset(), {sphere, far_capsule, far_plane}, path);
        ColliderWorld without(cooked.asset(), {sphere}, path);
        uint64_t skipped_first = 0, skipped_landed = 0;
        for (int i = 0; i < 60; ++i) {
            with.step_once();
            without.step_once();
            const uint64_t skipped = world_stats(with.owned.world).colliders_skipped;
            if (i == 0) skipped_first = skipped;
            if (i == 19) skipped_landed = skipped;  // a third of a second: fallen 0.2 m onto it
        }
        CHECK(same_bits(with.positions(), without.positions()));
        SolverSplit split;
        REQUIRE(cloth_solver_split(with.owned.world, with.cloth, &split).ok());
        CHECK(skipped_first == 3 * split.substeps);  // 0.2 m above the sphere: all three
        CHECK(skipped_landed == 2 * split.substeps);  // on the sphere: the far two
    }
}

// A collider stands where it was at each substep's end, as the body's hull and the character carry
// do: a cloth carried fully (inertia 0) by a root that moves with its collider drapes as it does on
// the still collider. With the collider at its end-of-step pose in every substep, the sphere ran
// ahead of the carried cloth by up to 2/3 of a step's motion and shoved it.
TEST_CASE("colliders: a cloth carried fully with its moving sphere drapes as on the still one, substep by substep") {
    scenes::SceneOptions o;
    o.n = 20;
    o.sweeps = 6;  // held by a collider: 3 substeps x 2 iterations
    const scenes::Scene scene = scenes::seed_scene(scenes::SeedScene::sphere, o);
    scenes::SceneWorld still, moving;
    REQUIRE(scenes::build_scene(scene, &still).empty());
    REQUIRE(scenes::build_scene(scene, &moving).empty());
    ClothDesc carried = moving.cloths[0].desc;
    carried.linear_inertia = carried.angular_inertia = 0.0f;
    REQUIRE(set_cloth_settings(moving.world, moving.cloths[0].id, carried).ok());
    REQUIRE(set_cloth_root(moving.world, moving.cloths[0].id, {}).ok());  // where the carry starts
    ColliderDesc sphere = scene.colliders[0];
    const float speed_m_s = 6.0f;  // a sprint: 20 cm a step at the seed's 1/30 s
    const uint32_t n = moving.cloths[0].asset->particle_count;
    double worst_m = 0.0;
    for (uint32_t frame = 1; frame <= 45; ++frame) {
        const Vec3 at{speed_m_s * scene.dt_s * float(frame), 0.0f, 0.0f};
        sphere.p0 = {scene.colliders[0].p0.x + at.x, scene.colliders[0].p0.y, scene.colliders[0].p0.z};
        REQUIRE(set_collider(moving.world, moving.colliders[0], sphere).ok());
        REQUIRE(set_cloth_root(moving.world, moving.cloths[0].id, {at, {}}).ok());
        REQUIRE(step(still.world, scene.dt_s).ok());
        REQUIRE(step(moving.world, scene.dt_s).ok());
        const std::vector<Vec3> a = read_all(still.world, still.cloths[0].id, n);
        const std::vector<Vec3> b = read_all(moving.world, moving.cloths[0].id, n);
        for (uint32_t p = 0; p < n; ++p)
            worst_m = std::max({worst_m, double(std::fabs(b[p].x - at.x - a[p].x)), double(std::fabs(b[p].y - a[p].y)),
                                double(std::fabs(b[p].z - a[p].z))});
    }
    MESSAGE("farthest particle from the still drape's: ", worst_m * 1000.0, " mm");
    CHECK(worst_m < 0.002);
}
