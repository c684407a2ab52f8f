// weft_pattern: sewing patterns -> meshed garments (tools/bake). Reads the project's samples and,
// when present, the shared GarmentCode patterns (../shared/data; skipped with a message if absent).
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "bake/batch.h"
#include "bake/garment.h"
#include "bake/outline.h"
#include "bake/pattern.h"
#include "body/body_mesh.h"
#include "weft/cloth_asset.h"
#include "weft/cook.h"

using namespace weft;
using namespace weft::bake;

namespace {

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

struct Meshed {
    Pattern pattern;
    MeshedGarment garment;
    double seconds = 0.0;
};

Meshed bake_text(const std::string& text, const ParseOptions& parse = {}, const MeshOptions& mesh = {}) {
    Meshed b;
    const auto start = std::chrono::steady_clock::now();
    const Status parsed = parse_pattern(text, parse, &b.pattern);
    REQUIRE_MESSAGE(parsed.ok(), parsed.error);
    const Status meshed = mesh_garment(b.pattern, mesh, &b.garment);
    REQUIRE_MESSAGE(meshed.ok(), meshed.error);
    b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return b;
}

// The garment cooked as weft-bake cooks it (cook_packings: the cheapest of the packings and run shapes it tries).
struct RunFigures {
    double contiguous_fraction = 0.0;  // constraints on SIMD runs / all constraints (the runtime's measure)
    double padding_ratio = 0.0;        // lane_padding: every batched pass
    double constraint_padding = 0.0;   // lane_padding: the constraint pass alone
};
RunFigures run_figures(const MeshedGarment& g) {
    CookedCloth cooked;
    size_t winner = 0;
    const Result r = cook_packings(cloth_mesh_desc(g), g, CookOptions{}, true, &cooked, nullptr, &winner);
    REQUIRE_MESSAGE(r.ok(), r.message);
    const LanePadding padding = lane_padding(cooked.asset());
    return {double(cooked.asset().constraints_on_runs) / double(cooked.asset().total_constraints()), padding.ratio(),
            padding.constraints.ratio()};
}

// Every property a baked garment promises (garment.h), checked from the outside.
void check_garment(const Meshed& b) {
    const Pattern& pattern = b.pattern;
    const MeshedGarment& g = b.garment;
    const size_t n = g.positions.size();
    REQUIRE(n > 0);
    CHECK(g.rest_positions.size() == n);
    CHECK(g.masses.size() == n);
    CHECK(g.lattice.size() == 2 * n);
    CHECK(g.uv.size() == 2 * n);
    CHECK(g.panel.size() == n);
    for (float v : g.uv) REQUIRE(std::isfinite(v));

    // Every seam's sides have the same number of points (seed 4.1.2).
    for (const Seam& seam : pattern.seams)
        for (const SeamSide& side : seam.sides)
            CHECK(g.edge_particles[side.panel][side.edge].size() ==
                  g.edge_particles[seam.sides[0].panel][seam.sides[0].edge].size());
    // Seam points: 2 sources, 3 or 4 where seams meet at a corner.
    for (size_t s = 0; s + 1 < g.seam_first.size(); ++s) {
        const uint32_t degree = g.seam_first[s + 1] - g.seam_first[s];
        CHECK(degree >= 2);
        CHECK(degree <= 4);
    }

    // Masses: rho * area, panel by panel (seed eq. 9).
    double expected = 0.0, mass = 0.0;
    std::vector<double> panel_area(pattern.panels.size(), 0.0);
    for (size_t t = 0; t < g.triangles.size(); t += 3) {
        const uint32_t a = g.triangles[t], bb = g.triangles[t + 1], c = g.triangles[t + 2];
        const Point2 pa{g.uv[2 * a], g.uv[2 * a + 1]}, pb{g.uv[2 * bb], g.uv[2 * bb + 1]}, pc{g.uv[2 * c], g.uv[2 * c + 1]};
        const double area = 0.5 * std::fabs((pb.x - pa.x) * (pc.y - pa.y) - (pc.x - pa.x) * (pb.y - pa.y));
        panel_area[g.panel[a]] += area;
    }
    for (size_t p = 0; p < pattern.panels.size(); ++p) {
        const double rho = pattern.panels[p].areal_density_kg_m2 > 0 ? pattern.panels[p].areal_density_kg_m2
                                                                     : pattern.fabric.areal_density_kg_m2;
        expected += rho * panel_area[p];
    }
    for (float m : g.masses) mass += m;
    CHECK(std::fabs(mass - expected) <= 1e-6 * expected);
    CHECK(std::fabs(g.total_mass_kg - expected) <= 1e-6 * expected);

    // Centroids inside the panel outlines (the polygon of the fine curved outline).
    for (size_t p = 0; p < pattern.panels.size(); ++p) {
        const std::vector<Point2> outline = fine_outline(pattern.panels[p]);
        uint32_t outside = 0;
        for (size_t t = 0; t < g.triangles.size(); t += 3) {
            const uint32_t a = g.triangles[t], bb = g.triangles[t + 1], c = g.triangles[t + 2];
            if (g.panel[a] != p) continue;
            const Point2 centroid{(g.uv[2 * a] + g.uv[2 * bb] + g.uv[2 * c]) / 3.0, (g.uv[2 * a + 1] + g.uv[2 * bb + 1] + g.uv[2 * c + 1]) / 3.0};
            outside += !point_in_polygon(outline, centroid);
        }
        CHECK_MESSAGE(outside == 0, pattern.panels[p].name);
    }
    // Minimum angle away from sharp outline corners.
    for (const PanelQuality& q : g.quality.panels) CHECK_MESSAGE(q.min_angle_deg_smooth >= 20.0 - 1e-6, q.name);
}

// Lattice nodes in the box the runtime allocates / particles: it refuses the lattice above about 2.
double lattice_fill(const MeshedGarment& g) {
    int32_t i0 = INT32_MAX, j0 = INT32_MAX, i1 = -1, j1 = -1;
    for (size_t k = 0; k < g.lattice.size(); k += 2)
        if (g.lattice[k] >= 0)
            i0 = std::min(i0, g.lattice[k]), i1 = std::max(i1, g.lattice[k]), j0 = std::min(j0, g.lattice[k + 1]),
            j1 = std::max(j1, g.lattice[k + 1]);
    i0 &= ~1, j0 &= ~1;
    return double((i1 - i0) / 2 + 1) * double((j1 - j0) / 2 + 1) * 4.0 / double(g.positions.size());
}

void report(const std::string& name, const Meshed& b, double reference_cm2 = 0.0) {
    const PanelQuality& q = b.garment.quality.overall;
    const RunFigures runs = run_figures(b.garment);
    const double area_cm2 = b.garment.area_m2 * 1e4;
    const double error = reference_cm2 > 0 ? (area_cm2 - reference_cm2) / reference_cm2 : 0.0;
    MESSAGE(name << ": " << q.particles << " particles (" << q.grid_particles << " grid), " << q.triangles
                 << " triangles, min angle " << q.min_angle_deg << " deg (" << q.min_angle_deg_smooth
                 << " away from sharp corners), edges " << q.edge_min_h << "/" << q.edge_mean_h << "/" << q.edge_max_h
                 << " h, area " << area_cm2 << " cm^2 (outline " << q.outline_area_m2 * 1e4 << ", reference error "
                 << error * 100 << "%), rounds " << b.garment.quality.rounds << ", seam points "
                 << b.garment.seam_first.size() - 1 << ", lattice box " << lattice_fill(b.garment) << " nodes per particle, contiguous_fraction " << runs.contiguous_fraction << ", padding_ratio "
                 << runs.padding_ratio << ", bake " << b.seconds << " s");
}

// The issue's acceptance at the default resolution: contiguous_fraction >= 0.90 (met by every
// sample and GarmentCode pattern: 0.91-0.999, docs/pattern-format.md) and padding waste under 10%,
// over every pass and in the constraint pass alone, met by the samples (skirt 0.055 / 0.072, tee
// 0.074 / 0.097: the baker's padding budget, kMaxPaddingRatio; tests/test_pipeline.cpp checks what
// weft-bake writes); the GarmentCode garments stay at 0.13-0.18
// (more panels, each boundary costs padding lanes), so for them the bound warns and guards against
// regressions only.
void check_contiguous(const std::string& name, const MeshedGarment& g, bool sample) {
    const RunFigures runs = run_figures(g);
    CHECK_MESSAGE(runs.contiguous_fraction >= 0.90, name);
    if (sample) {
        CHECK_MESSAGE(runs.padding_ratio < 0.10, name);
        CHECK_MESSAGE(runs.constraint_padding < 0.10, name);
    } else {
        WARN_MESSAGE(runs.padding_ratio < 0.10, name << ": padding_ratio " << runs.padding_ratio << " above the 0.10 target");
        CHECK_MESSAGE(runs.padding_ratio < 0.25, name);
    }
}

const std::filesystem::path kSamples = WEFT_SAMPLES_DIR;
const std::filesystem::path kShared = WEFT_SHARED_DATA_DIR;

}  // namespace

