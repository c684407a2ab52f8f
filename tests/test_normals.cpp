// The step's render output (WorldDesc::normals): unit, area-weighted vertex normals in the caller's
// particle order, the same bits on every SIMD path.
#include "common/scene.h"
#include "support/test_support.h"

namespace weft {
namespace {

using test::OwnedWorld;

// A cloth of one cooked mesh in a world with the normals feature (and, optionally, a sphere).
struct NormalsWorld {
    CookedCloth cooked;
    OwnedWorld owned;
    ClothId cloth;
};

void make_normals_world(const ClothMeshDesc& mesh, SimdPath path, bool sphere, NormalsWorld& out) {
    out.cooked = test::cook(mesh);
    WorldDesc desc = test::world_for({&out.cooked.asset()}, sphere ? 1 : 0, path);
    desc.normals = true;
    REQUIRE(test::make_world(desc, &out.owned).ok());
    ClothDesc cloth;
    cloth.asset = &out.cooked.asset();
    REQUIRE(add_cloth(out.owned.world, cloth, &out.cloth).ok());
    if (sphere) {
        ColliderDesc c;
        c.shape = ColliderShape::sphere;
        c.p0 = {0.1f, 0.5f, 0.05f};  // off-centre: the cloth slides and folds
        c.radius_m = 0.3f;
        c.inflation_m = 0.01f;
        ColliderId id;
        REQUIRE(add_collider(out.owned.world, c, &id).ok());
    }
}

std::vector<Vec3> normals_of(const NormalsWorld& w) {
    std::vector<Vec3> n(w.cooked.asset().particle_count);
    REQUIRE(read_normals(w.owned.world, w.cloth, n.data(), uint32_t(n.size())).ok());
    return n;
}

// Area-weighted vertex normals in double from the caller's triangles and positions.
std::vector<Vec3> reference_normals(const ClothMeshDesc& mesh, const std::vector<Vec3>& x) {
    std::vector<double> sum(3 * x.size(), 0.0);
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        const double e1[3] = {double(x[v[1]].x) - x[v[0]].x, double(x[v[1]].y) - x[v[0]].y, double(x[v[1]].z) - x[v[0]].z};
        const double e2[3] = {double(x[v[2]].x) - x[v[0]].x, double(x[v[2]].y) - x[v[0]].y, double(x[v[2]].z) - x[v[0]].z};
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) sum[3 * v[k] + a] += n[a];
    }
    std::vector<Vec3> out(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double l = std::sqrt(sum[3 * i] * sum[3 * i] + sum[3 * i + 1] * sum[3 * i + 1] + sum[3 * i + 2] * sum[3 * i + 2]);
        if (l > 0.0) out[i] = {float(sum[3 * i] / l), float(sum[3 * i + 1] / l), float(sum[3 * i + 2] / l)};
    }
    return out;
}

