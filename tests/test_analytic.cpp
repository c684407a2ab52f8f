// Analytic checks that need no reference run (docs/accuracy.md): free fall, the pendulum, the catenary.
// Verlet is exact for a constant acceleration once it starts right, so a cloth in free fall must
// follow x0 + g t^2 / 2 to float rounding, whatever the substeps.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "support/test_support.h"
#include "weft/weft.h"

using namespace weft;

namespace {

// One triangle of cloth in its own world, explicit split, no damping: the closed-form cases.
struct TriangleWorld {
    CookedCloth cooked;
    test::OwnedWorld owned;
    ClothId cloth{};
};

std::unique_ptr<TriangleWorld> triangle_world(const std::vector<Vec3>& positions, const std::vector<float>& masses,
                                              uint32_t substeps, uint32_t iterations) {
    const std::vector<uint32_t> triangles{0, 1, 2};
    ClothMeshDesc mesh;
    mesh.particle_count = 3;
    mesh.positions = positions.data();
    mesh.triangle_count = 1;
    mesh.triangles = triangles.data();
    mesh.masses = masses.data();
    auto w = std::make_unique<TriangleWorld>();
    w->cooked = test::cook(mesh);
    REQUIRE(test::make_world(test::world_for({&w->cooked.asset()}), &w->owned).ok());
    ClothDesc cd;
    cd.asset = &w->cooked.asset();
    cd.policy = BudgetPolicy::explicit_split;
    cd.substeps = substeps;
    cd.iterations = iterations;
    cd.coarse_level = CoarseLevel::off;  // three particles: nothing to carry further than one edge
    cd.damping_per_s = 0.0f;
    REQUIRE(add_cloth(w->owned.world, cd, &w->cloth).ok());
    return w;
}

}  // namespace

TEST_CASE("free fall: a rigid triangle with no damping follows y0 - g t^2 / 2") {
    const std::vector<Vec3> positions{{0.0f, 10.0f, 0.0f}, {0.1f, 10.0f, 0.0f}, {0.0f, 10.0f, 0.1f}};
    for (uint32_t substeps : {1u, 3u, 7u}) {
        CAPTURE(substeps);
        const auto tw = triangle_world(positions, {0.01f, 0.01f, 0.01f}, substeps, 2);
        World* world = tw->owned.world;
        const ClothId cloth = tw->cloth;

        const float dt = 0.033f;
        const uint32_t steps = 60;  // ~2 s, a 19.6 m fall
        for (uint32_t i = 0; i < steps; ++i) REQUIRE(step(world, dt).ok());
        Vec3 out[3];
        REQUIRE(read_positions(world, cloth, out, 3).ok());
        const double t = double(dt) * steps;
        const double expected_drop = 0.5 * 9.81 * t * t;
        MESSAGE("drop after ", t, " s: ", double(positions[0].y) - out[0].y, " m, exact ", expected_drop, " m");
        for (int k = 0; k < 3; ++k) {
            const double drop = double(positions[k].y) - out[k].y;
            // Float32 positions near 10 m round at 1e-6 m, and Verlet's velocity is a difference of
            // two of them, so rounding grows with the substeps (0.01% at 60, 0.07% at 420). A wrong
            // start (x1 = x0 + g h^2) would be off by g h t / 2: 1.6% at 1 substep, 0.2% at 7.
            CHECK(std::fabs(drop - expected_drop) < 1e-3 * expected_drop);
            CHECK(out[k].x == doctest::Approx(positions[k].x).epsilon(1e-6));
            CHECK(out[k].z == doctest::Approx(positions[k].z).epsilon(1e-6));
        }
    }
}