TEST_CASE("bake: the sample patterns mesh, sew and cook") {
    for (const char* name : {"sheet", "flag", "skirt", "tee"}) {
        CAPTURE(std::string(name));
        const Meshed b = bake_text(read_text(kSamples / (std::string(name) + ".json")));
        check_garment(b);
        report(name, b);
        check_contiguous(name, b.garment, true);
    }
}

TEST_CASE("bake: a render mesh from --render-subdivide, or read from an OBJ, is bound to the cloth and stored in the asset") {
    const std::string text = read_text(kSamples / "skirt.json");
    BakeOptions options;
    options.render_subdivide = 1;
    Baked sub;
    REQUIRE(bake_pattern(text, options, &sub).ok());
    const RenderMesh& m = sub.cooked.asset().render;
    CHECK(m.triangle_count == 4 * sub.cooked.asset().triangle_count);
    CHECK(sub.render_bind_error_m < 1e-6);
    // The same mesh through an OBJ file (lib/body's reader, as weft-bake --render-mesh reads it).
    RenderMeshSource fine;
    REQUIRE(subdivide_cloth_mesh(sub.cooked.asset(), 1, &fine).ok());
    const std::string path = (std::filesystem::temp_directory_path() / "weft_test_render_mesh.obj").string();
    REQUIRE(body::save_obj(path, fine.positions, fine.triangles, fine.uv).empty());
    body::BodyMesh read;
    REQUIRE(body::load_body_mesh(path, &read).empty());
    std::filesystem::remove(path);
    RenderMeshSource from_file;
    from_file.positions = read.positions, from_file.triangles = read.triangles, from_file.uv = read.uv;
    options.render_subdivide = -1;
    options.render_mesh = &from_file;
    Baked obj;
    REQUIRE(bake_pattern(text, options, &obj).ok());
    const RenderMesh& o = obj.cooked.asset().render;
    REQUIRE(o.vertex_count == m.vertex_count);
    CHECK(o.triangle_count == m.triangle_count);
    CHECK(obj.render_bind_error_m < 1e-5);
    double worst_uv = 0;
    for (uint32_t v = 0; v < 2 * o.vertex_count; ++v) worst_uv = std::max(worst_uv, std::fabs(double(o.uv[v]) - m.uv[v]));
    CHECK(worst_uv < 1e-5);
    // A render mesh far from the cloth is refused.
    RenderMeshSource far = from_file;
    for (Vec3& x : far.positions) x.x += 5.0f, x.y += 5.0f, x.z += 5.0f;
    options.render_mesh = &far;
    Baked refused;
    const Status s = bake_pattern(text, options, &refused);
    CHECK_FALSE(s.ok());
    CHECK(s.error.find("render mesh") != std::string::npos);
}

