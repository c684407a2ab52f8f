// Analytic checks that need no reference run (docs/accuracy in the run-time-against-error issue):
// Verlet is exact for a constant acceleration once it starts right, so a cloth in free fall must
// follow x0 + g t^2 / 2 to float rounding, whatever the substeps.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "test_support.h"
#include "weft/weft.h"

using namespace weft;

TEST_CASE("free fall: a rigid triangle with no damping follows y0 - g t^2 / 2") {
    const std::vector<Vec3> positions{{0.0f, 10.0f, 0.0f}, {0.1f, 10.0f, 0.0f}, {0.0f, 10.0f, 0.1f}};
    const std::vector<uint32_t> triangles{0, 1, 2};
    const std::vector<float> masses{0.01f, 0.01f, 0.01f};
    ClothMeshDesc mesh;
    mesh.particle_count = 3;
    mesh.positions = positions.data();
    mesh.triangle_count = 1;
    mesh.triangles = triangles.data();
    mesh.masses = masses.data();
    const CookedCloth cooked = test::cook(mesh);

    for (uint32_t substeps : {1u, 3u, 7u}) {
        CAPTURE(substeps);
        test::OwnedWorld owned;
        REQUIRE(test::make_world(test::world_for({&cooked.asset()}), &owned).ok());
        World* world = owned.world;
        ClothDesc cd;
        cd.asset = &cooked.asset();
        cd.policy = BudgetPolicy::explicit_split;
        cd.substeps = substeps;
        cd.iterations = 2;
        cd.damping_per_s = 0.0f;
        ClothId cloth;
        REQUIRE(add_cloth(world, cd, &cloth).ok());

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
    for (uint32_t i = 0; i + 1 < along; ++i)
        for (uint32_t j = 0; j + 1 < across; ++j) {
            const uint32_t a = i * across + j, b = a + 1, c = a + across, d = c + 1;
            triangles.insert(triangles.end(), {a, c, b, b, c, d});
        }
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
