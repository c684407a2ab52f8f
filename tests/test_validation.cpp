// Asset validation: a valid cooked asset, copied into the test's own arrays and corrupted one thing
// at a time, must fail validate_asset with corrupt_asset, and add_cloth must refuse it without
// changing the world.
#include "support/test_support.h"

#include <functional>
#include <limits>

using namespace weft;
using namespace weft::test;

namespace {

// A ClothAsset over arrays the test owns (so they can be corrupted).
struct AssetCopy {
    std::vector<uint32_t> slot_of_particle, particle_of_slot;
    std::vector<float> start_x, start_y, start_z, inverse_mass;
    std::vector<float> rest_length, lane_weight;
    std::vector<uint32_t> index_a, index_b;
    std::vector<ConstraintBatch> batches;
    std::vector<float> tether_rest[2];
    std::vector<TetherBatch> tether_batches;
    std::vector<uint32_t> tether_anchor[2];
    std::vector<uint32_t> triangles;
    std::vector<uint32_t> coarse_node_slot, coarse_slot_of_node, coarse_node_of_slot;
    std::vector<float> coarse_inverse_mass, coarse_rest_length, coarse_lane_weight;
    std::vector<uint32_t> coarse_index_a, coarse_index_b;
    std::vector<ConstraintBatch> coarse_batches;
    std::vector<uint32_t> coarse_weight_node[kCoarseWeights];
    std::vector<float> coarse_weight[kCoarseWeights];
    std::vector<uint32_t> coarse_row_node[2], coarse_col_node[2];
    std::vector<float> coarse_row_frac[2], coarse_col_frac[2];
    std::vector<TriangleRun> wind_runs;
    std::vector<float> wind_lane_weight, wind_rest_area;
    ClothAsset asset;

    template <class T>
    static void copy(std::vector<T>& to, const T* from, size_t count) {
        if (from != nullptr) to.assign(from, from + count);
    }
    template <class T>
    static void repoint(const T*& pointer, std::vector<T>& from) {
        if (pointer != nullptr) pointer = from.data();
    }

    explicit AssetCopy(const ClothAsset& a) : asset(a) {
        slot_of_particle.assign(a.slot_of_particle, a.slot_of_particle + a.particle_count);
        particle_of_slot.assign(a.particle_of_slot, a.particle_of_slot + a.slot_count);
        start_x.assign(a.start_x, a.start_x + a.slot_count);
        start_y.assign(a.start_y, a.start_y + a.slot_count);
        start_z.assign(a.start_z, a.start_z + a.slot_count);
        inverse_mass.assign(a.inverse_mass, a.inverse_mass + a.slot_count);
        rest_length.assign(a.rest_length, a.rest_length + a.lane_count);
        lane_weight.assign(a.lane_weight, a.lane_weight + a.lane_count);
        index_a.assign(a.index_a, a.index_a + a.lane_count);
        index_b.assign(a.index_b, a.index_b + a.lane_count);
        batches.assign(a.batches, a.batches + a.batch_count);
        for (int side = 0; side < 2; ++side)
            tether_rest[side].assign(a.tether_rest[side], a.tether_rest[side] + a.tether_lane_count);
        tether_batches.assign(a.tether_batches, a.tether_batches + a.tether_batch_count);
        for (int side = 0; side < 2; ++side) copy(tether_anchor[side], a.tether_anchor[side], a.tether_anchor_lane_count);
        triangles.assign(a.triangles, a.triangles + 3 * a.triangle_count);
        copy(wind_runs, a.wind_runs, a.wind_run_count);
        copy(wind_lane_weight, a.wind_lane_weight, a.wind_lane_count);
        copy(wind_rest_area, a.wind_rest_area, a.wind_lane_count + (a.triangle_count - a.wind_run_triangles));
        copy(coarse_node_slot, a.coarse_node_slot, a.coarse_node_count);
        copy(coarse_slot_of_node, a.coarse_slot_of_node, a.coarse_node_count);
        copy(coarse_node_of_slot, a.coarse_node_of_slot, a.coarse_slot_count);
        copy(coarse_inverse_mass, a.coarse_inverse_mass, a.coarse_slot_count);
        copy(coarse_rest_length, a.coarse_rest_length, a.coarse_lane_count);
        copy(coarse_lane_weight, a.coarse_lane_weight, a.coarse_lane_count);
        copy(coarse_index_a, a.coarse_index_a, a.coarse_lane_count);
        copy(coarse_index_b, a.coarse_index_b, a.coarse_lane_count);
        copy(coarse_batches, a.coarse_batches, a.coarse_batch_count);
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            copy(coarse_weight_node[k], a.coarse_weight_node[k], a.slot_count);
            copy(coarse_weight[k], a.coarse_weight[k], a.slot_count);
        }
        for (int parity = 0; parity < 2; ++parity) {
            copy(coarse_row_node[parity], a.coarse_row_node[parity], a.lattice_plane_rows);
            copy(coarse_row_frac[parity], a.coarse_row_frac[parity], a.lattice_plane_rows);
            copy(coarse_col_node[parity], a.coarse_col_node[parity], a.lattice_plane_cols);
            copy(coarse_col_frac[parity], a.coarse_col_frac[parity], a.lattice_plane_cols);
        }
        point();
    }
    AssetCopy(const AssetCopy&) = delete;

