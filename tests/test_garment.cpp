// The asset's garment data (texture coordinates, seam points, panels, fabric), the SIMD width an
// asset is padded for, and the padding it costs.
#include "support/test_support.h"

#include <functional>
#include <limits>

using namespace weft;
using namespace weft::test;

namespace {

struct GarmentGrid {
    scenes::GridMesh grid = scenes::make_grid(9, 1.0f, 1.0f, false, 1.0f);
    scenes::GridGarment garment = scenes::make_grid_garment(grid);
    ClothMeshDesc desc() const {
        ClothMeshDesc d = grid.desc();
        garment.apply(d);
        return d;
    }
};

Result cook_result(const ClothMeshDesc& mesh, const CookOptions& options = {}) {
    CookedCloth cooked;
    return cook_cloth(mesh, options, &cooked);
}

}  // namespace

TEST_CASE("garment data: cook copies it in caller particle order") {
    const GarmentGrid g;
    const CookedCloth cooked = cook(g.desc());
    const ClothAsset& a = cooked.asset();
    REQUIRE(validate_asset(a).ok());
    const uint32_t n = a.particle_count;
    REQUIRE(a.uv != nullptr);
    CHECK(std::equal(a.uv, a.uv + 2 * n, g.garment.uv.begin()));
    CHECK(a.seam_point_count == g.garment.seam_first.size() - 1);
    CHECK(a.seam_source_count == g.garment.seam_source.size());
    CHECK(std::equal(a.seam_first, a.seam_first + a.seam_point_count + 1, g.garment.seam_first.begin()));
    CHECK(std::equal(a.seam_source, a.seam_source + a.seam_source_count, g.garment.seam_source.begin()));
    CHECK(a.panel_count == 2);
    CHECK(std::equal(a.panel, a.panel + n, g.garment.panel.begin()));
    CHECK(a.has_fabric);
    CHECK(std::memcmp(&a.fabric, &g.garment.fabric, sizeof(Fabric)) == 0);
}

TEST_CASE("garment data: absent by default, and the default fabric is ClothDesc's") {
    const scenes::GridMesh grid = scenes::make_grid(9, 1.0f, 1.0f, false, 1.0f);
    const CookedCloth cooked = cook(grid.desc());
    const ClothAsset& a = cooked.asset();
    CHECK(a.uv == nullptr);
    CHECK(a.seam_point_count == 0);
    CHECK(a.seam_first == nullptr);
    CHECK(a.seam_source_count == 0);
    CHECK(a.seam_source == nullptr);
    CHECK(a.panel_count == 0);
    CHECK(a.panel == nullptr);
    CHECK(!a.has_fabric);
    const Fabric fabric;
    const ClothDesc cloth;
    for (uint32_t k = 0; k < kConstraintKindCount; ++k)
        CHECK(fabric.compliance_m_per_n[k] == cloth.compliance_m_per_n[k]);
    CHECK(fabric.damping_per_s == cloth.damping_per_s);
    CHECK(std::memcmp(&a.fabric, &fabric, sizeof(Fabric)) == 0);
}

TEST_CASE("garment data: bad input is refused by cook_cloth with a message") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    struct Case {
        const char* what;
        std::function<void(GarmentGrid&)> spoil;
        ErrorCode expected;
    };
    const Case cases[] = {
        {"NaN texture coordinate", [&](GarmentGrid& g) { g.garment.uv[7] = nan; }, ErrorCode::non_finite},
        {"seam_first[0] not 0", [](GarmentGrid& g) { g.garment.seam_first[0] = 1; }, ErrorCode::invalid_argument},
        {"a seam point with one source", [](GarmentGrid& g) { g.garment.seam_first[1] = 1; },
         ErrorCode::invalid_argument},
        {"a seam point with nine sources", [](GarmentGrid& g) { g.garment.seam_first[1] = 9; },
         ErrorCode::invalid_argument},
        {"decreasing seam offsets", [](GarmentGrid& g) { g.garment.seam_first[2] = 0; }, ErrorCode::invalid_argument},
        {"seam source past the particles", [](GarmentGrid& g) { g.garment.seam_source[4] = g.grid.n * g.grid.n; },
         ErrorCode::out_of_range},
        {"seam source named twice in one point",
         [](GarmentGrid& g) { g.garment.seam_source[1] = g.garment.seam_source[0]; }, ErrorCode::invalid_argument},
        {"panel past panel_count", [](GarmentGrid& g) { g.garment.panel[3] = 2; }, ErrorCode::out_of_range},
        {"negative fabric friction", [](GarmentGrid& g) { g.garment.fabric.friction = -0.1f; },
         ErrorCode::out_of_range},
        {"NaN fabric density", [&](GarmentGrid& g) { g.garment.fabric.areal_density_kg_m2 = nan; },
         ErrorCode::non_finite},
    };
    for (const Case& c : cases) {
        GarmentGrid g;
        c.spoil(g);
        const Result r = cook_result(g.desc());
        CAPTURE(c.what);
        INFO(r.message);
        CHECK(r.code == c.expected);
        CHECK(r.message[0] != '\0');
    }
    GarmentGrid g;
    ClothMeshDesc d = g.desc();
    d.panel = nullptr;  // panel_count without panels
    CHECK(cook_result(d).code == ErrorCode::invalid_argument);
}

