// Analytic checks that need no reference run (docs/accuracy in the run-time-against-error issue):
// Verlet is exact for a constant acceleration once it starts right, so a cloth in free fall must
// follow x0 + g t^2 / 2 to float rounding, whatever the substeps.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

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
    CookedCloth cooked;
    REQUIRE(cook_cloth(mesh, CookOptions{}, &cooked).ok());

    for (uint32_t substeps : {1u, 3u, 7u}) {
        CAPTURE(substeps);
        WorldDesc wd;
        wd.max_cloths = 0;
        reserve_cloth(wd, cooked.asset());
        const MemoryRequirements need = world_memory_requirements(wd);
        std::unique_ptr<unsigned char[], void (*)(void*)> block(
            static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes + 63) / 64 * 64)), std::free);
        World* world = nullptr;
        REQUIRE(create_world(wd, block.get(), need.bytes, &world).ok());
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