    // Re-points the asset at the vectors (after one was resized); counts of arrays follow them.
    void point() {
        asset.slot_of_particle = slot_of_particle.data();
        asset.particle_of_slot = particle_of_slot.data();
        asset.start_x = start_x.data();
        asset.start_y = start_y.data();
        asset.start_z = start_z.data();
        asset.inverse_mass = inverse_mass.data();
        asset.rest_length = rest_length.data();
        asset.lane_weight = lane_weight.data();
        asset.index_a = index_a.data();
        asset.index_b = index_b.data();
        asset.batches = batches.data();
        asset.batch_count = uint32_t(batches.size());
        asset.lane_count = uint32_t(rest_length.size());
        asset.tether_rest[0] = tether_rest[0].data();
        asset.tether_rest[1] = tether_rest[1].data();
        asset.tether_lane_count = uint32_t(tether_rest[0].size());
        asset.tether_batches = tether_batches.data();
        asset.tether_batch_count = uint32_t(tether_batches.size());
        for (int side = 0; side < 2; ++side) repoint(asset.tether_anchor[side], tether_anchor[side]);
        asset.triangles = triangles.data();
        repoint(asset.wind_runs, wind_runs);
        repoint(asset.wind_lane_weight, wind_lane_weight);
        repoint(asset.wind_rest_area, wind_rest_area);
        repoint(asset.coarse_node_slot, coarse_node_slot);
        repoint(asset.coarse_slot_of_node, coarse_slot_of_node);
        repoint(asset.coarse_node_of_slot, coarse_node_of_slot);
        repoint(asset.coarse_inverse_mass, coarse_inverse_mass);
        repoint(asset.coarse_rest_length, coarse_rest_length);
        repoint(asset.coarse_lane_weight, coarse_lane_weight);
        repoint(asset.coarse_index_a, coarse_index_a);
        repoint(asset.coarse_index_b, coarse_index_b);
        repoint(asset.coarse_batches, coarse_batches);
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            repoint(asset.coarse_weight_node[k], coarse_weight_node[k]);
            repoint(asset.coarse_weight[k], coarse_weight[k]);
        }
        for (int parity = 0; parity < 2; ++parity) {
            repoint(asset.coarse_row_node[parity], coarse_row_node[parity]);
            repoint(asset.coarse_row_frac[parity], coarse_row_frac[parity]);
            repoint(asset.coarse_col_node[parity], coarse_col_node[parity]);
            repoint(asset.coarse_col_frac[parity], coarse_col_frac[parity]);
        }
    }

    uint32_t first_run() const {
        for (uint32_t b = 0; b < batches.size(); ++b)
            if (batches[b].layout == BatchLayout::run) return b;
        FAIL("asset has no run batch");
        return 0;
    }
    // A real (weight 1) lane of batch b.
    uint32_t real_lane(uint32_t b) const {
        for (uint32_t l = batches[b].first_lane; l < batches[b].first_lane + batches[b].lane_count; ++l)
            if (lane_weight[l] == 1.0f) return l;
        FAIL("batch has no real lane");
        return 0;
    }
    uint32_t free_slot() const {
        for (uint32_t s = 0; s < particle_of_slot.size(); ++s)
            if (particle_of_slot[s] != kNoParticle && inverse_mass[s] > 0.0f) return s;
        FAIL("no free slot");
        return 0;
    }
    uint32_t padding_slot() const {
        for (uint32_t s = 0; s < particle_of_slot.size(); ++s)
            if (particle_of_slot[s] == kNoParticle) return s;
        FAIL("no padding slot");
        return 0;
    }
};