TEST_CASE("garment data: a corrupted asset fails validation as corrupt_asset") {
    const GarmentGrid g;
    CookedCloth cooked = cook(g.desc());
    SUBCASE("infinite texture coordinate") { cooked.uv[0] = std::numeric_limits<float>::infinity(); }
    SUBCASE("seam source past the particles") { cooked.seam_source[0] = 1000; }
    SUBCASE("seam offsets end before the sources") { cooked.seam_first.back() -= 1; }
    SUBCASE("panel past panel_count") { cooked.panel_count = 1; }
    SUBCASE("negative thickness") { cooked.fabric.thickness_m = -1.0f; }
    cooked.refresh_asset();
    const Result r = validate_asset(cooked.asset());
    INFO(r.message);
    CHECK(r.code == ErrorCode::corrupt_asset);
}

TEST_CASE("simd_width 16: every padded count is a multiple of 16, and the 8-wide runtime steps it") {
    scenes::GridMesh grid = scenes::make_grid(20, 2.0f, 2.0f, false, 2.0f);
    grid.masses[grid.index(0, 0)] = 0.0f;
    grid.masses[grid.index(0, 19)] = 0.0f;
    CookOptions options;
    options.simd_width = 16;
    const CookedCloth cooked = cook(grid.desc(), options);
    const ClothAsset& a = cooked.asset();
    CHECK(a.simd_width == 16);
    CHECK(a.slot_count % 16 == 0);
    uint32_t runs = 0;
    for (uint32_t i = 0; i < a.batch_count; ++i) {
        if (a.batches[i].layout != BatchLayout::run) continue;
        CHECK(a.batches[i].lane_count % 16 == 0);
        ++runs;
    }
    CHECK(runs > 0);
    REQUIRE(a.tether_batch_count > 0);
    for (uint32_t i = 0; i < a.tether_batch_count; ++i) CHECK(a.tether_batches[i].lane_count % 16 == 0);
    for (uint32_t i = 0; i < a.wind_run_count; ++i) CHECK(a.wind_runs[i].lane_count % 16 == 0);
    CHECK(a.total_constraints() == cook(grid.desc()).asset().total_constraints());

    for (SimdPath path : available_paths()) {
        OwnedWorld w;
        REQUIRE(make_world(world_for({&a}, 0, path), &w).ok());
        ClothDesc cd;
        cd.asset = &a;
        ClothId id;
        REQUIRE(add_cloth(w.world, cd, &id).ok());
        for (int i = 0; i < 30; ++i) REQUIRE(step(w.world, scenes::kSeedTimeStep_s).ok());
        CHECK(all_finite(read_all(w.world, id, a.particle_count)));
    }
}

TEST_CASE("simd_width other than 8 or 16 is refused") {
    const scenes::GridMesh grid = scenes::make_grid(5, 1.0f, 1.0f, false, 1.0f);
    for (uint32_t width : {0u, 4u, 12u, 32u}) {
        CookOptions options;
        options.simd_width = width;
        const Result r = cook_result(grid.desc(), options);
        CAPTURE(width);
        CHECK(r.code == ErrorCode::invalid_argument);
        CHECK(std::string(r.message).find("simd_width") != std::string::npos);
    }
    // An asset claiming 16 lanes whose runs are padded to 8 is corrupt.
    CookedCloth cooked = cook(scenes::make_grid(20, 2.0f, 2.0f, false, 2.0f).desc());
    cooked.simd_width = 16;
    cooked.refresh_asset();
    CHECK(validate_asset(cooked.asset()).code == ErrorCode::corrupt_asset);
}

TEST_CASE("lane_padding counts every batched pass: constraints, coarse level, tethers and wind") {
    scenes::GridMesh grid = scenes::make_grid(20, 2.0f, 2.0f, false, 2.0f);
    grid.masses[grid.index(0, 0)] = 0.0f;
    grid.masses[grid.index(0, 19)] = 0.0f;
    for (uint32_t width : {8u, 16u}) {
        CookOptions options;
        options.simd_width = width;
        const CookedCloth cooked = cook(grid.desc(), options);
        const ClothAsset& a = cooked.asset();
        const LanePadding p = lane_padding(a);
        CAPTURE(width);
        REQUIRE(a.coarse_lane_count > 0);
        CHECK(p.constraints.all_lanes == a.lane_count);
        CHECK(p.coarse.all_lanes == a.coarse_lane_count);
        CHECK(p.tethers.all_lanes == a.tether_lane_count);
        // The wind's lanes: its runs' lanes and the triangles it gathers or takes one at a time.
        CHECK(p.wind.all_lanes == uint64_t(a.wind_lane_count) + (a.triangle_count - a.wind_run_triangles));
        CHECK(p.all_lanes == p.constraints.all_lanes + p.coarse.all_lanes + p.tethers.all_lanes + p.wind.all_lanes);
        CHECK(p.padding_lanes ==
              p.constraints.padding_lanes + p.coarse.padding_lanes + p.tethers.padding_lanes + p.wind.padding_lanes);
        // Every lane is real or padding: the real ones are the constraints, coarse constraints,
        // tethers and triangles.
        CHECK(p.all_lanes - p.padding_lanes == uint64_t(a.total_constraints()) + a.coarse_constraint_count +
                                                    a.tethered_particles + a.triangle_count);
        // Wind runs are whole SIMD groups of real triangles.
        CHECK(p.wind.padding_lanes == 0);
        CHECK(p.ratio() >= 0.0);
        CHECK(p.ratio() < 0.5);
    }
    CHECK(lane_padding(ClothAsset{}).ratio() == 0.0);
}
