// Cooking: the seed paper's spring counts (section 3 table) and the contiguous-run layout.
#include "support/test_support.h"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <utility>

using namespace weft;
using namespace weft::test;

TEST_CASE("spring counts of an n x n grid match the seed paper") {
    struct Expected {
        uint32_t n, total;
    };
    // The paper's table: 3 456, 14 406, 32 856, 58 806 springs.
    for (const Expected e : {Expected{25, 3456}, Expected{50, 14406}, Expected{75, 32856}, Expected{100, 58806}}) {
        CAPTURE(e.n);
        const uint32_t n = e.n;
        const scenes::GridMesh grid = scenes::make_grid(n, 2.0f, 2.0f, false, 2.0f);
        for (float m : grid.masses) REQUIRE(m > 0.0f);  // nothing pinned: no spring is dropped
        CHECK(grid.positions.size() == size_t(n) * n);
        CHECK(grid.triangles.size() / 3 == size_t(2) * (n - 1) * (n - 1));

        const CookedCloth cooked = cook(grid.desc());
        const ClothAsset& a = cooked.asset();
        const uint32_t stretch = a.constraint_count[uint32_t(ConstraintKind::stretch)];
        const uint32_t shear = a.constraint_count[uint32_t(ConstraintKind::shear)];
        const uint32_t bend = a.constraint_count[uint32_t(ConstraintKind::bend)];
        CHECK(stretch + shear == 3 * n * n - 4 * n + 1);
        CHECK(bend == 3 * n * n - 8 * n + 5);
        CHECK(a.total_constraints() == 6 * n * n - 12 * n + 6);
        CHECK(a.total_constraints() == e.total);
        // With the lattice the one diagonal per quad is told apart from the axis-aligned edges.
        CHECK(shear == (n - 1) * (n - 1));
        CHECK(stretch == 2 * n * (n - 1));
        CHECK(a.particle_count == n * n);
        CHECK(a.triangle_count == 2 * (n - 1) * (n - 1));
        CHECK(a.tethered_particles == 0);  // nothing pinned, nothing to tether to
        CHECK(a.tether_batch_count == 0);
    }
}

TEST_CASE("spring counts without a lattice: every edge is a stretch spring") {
    const uint32_t n = 25;
    scenes::GridMesh grid = scenes::make_grid(n, 2.0f, 2.0f, false, 2.0f);
    ClothMeshDesc desc = grid.desc();
    desc.lattice = nullptr;
    const CookedCloth cooked = cook(desc);
    const ClothAsset& a = cooked.asset();
    CHECK(a.constraint_count[uint32_t(ConstraintKind::stretch)] == 3 * n * n - 4 * n + 1);
    CHECK(a.constraint_count[uint32_t(ConstraintKind::shear)] == 0);
    CHECK(a.constraint_count[uint32_t(ConstraintKind::bend)] == 3 * n * n - 8 * n + 5);
}

TEST_CASE("cooked springs are exactly the mesh edges and the bend pairs, with rest lengths from the mesh") {
    // Recomputes the seed's spring set (section 1.1) independently and compares pair by pair.
    const uint32_t n = 12;
    const scenes::GridMesh grid = scenes::make_grid(n, 2.0f, 1.5f, false, 2.0f);
    const CookedCloth cooked = cook(grid.desc());
    const ClothAsset& a = cooked.asset();

    std::set<std::pair<uint32_t, uint32_t>> edges, bends;
    auto key = [](uint32_t p, uint32_t q) { return std::make_pair(std::min(p, q), std::max(p, q)); };
    for (uint32_t r = 0; r < n; ++r) {
        for (uint32_t c = 0; c < n; ++c) {
            if (c + 1 < n) edges.insert(key(grid.index(r, c), grid.index(r, c + 1)));
            if (r + 1 < n) edges.insert(key(grid.index(r, c), grid.index(r + 1, c)));
            if (r + 1 < n && c + 1 < n) edges.insert(key(grid.index(r, c + 1), grid.index(r + 1, c)));
        }
    }
    // Bend pairs: for each interior edge, the two vertices opposite it.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> opposite;
    for (size_t t = 0; t < grid.triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e)
            opposite[key(grid.triangles[t + e], grid.triangles[t + (e + 1) % 3])].push_back(grid.triangles[t + (e + 2) % 3]);
    for (const auto& [edge, opp] : opposite)
        if (opp.size() == 2) bends.insert(key(opp[0], opp[1]));

    std::set<std::pair<uint32_t, uint32_t>> cooked_edges, cooked_bends;
    for (uint32_t b = 0; b < a.batch_count; ++b) {
        const ConstraintBatch& batch = a.batches[b];
        for (uint32_t l = batch.first_lane; l < batch.first_lane + batch.lane_count; ++l) {
            if (a.lane_weight[l] == 0.0f) continue;
            const uint32_t p = a.particle_of_slot[a.index_a[l]], q = a.particle_of_slot[a.index_b[l]];
            REQUIRE(p != kNoParticle);
            REQUIRE(q != kNoParticle);
            const Vec3 x = grid.positions[p], y = grid.positions[q];
            const double rest = std::sqrt(double(x.x - y.x) * (x.x - y.x) + double(x.y - y.y) * (x.y - y.y) +
                                          double(x.z - y.z) * (x.z - y.z));
            CHECK(a.rest_length[l] == doctest::Approx(rest).epsilon(1e-6));
            auto& target = batch.kind == ConstraintKind::bend ? cooked_bends : cooked_edges;
            CHECK(target.insert(key(p, q)).second);  // no spring twice
        }
    }
    CHECK(cooked_edges == edges);
    CHECK(cooked_bends == bends);
}