TEST_CASE("bake: the GarmentCode patterns match the reference areas") {
    if (!std::filesystem::exists(kShared / "patterns")) {
        MESSAGE("skipped: no shared data at " << kShared.string());
        return;
    }
    struct Case {
        const char* file;
        double area_cm2;
        double offset_y;
    };
    // The v1 patterns are placed for another body (origin near the pelvis): lift them.
    for (const Case& c : {Case{"garmentcode/shirt_mean_specification.json", 6396.3, 0.0},
                          Case{"garmentcode/dress_pencil_specification.json", 11643.9, 0.0},
                          Case{"garmentcode-v1/skirt_2_panels.json", 6835.9, 1.05},
                          Case{"garmentcode-v1/tee.json", 5775.0, 1.2}}) {
        CAPTURE(std::string(c.file));
        ParseOptions options;
        options.placement_offset_m[1] = c.offset_y;
        const Meshed b = bake_text(read_text(kShared / "patterns" / c.file), options);
        check_garment(b);
        report(c.file, b, c.area_cm2);
        CHECK(std::fabs(b.garment.quality.overall.outline_area_m2 * 1e4 - c.area_cm2) <= 0.005 * c.area_cm2);
        CHECK(std::fabs(b.garment.area_m2 * 1e4 - c.area_cm2) <= 0.005 * c.area_cm2);
        check_contiguous(c.file, b.garment, false);
    }
}