// The catenary: a narrow strip of cloth of length L hung by its two ends a span D < L apart comes to
// rest near y = a cosh(x / a) (the inextensible, bending-free limit), L = 2 a sinh(D / (2 a)). The
// strip starts as a V of the right length with its flat rest pose given separately; bending is made
// soft (compliance) so only the length constraints and gravity shape it. Tethers are off: the V
// satisfies every tether exactly (each particle sits at the bottom of its two-ball lens), so with
// them the strip stays a V (docs/solver.md). The residual is the strip's stretch at a finite budget,
// so the error must shrink as the budget grows.
namespace {

struct CatenaryRun {
    double sag = 0.0, expected_sag = 0.0, worst = 0.0;
};

CatenaryRun hang_strip(uint32_t sweeps) {
    const uint32_t along = 81, across = 3;  // 2 m x 5 cm, 2.5 cm spacing
    const double length = 2.0, span = 1.6, width = 0.05;
    std::vector<Vec3> rest, start;
    std::vector<float> masses;
    std::vector<int32_t> lattice;
    for (uint32_t i = 0; i < along; ++i) {
        const double s = length * i / (along - 1) - 0.5 * length;  // arc length from the middle
        // The V: two straight halves of length L/2 from (+-D/2, 0) down to the middle.
        const double half = 0.5 * length, depth = std::sqrt(half * half - 0.25 * span * span);
        const double x = s * (0.5 * span) / half, y = -depth * (1.0 - std::fabs(s) / half);
        for (uint32_t j = 0; j < across; ++j) {
            const double z = width * j / (across - 1) - 0.5 * width;
            rest.push_back({float(s), 0.0f, float(z)});
            start.push_back({float(x), float(y), float(z)});
            const bool end = i == 0 || i == along - 1;
            masses.push_back(end ? 0.0f : float(0.15 * (length / (along - 1)) * (width / (across - 1))));
            lattice.push_back(int32_t(i));
            lattice.push_back(int32_t(j));
        }
    }
    std::vector<uint32_t> triangles;
    test::grid_triangles(along, across, 0, &triangles);
    ClothMeshDesc mesh;
    mesh.particle_count = uint32_t(start.size());
    mesh.positions = start.data();
    mesh.rest_positions = rest.data();
    mesh.triangle_count = uint32_t(triangles.size() / 3);
    mesh.triangles = triangles.data();
    mesh.masses = masses.data();
    mesh.lattice = lattice.data();
    const CookedCloth cooked = test::cook(mesh);

    test::OwnedWorld owned;
    REQUIRE(test::make_world(test::world_for({&cooked.asset()}), &owned).ok());
    World* world = owned.world;
    ClothDesc cd;
    cd.asset = &cooked.asset();
    cd.sweeps = sweeps;
    cd.tethers = false;
    cd.compliance_m_per_n[static_cast<int>(ConstraintKind::bend)] = 10.0f;  // bending-free limit
    ClothId cloth;
    REQUIRE(add_cloth(world, cd, &cloth).ok());
    for (int i = 0; i < 900; ++i) REQUIRE(step(world, 0.033f).ok());

    std::vector<Vec3> out(start.size());
    REQUIRE(read_positions(world, cloth, out.data(), uint32_t(out.size())).ok());
    // The catenary's parameter a: L = 2 a sinh(D / 2a), by bisection (the left side falls with a).
    double lo = 0.01, hi = 100.0;
    for (int it = 0; it < 200; ++it) {
        const double a = 0.5 * (lo + hi);
        (2.0 * a * std::sinh(span / (2.0 * a)) > length ? lo : hi) = a;
    }
    const double a = 0.5 * (lo + hi);
    CatenaryRun run;
    run.expected_sag = a * (std::cosh(span / (2.0 * a)) - 1.0);
    // The centre line (middle row) against y(x) = a (cosh(x / a) - cosh(D / 2a)).
    for (uint32_t i = 0; i < along; ++i) {
        const Vec3 p = out[i * across + 1];
        const double expected = a * (std::cosh(p.x / a) - std::cosh(span / (2.0 * a)));
        run.worst = std::max(run.worst, std::fabs(p.y - expected));
    }
    run.sag = -out[(along / 2) * across + 1].y;
    return run;
}

}  // namespace

TEST_CASE("catenary: a hanging strip comes to rest near the catenary, closer with a larger budget") {
    const CatenaryRun small = hang_strip(20), large = hang_strip(100);
    MESSAGE("catenary sag ", small.expected_sag, " m; strip sag at 20 sweeps ", small.sag, " m (centre line within ",
            small.worst, " m), at 100 sweeps ", large.sag, " m (within ", large.worst, " m)");
    CHECK(std::fabs(small.sag - small.expected_sag) < 0.15 * small.expected_sag);
    CHECK(std::fabs(large.sag - large.expected_sag) < 0.10 * large.expected_sag);
    CHECK(large.worst < small.worst);  // more budget, less stretch, closer to the inextensible limit
    CHECK(large.worst < 0.05);
}