TEST_CASE("drape 100 x 100: at least 95% of the constraints sit on contiguous runs") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(100));
    const ClothAsset& a = w->asset();
    const uint32_t n = 100;
    // Two corners pinned, not adjacent: no spring joins two pinned particles, none is dropped.
    CHECK(a.total_constraints() == 6 * n * n - 12 * n + 6);
    const double fraction = double(a.constraints_on_runs) / double(a.total_constraints());
    MESSAGE("constraints on runs: ", a.constraints_on_runs, " of ", a.total_constraints(), " = ", fraction);
    CHECK(fraction >= 0.95);

    // The run invariants the AVX2 kernel relies on, checked independently of validate_asset.
    uint32_t on_runs = 0, lanes_seen = 0;
    std::vector<int> colour_of_slot(a.slot_count, -1);
    uint16_t current_colour = 0xFFFE;
    for (uint32_t b = 0; b < a.batch_count; ++b) {
        const ConstraintBatch& batch = a.batches[b];
        CAPTURE(b);
        CHECK(batch.first_lane == lanes_seen);
        lanes_seen += batch.lane_count;
        if (batch.colour != current_colour) {
            current_colour = batch.colour;
            std::fill(colour_of_slot.begin(), colour_of_slot.end(), -1);
        }
        if (batch.layout == BatchLayout::run) {
            CHECK(batch.lane_count % kSimdWidth == 0);
            CHECK(batch.a0 + batch.lane_count <= a.slot_count);
            CHECK(batch.b0 + batch.lane_count <= a.slot_count);
            const uint32_t gap = batch.a0 < batch.b0 ? batch.b0 - batch.a0 : batch.a0 - batch.b0;
            CHECK(gap >= batch.lane_count);  // the a side and the b side do not overlap
            for (uint32_t k = 0; k < batch.lane_count; ++k) {
                const uint32_t l = batch.first_lane + k;
                if (a.index_a[l] != batch.a0 + k || a.index_b[l] != batch.b0 + k) {
                    FAIL_CHECK("run ", b, " is not contiguous at lane ", k);
                    break;
                }
                if (a.lane_weight[l] != 0.0f) ++on_runs;
            }
        }
        if (batch.colour == 0xFFFF) continue;  // the overflow colour shares particles by design
        for (uint32_t l = batch.first_lane; l < batch.first_lane + batch.lane_count; ++l) {
            if (a.lane_weight[l] == 0.0f) continue;
            for (uint32_t s : {a.index_a[l], a.index_b[l]}) {
                if (colour_of_slot[s] != -1) {
                    FAIL_CHECK("colour ", batch.colour, " touches slot ", s, " twice");
                }
                colour_of_slot[s] = int(b);
            }
        }
    }
    CHECK(lanes_seen == a.lane_count);
    CHECK(on_runs == a.constraints_on_runs);
    CHECK(validate_asset(a).ok());

    // The step reports the same split.
    step_n(*w, 1);
    const WorldStats stats = world_stats(w->world);
    CHECK(stats.run_projections == uint64_t(a.constraints_on_runs) * 3);
    CHECK(stats.indexed_projections == uint64_t(a.total_constraints() - a.constraints_on_runs) * 3);
}

