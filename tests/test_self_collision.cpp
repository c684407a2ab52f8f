// Self-collision (ClothDesc::self_collision, runtime/src/collide/self_collision.h): a free sheet
// dropped on a pinned sheet of the same cloth stays on it only with self-collision; the scalar and
// AVX2 paths give the same bits; the settings are checked and the memory is the world's.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "common/metrics.h"
#include "common/seed_scenes.h"
#include "support/test_support.h"
#include "weft/debug.h"

using namespace weft;

namespace {

// One cloth of two square sheets, 2 cm edges: a lower one (21 x 21, 0.4 m) pinned round its
// border at y = 0, and an upper one (11 x 11, 0.2 m) 3 cm above its middle, shifted half an edge
// so that its particles fall between the lower sheet's.
struct TwoSheets {
    std::vector<Vec3> positions;
    std::vector<uint32_t> triangles;
    std::vector<float> masses;
    uint32_t upper_first = 0;
    CookedCloth cooked;

    TwoSheets() {
        add_sheet(21, {-0.2f, 0.0f, -0.2f}, true);
        upper_first = uint32_t(positions.size());
        add_sheet(11, {-0.09f, 0.03f, -0.09f}, false);
        ClothMeshDesc mesh;
        mesh.particle_count = uint32_t(positions.size());
        mesh.positions = positions.data();
        mesh.triangle_count = uint32_t(triangles.size() / 3);
        mesh.triangles = triangles.data();
        mesh.masses = masses.data();
        cooked = test::cook(mesh);
    }
    void add_sheet(uint32_t n, Vec3 corner, bool pin_border) {
        const uint32_t first = uint32_t(positions.size());
        const float edge = 0.02f, mass = 0.15f * edge * edge;  // cotton, kg a particle
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t j = 0; j < n; ++j) {
                positions.push_back({corner.x + edge * float(j), corner.y, corner.z + edge * float(i)});
                const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1;
                masses.push_back(pin_border && border ? 0.0f : mass);
            }
        for (uint32_t i = 0; i + 1 < n; ++i)
            for (uint32_t j = 0; j + 1 < n; ++j) {
                const uint32_t a = first + i * n + j, b = a + 1, c = a + n, d = c + 1;
                triangles.insert(triangles.end(), {a, c, b, b, c, d});
            }
    }
};

struct SheetsWorld {
    test::OwnedWorld owned;
    ClothId cloth{};
};

void make_sheets_world(const TwoSheets& sheets, bool self_collision, SimdPath path, SheetsWorld* out) {
    ClothDesc cd;
    cd.asset = &sheets.cooked.asset();
    cd.sweeps = 8;
    cd.tethers = false;  // they would tie the upper sheet to the lower one's pinned border
    cd.self_collision = self_collision;
    WorldDesc wd;
    wd.max_cloths = 0;
    reserve_cloth(wd, cd);
    wd.simd = path;
    REQUIRE(test::make_world(wd, &out->owned).ok());
    REQUIRE(add_cloth(out->owned.world, cd, &out->cloth).ok());
}

}  // namespace

TEST_CASE("self-collision: a sheet dropped on a pinned sheet of the same cloth rests on it, and falls through without") {
    const TwoSheets sheets;
    for (bool on : {false, true}) {
        CAPTURE(on);
        SheetsWorld w;
        make_sheets_world(sheets, on, SimdPath::automatic, &w);
        uint32_t crossing_frames = 0;
        uint64_t contacts = 0;
        for (uint32_t f = 0; f < 120; ++f) {  // 2 s
            REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
            crossing_frames += metrics::self_crossings(test::view_of(w.owned.world, w.cloth)) > 0;
            contacts += world_stats(w.owned.world).self_contacts;
        }
        const std::vector<Vec3> x = test::read_all(w.owned.world, w.cloth, uint32_t(sheets.positions.size()));
        REQUIRE(test::all_finite(x));
        // The upper sheet's middle against the lower sheet's middle (particle 10 * 21 + 10).
        const float upper_middle = x[sheets.upper_first + 5 * 11 + 5].y, lower_middle = x[10 * 21 + 10].y;
        if (on) {
            CHECK(crossing_frames == 0);
            CHECK(contacts > 0);
            CHECK(upper_middle > lower_middle);
        } else {
            CHECK(crossing_frames > 0);
            CHECK(contacts == 0);
            CHECK(upper_middle < lower_middle - 0.1f);  // fell through and on
        }
    }
}