// The pendulum: a triangle whose two upper corners are pinned on the x axis swings its third corner
// (the bob) on a circle of radius L about that axis, a rigid pendulum. From rest at angle theta0 the
// exact period is T = 4 sqrt(L / g) K(sin(theta0 / 2)) (complete elliptic integral of the first
// kind), whatever the amplitude. No damping; the period is measured from the bob's zero crossings.
namespace {

struct PendulumRun {
    double period_s = 0.0;  // of the first swing (position projection loses energy, so later swings
                            // are smaller and, the pendulum being nonlinear, faster)
    double exact_s = 0.0;
    double amplitude_after_rad = 0.0;  // largest angle during the second period
};

PendulumRun swing(uint32_t substeps, double theta0) {
    const double length = 1.0, half_axis = 0.2, g = 9.81;
    const std::vector<Vec3> positions{{float(-half_axis), 0.0f, 0.0f},
                                      {float(half_axis), 0.0f, 0.0f},
                                      {0.0f, float(-length * std::cos(theta0)), float(length * std::sin(theta0))}};
    const auto tw = triangle_world(positions, {0.0f, 0.0f, 0.1f}, substeps, 1);  // the two hinge corners pinned
    World* world = tw->owned.world;
    const ClothId cloth = tw->cloth;

    const float dt = 0.033f;
    std::vector<double> crossings;  // times the bob passes the vertical (z = 0)
    double previous_angle = theta0, amplitude = 0.0;
    for (uint32_t i = 1; i <= 200 && crossings.size() < 5; ++i) {  // two periods
        REQUIRE(step(world, dt).ok());
        Vec3 p[3];
        REQUIRE(read_positions(world, cloth, p, 3).ok());
        const double angle = std::atan2(double(p[2].z), -double(p[2].y));
        if ((angle < 0.0) != (previous_angle < 0.0))  // linear interpolation between the two steps
            crossings.push_back(dt * (i - 1 + previous_angle / (previous_angle - angle)));
        if (crossings.size() >= 3) amplitude = std::max(amplitude, std::fabs(angle));
        previous_angle = angle;
    }
    REQUIRE(crossings.size() == 5);
    PendulumRun run;
    run.period_s = crossings[2] - crossings[0];  // the first full period after the first crossing
    // K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
    const double k = std::sin(0.5 * theta0);
    double a = 1.0, b = std::sqrt(1.0 - k * k);
    for (int it = 0; it < 30; ++it) {
        const double next_a = 0.5 * (a + b);
        b = std::sqrt(a * b);
        a = next_a;
    }
    run.exact_s = 4.0 * std::sqrt(length / g) * (3.14159265358979 / (2.0 * a));
    run.amplitude_after_rad = amplitude;
    return run;
}

}  // namespace

TEST_CASE("pendulum: a bob hinged on two pins swings with the exact large-amplitude period") {
    const double theta0 = 60.0 * 3.14159265358979 / 180.0;  // far from the small-angle 2 pi sqrt(L / g)
    double previous_error = 1.0;
    for (uint32_t substeps : {1u, 4u, 16u, 64u}) {
        CAPTURE(substeps);
        const PendulumRun run = swing(substeps, theta0);
        const double error = std::fabs(run.period_s / run.exact_s - 1.0);
        const std::string line = "pendulum, 60 degrees, " + std::to_string(substeps) + " substep(s): first period " +
                std::to_string(run.period_s) + " s, exact " + std::to_string(run.exact_s) + " s (" +
                std::to_string(100.0 * error) + "%); amplitude in the second period " +
                std::to_string(run.amplitude_after_rad * 180.0 / 3.14159265358979) + " degrees";
        MESSAGE(line);
        // Position projection removes energy every substep (measured: the amplitude falls from 60
        // to 30 degrees in one period at 1 substep, to 59 at 64), at a rate that falls with the
        // substep, so period and amplitude approach the exact pendulum as substeps are added. From
        // 16 substeps on the rest of the error is that small amplitude loss (a 59 degree pendulum
        // is 0.2% faster) and float rounding.
        if (substeps <= 16) CHECK(error < previous_error);
        previous_error = error;
        if (substeps >= 16) CHECK(error < 0.006);
        if (substeps == 64) CHECK(run.amplitude_after_rad > 0.95 * theta0);
    }
}