TEST_CASE("slot permutation maps both ways and padding slots are pinned") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(25));
    const ClothAsset& a = w->asset();
    CHECK(a.slot_count % kSimdWidth == 0);
    std::vector<int> seen(a.slot_count, 0);
    for (uint32_t p = 0; p < a.particle_count; ++p) {
        const uint32_t s = a.slot_of_particle[p];
        REQUIRE(s < a.slot_count);
        CHECK(a.particle_of_slot[s] == p);
        CHECK(++seen[s] == 1);
        const Vec3 start = w->mesh.positions[p];
        CHECK(a.start_x[s] == start.x);
        CHECK(a.start_y[s] == start.y);
        CHECK(a.start_z[s] == start.z);
    }
    for (uint32_t s = 0; s < a.slot_count; ++s)
        if (a.particle_of_slot[s] == kNoParticle) CHECK(a.inverse_mass[s] == 0.0f);
    // The two pinned corners and nothing else.
    uint32_t pinned = 0;
    for (uint32_t p = 0; p < a.particle_count; ++p) pinned += a.inverse_mass[a.slot_of_particle[p]] == 0.0f;
    CHECK(pinned == 2);
    CHECK(a.inverse_mass[a.slot_of_particle[w->mesh.index(0, 0)]] == 0.0f);
    CHECK(a.inverse_mass[a.slot_of_particle[w->mesh.index(0, 24)]] == 0.0f);
    // Tethers: one lane per free particle, to pinned anchors, at the rest-mesh distances.
    CHECK(a.tethered_particles == a.particle_count - 2);
    std::vector<int> tethered(a.slot_count, 0);
    for (uint32_t b = 0; b < a.tether_batch_count; ++b) {
        const TetherBatch& t = a.tether_batches[b];
        for (uint32_t k = 0; k < t.lane_count; ++k) {
            const float r0 = a.tether_rest[0][t.first_lane + k], r1 = a.tether_rest[1][t.first_lane + k];
            if (std::isinf(r0) && std::isinf(r1)) continue;
            const uint32_t s = t.particle0 + k;
            REQUIRE(s < a.slot_count);
            ++tethered[s];
            CHECK(a.inverse_mass[s] > 0.0f);
            for (int side = 0; side < 2; ++side) {
                const uint32_t q = tether_anchor(a, t, k, uint32_t(side));
                CHECK(a.inverse_mass[q] == 0.0f);
                const double dx = double(a.start_x[s]) - a.start_x[q], dy = double(a.start_y[s]) - a.start_y[q],
                             dz = double(a.start_z[s]) - a.start_z[q];
                CHECK(a.tether_rest[side][t.first_lane + k] == doctest::Approx(std::sqrt(dx * dx + dy * dy + dz * dz)));
            }
        }
    }
    for (uint32_t p = 0; p < a.particle_count; ++p) {
        const uint32_t s = a.slot_of_particle[p];
        CHECK(tethered[s] == (a.inverse_mass[s] > 0.0f ? 1 : 0));
    }
}

// ClothMeshDesc::lattice_plane_stride: plane rows at a stride other than the lattice's width
// (weft-bake's helix). The plane width itself is the default layout; a wider stride leaves holes
// that runs bridge; a narrower one makes nodes meet at one slot, and those go after the planes:
// every stride gives a valid asset with every spring, each particle in its own slot.
TEST_CASE("cook: lattice_plane_stride lays the parity planes' rows at any stride") {
    const uint32_t n = 20;  // plane rows of 10 columns
    const scenes::GridMesh grid = scenes::make_grid(n, 2.0f, 2.0f, false, 2.0f);
    ClothMeshDesc desc = grid.desc();
    REQUIRE(desc.lattice != nullptr);
    const CookedCloth box = cook(desc);
    for (const uint32_t stride : {10u, 13u, 7u, 1u}) {
        CAPTURE(stride);
        desc.lattice_plane_stride = stride;
        const CookedCloth cooked = cook(desc);  // validated inside cook_cloth
        const ClothAsset& a = cooked.asset();
        CHECK(a.total_constraints() == box.asset().total_constraints());
        std::set<uint32_t> slots(cooked.slot_of_particle.begin(), cooked.slot_of_particle.end());
        CHECK(slots.size() == n * n);
        const double contiguous = double(a.constraints_on_runs) / double(a.total_constraints());
        if (stride == 10) CHECK(cooked.slot_of_particle == box.slot_of_particle);
        if (stride == 13) CHECK(contiguous > 0.95);  // holes of 3 slots between rows, mostly bridged
        if (stride == 13) CHECK(lane_padding(a).constraints.ratio() > lane_padding(box.asset()).constraints.ratio());
    }
}