// The drape (two pinned corners, tethers on) at n = 25: runs, indexed batches, tethers, padding.
struct Fixture {
    std::unique_ptr<scenes::SeedWorld> scene = make_scene(scenes::SeedScene::drape, options());
    static scenes::SceneOptions options() {
        scenes::SceneOptions o = scene_options(25);
        o.tethers_per_particle = 2;  // two distinct anchors per lane
        return o;
    }
    const ClothAsset& original() const { return scene->asset(); }
};

// Applies `corrupt` to a copy of a valid asset and checks that validation and add_cloth refuse it.
void expect_corrupt(const std::function<void(AssetCopy&)>& corrupt) {
    Fixture f;
    const ClothAsset& original = f.original();
    AssetCopy copy(original);
    REQUIRE(validate_asset(copy.asset).ok());  // the copy itself is sound

    corrupt(copy);
    const Result r = validate_asset(copy.asset);
    INFO("validate_asset: ", r.message);
    CHECK(r.code == ErrorCode::corrupt_asset);
    CHECK(r.message[0] != '\0');

    // Two identical worlds, each with the valid cloth and room for a second (even a larger one).
    OwnedWorld world, twin;
    WorldDesc desc = world_for({&original, &original});
    desc.max_particles *= 2;
    desc.max_constraints *= 2;
    REQUIRE(make_world(desc, &world).ok());
    REQUIRE(make_world(desc, &twin).ok());
    ClothDesc cd;
    cd.asset = &original;
    ClothId id, twin_id;
    REQUIRE(add_cloth(world.world, cd, &id).ok());
    REQUIRE(add_cloth(twin.world, cd, &twin_id).ok());
    for (int i = 0; i < 3; ++i) {
        REQUIRE(step(world.world, scenes::kSeedTimeStep_s).ok());
        REQUIRE(step(twin.world, scenes::kSeedTimeStep_s).ok());
    }
    const std::vector<Vec3> before = read_all(world.world, id, original.particle_count);

    cd.asset = &copy.asset;
    ClothId bad{12345};
    const Result added = add_cloth(world.world, cd, &bad);
    INFO("add_cloth: ", added.message);
    CHECK(added.code == ErrorCode::corrupt_asset);
    CHECK(added.message[0] != '\0');

    // Unchanged: still one cloth, same positions, and the next step matches the untouched twin.
    std::vector<Vec3> scratch(original.particle_count);
    CHECK(read_positions(world.world, ClothId{1}, scratch.data(), original.particle_count).code ==
          ErrorCode::out_of_range);
    CHECK(same_bits(read_all(world.world, id, original.particle_count), before));
    REQUIRE(step(world.world, scenes::kSeedTimeStep_s).ok());
    REQUIRE(step(twin.world, scenes::kSeedTimeStep_s).ok());
    CHECK(same_bits(read_all(world.world, id, original.particle_count),
                    read_all(twin.world, twin_id, original.particle_count)));
    CHECK(world_stats(world.world).steps == world_stats(twin.world).steps);
    // The failed add consumed no capacity: the valid asset still fits as the second cloth.
    cd.asset = &original;
    ClothId second;
    CHECK(add_cloth(world.world, cd, &second).ok());
    CHECK(second.index == 1);
}

}  // namespace