// The heap (scenes::heap_scene): a sheet landing at 4-5 m/s folds onto itself. It crossed itself
// in 2 frames of 300 until the edge-edge contacts had friction too (layers sliding over each other
// slipped through at the landing).
TEST_CASE("self-collision: a sheet dropped in a heap on the ground passes through itself without it, never with it") {
    for (bool on : {false, true}) {
        CAPTURE(on);
        scenes::Scene scene = scenes::heap_scene();
        scene.cloths[0].desc.self_collision = on;
        scenes::SceneWorld w;
        REQUIRE(scenes::build_scene(scene, &w).empty());
        uint32_t crossing_frames = 0;
        for (uint32_t f = 0; f < 90; ++f) {  // falls, lands (about frame 35) and folds
            REQUIRE(step(w.world, scene.dt_s).ok());
            crossing_frames += metrics::self_crossings(test::view_of(w.world, w.cloths[0].id)) > 0;
        }
        if (on)
            CHECK(crossing_frames == 0);
        else
            CHECK(crossing_frames > 0);
    }
}

TEST_CASE("self-collision: the scalar and AVX2 paths give the same bits") {
    const TwoSheets sheets;
    std::vector<std::vector<Vec3>> results;
    for (SimdPath path : test::available_paths()) {
        SheetsWorld w;
        make_sheets_world(sheets, true, path, &w);
        for (uint32_t f = 0; f < 60; ++f) REQUIRE(step(w.owned.world, 1.0f / 60.0f).ok());
        CHECK(world_stats(w.owned.world).self_contacts > 0);
        results.push_back(test::read_all(w.owned.world, w.cloth, uint32_t(sheets.positions.size())));
    }
    for (size_t i = 1; i < results.size(); ++i) CHECK(test::same_bits(results[0], results[i]));
}

TEST_CASE("self-collision: chosen at add_cloth from the world's capacity, bad settings refused") {
    const TwoSheets sheets;
    ClothDesc cd;
    cd.asset = &sheets.cooked.asset();
    {  // a world reserved without it has no room for the hash
        test::OwnedWorld owned;
        REQUIRE(test::make_world(test::world_for({cd.asset}), &owned).ok());
        cd.self_collision = true;
        ClothId id;
        CHECK(add_cloth(owned.world, cd, &id).code == ErrorCode::capacity_exceeded);
        cd.self_collision = false;
        REQUIRE(add_cloth(owned.world, cd, &id).ok());
        cd.self_collision = true;  // nor can it be turned on later
        CHECK(set_cloth_settings(owned.world, id, cd).code == ErrorCode::invalid_argument);
    }
    SheetsWorld w;
    make_sheets_world(sheets, true, SimdPath::automatic, &w);
    cd.self_collision = true;
    for (float bad : {0.0f, -0.004f, 0.2f}) {
        cd.self_thickness_m = bad;
        CHECK(set_cloth_settings(w.owned.world, w.cloth, cd).code == ErrorCode::out_of_range);
    }
    cd.self_thickness_m = std::nanf("");
    CHECK(set_cloth_settings(w.owned.world, w.cloth, cd).code == ErrorCode::non_finite);
    cd.self_thickness_m = 0.004f;
    cd.self_friction = -1.0f;
    CHECK(set_cloth_settings(w.owned.world, w.cloth, cd).code == ErrorCode::out_of_range);
    cd.self_friction = 0.2f;
    cd.self_collision = false;  // nor turned off (its memory stays the cloth's until removed)
    CHECK(set_cloth_settings(w.owned.world, w.cloth, cd).code == ErrorCode::invalid_argument);
    // Removed, its slots go back: the same cloth fits again.
    REQUIRE(remove_cloth(w.owned.world, w.cloth).ok());
    cd.self_collision = true;
    CHECK(add_cloth(w.owned.world, cd, &w.cloth).ok());
}