// Per-lane anchors (a tether batch whose lanes hold different anchor pairs, kTetherLaneAnchors)
// project exactly as a batch with one pair: a hanging grid pinned at every third particle of its
// top and bottom rows (neighbouring particles mostly have different anchor pairs, as a dressed
// garment's near its band), cooked as is and re-batched with one real lane per batch (each batch
// its lane's pair), steps to the same bits, on the scalar and the AVX2 path alike.
TEST_CASE("tethers: per-lane anchor batches step to the bits of one-pair batches on every path") {
    scenes::GridMesh grid = scenes::make_grid(24, 1.0f, 1.0f, true, 2.0f);
    for (uint32_t c = 0; c < grid.n; c += 3) grid.masses[grid.index(0, c)] = grid.masses[grid.index(grid.n - 1, c)] = 0.0f;
    const ClothMeshDesc mesh = grid.desc();
    CookedCloth lanes = cook(mesh), pairs = cook(mesh);
    const ClothAsset& a = lanes.asset();
    const uint32_t width = a.simd_width;
    uint32_t per_lane = 0;
    for (uint32_t b = 0; b < a.tether_batch_count; ++b) per_lane += a.tether_batches[b].anchor[0] == kTetherLaneAnchors;
    REQUIRE(per_lane > 0);
    REQUIRE(a.tether_anchor_lane_count == a.tether_lane_count);
    std::vector<float> rest[2];
    std::vector<TetherBatch> batches;
    for (uint32_t b = 0; b < a.tether_batch_count; ++b) {
        const TetherBatch& t = a.tether_batches[b];
        for (uint32_t k = 0; k < t.lane_count; ++k) {
            if (std::isinf(a.tether_rest[0][t.first_lane + k])) continue;  // padding
            const uint32_t s = t.particle0 + k, first = std::min(s, a.slot_count - width);
            batches.push_back({uint32_t(rest[0].size()), width, first, {tether_anchor(a, t, k, 0), tether_anchor(a, t, k, 1)}});
            for (uint32_t j = 0; j < width; ++j)
                for (int side = 0; side < 2; ++side)
                    rest[side].push_back(first + j == s ? a.tether_rest[side][t.first_lane + k] : INFINITY);
        }
    }
    for (int side = 0; side < 2; ++side) pairs.tether_rest[side] = rest[side], pairs.tether_anchor[side].clear();
    pairs.tether_batches = batches;
    pairs.refresh_asset();
    REQUIRE(validate_asset(pairs.asset()).ok());
    REQUIRE(pairs.asset().tether_anchor_lane_count == 0);

    std::vector<std::vector<Vec3>> results;
    for (const ClothAsset* asset : {&lanes.asset(), &pairs.asset()})
        for (SimdPath path : available_paths()) {
            OwnedWorld world;
            REQUIRE(make_world(world_for({asset}, 0, path), &world).ok());
            ClothDesc cd;
            cd.asset = asset;
            cd.tethers_before_sweeps = true;  // two tether passes a step
            ClothId id;
            REQUIRE(add_cloth(world.world, cd, &id).ok());
            for (int i = 0; i < 100; ++i) REQUIRE(step(world.world, 1.0f / 30.0f).ok());
            results.push_back(read_all(world.world, id, asset->particle_count));
        }
    CHECK(!same_bits(results[0], grid.positions));  // it moved
    for (const std::vector<Vec3>& r : results) CHECK(same_bits(r, results[0]));
}