// Corpus garments (../shared/data/patterns/garmentcode-sampled, GarmentCode's own sampler) that
// showed each cause the flat bake used to stop at (docs/decisions/flat-bake-corpus.md). The whole
// corpus is a benchmark, not a test: these few stand for it.
namespace {

const std::filesystem::path kCorpus = kShared / "patterns" / "garmentcode-sampled";

bool have_corpus() {
    if (std::filesystem::exists(kCorpus)) return true;
    MESSAGE("skipped: no GarmentCode corpus at " << kCorpus.string());
    return false;
}

}  // namespace

TEST_CASE("bake: sharp outline corners no longer keep the strip mesher splitting") {
    if (!have_corpus()) return;
    // gc_1001_0014 (a four-panel top): corners under 60 degrees, where CGAL's mesher splits the
    // outline in every run (a new cluster of Shewchuk's concentric shells each time), so sampling
    // there finer never ended. gc_1001_0138 (a top with a waistband): darts, whose segments the
    // mesher splits near their tips; sampled finer there alone, they settle in 3 rounds. Both
    // stopped at 16 rounds before.
    for (const char* name : {"gc_1001_0014", "gc_1001_0138"}) {
        CAPTURE(std::string(name));
        const Meshed b = bake_text(read_text(kCorpus / (std::string(name) + "_specification.json")));
        check_garment(b);  // seam sides one to one, masses, every triangle inside, 20 degrees away from sharp corners
        CHECK(b.garment.quality.rounds <= 3);
        const PanelQuality& q = b.garment.quality.overall;
        CHECK(std::fabs(q.mesh_area_m2 - q.outline_area_m2) <= 0.005 * q.outline_area_m2);
        CHECK(q.edge_max_h <= 2.6);  // the strip's longest edge stays near its 1.5 h bound (the grid: sqrt(2) h)
    }
}

TEST_CASE("bake: an outline that truly crosses itself is refused, naming its panel and edges") {
    if (!have_corpus()) return;
    // GarmentCode checks its panels with arcs cut into 11 chords; the exact arc of this neckline
    // (edge 1) crosses the armhole (edge 4) by about 0.45 mm, pinching the shoulder to nothing.
    Pattern pattern;
    const Status s = parse_pattern(read_text(kCorpus / "gc_1001_0021_specification.json"), {}, &pattern);
    REQUIRE_FALSE(s.ok());
    CHECK(s.error.find("panel \"right_ftorso\"") != std::string::npos);
    CHECK(s.error.find("edge \"1\" meets edge \"4\"") != std::string::npos);
}

TEST_CASE("bake: a curve that overshoots its corner is made flatter, and the pattern says so") {
    if (!have_corpus()) return;
    // The arc of gc_1001_0080's hem leaves its corner about 4 degrees outside it and crosses the
    // side 11 cm up; gc_1001_0144's neckline overshoots the shoulder's corner. GarmentCode's check
    // (10 chords a curve) passes both.
    for (const char* name : {"gc_1001_0080", "gc_1001_0144"}) {
        CAPTURE(name);
        const std::string text = read_text(kCorpus / (std::string(name) + "_specification.json"));
        Pattern pattern;
        const Status s = parse_pattern(text, {}, &pattern);
        REQUIRE_MESSAGE(s.ok(), s.error);
        REQUIRE_FALSE(pattern.repairs.empty());
        for (const std::string& note : pattern.repairs) {
            CHECK(note.find("panel \"") == 0);
            CHECK(note.find("flatter") != std::string::npos);
        }
        CHECK(validate_pattern(pattern).ok());
        Baked baked;
        const Status b = bake_pattern(text, BakeOptions{}, &baked);
        CHECK_MESSAGE(b.ok(), b.error);
    }
}

TEST_CASE("bake: the sample skirt bakes to the same bytes whichever compiler built the baker") {
    // The expected hash is what a GCC build and a Clang build of this baker write (both checked,
    // docs/decisions/flat-bake-corpus.md). They differed while mesh_panel inserted grid nodes into
    // CGAL's triangulation as arguments of one call: the two compilers evaluate arguments in other
    // orders. A change that means to alter the mesh or the file updates the value.
    Baked baked;
    const Status s = bake_pattern(read_text(kSamples / "skirt.json"), BakeOptions{}, &baked);
    REQUIRE_MESSAGE(s.ok(), s.error);
    uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits
    for (std::byte b : baked.bytes) hash = (hash ^ uint64_t(b)) * 0x100000001b3ull;
    MESSAGE("skirt asset: " << baked.bytes.size() << " bytes, FNV-1a " << hash);
    // The value changes only with the asset's bytes (last: runs cut at their gaps, 2026-11-29); a
    // GCC and a Clang build of the baker write these same bytes.
    CHECK(hash == 0x6fcf00d091bb261bull);
}

