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
        test::grid_triangles(n, n, first, &triangles);
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

namespace {

// An n x n sheet of `edge` edges cooked flat (in the x-z plane), `mass_of(i, j)` kg a particle
// (0: pinned), added to its own world with or without self-collision and tethers; then each
// particle k is put at `start[k]` keeping its mass (rest lengths stay the flat sheet's).
struct ReshapedSheet {
    std::vector<float> masses;
    CookedCloth cooked;
    test::OwnedWorld owned;
    ClothId id{};
};
template <class MassOf>
void reshaped_sheet(uint32_t n, float edge, MassOf&& mass_of, const std::vector<Vec3>& start, bool self_collision,
                    bool tethers, ReshapedSheet* out) {
    std::vector<Vec3> flat;
    std::vector<uint32_t> triangles;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) {
            flat.push_back({edge * float(j), 0.0f, edge * float(i)});
            out->masses.push_back(mass_of(i, j));
        }
    test::grid_triangles(n, n, 0, &triangles);
    ClothMeshDesc mesh;
    mesh.particle_count = uint32_t(flat.size());
    mesh.positions = flat.data();
    mesh.triangle_count = uint32_t(triangles.size() / 3);
    mesh.triangles = triangles.data();
    mesh.masses = out->masses.data();
    out->cooked = test::cook(mesh);
    ClothDesc cd;
    cd.asset = &out->cooked.asset();
    cd.tethers = tethers;
    cd.self_collision = self_collision;
    WorldDesc wd;
    wd.max_cloths = 0;
    reserve_cloth(wd, cd);
    REQUIRE(test::make_world(wd, &out->owned).ok());
    REQUIRE(add_cloth(out->owned.world, cd, &out->id).ok());
    REQUIRE(start.size() == flat.size());
    for (uint32_t k = 0; k < start.size(); ++k) {
        const float m = out->masses[k];
        REQUIRE(set_particle(out->owned.world, out->id, k, start[k], m > 0.0f ? 1.0f / m : 0.0f).ok());
    }
}

}  // namespace

// A sheet crumpled into a 4 cm cube, a quarter of its particles pinned where they landed: every
// kind of contact at once, many of them next to a pinned particle. Stepped with self-collision, no
// particle goes further in a frame than it does without (plus the contacts' own reach): each
// contact moves a particle at most its depth. A closest point near an edge's pinned end used to
// move the free end by depth / (its barycentric weight): a dressed garment whose attached waistband
// met a fold blew up in its first frame.
TEST_CASE("self-collision: a crumpled sheet with pinned particles is not thrown apart") {
    const uint32_t n = 15;
    std::vector<Vec3> crumpled;
    uint32_t seed = 12345u;
    const auto next = [&seed] { return float((seed = seed * 1664525u + 1013904223u) >> 8) / float(1u << 24); };
    for (uint32_t k = 0; k < n * n; ++k) crumpled.push_back({0.04f * next(), 0.04f * next(), 0.04f * next()});
    float furthest[2] = {};  // without, with
    for (bool on : {false, true}) {
        ReshapedSheet sheet;
        reshaped_sheet(n, 0.02f, [n](uint32_t i, uint32_t j) { return (i * n + j) % 4 == 1 ? 0.0f : 6e-5f; }, crumpled, on,
                       false, &sheet);
        for (uint32_t f = 0; f < 10; ++f) {
            const std::vector<Vec3> before = test::read_all(sheet.owned.world, sheet.id, n * n);
            REQUIRE(step(sheet.owned.world, 1.0f / 60.0f).ok());
            const std::vector<Vec3> after = test::read_all(sheet.owned.world, sheet.id, n * n);
            for (size_t k = 0; k < after.size(); ++k) {
                const float dx = after[k].x - before[k].x, dy = after[k].y - before[k].y, dz = after[k].z - before[k].z;
                const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
                furthest[on] = std::isfinite(d) ? std::fmax(furthest[on], d) : INFINITY;
            }
        }
        if (on) CHECK(world_stats(sheet.owned.world).self_contacts > 0);
    }
    CAPTURE(furthest[0]);
    CAPTURE(furthest[1]);
    CHECK(furthest[0] > 0.0f);
    CHECK(furthest[1] <= furthest[0] + 0.05f);
}

// A sheet meshed finer than the thickness (1 mm edges against 4 mm), corrugated with no stretch
// (each row 0.8 mm off the plane of the rows beside it) and hanging from its top row: a particle
// lies within the thickness of triangles two rows away without any fold. A contact is at most half
// the shortest edge around it thick, so the sheet hangs as it does without self-collision. Held to
// the full thickness, a pooled hem meshed at 0.6 mm (gc_1001_0080 dressed) had springs 25 times
// their length in its first frame.
TEST_CASE("self-collision: a mesh finer than the thickness is not torn apart") {
    const uint32_t n = 21;
    const float edge = 0.001f, offset = 0.0008f, drop = std::sqrt(edge * edge - offset * offset);
    std::vector<Vec3> corrugated;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) corrugated.push_back({edge * float(j), -drop * float(i), offset * float(i % 2)});
    double max_strain[2] = {};  // without, with
    for (bool on : {false, true}) {
        ReshapedSheet sheet;
        reshaped_sheet(n, edge, [edge](uint32_t i, uint32_t) { return i == 0 ? 0.0f : 0.15f * edge * edge; }, corrugated,
                       on, true, &sheet);
        for (uint32_t f = 0; f < 30; ++f) {
            REQUIRE(step(sheet.owned.world, 1.0f / 60.0f).ok());
            max_strain[on] = std::max(max_strain[on], metrics::stretch_strain(test::view_of(sheet.owned.world, sheet.id)).max);
        }
    }
    CAPTURE(max_strain[0]);
    CAPTURE(max_strain[1]);
    CHECK(max_strain[1] <= max_strain[0] + 0.02);
}