TEST_CASE("a freshly cooked asset and its copy validate") {
    Fixture f;
    CHECK(validate_asset(f.original()).ok());
    AssetCopy copy(f.original());
    CHECK(validate_asset(copy.asset).ok());
    // The fixture exercises every kind of data the checks below corrupt.
    bool has_indexed = false, has_run = false;
    for (const ConstraintBatch& b : copy.batches) {
        has_indexed |= b.layout == BatchLayout::indexed;
        has_run |= b.layout == BatchLayout::run;
    }
    CHECK(has_run);
    CHECK(has_indexed);
    CHECK(copy.asset.tether_batch_count > 0);
    CHECK(copy.asset.slot_count > copy.asset.particle_count);
}

TEST_CASE("corrupt asset: lane index out of range") {
    expect_corrupt([](AssetCopy& c) {
        // An indexed lane (runs would also fail their contiguity check).
        for (uint32_t b = 0; b < c.batches.size(); ++b) {
            if (c.batches[b].layout != BatchLayout::indexed) continue;
            c.index_b[c.real_lane(b)] = c.asset.slot_count + 3;
            return;
        }
        FAIL("no indexed batch");
    });
}

TEST_CASE("corrupt asset: run not contiguous") {
    expect_corrupt([](AssetCopy& c) {
        const uint32_t b = c.first_run();
        const uint32_t l = c.real_lane(b);
        // Still in range and still a different particle at each end, but not a0 + k.
        c.index_a[l] = c.index_a[l] == 0 ? 1 : c.index_a[l] - 1;
        REQUIRE(c.index_a[l] != c.index_b[l]);
    });
}

TEST_CASE("corrupt asset: two batches of one colour share a particle") {
    expect_corrupt([](AssetCopy& c) {
        // Find batch i, the first of colour k + 1, that shares a slot with some batch of colour k,
        // and give it colour k (the colour order stays non-decreasing).
        for (uint32_t i = 1; i < c.batches.size(); ++i) {
            const uint16_t k = c.batches[i - 1].colour;
            if (k == 0xFFFF || c.batches[i].colour != k + 1) continue;
            std::vector<char> touched(c.asset.slot_count, 0);
            for (uint32_t j = 0; j < i; ++j) {
                if (c.batches[j].colour != k) continue;
                for (uint32_t l = c.batches[j].first_lane; l < c.batches[j].first_lane + c.batches[j].lane_count; ++l)
                    if (c.lane_weight[l] != 0.0f) touched[c.index_a[l]] = touched[c.index_b[l]] = 1;
            }
            bool shares = false;
            for (uint32_t l = c.batches[i].first_lane; l < c.batches[i].first_lane + c.batches[i].lane_count; ++l)
                if (c.lane_weight[l] != 0.0f && (touched[c.index_a[l]] || touched[c.index_b[l]])) shares = true;
            if (!shares) continue;
            c.batches[i].colour = k;
            return;
        }
        FAIL("no pair of adjacent colours that share a particle");
    });
}

TEST_CASE("corrupt asset: NaN rest length") {
    expect_corrupt([](AssetCopy& c) {
        c.rest_length[c.real_lane(c.first_run())] = std::numeric_limits<float>::quiet_NaN();
    });
}

TEST_CASE("corrupt asset: NaN rest length on a padding lane") {
    expect_corrupt([](AssetCopy& c) {
        for (uint32_t l = 0; l < c.lane_weight.size(); ++l) {
            if (c.lane_weight[l] != 0.0f) continue;
            c.rest_length[l] = std::numeric_limits<float>::quiet_NaN();
            return;
        }
        FAIL("no padding lane");
    });
}

TEST_CASE("corrupt asset: negative rest length") {
    expect_corrupt([](AssetCopy& c) { c.rest_length[c.real_lane(c.first_run())] = -0.01f; });
}

TEST_CASE("corrupt asset: lane weight 0.5") {
    expect_corrupt([](AssetCopy& c) { c.lane_weight[c.real_lane(c.first_run())] = 0.5f; });
}