// weft-bake's manifests (batch.h): paths relative to the manifest, "defaults" under each entry's
// own keys and over the command line's, mistakes refused naming the entry.
TEST_CASE("bake: a manifest's entries take the defaults, their own options and paths beside it") {
    BatchEntry command_line;
    command_line.sweeps = 12;
    command_line.body = "mannequin";
    const std::string manifest = R"({
      "format": "weft-bake-manifest",
      "defaults": { "target_edge_m": 0.03, "body": "bodies/mean_all.obj" },
      "assets": [
        { "pattern": "patterns/skirt.json" },
        { "pattern": "gc/gc_1001_0000_specification.json", "target_edge_m": 0.015, "body": null },
        { "pattern": "patterns/skirt.json", "name": "skirt-16", "simd_width": 16, "sweeps": 16, "offset_m": [0, 0.1, 0] },
        { "pattern": "patterns/overshirt.json", "over": ["patterns/tee.json"] }
      ]
    })";
    REQUIRE(is_manifest(manifest));
    std::vector<BatchEntry> entries;
    REQUIRE(read_manifest("/art/assets.json", manifest, command_line, &entries) == "");
    REQUIRE(entries.size() == 4);
    CHECK(entries[0].name == "skirt");
    CHECK(entries[0].pattern == "/art/patterns/skirt.json");
    CHECK(entries[0].body == "/art/bodies/mean_all.obj");
    CHECK(entries[0].target_edge_m == 0.03);
    CHECK(entries[0].sweeps == 12);
    CHECK(entries[0].manifest == "/art/assets.json");
    CHECK(entries[1].name == "gc_1001_0000");
    CHECK(entries[1].body.empty());
    CHECK(entries[1].target_edge_m == 0.015);
    CHECK(entries[2].name == "skirt-16");
    CHECK(entries[2].simd_width == 16);
    CHECK(entries[2].sweeps == 16);
    CHECK(entries[2].offset_m[1] == 0.1);
    CHECK(entries[0].over.empty());
    CHECK(entries[3].over == std::vector<std::string>{"/art/patterns/tee.json"});  // worn over it: --over
}

TEST_CASE("bake: a manifest's mistakes are refused, naming the entry") {
    const auto error = [](const std::string& assets) {
        std::vector<BatchEntry> entries;
        return read_manifest("m.json", R"({"format": "weft-bake-manifest", "assets": )" + assets + "}", BatchEntry{}, &entries);
    };
    CHECK(error(R"([{"pattern": "a.json", "traget_edge_m": 0.02}])") == "m.json: assets[0]: unknown key 'traget_edge_m'");
    CHECK(error(R"([{"pattern": "a.json"}, {"pattern": "b/a.json"}])") ==
          "m.json: assets[1]: a second asset named 'a' (give it a \"name\")");
    CHECK(error(R"([{"name": "a"}])") == "m.json: assets[0]: no \"pattern\"");
    CHECK(error(R"([{"pattern": "a.json", "simd_width": 4}])") == "m.json: assets[0].simd_width: not 8 or 16");
    CHECK(error(R"([{"pattern": "a.json", "name": "../a"}])") ==
          "m.json: assets[0].name: not an asset name (a file name without folders)");
    CHECK(error("[]") == "m.json: \"assets\" is not a list of patterns");
    CHECK(error(R"([{"pattern": "a.json", "over": [3]}])") == "m.json: assets[0].over: not a pattern file name");
    CHECK(error(R"([{"pattern": "a.json", "over": ["a", "b", "c", "d", "e"]}])") ==
          "m.json: assets[0].over: not a pattern or a list of at most 4");
    CHECK_FALSE(is_manifest(R"({"format": "weft-pattern"})"));
    CHECK_FALSE(is_manifest("{ not json"));
}

// weft-bake --over: a garment worn over others is sewn on a body.
TEST_CASE("bake: a garment worn over another needs a body") {
    BakeOptions options;
    options.over_patterns.push_back(read_text(kSamples / "tee.json"));
    Baked baked;
    const Status s = bake_pattern(read_text(kSamples / "overshirt.json"), options, &baked);
    CHECK(s.error == "a garment worn over others is sewn on a body (--over needs --body)");
}