double dot(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

TEST_CASE("vertex normals: a flat grid's point up its winding's side, from add_cloth on") {
    const scenes::GridMesh grid = scenes::make_grid(12, 1.0f, 1.0f, false, 1.0f);
    for (SimdPath path : test::available_paths()) {
        NormalsWorld w;
        make_normals_world(grid.desc(), path, false, w);
        for (const Vec3& n : normals_of(w)) {  // +y: each triangle (a, d, b) turns from +z to +x
            CHECK(n.x == 0.0f);
            CHECK(n.y == doctest::Approx(1.0f).epsilon(1e-6));
            CHECK(n.z == 0.0f);
        }
    }
}

TEST_CASE("vertex normals follow a cloth draped on a sphere, as double-precision area-weighted normals") {
    const scenes::GridMesh grid = scenes::make_grid(24, 1.0f, 1.0f, false, 1.0f);
    for (bool lattice : {true, false}) {  // runs and vector loads; every triangle gathered
        ClothMeshDesc mesh = grid.desc();
        if (!lattice) mesh.lattice = nullptr;
        for (SimdPath path : test::available_paths()) {
            NormalsWorld w;
            make_normals_world(mesh, path, true, w);
            for (int frame = 0; frame < 60; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
            const std::vector<Vec3> x = test::read_all(w.owned.world, w.cloth, mesh.particle_count);
            const std::vector<Vec3> n = normals_of(w), expected = reference_normals(mesh, x);
            double worst = 1.0, lowest_y = 1.0;
            for (size_t i = 0; i < n.size(); ++i) {
                CHECK(dot(n[i], n[i]) == doctest::Approx(1.0).epsilon(1e-5));
                worst = std::min(worst, dot(n[i], expected[i]));
                lowest_y = std::min(lowest_y, double(n[i].y));
            }
            INFO("lattice ", lattice, " path ", int(path));
            CHECK(worst > 1.0 - 1e-5);  // within 0.26 degrees everywhere
            CHECK(lowest_y < 0.5);      // the cloth did fold over the sphere: not a flat sheet's normals
        }
    }
}

TEST_CASE("vertex normals: the scalar and AVX2 paths give the same bits") {
    if (test::available_paths().size() < 2) return;
    const scenes::GridMesh grid = scenes::make_grid(24, 1.0f, 1.0f, false, 1.0f);
    for (bool lattice : {true, false}) {
        ClothMeshDesc mesh = grid.desc();
        if (!lattice) mesh.lattice = nullptr;
        NormalsWorld scalar, avx2;
        make_normals_world(mesh, SimdPath::scalar, true, scalar);
        make_normals_world(mesh, SimdPath::avx2, true, avx2);
        for (int frame = 0; frame < 40; ++frame) {
            REQUIRE(step(scalar.owned.world, 1.0f / 60.0f).ok());
            REQUIRE(step(avx2.owned.world, 1.0f / 60.0f).ok());
        }
        CHECK(test::same_bits(normals_of(scalar), normals_of(avx2)));
    }
}

TEST_CASE("vertex normals: reset_cloth restores the start pose's, bad calls are refused") {
    const scenes::GridMesh grid = scenes::make_grid(8, 1.0f, 1.0f, false, 1.0f);
    NormalsWorld w;
    make_normals_world(grid.desc(), SimdPath::automatic, true, w);
    const std::vector<Vec3> start = normals_of(w);
    for (int frame = 0; frame < 30; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
    CHECK_FALSE(test::same_bits(normals_of(w), start));
    REQUIRE(reset_cloth(w.owned.world, w.cloth).ok());
    CHECK(test::same_bits(normals_of(w), start));

    std::vector<Vec3> out(grid.positions.size());
    CHECK(read_normals(w.owned.world, w.cloth, out.data(), uint32_t(out.size()) - 1).code == ErrorCode::out_of_range);
    CHECK(read_normals(w.owned.world, w.cloth, nullptr, uint32_t(out.size())).code == ErrorCode::invalid_argument);
    CHECK(read_normals(w.owned.world, ClothId{7}, out.data(), uint32_t(out.size())).code == ErrorCode::out_of_range);
    CHECK(read_normals(nullptr, w.cloth, out.data(), uint32_t(out.size())).code == ErrorCode::invalid_argument);

    // Without the feature: refused, no arrays, and no normals pass in the step.
    const CookedCloth cooked = test::cook(grid.desc());
    OwnedWorld plain;
    WorldDesc desc = test::world_for({&cooked.asset()});
    REQUIRE(test::make_world(desc, &plain).ok());
    REQUIRE(set_profiling(plain.world, true).ok());
    ClothDesc cloth;
    cloth.asset = &cooked.asset();
    ClothId id;
    REQUIRE(add_cloth(plain.world, cloth, &id).ok());
    CHECK(read_normals(plain.world, id, out.data(), uint32_t(out.size())).code == ErrorCode::invalid_argument);
    CHECK(test::view_of(plain.world, id).normal_x == nullptr);
    REQUIRE(step(plain.world, 1.0f / 60.0f).ok());
    CHECK(world_stats(plain.world).pass_ns[int(Pass::normals)] == 0);
    // A world with normals costs three more arrays a particle slot.
    WorldDesc with = desc;
    with.normals = true;
    CHECK(world_memory_requirements(with).bytes >= world_memory_requirements(desc).bytes + 3 * sizeof(float) * cooked.asset().slot_count);
}

}  // namespace
}  // namespace weft
