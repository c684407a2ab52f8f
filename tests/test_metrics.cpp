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