TEST_CASE("corrupt asset: tether anchor not pinned (first anchor moved to a free particle)") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.tether_batches.empty());
        c.tether_batches[0].anchor[0] = c.free_slot();
    });
}

TEST_CASE("corrupt asset: tether anchor not pinned (second anchor moved to a free particle)") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.tether_batches.empty());
        c.tether_batches.back().anchor[1] = c.free_slot();
    });
}

TEST_CASE("corrupt asset: tether anchor not pinned (anchor given an inverse mass)") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.tether_batches.empty());
        c.inverse_mass[c.tether_batches[0].anchor[0]] = 1.0f;
    });
}

TEST_CASE("corrupt asset: tether batch with per-lane anchors the asset does not hold") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.asset.tether_anchor_lane_count == 0);
        c.tether_batches[0].anchor[0] = c.tether_batches[0].anchor[1] = kTetherLaneAnchors;
    });
}

TEST_CASE("corrupt asset: tether anchor past the slots") {
    expect_corrupt([](AssetCopy& c) { c.tether_batches[0].anchor[1] = c.asset.slot_count; });
}

TEST_CASE("corrupt asset: padding slot with nonzero inverse mass") {
    expect_corrupt([](AssetCopy& c) { c.inverse_mass[c.padding_slot()] = 1.0f; });
}

TEST_CASE("corrupt asset: slot permutation broken (two particles share a slot)") {
    expect_corrupt([](AssetCopy& c) { c.slot_of_particle[1] = c.slot_of_particle[0]; });
}

TEST_CASE("corrupt asset: slot permutation broken (padding slot claims a particle)") {
    expect_corrupt([](AssetCopy& c) { c.particle_of_slot[c.padding_slot()] = 0; });
}

TEST_CASE("corrupt asset: slot permutation broken (slot past the end)") {
    expect_corrupt([](AssetCopy& c) { c.slot_of_particle[3] = c.asset.slot_count; });
}

TEST_CASE("corrupt asset: NaN start position") {
    expect_corrupt([](AssetCopy& c) { c.start_y[c.free_slot()] = std::numeric_limits<float>::quiet_NaN(); });
}

TEST_CASE("corrupt asset: negative inverse mass") {
    expect_corrupt([](AssetCopy& c) { c.inverse_mass[c.free_slot()] = -1.0f; });
}

TEST_CASE("corrupt asset: slot count not a multiple of the SIMD width") {
    expect_corrupt([](AssetCopy& c) { c.asset.slot_count -= 1; });
}

TEST_CASE("corrupt asset: run overlaps its own particles") {
    expect_corrupt([](AssetCopy& c) {
        const uint32_t b = c.first_run();
        ConstraintBatch& run = c.batches[b];
        // Make the b side start inside the a side (indices follow so only the overlap is wrong).
        run.b0 = run.a0 + 1;
        for (uint32_t k = 0; k < run.lane_count; ++k) c.index_b[run.first_lane + k] = run.b0 + k;
    });
}

TEST_CASE("corrupt asset: batches do not tile the lanes") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.batches.size() >= 2);
        c.batches[1].first_lane += 1;
    });
}

TEST_CASE("corrupt asset: constraint counts disagree with the batches") {
    expect_corrupt([](AssetCopy& c) { c.asset.constraint_count[uint32_t(ConstraintKind::bend)] += 1; });
}

TEST_CASE("corrupt asset: lane joins a particle to itself") {
    expect_corrupt([](AssetCopy& c) {
        for (uint32_t b = 0; b < c.batches.size(); ++b) {
            if (c.batches[b].layout != BatchLayout::indexed) continue;
            const uint32_t l = c.real_lane(b);
            c.index_b[l] = c.index_a[l];
            return;
        }
        FAIL("no indexed batch");
    });
}

TEST_CASE("corrupt asset: batches out of colour order") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.batches.back().colour > 0);
        c.batches.back().colour = 0;
    });
}

