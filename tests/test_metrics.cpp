// The accuracy metrics (docs/accuracy.md) on cases whose answer is known by hand.
#include "support/test_support.h"

#include <limits>

using namespace weft;

TEST_CASE("trajectory error: RMS distance over the sampled frames, divided by the diagonal") {
    const std::vector<Vec3> a{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
    // Frame 1: both particles 0.3 m off; frame 2: one 0.4 m off, one exact.
    const std::vector<Vec3> b1{{0.3f, 0.0f, 0.0f}, {1.0f, 0.3f, 0.0f}};
    const std::vector<Vec3> b2{{0.0f, 0.0f, 0.4f}, {1.0f, 0.0f, 0.0f}};
    CHECK(metrics::rms_distance(a, b1) == doctest::Approx(0.3).epsilon(1e-6));
    CHECK(metrics::rms_distance(a, b2) == doctest::Approx(std::sqrt(0.16 / 2.0)).epsilon(1e-6));
    const metrics::Frames run{a, a}, reference{b1, b2};
    // sqrt((0.09 + 0.09 + 0.16 + 0) / 4) / 2
    CHECK(metrics::trajectory_error(run, reference, 2.0) == doctest::Approx(std::sqrt(0.34 / 4.0) / 2.0).epsilon(1e-6));
    CHECK(metrics::rest_state_error(run, reference, 2.0) == doctest::Approx(std::sqrt(0.08) / 2.0).epsilon(1e-6));
    CHECK(metrics::trajectory_error(run, run, 2.0) == 0.0);
}

TEST_CASE("trajectory error: a non-finite position or mismatched runs are infinitely wrong") {
    const std::vector<Vec3> a{{0.0f, 0.0f, 0.0f}};
    const std::vector<Vec3> nan{{std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f}};
    CHECK(std::isinf(metrics::trajectory_error({a}, {nan}, 1.0)));
    CHECK(std::isinf(metrics::trajectory_error({a, a}, {a}, 1.0)));
    CHECK(std::isinf(metrics::trajectory_error({a}, {a}, 0.0)));
    CHECK(std::isinf(metrics::rms_distance(a, {})));
}

TEST_CASE("diagonal of the 2 m seed cloth, and strain over caller-order positions equals the view's") {
    auto w = test::make_scene(scenes::SeedScene::drape, test::scene_options(12));
    const std::vector<Vec3> start = test::read_all(*w);
    CHECK(metrics::diagonal_m(start) == doctest::Approx(2.0 * std::sqrt(2.0)).epsilon(1e-6));
    test::step_n(*w, 40);
    const metrics::Strain from_view = metrics::stretch_strain(test::view_of(*w));
    const metrics::Strain from_positions = metrics::stretch_strain(w->asset(), test::read_all(*w));
    CHECK(from_view.max > 0.0);
    CHECK(from_positions.max == from_view.max);
    CHECK(from_positions.mean == doctest::Approx(from_view.mean).epsilon(1e-12));
}

TEST_CASE("penetration over caller-order positions equals the view's") {
    scenes::SceneOptions o = test::scene_options(12);
    o.sphere_inflation_m = 0.05f;
    o.sphere_friction = 0.5f;  // so that the small cloth is still on the sphere after 60 steps
    auto w = test::make_scene(scenes::SeedScene::sphere, o);
    test::step_n(*w, 60);
    ColliderDesc larger;  // a sphere 3 cm larger than the world's: the cloth lies 2 to 3 cm inside it
    larger.radius_m = 0.53f;
    larger.inflation_m = 0.05f;
    const double from_view = metrics::max_penetration_m(test::view_of(*w), &larger, 1);
    const double from_positions = metrics::max_penetration_m(w->asset(), test::read_all(*w), &larger, 1);
    CHECK(from_view > 0.0);
    CHECK(from_positions == from_view);
}

namespace {

// A flat n x n grid of `spacing` in z = 0, each cell cut along its (i, j)-(i + 1, j + 1) diagonal.
void add_grid(uint32_t n, float spacing, std::vector<Vec3>* x, std::vector<uint32_t>* triangles) {
    const uint32_t base = uint32_t(x->size());
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) x->push_back({float(i) * spacing, float(j) * spacing, 0.0f});
    const auto at = [&](uint32_t i, uint32_t j) { return base + j * (n + 1) + i; };
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i)
            triangles->insert(triangles->end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
}

}  // namespace

TEST_CASE("self crossings: two triangles pierced through each other count 2, a flat or doubled sheet none") {
    const std::vector<Vec3> pierced{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25f, 0.25f, -0.5f}, {0.25f, 0.25f, 0.5f}, {2, 2, 0}};
    const uint32_t two[] = {0, 1, 2, 3, 4, 5};
    CHECK(metrics::self_crossings(two, 2, pierced) == 2);  // an edge of each through the other
    std::vector<Vec3> x;
    std::vector<uint32_t> t;
    add_grid(10, 0.1f, &x, &t);
    CHECK(metrics::self_crossings(t.data(), uint32_t(t.size() / 3), x) == 0);
    // A second sheet 1 mm above the first (a fold that only touches): still none.
    const size_t first = x.size();
    add_grid(10, 0.1f, &x, &t);
    for (size_t p = first; p < x.size(); ++p) x[p].z = 0.001f;
    CHECK(metrics::self_crossings(t.data(), uint32_t(t.size() / 3), x) == 0);
}

TEST_CASE("self crossings: a quad through a sheet counts each edge through a triangle, wherever the mesh stands") {
    // The quad stands in y = 0.55 from x = 0.02 to 0.98, z = -0.3 to 0.1. Through it pass the
    // sheet's edges across y = 0.55: 9 columns (x = 0.1 .. 0.9) and 10 diagonals (x = 0.05 .. 0.95);
    // through the sheet pass its two upright edges and its diagonal (at x = 0.74): 22.
    std::vector<Vec3> x;
    std::vector<uint32_t> t;
    add_grid(10, 0.1f, &x, &t);
    const uint32_t q = uint32_t(x.size());
    x.insert(x.end(), {{0.02f, 0.55f, -0.3f}, {0.98f, 0.55f, -0.3f}, {0.98f, 0.55f, 0.1f}, {0.02f, 0.55f, 0.1f}});
    t.insert(t.end(), {q, q + 1, q + 2, q, q + 2, q + 3});
    CHECK(metrics::self_crossings(t.data(), uint32_t(t.size() / 3), x) == 22);
    // Moved far off and turned a quarter about z: the grid's cells fall elsewhere, the count does not.
    std::vector<Vec3> moved(x.size());
    for (size_t p = 0; p < x.size(); ++p) moved[p] = {-x[p].y + 12.345f, x[p].x - 6.789f, x[p].z + 3.21f};
    CHECK(metrics::self_crossings(t.data(), uint32_t(t.size() / 3), moved) == 22);
}
