// A finer render mesh driven by the cloth (ClothAsset::render, WorldDesc::render_meshes): bound by
// barycentric weights and an offset along the normal (bind_render_mesh), it follows the cloth, the
// same bits on every SIMD path.
#include <algorithm>

#include "common/scene.h"
#include "support/test_support.h"

namespace weft {
namespace {

using test::OwnedWorld;

// A grid cloth with a render mesh (its triangles subdivided `levels` times), in a world with render
// meshes, optionally over a sphere.
struct RenderWorld : test::OneClothWorld {
    uint32_t vertices = 0;
};

void make_render_world(const ClothMeshDesc& mesh, uint32_t levels, SimdPath path, bool sphere, RenderWorld& out) {
    out.cooked = test::cook(mesh);
    RenderMeshSource fine;
    REQUIRE(subdivide_cloth_mesh(out.cooked.asset(), levels, &fine).ok());
    double error_m = 1.0;
    REQUIRE(bind_render_mesh(fine.desc(), &out.cooked, &error_m).ok());
    CHECK(error_m < 1e-6);
    out.vertices = out.cooked.asset().render.vertex_count;
    WorldDesc desc = test::world_for({&out.cooked.asset()}, 0, path);
    desc.render_meshes = true;
    test::make_one_cloth_world(desc, sphere, out);
}

void read_render(const RenderWorld& w, std::vector<Vec3>& x, std::vector<Vec3>& n) {
    x.assign(w.vertices, {});
    n.assign(w.vertices, {});
    REQUIRE(read_render_mesh(w.owned.world, w.cloth, x.data(), n.data(), w.vertices).ok());
}

double distance(Vec3 a, Vec3 b) {
    const double dx = double(a.x) - b.x, dy = double(a.y) - b.y, dz = double(a.z) - b.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// Distance from p to triangle (a, b, c), double: the plane's when p projects inside, else an edge's.
double distance_to_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    auto segment = [](Vec3 p, Vec3 a, Vec3 b) {
        const double ab[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
        const double ap[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
        const double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        const double t = l2 > 0 ? std::clamp((ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / l2, 0.0, 1.0) : 0.0;
        const double d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
        return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    };
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double ap[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (n2 > 0) {
        // Barycentric of p's projection: inside when all three are >= 0.
        const double h = (ap[0] * n[0] + ap[1] * n[1] + ap[2] * n[2]) / n2;
        const double q[3] = {ap[0] - h * n[0], ap[1] - h * n[1], ap[2] - h * n[2]};
        auto cross_dot = [&](const double* u, const double* v) {
            return (u[1] * v[2] - u[2] * v[1]) * n[0] + (u[2] * v[0] - u[0] * v[2]) * n[1] + (u[0] * v[1] - u[1] * v[0]) * n[2];
        };
        const double w2 = cross_dot(e1, q) / n2, w1 = cross_dot(q, e2) / n2;
        if (w1 >= 0 && w2 >= 0 && w1 + w2 <= 1) return std::fabs(h) * std::sqrt(n2);
    }
    return std::min({segment(p, a, b), segment(p, b, c), segment(p, c, a)});
}

TEST_CASE("render mesh: the cloth's own mesh (no subdivision) reproduces the particles within 1e-6 m, at rest and draped") {
    const scenes::GridMesh grid = scenes::make_grid(16, 1.0f, 1.0f, false, 1.0f);
    for (SimdPath path : test::available_paths()) {
        RenderWorld w;
        make_render_world(grid.desc(), 0, path, true, w);
        const ClothAsset& a = w.cooked.asset();
        CHECK(w.vertices == a.particle_count);  // no uv: one render vertex a particle
        // Each render vertex sits on a corner of its triangle: that corner's particle.
        std::vector<uint32_t> particle(w.vertices);
        for (uint32_t v = 0; v < w.vertices; ++v) {
            const float w1 = a.render.weight_1[v], w2 = a.render.weight_2[v];
            const uint32_t k = w1 == 1.0f ? 1 : w2 == 1.0f ? 2 : 0;
            particle[v] = a.particle_of_slot[a.triangles[3 * a.render.cloth_triangle[v] + k]];
            CHECK(a.render.offset_m[v] == 0.0f);
        }
        for (int frame = 0; frame <= 60; ++frame) {
            if (frame % 30 == 0) {
                std::vector<Vec3> x, n;
                read_render(w, x, n);
                const std::vector<Vec3> p = test::read_all(w.owned.world, w.cloth, a.particle_count);
                std::vector<Vec3> pn(a.particle_count);
                REQUIRE(read_normals(w.owned.world, w.cloth, pn.data(), a.particle_count).ok());
                double worst = 0, worst_normal = 0;
                for (uint32_t v = 0; v < w.vertices; ++v) {
                    worst = std::max(worst, distance(x[v], p[particle[v]]));
                    worst_normal = std::max(worst_normal, distance(n[v], pn[particle[v]]));
                }
                INFO("frame ", frame, " path ", int(path));
                CHECK(worst < 1e-6);
                CHECK(worst_normal < 1e-6);
            }
            REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
        }
    }
}

TEST_CASE("render mesh: a subdivided render mesh stays on the cloth's surface as it drapes over a sphere") {
    const scenes::GridMesh grid = scenes::make_grid(16, 1.0f, 1.0f, false, 1.0f);
    for (bool lattice : {true, false}) {
        ClothMeshDesc mesh = grid.desc();
        if (!lattice) mesh.lattice = nullptr;
        for (SimdPath path : test::available_paths()) {
            RenderWorld w;
            make_render_world(mesh, 2, path, true, w);
            const ClothAsset& a = w.cooked.asset();
            CHECK(a.render.triangle_count == 16 * a.triangle_count);
            for (int frame = 0; frame < 60; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
            std::vector<Vec3> x, n;
            read_render(w, x, n);
            const std::vector<Vec3> p = test::read_all(w.owned.world, w.cloth, a.particle_count);
            std::vector<uint32_t> tri(3 * size_t(a.triangle_count));
            REQUIRE(read_triangles(a, tri.data(), uint32_t(tri.size())).ok());
            double worst = 0, lowest_y = 1.0, worst_unit = 0;
            for (uint32_t v = 0; v < w.vertices; ++v) {
                double nearest = 1e9;
                for (size_t t = 0; t < tri.size(); t += 3)
                    nearest = std::min(nearest, distance_to_triangle(x[v], p[tri[t]], p[tri[t + 1]], p[tri[t + 2]]));
                worst = std::max(worst, nearest);
                lowest_y = std::min(lowest_y, double(n[v].y));
                worst_unit = std::max(worst_unit, std::fabs(distance(n[v], {}) - 1.0));
            }
            INFO("lattice ", lattice, " path ", int(path));
            CHECK(worst < 1e-6);       // on the surface (offset 0)
            CHECK(worst_unit < 1e-6);  // unit normals
            CHECK(lowest_y < 0.5);     // the cloth did fold over the sphere
        }
    }
}

TEST_CASE("render mesh: a vertex bound off the surface keeps its offset along the normal") {
    // The grid's own mesh lifted 3 mm along its normal (+y): offset 3 mm, reconstructed exactly at rest.
    const scenes::GridMesh grid = scenes::make_grid(8, 1.0f, 1.0f, false, 1.0f);
    CookedCloth cooked = test::cook(grid.desc());
    RenderMeshSource fine;
    REQUIRE(subdivide_cloth_mesh(cooked.asset(), 1, &fine).ok());
    for (Vec3& x : fine.positions) x.y += 0.003f;
    double error_m = 1.0;
    REQUIRE(bind_render_mesh(fine.desc(), &cooked, &error_m).ok());
    CHECK(error_m < 1e-6);
    for (uint32_t v = 0; v < cooked.asset().render.vertex_count; ++v)
        CHECK(cooked.asset().render.offset_m[v] == doctest::Approx(0.003f).epsilon(1e-4));
    WorldDesc desc = test::world_for({&cooked.asset()});
    desc.render_meshes = true;
    OwnedWorld owned;
    REQUIRE(test::make_world(desc, &owned).ok());
    ClothDesc cloth;
    cloth.asset = &cooked.asset();
    ClothId id;
    REQUIRE(add_cloth(owned.world, cloth, &id).ok());
    std::vector<Vec3> x(fine.positions.size());
    REQUIRE(read_render_mesh(owned.world, id, x.data(), nullptr, uint32_t(x.size())).ok());
    for (size_t v = 0; v < x.size(); ++v) CHECK(distance(x[v], fine.positions[v]) < 1e-6);
}

TEST_CASE("render mesh: the scalar and AVX2 paths give the same bits") {
    if (test::available_paths().size() < 2) return;
    const scenes::GridMesh grid = scenes::make_grid(16, 1.0f, 1.0f, false, 1.0f);
    for (bool lattice : {true, false}) {
        ClothMeshDesc mesh = grid.desc();
        if (!lattice) mesh.lattice = nullptr;
        RenderWorld scalar, avx2;
        make_render_world(mesh, 1, SimdPath::scalar, true, scalar);
        make_render_world(mesh, 1, SimdPath::avx2, true, avx2);
        for (int frame = 0; frame < 40; ++frame) {
            REQUIRE(step(scalar.owned.world, 1.0f / 60.0f).ok());
            REQUIRE(step(avx2.owned.world, 1.0f / 60.0f).ok());
        }
        std::vector<Vec3> xs, ns, xa, na;
        read_render(scalar, xs, ns);
        read_render(avx2, xa, na);
        CHECK(test::same_bits(xs, xa));
        CHECK(test::same_bits(ns, na));
    }
}

TEST_CASE("render mesh: refused without the feature, without a render mesh or with a wrong count, and reset_cloth restores it") {
    const scenes::GridMesh grid = scenes::make_grid(8, 1.0f, 1.0f, false, 1.0f);
    RenderWorld w;
    make_render_world(grid.desc(), 1, SimdPath::automatic, true, w);
    std::vector<Vec3> start, start_n, x, n;
    read_render(w, start, start_n);
    for (int frame = 0; frame < 30; ++frame) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
    read_render(w, x, n);
    CHECK_FALSE(test::same_bits(x, start));
    REQUIRE(reset_cloth(w.owned.world, w.cloth).ok());
    read_render(w, x, n);
    CHECK(test::same_bits(x, start));
    CHECK(read_render_mesh(w.owned.world, w.cloth, x.data(), nullptr, w.vertices - 1).code == ErrorCode::out_of_range);
    CHECK(read_render_mesh(w.owned.world, w.cloth, nullptr, n.data(), w.vertices).code == ErrorCode::invalid_argument);
    CHECK(read_render_mesh(nullptr, w.cloth, x.data(), nullptr, w.vertices).code == ErrorCode::invalid_argument);

    // A world without the feature: refused, no render pass, and no bytes for it.
    WorldDesc desc = test::world_for({&w.cooked.asset()});
    OwnedWorld plain;
    REQUIRE(test::make_world(desc, &plain).ok());
    REQUIRE(set_profiling(plain.world, true).ok());
    ClothDesc cloth;
    cloth.asset = &w.cooked.asset();
    ClothId id;
    REQUIRE(add_cloth(plain.world, cloth, &id).ok());
    CHECK(read_render_mesh(plain.world, id, x.data(), nullptr, w.vertices).code == ErrorCode::invalid_argument);
    REQUIRE(step(plain.world, 1.0f / 60.0f).ok());
    CHECK(world_stats(plain.world).pass_ns[int(Pass::render_mesh)] == 0);
    WorldDesc with = desc;
    with.render_meshes = true;
    CHECK(world_memory_requirements(with).bytes >= world_memory_requirements(desc).bytes + 6 * sizeof(float) * w.vertices);

    // A cloth whose asset has no render mesh in a world with the feature: refused by name.
    const CookedCloth bare = test::cook(grid.desc());
    WorldDesc both = test::world_for({&w.cooked.asset(), &bare.asset()});
    both.render_meshes = true;
    OwnedWorld owned;
    REQUIRE(test::make_world(both, &owned).ok());
    cloth.asset = &bare.asset();
    REQUIRE(add_cloth(owned.world, cloth, &id).ok());
    const Result r = read_render_mesh(owned.world, id, x.data(), nullptr, w.vertices);
    CHECK(r.code == ErrorCode::invalid_argument);
    CHECK(std::string(r.message).find("no render mesh") != std::string::npos);

    // Bad input to the binder: refused with a message, the cloth unchanged.
    CookedCloth target = test::cook(grid.desc());
    const Vec3 far[3] = {{0, 50, 0}, {1, 50, 0}, {0, 50, 1}};
    const uint32_t one[3] = {0, 1, 2}, bad[3] = {0, 1, 3};
    CHECK(bind_render_mesh({3, far, nullptr, 1, one}, &target).code == ErrorCode::out_of_range);
    CHECK(bind_render_mesh({3, far, nullptr, 1, bad}, &target).code == ErrorCode::out_of_range);
    CHECK(target.asset().render.vertex_count == 0);
}

}  // namespace
}  // namespace weft