TEST_CASE("corrupt asset: colour past colour_count") {
    expect_corrupt([](AssetCopy& c) {
        // The last batch of the last real colour gets a colour that does not exist.
        for (uint32_t b = uint32_t(c.batches.size()); b-- > 0;) {
            if (c.batches[b].colour == 0xFFFF) continue;
            c.batches[b].colour = uint16_t(c.asset.colour_count);
            return;
        }
    });
}

TEST_CASE("corrupt asset: tether with NaN length") {
    expect_corrupt([](AssetCopy& c) {
        for (float& r : c.tether_rest[1]) {
            if (std::isinf(r)) continue;
            r = std::numeric_limits<float>::quiet_NaN();
            return;
        }
        FAIL("no real tether");
    });
}

TEST_CASE("corrupt asset: tether batch reaching past the slots") {
    expect_corrupt([](AssetCopy& c) {
        TetherBatch& t = c.tether_batches.back();
        t.particle0 = c.asset.slot_count - t.lane_count + kSimdWidth;
    });
}

// An extra tether batch longer than the particle arrays: particle0 + lane_count > slot_count. The
// bounds check `particle0 > slot_count - lane_count` wraps around when lane_count > slot_count, so
// the batch passes validation and the tether kernel then reads and writes past every particle
// array (see the report: runtime/src/asset/validate.cpp, check_tethers).
TEST_CASE("corrupt asset: tether batch longer than all the slots") {
    expect_corrupt([](AssetCopy& c) {
        TetherBatch t;
        t.first_lane = uint32_t(c.tether_rest[0].size());
        t.lane_count = c.asset.slot_count + 2 * kSimdWidth;  // a multiple of the SIMD width
        t.particle0 = c.asset.slot_count - kSimdWidth;
        t.anchor[0] = c.tether_batches[0].anchor[0];  // pinned
        t.anchor[1] = c.tether_batches[0].anchor[1];
        // Padding lanes only (+inf lengths): no real tether is added, so the counts agree.
        for (std::vector<float>& rest : c.tether_rest)
            rest.insert(rest.end(), t.lane_count, std::numeric_limits<float>::infinity());
        c.tether_batches.push_back(t);
        c.point();
    });
}

TEST_CASE("corrupt asset: triangle index past the slots") {
    expect_corrupt([](AssetCopy& c) { c.triangles[4] = c.asset.slot_count + 1; });
}

TEST_CASE("corrupt asset: triangle on a padding slot") {
    expect_corrupt([](AssetCopy& c) { c.triangles[4] = c.padding_slot(); });
}

TEST_CASE("corrupt asset: missing arrays") {
    expect_corrupt([](AssetCopy& c) { c.asset.rest_length = nullptr; });
}

// --- the coarse level ---------------------------------------------------------------------------------

TEST_CASE("the fixture has a coarse level in lattice form") {
    Fixture f;
    const ClothAsset& a = f.original();
    CHECK(a.coarse_node_count > 0);
    CHECK(a.coarse_constraint_count > 0);
    CHECK(a.coarse_lattice_cols > 0);
    // The copy no longer points into the cooked asset.
    AssetCopy copy(a);
    CHECK(copy.asset.coarse_weight[0] != a.coarse_weight[0]);
    CHECK(copy.asset.coarse_row_node[1] != a.coarse_row_node[1]);
    CHECK(validate_asset(copy.asset).ok());
}

TEST_CASE("corrupt asset: coarse node slot past the slots") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.coarse_node_slot.empty());
        c.coarse_node_slot.back() = c.asset.slot_count;
    });
}

TEST_CASE("corrupt asset: coarse constraint joins a node slot past the node slots") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.coarse_index_b.empty());
        c.coarse_index_b.back() = c.asset.coarse_slot_count;
    });
}

TEST_CASE("corrupt asset: coarse constraint with NaN rest length") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.coarse_rest_length.empty());
        c.coarse_rest_length[c.coarse_rest_length.size() / 2] = std::numeric_limits<float>::quiet_NaN();
    });
}