TEST_CASE("tethers: a mesh with rest corners (sewn) measures them along its flat panels, not across its pose") {
    // A strip 2 x 21 particles, 1 m long flat, folded in its pose into a hairpin whose free end lies
    // 5 cm from the pinned one: straight in the pose the far end's tether would be 5 cm and hold the
    // fold shut; along the panel it is 1 m.
    const uint32_t columns = 21;
    const float h = 0.05f;  // m between columns
    std::vector<Vec3> flat, pose;
    for (uint32_t c = 0; c < columns; ++c)
        for (uint32_t r = 0; r < 2; ++r) {
            flat.push_back({h * float(c), 0.1f * float(r), 0.0f});
            const float s = h * float(c), half = 0.5f * h * float(columns - 1);  // fold at the middle
            pose.push_back(s <= half ? Vec3{s, 0.1f * float(r), 0.0f} : Vec3{2.0f * half - s, 0.1f * float(r), 0.05f});
        }
    std::vector<uint32_t> triangles;
    std::vector<Vec3> corners;
    for (uint32_t c = 0; c + 1 < columns; ++c) {
        const uint32_t a = 2 * c, b = 2 * c + 1, d = 2 * c + 2, e = 2 * c + 3;
        for (const uint32_t t : {a, d, e, a, e, b}) triangles.push_back(t), corners.push_back(flat[t]);
    }
    std::vector<float> masses(flat.size(), 0.01f);
    masses[0] = masses[1] = 0.0f;  // the pinned end
    ClothMeshDesc mesh;
    mesh.particle_count = uint32_t(pose.size());
    mesh.positions = pose.data();
    mesh.triangle_count = uint32_t(triangles.size() / 3);
    mesh.triangles = triangles.data();
    mesh.masses = masses.data();
    mesh.rest_corners = corners.data();
    CookOptions options;
    options.coarse_spacing_m = 0.0f;
    const CookedCloth cooked = cook(mesh, options);
    const ClothAsset& a = cooked.asset();
    uint32_t checked = 0;
    for (uint32_t b = 0; b < a.tether_batch_count; ++b) {
        const TetherBatch& t = a.tether_batches[b];
        for (uint32_t k = 0; k < t.lane_count; ++k) {
            const float rest = a.tether_rest[0][t.first_lane + k];
            if (!std::isfinite(rest)) continue;
            const uint32_t p = a.particle_of_slot[t.particle0 + k], pin = a.particle_of_slot[tether_anchor(a, t, k, 0)];
            REQUIRE(p != kNoParticle);
            const Vec3 d{flat[p].x - flat[pin].x, flat[p].y - flat[pin].y, 0.0f};
            const float along = std::sqrt(d.x * d.x + d.y * d.y);  // the flat strip is convex: a straight path on it
            CHECK(rest >= along * (1.0f - 1e-5f));  // never shorter than the path on the panel
            CHECK(rest <= along * 1.09f + 1e-6f);   // edges and unfolded bend pairs: close to it
            ++checked;
        }
    }
    CHECK(checked == pose.size() - 2);
}

TEST_CASE("an asset's start pose and triangles read back in the caller's particle order") {
    auto w = make_scene(scenes::SeedScene::drape, scene_options(25));
    const ClothAsset& a = w->asset();
    REQUIRE(a.slot_of_particle[1] != 1);  // the lattice's parity planes reorder the particles
    std::vector<Vec3> start(a.particle_count);
    REQUIRE(read_start_positions(a, start.data(), a.particle_count).ok());
    for (uint32_t p = 0; p < a.particle_count; ++p) CHECK(same_bits({start[p]}, {w->mesh.positions[p]}));
    // The same triangles as the cooked mesh, each wound the same way (a rotation of its corners),
    // in any order.
    std::vector<uint32_t> read(3 * size_t(a.triangle_count));
    REQUIRE(read_triangles(a, read.data(), uint32_t(read.size())).ok());
    REQUIRE(read.size() == w->mesh.triangles.size());
    const auto canonical = [](const std::vector<uint32_t>& t) {
        std::vector<std::array<uint32_t, 3>> out;
        for (size_t k = 0; k + 2 < t.size(); k += 3) {
            std::array<uint32_t, 3> c{t[k], t[k + 1], t[k + 2]};
            std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
            out.push_back(c);
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    CHECK(canonical(read) == canonical(w->mesh.triangles));
    // Wrong counts and null outputs are refused.
    CHECK(read_start_positions(a, start.data(), a.particle_count - 1).code == ErrorCode::out_of_range);
    CHECK(read_start_positions(a, nullptr, a.particle_count).code == ErrorCode::invalid_argument);
    CHECK(read_triangles(a, read.data(), uint32_t(read.size()) + 3).code == ErrorCode::out_of_range);
    CHECK(read_triangles(a, nullptr, uint32_t(read.size())).code == ErrorCode::invalid_argument);
}
