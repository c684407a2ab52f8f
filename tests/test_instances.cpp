// Instances that come and go (remove_cloth, remove_body, remove_collider): ids carry a generation so
// a removed instance's id is refused, the freed memory is taken by the next add, and when the gaps
// left behind are too small the live instances are compacted without changing a bit of their state.
#include <cstring>
#include <vector>

#include "body/body_mesh.h"
#include "weft/debug.h"
#include "common/skin_binding.h"
#include "support/test_support.h"

using namespace weft;
using namespace weft::test;

namespace {

struct Grid {
    scenes::GridMesh mesh;
    CookedCloth cooked;
    explicit Grid(uint32_t n, float y_m) : mesh(scenes::make_grid(n, 0.6f, 0.6f, false, y_m)) {
        ClothMeshDesc d;
        d.particle_count = uint32_t(mesh.positions.size());
        d.positions = mesh.positions.data();
        d.masses = mesh.masses.data();
        d.triangle_count = uint32_t(mesh.triangles.size() / 3);
        d.triangles = mesh.triangles.data();
        d.lattice = mesh.lattice.data();
        cooked = cook(d);
    }
    const ClothAsset& asset() const { return cooked.asset(); }
};

ClothId add(World* world, const ClothAsset& asset, float x_m) {
    ClothDesc cd;
    cd.asset = &asset;
    cd.translation_m = {x_m, 0.0f, 0.0f};
    ClothId id;
    const Result r = add_cloth(world, cd, &id);
    INFO(r.message);
    REQUIRE(r.ok());
    return id;
}

BodyId add_ball(World* world, const body::BodyMesh& ball) {
    BodyDesc bd;
    bd.positions = ball.positions.data();
    bd.vertex_count = uint32_t(ball.positions.size());
    bd.triangles = ball.triangles.data();
    bd.triangle_count = uint32_t(ball.triangles.size() / 3);
    BodyId id;
    const Result r = add_body(world, bd, &id);
    INFO(r.message);
    REQUIRE(r.ok());
    return id;
}

}  // namespace

TEST_CASE("a removed cloth's, body's and collider's ids are stale, and the next add takes the place with a new generation") {
    const Grid grid(8, 1.0f);
    const body::BodyMesh ball = body::make_icosphere({0.0f, 0.5f, 0.0f}, 0.2f, 2);
    WorldDesc desc;
    desc.max_cloths = 0;
    reserve_cloth(desc, grid.asset());
    reserve_cloth(desc, grid.asset());
    desc.max_colliders = 1;
    desc.max_bodies = 1;
    desc.max_body_vertices = uint32_t(ball.positions.size());
    desc.max_body_triangles = uint32_t(ball.triangles.size() / 3);
    OwnedWorld w;
    REQUIRE(make_world(desc, &w).ok());
    const WorldUsage empty = world_usage(w.world);

    const ClothId first = add(w.world, grid.asset(), 0.0f);
    const ClothId second = add(w.world, grid.asset(), 1.0f);
    const BodyId body = add_ball(w.world, ball);
    REQUIRE(set_cloth_body(w.world, first, body).ok());
    ColliderId ground;
    ColliderDesc plane;
    plane.shape = ColliderShape::plane;
    REQUIRE(add_collider(w.world, plane, &ground).ok());
    REQUIRE(step(w.world, 0.016f).ok());

    // A body a cloth still uses stays.
    CHECK(remove_body(w.world, body).code == ErrorCode::invalid_argument);
    REQUIRE(remove_cloth(w.world, first).ok());
    std::vector<Vec3> out(grid.asset().particle_count);
    CHECK(read_positions(w.world, first, out.data(), uint32_t(out.size())).code == ErrorCode::stale_id);
    CHECK(remove_cloth(w.world, first).code == ErrorCode::stale_id);
    CHECK(set_cloth_settings(w.world, first, ClothDesc{}).code == ErrorCode::stale_id);
    CHECK(read_positions(w.world, second, out.data(), uint32_t(out.size())).ok());
    CHECK(world_usage(w.world).cloths == 1);

    // The freed place is taken again under a new generation; the old id stays stale.
    const ClothId again = add(w.world, grid.asset(), 2.0f);
    CHECK(again.index == first.index);
    CHECK(again.generation != first.generation);
    CHECK(read_positions(w.world, first, out.data(), uint32_t(out.size())).code == ErrorCode::stale_id);
    CHECK(read_positions(w.world, again, out.data(), uint32_t(out.size())).ok());
    CHECK(read_positions(w.world, ClothId{7, 0}, out.data(), uint32_t(out.size())).code == ErrorCode::out_of_range);

    REQUIRE(remove_body(w.world, body).ok());
    CHECK(remove_body(w.world, body).code == ErrorCode::stale_id);
    CHECK(set_body_vertices(w.world, body, ball.positions.data(), uint32_t(ball.positions.size())).code ==
          ErrorCode::stale_id);
    CHECK(set_cloth_body(w.world, again, body).code == ErrorCode::stale_id);
    REQUIRE(remove_collider(w.world, ground).ok());
    CHECK(set_collider(w.world, ground, plane).code == ErrorCode::stale_id);
    REQUIRE(step(w.world, 0.016f).ok());  // stepping with free places

    REQUIRE(remove_cloth(w.world, second).ok());
    REQUIRE(remove_cloth(w.world, again).ok());
    CHECK(world_usage(w.world) == empty);
    CHECK(step_stage_items(w.world, StepStage::cloths) == 0);  // no place is kept for nothing
}

