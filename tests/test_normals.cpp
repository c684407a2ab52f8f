// The step's render output (WorldDesc::normals, WorldDesc::tangents): unit, area-weighted vertex
// normals and tangents from the uv in the caller's particle order, the same bits on every SIMD path.
#include "common/scene.h"
#include "support/test_support.h"

namespace weft {
namespace {

using test::OwnedWorld;
using NormalsWorld = test::OneClothWorld;

// A cloth of one cooked mesh in a world with the normals feature (and, optionally, a sphere).
void make_normals_world(const ClothMeshDesc& mesh, SimdPath path, bool sphere, NormalsWorld& out) {
    out.cooked = test::cook(mesh);
    WorldDesc desc = test::world_for({&out.cooked.asset()}, 0, path);
    desc.normals = true;
    test::make_one_cloth_world(desc, sphere, out);
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

// --- tangents ------------------------------------------------------------------------------------

// A grid's uv: (x, sign_v * z) metres.
std::vector<float> grid_uv(const scenes::GridMesh& grid, float sign_v) {
    std::vector<float> uv;
    for (const Vec3& x : grid.positions) uv.insert(uv.end(), {x.x, sign_v * x.z});
    return uv;
}

using TangentWorld = test::OneClothWorld;

void make_tangent_world(const ClothMeshDesc& mesh, SimdPath path, bool sphere, TangentWorld& out, bool tangents = true) {
    out.cooked = test::cook(mesh);
    WorldDesc desc = test::world_for({&out.cooked.asset()}, 0, path);
    desc.normals = true;
    desc.tangents = tangents;
    test::make_one_cloth_world(desc, sphere, out);
}

std::vector<Vec4> tangents_of(const TangentWorld& w) {
    std::vector<Vec4> t(w.cooked.asset().particle_count);
    REQUIRE(read_tangents(w.owned.world, w.cloth, t.data(), uint32_t(t.size())).ok());
    return t;
}

bool same_bits(const std::vector<Vec4>& a, const std::vector<Vec4>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(Vec4) * a.size()) == 0;
}

// Lengyel's tangents in double from the caller's triangles, positions and uv: per triangle
// (t2 e1 - t1 e2) sign(r) and (s1 e2 - s2 e1) sign(r), summed, Gram-Schmidt against `normal`.
std::vector<Vec4> reference_tangents(const ClothMeshDesc& mesh, const std::vector<Vec3>& x, const std::vector<Vec3>& normal) {
    std::vector<double> sum_t(3 * x.size(), 0.0), sum_b(3 * x.size(), 0.0);
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        const double e1[3] = {double(x[v[1]].x) - x[v[0]].x, double(x[v[1]].y) - x[v[0]].y, double(x[v[1]].z) - x[v[0]].z};
        const double e2[3] = {double(x[v[2]].x) - x[v[0]].x, double(x[v[2]].y) - x[v[0]].y, double(x[v[2]].z) - x[v[0]].z};
        const float* uv = mesh.uv;
        const double s1 = double(uv[2 * v[1]]) - uv[2 * v[0]], t1 = double(uv[2 * v[1] + 1]) - uv[2 * v[0] + 1];
        const double s2 = double(uv[2 * v[2]]) - uv[2 * v[0]], t2 = double(uv[2 * v[2] + 1]) - uv[2 * v[0] + 1];
        const double r = s1 * t2 - s2 * t1, sign = r > 0 ? 1.0 : r < 0 ? -1.0 : 0.0;
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) {
                sum_t[3 * v[k] + a] += sign * (t2 * e1[a] - t1 * e2[a]);
                sum_b[3 * v[k] + a] += sign * (s1 * e2[a] - s2 * e1[a]);
            }
    }
    std::vector<Vec4> out(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double n[3] = {normal[i].x, normal[i].y, normal[i].z};
        const double along = n[0] * sum_t[3 * i] + n[1] * sum_t[3 * i + 1] + n[2] * sum_t[3 * i + 2];
        const double t[3] = {sum_t[3 * i] - n[0] * along, sum_t[3 * i + 1] - n[1] * along, sum_t[3 * i + 2] - n[2] * along};
        const double l = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        const double c[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
        const double side = c[0] * sum_b[3 * i] + c[1] * sum_b[3 * i + 1] + c[2] * sum_b[3 * i + 2];
        if (l > 0.0) out[i] = {float(t[0] / l), float(t[1] / l), float(t[2] / l), side < 0.0 ? -1.0f : 1.0f};
    }
    return out;
}

TEST_CASE("tangents: a flat sheet with u along x has tangent (1, 0, 0), w from the side v runs to") {
    const scenes::GridMesh grid = scenes::make_grid(12, 1.0f, 1.0f, false, 1.0f);
    for (float sign_v : {1.0f, -1.0f}) {
        const std::vector<float> uv = grid_uv(grid, sign_v);
        ClothMeshDesc mesh = grid.desc();
        mesh.uv = uv.data();
        for (SimdPath path : test::available_paths()) {
            TangentWorld w;
            make_tangent_world(mesh, path, false, w);
            // Normal +y: cross(n, +x) = -z, so v along +z is the mirrored side (w = -1).
            for (const Vec4& t : tangents_of(w)) {
                CHECK(t.x == doctest::Approx(1.0f).epsilon(1e-6));
                CHECK(t.y == 0.0f);
                CHECK(std::fabs(t.z) < 1e-6f);
                CHECK(t.w == -sign_v);
            }
        }
    }
}

TEST_CASE("tangents follow a cloth draped on a sphere, as double-precision Lengyel tangents") {
    const scenes::GridMesh grid = scenes::make_grid(24, 1.0f, 1.0f, false, 1.0f);
    const std::vector<float> uv = grid_uv(grid, -1.0f);
    for (bool lattice : {true, false}) {  // runs and vector loads; every triangle gathered
        ClothMeshDesc mesh = grid.desc();
        mesh.uv = uv.data();
        if (!lattice) mesh.lattice = nullptr;
        for (SimdPath path : test::available_paths()) {
            TangentWorld w;
            make_tangent_world(mesh, path, true, w);
            for (int frame = 0; frame < 60; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
            const std::vector<Vec3> x = test::read_all(w.owned.world, w.cloth, mesh.particle_count);
            std::vector<Vec3> n(x.size());
            REQUIRE(read_normals(w.owned.world, w.cloth, n.data(), uint32_t(n.size())).ok());
            const std::vector<Vec4> t = tangents_of(w), expected = reference_tangents(mesh, x, reference_normals(mesh, x));
            double worst = 1.0, worst_normal = 0.0, lowest_x = 1.0;
            uint32_t same_side = 0;
            for (size_t i = 0; i < t.size(); ++i) {
                const Vec3 ti{t[i].x, t[i].y, t[i].z}, ei{expected[i].x, expected[i].y, expected[i].z};
                CHECK(dot(ti, ti) == doctest::Approx(1.0).epsilon(1e-5));
                worst = std::min(worst, dot(ti, ei));
                worst_normal = std::max(worst_normal, std::fabs(dot(ti, n[i])));
                lowest_x = std::min(lowest_x, double(t[i].x));
                same_side += t[i].w == expected[i].w;
            }
            INFO("lattice ", lattice, " path ", int(path));
            CHECK(worst > 1.0 - 1e-5);        // within 0.26 degrees everywhere
            CHECK(worst_normal < 1e-5);       // orthogonal to the step's own normal
            CHECK(lowest_x < 0.9);            // the cloth did curve: not a flat sheet's tangents
            CHECK(same_side == t.size());
        }
    }
}

TEST_CASE("tangents: the scalar and AVX2 paths give the same bits, and the normals stay those of a world without tangents") {
    if (test::available_paths().size() < 2) return;
    const scenes::GridMesh grid = scenes::make_grid(24, 1.0f, 1.0f, false, 1.0f);
    const std::vector<float> uv = grid_uv(grid, 1.0f);
    for (bool lattice : {true, false}) {
        ClothMeshDesc mesh = grid.desc();
        mesh.uv = uv.data();
        if (!lattice) mesh.lattice = nullptr;
        TangentWorld scalar, avx2, plain;
        make_tangent_world(mesh, SimdPath::scalar, true, scalar);
        make_tangent_world(mesh, SimdPath::avx2, true, avx2);
        make_tangent_world(mesh, SimdPath::avx2, true, plain, false);
        for (int frame = 0; frame < 40; ++frame) {
            REQUIRE(step(scalar.owned.world, 1.0f / 60.0f).ok());
            REQUIRE(step(avx2.owned.world, 1.0f / 60.0f).ok());
            REQUIRE(step(plain.owned.world, 1.0f / 60.0f).ok());
        }
        CHECK(same_bits(tangents_of(scalar), tangents_of(avx2)));
        std::vector<Vec3> a(mesh.particle_count), b(mesh.particle_count);
        REQUIRE(read_normals(avx2.owned.world, avx2.cloth, a.data(), mesh.particle_count).ok());
        REQUIRE(read_normals(plain.owned.world, plain.cloth, b.data(), mesh.particle_count).ok());
        CHECK(test::same_bits(a, b));
        CHECK(test::same_bits(test::read_all(avx2.owned.world, avx2.cloth, mesh.particle_count),
                              test::read_all(plain.owned.world, plain.cloth, mesh.particle_count)));
    }
}

// Two panels sewn along one edge, flat in the xz plane: panel B's uv lies 10 m further along u, so
// a triangle given the other panel's uv at its seam corners would turn its tangent far off +x.
TEST_CASE("tangents: a triangle whose corners are sewn seam particles uses its own panel's uv") {
    // 0 --- 1 --- 2   (z = 0)      panel A: triangles (0, 3, 1), (1, 3, 4); panel B: (1, 4, 2), (2, 4, 5)
    // 3 --- 4 --- 5   (z = 0.1)    seam particles 1 and 4 (sewn: uv in A, then in B)
    const std::vector<Vec3> x = {{0, 0, 0}, {0.1f, 0, 0}, {0.2f, 0, 0}, {0, 0, 0.1f}, {0.1f, 0, 0.1f}, {0.2f, 0, 0.1f}};
    const std::vector<uint32_t> triangles = {0, 3, 1, 1, 3, 4, 1, 4, 2, 2, 4, 5};
    const std::vector<float> masses(6, 0.01f);
    const std::vector<float> uv = {0, 0, 0.1f, 0, 10.2f, 0, 0, -0.1f, 0.1f, -0.1f, 10.2f, -0.1f};
    const std::vector<uint32_t> sewn_particle = {1, 4}, sewn_uv_first = {0, 2, 4};
    const std::vector<float> sewn_uv = {0.1f, 0, 10.1f, 0, 0.1f, -0.1f, 10.1f, -0.1f};
    ClothMeshDesc mesh;
    mesh.particle_count = 6;
    mesh.positions = x.data();
    mesh.triangle_count = 4;
    mesh.triangles = triangles.data();
    mesh.masses = masses.data();
    mesh.uv = uv.data();
    mesh.sewn_point_count = 2;
    mesh.sewn_particle = sewn_particle.data();
    mesh.sewn_uv_first = sewn_uv_first.data();
    mesh.sewn_uv = sewn_uv.data();
    for (SimdPath path : test::available_paths()) {
        TangentWorld w;
        make_tangent_world(mesh, path, false, w);
        for (const Vec4& t : tangents_of(w)) {
            CHECK(t.x == doctest::Approx(1.0f).epsilon(1e-6));
            CHECK(std::fabs(t.y) < 1e-6f);
            CHECK(std::fabs(t.z) < 1e-6f);
            CHECK(t.w == 1.0f);
        }
    }
}

TEST_CASE("tangents: refused without the feature or without uv, reset_cloth restores them, and they cost 7 arrays a slot") {
    const scenes::GridMesh grid = scenes::make_grid(8, 1.0f, 1.0f, false, 1.0f);
    const std::vector<float> uv = grid_uv(grid, 1.0f);
    ClothMeshDesc mesh = grid.desc();
    mesh.uv = uv.data();
    TangentWorld w;
    make_tangent_world(mesh, SimdPath::automatic, true, w);
    const std::vector<Vec4> start = tangents_of(w);
    for (int frame = 0; frame < 30; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
    CHECK_FALSE(same_bits(tangents_of(w), start));
    REQUIRE(reset_cloth(w.owned.world, w.cloth).ok());
    CHECK(same_bits(tangents_of(w), start));
    std::vector<Vec4> out(grid.positions.size());
    CHECK(read_tangents(w.owned.world, w.cloth, out.data(), uint32_t(out.size()) - 1).code == ErrorCode::out_of_range);
    CHECK(read_tangents(w.owned.world, w.cloth, nullptr, uint32_t(out.size())).code == ErrorCode::invalid_argument);
    CHECK(read_tangents(nullptr, w.cloth, out.data(), uint32_t(out.size())).code == ErrorCode::invalid_argument);

    // A world with normals only: refused, no tangent arrays.
    TangentWorld normals_only;
    make_tangent_world(mesh, SimdPath::automatic, false, normals_only, false);
    CHECK(read_tangents(normals_only.owned.world, normals_only.cloth, out.data(), uint32_t(out.size())).code ==
          ErrorCode::invalid_argument);

    // Tangents imply normals; an asset without uv is refused by add_cloth, changing nothing.
    const CookedCloth bare = test::cook(grid.desc());
    WorldDesc desc = test::world_for({&bare.asset()});
    desc.tangents = true;
    OwnedWorld tangents_world;
    REQUIRE(test::make_world(desc, &tangents_world).ok());
    ClothDesc cloth;
    cloth.asset = &bare.asset();
    ClothId id;
    CHECK(add_cloth(tangents_world.world, cloth, &id).code == ErrorCode::invalid_argument);
    CHECK(world_usage(tangents_world.world).cloths == 0);
    cloth.asset = &w.cooked.asset();
    REQUIRE(add_cloth(tangents_world.world, cloth, &id).ok());
    std::vector<Vec3> n(grid.positions.size());
    CHECK(read_normals(tangents_world.world, id, n.data(), uint32_t(n.size())).ok());
    // A world with tangents costs 7 more arrays a slot and 4 floats a triangle lane.
    WorldDesc plain = desc;
    plain.tangents = false;
    plain.normals = true;
    CHECK(world_memory_requirements(desc).bytes >=
          world_memory_requirements(plain).bytes + 7 * sizeof(float) * w.cooked.asset().slot_count);
}

}  // namespace
}  // namespace weft