TEST_CASE("corrupt asset: coarse run that is not contiguous") {
    expect_corrupt([](AssetCopy& c) {
        for (const ConstraintBatch& b : c.coarse_batches)
            if (b.layout == BatchLayout::run) {
                c.coarse_index_a[b.first_lane + 3] += 1;
                return;
            }
        FAIL("the fixture's coarse level has no run");
    });
}

TEST_CASE("corrupt asset: two coarse batches of one colour share a node slot") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.coarse_batches.size() >= 2);
        for (ConstraintBatch& b : c.coarse_batches) b.colour = 0;  // neighbouring families share nodes
    });
}

TEST_CASE("corrupt asset: coarse node and node slot that do not map both ways") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.coarse_slot_of_node.size() >= 2);
        std::swap(c.coarse_slot_of_node[0], c.coarse_slot_of_node[1]);
    });
}

TEST_CASE("corrupt asset: coarse weight naming a node past the nodes") {
    expect_corrupt([](AssetCopy& c) { c.coarse_weight_node[2][c.free_slot()] = c.asset.coarse_node_count + 7; });
}

TEST_CASE("corrupt asset: coarse weight on a pinned slot") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.tether_batches.empty());
        c.coarse_weight[1][c.tether_batches[0].anchor[0]] = 0.5f;
    });
}

TEST_CASE("corrupt asset: coarse weight NaN") {
    expect_corrupt([](AssetCopy& c) { c.coarse_weight[0][c.free_slot()] = std::numeric_limits<float>::quiet_NaN(); });
}

TEST_CASE("corrupt asset: coarse lattice row table past the coarse rows") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.coarse_row_node[1].empty());
        c.coarse_row_node[1].back() = c.asset.coarse_node_count / c.asset.coarse_lattice_cols - 1;
    });
}

TEST_CASE("corrupt asset: coarse lattice column table past the coarse columns") {
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(!c.coarse_col_node[0].empty());
        c.coarse_col_node[0][0] = c.asset.coarse_lattice_cols;
    });
}

TEST_CASE("corrupt asset: coarse lattice column table out of order") {
    // The lattice form reads 8 columns' nodes with one load and one permute (gather_near): they
    // must be in order and within 8 nodes of each other.
    expect_corrupt([](AssetCopy& c) {
        REQUIRE(c.coarse_col_node[0].size() > 2);
        std::swap(c.coarse_col_node[0][1], c.coarse_col_node[0].back());
    });
}

TEST_CASE("corrupt asset: coarse lattice planes larger than the slots") {
    expect_corrupt([](AssetCopy& c) { c.asset.lattice_plane_rows = c.asset.slot_count; });
}

TEST_CASE("the fixture has triangle runs for the wind pass") {
    Fixture f;
    CHECK(f.original().wind_run_count > 0);
    CHECK(f.original().wind_run_triangles > 0);
    CHECK(f.original().wind_run_triangles <= f.original().triangle_count);
}

TEST_CASE("corrupt asset: wind run reaching past the slots") {
    expect_corrupt([](AssetCopy& c) { c.wind_runs[0].c0 = uint32_t(c.particle_of_slot.size()) - 1; });
}

TEST_CASE("corrupt asset: wind run whose corners overlap") {
    expect_corrupt([](AssetCopy& c) { c.wind_runs[0].b0 = c.wind_runs[0].a0 + 1; });
}

TEST_CASE("corrupt asset: wind lane weight other than 0 or 1 and a negative or NaN rest area") {
    expect_corrupt([](AssetCopy& c) { c.wind_lane_weight[0] = 0.5f; });
    expect_corrupt([](AssetCopy& c) { c.wind_rest_area[0] = -1.0f; });
    expect_corrupt([](AssetCopy& c) { c.wind_rest_area.back() = std::numeric_limits<float>::quiet_NaN(); });
}

TEST_CASE("corrupt asset: wind runs counting more triangles than the asset has") {
    expect_corrupt([](AssetCopy& c) { c.asset.wind_run_triangles = c.asset.triangle_count + 1; });
}