TEST_CASE("instances come and go: compaction moves the live ones without changing a bit, and the world holds what it promised") {
    // World A, sized for four 20 x 20 cloths and a ball, is filled: cloth 0, the ball, cloths 1, 2, 3,
    // each bound to the ball by skin constraints. Cloths 0 and 2 go, and a 26 x 26 cloth W comes: within the totals, but larger than either
    // gap they left and than the room after cloth 3, so the ball and cloths 1 and 3 (and their skin
    // constraints in the skin pool) slide down to make room. World B holds the ball, cloths 1 and 3 and W from the start. The cloths (falling
    // onto the ball) step to the same bits in both.
    const Grid twenty(20, 1.0f), large(26, 1.0f);
    const body::BodyMesh ball = body::make_icosphere({0.0f, 0.4f, 0.0f}, 0.25f, 3);
    for (const SimdPath path : available_paths()) {
        CAPTURE(simd_path_name(path));
        WorldDesc desc;
        desc.max_cloths = 0;
        for (int k = 0; k < 4; ++k) reserve_cloth(desc, twenty.asset());
        desc.max_bodies = 1;
        desc.max_body_vertices = uint32_t(ball.positions.size());
        desc.max_body_triangles = uint32_t(ball.triangles.size() / 3);
        desc.max_skin_constraints = 4 * twenty.asset().particle_count;  // the skin pool compacts too
        desc.simd = path;
        OwnedWorld a, b;
        REQUIRE(make_world(desc, &a).ok());
        REQUIRE(make_world(desc, &b).ok());

        // Every cloth is bound to the ball by skin constraints where it starts (their max distance
        // lets it fall onto the ball).
        std::vector<SkinBinding> bindings(8);
        size_t bound = 0;
        const auto bind = [&](World* world, ClothId cloth, BodyId body) {
            const std::string e = scenes::bind_skin(world, cloth, body, SkinBindingOptions{}, &bindings[bound++]);
            INFO(e);
            REQUIRE(e.empty());
        };
        const float x_m[4] = {0.0f, 0.1f, 2.0f, -0.1f};  // cloths 1 and 3 fall onto the ball
        ClothId in_a[4];
        in_a[0] = add(a.world, twenty.asset(), x_m[0]);
        const BodyId a_ball = add_ball(a.world, ball);
        bind(a.world, in_a[0], a_ball);
        for (int k = 1; k < 4; ++k) in_a[k] = add(a.world, twenty.asset(), x_m[k]), bind(a.world, in_a[k], a_ball);
        REQUIRE(remove_cloth(a.world, in_a[0]).ok());
        REQUIRE(remove_cloth(a.world, in_a[2]).ok());
        const BodyId b_ball = add_ball(b.world, ball);
        const ClothId in_b[2] = {add(b.world, twenty.asset(), x_m[1]), add(b.world, twenty.asset(), x_m[3])};
        bind(b.world, in_b[0], b_ball);
        bind(b.world, in_b[1], b_ball);
        for (int i = 0; i < 20; ++i) {
            REQUIRE(step(a.world, 0.016f).ok());
            REQUIRE(step(b.world, 0.016f).ok());
        }
        const uint32_t n = twenty.asset().particle_count;
        REQUIRE(same_bits(read_all(a.world, in_a[1], n), read_all(b.world, in_b[0], n)));

        const ClothId w = add(a.world, large.asset(), 1.0f);  // compacts
        bind(a.world, w, a_ball);                              // compacts the skin pool
        const ClothId b_w = add(b.world, large.asset(), 1.0f);
        bind(b.world, b_w, b_ball);
        CHECK(world_stats(a.world).memory_compactions == 2);
        CHECK(world_stats(b.world).memory_compactions == 0);
        CHECK(world_usage(a.world).instance_bytes == world_usage(b.world).instance_bytes);
        CHECK(world_usage(a.world).skin_bytes == world_usage(b.world).skin_bytes);
        for (int i = 0; i < 30; ++i) {
            REQUIRE(step(a.world, 0.016f).ok());
            REQUIRE(step(b.world, 0.016f).ok());
        }
        CHECK(same_bits(read_all(a.world, in_a[1], n), read_all(b.world, in_b[0], n)));
        CHECK(same_bits(read_all(a.world, in_a[3], n), read_all(b.world, in_b[1], n)));
        CHECK(same_bits(read_all(a.world, w, large.asset().particle_count),
                        read_all(b.world, b_w, large.asset().particle_count)));
        // The moved body answers as the one that never moved.
        BodyContact ca, cb;
        REQUIRE(query_body(a.world, a_ball, {0.0f, 0.4f, 0.255f}, &ca).ok());
        REQUIRE(query_body(b.world, b_ball, {0.0f, 0.4f, 0.255f}, &cb).ok());
        CHECK(ca.found);
        CHECK(ca.penetration_m == cb.penetration_m);
        CHECK(ca.triangle == cb.triangle);
        // Every array of its hierarchy moved with it (a stale pointer reads what now lies there).
        BodyView va, vb;
        REQUIRE(view_body(a.world, a_ball, &va).ok());
        REQUIRE(view_body(b.world, b_ball, &vb).ok());
        REQUIRE(va.leaf_count == vb.leaf_count);
        CHECK(std::memcmp(va.in_crease, vb.in_crease, va.triangle_count) == 0);
        CHECK(std::memcmp(va.leaf_triangle, vb.leaf_triangle, sizeof(uint32_t) * 8 * va.leaf_count) == 0);
        CHECK(std::memcmp(va.leaf_fold_m, vb.leaf_fold_m, sizeof(float) * va.leaf_count) == 0);
    }
}
