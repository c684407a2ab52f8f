// weft_pattern on malformed input: every case returns an error with a message; none crashes,
// hangs or trips the sanitizers (the ASan/UBSan build runs these too).
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bake/garment.h"
#include "bake/pattern.h"

using namespace weft::bake;

namespace {

// A valid one-panel Weft pattern with `panel` spliced in and `extra` top-level members.
std::string weft_pattern(const std::string& panels, const std::string& extra = "") {
    return R"({"format": "weft-pattern", "version": 1, "units": "m", "panels": )" + panels + extra + "}";
}

const std::string kSquare =
    R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1],[0,1]], "edges": [
        {"name": "s", "endpoints": [0,1]}, {"name": "e", "endpoints": [1,2]},
        {"name": "n", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]}])";

const std::string kTwoSquares =
    R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1],[0,1]], "edges": [
        {"name": "s", "endpoints": [0,1]}, {"name": "e", "endpoints": [1,2]},
        {"name": "n", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]},
       {"name": "b", "vertices": [[0,0],[1.5,0],[1.5,1],[0,1]], "edges": [
        {"name": "s", "endpoints": [0,1]}, {"name": "e", "endpoints": [1,2]},
        {"name": "n", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]}])";

// The pattern fuzzer's find (tests/fuzz/corpus/pattern/broken_curves_nearly_touch.json): panel
// a's circle arc passes 82 nm from its next edge, and the strip mesher refined the gap without end.
const std::string kCurvesNearlyTouch = R"({"pattern": {"panels": {
    "a": {"vertices": [[0,0],[30,0],[30,40],[0,40]], "translation": [0,100,10], "rotation": [0,0,30], "edges": [
      {"endpoints": [0,1], "curvature": [0.5, 0.2]}, {"endpoints": [2,1]},
      {"endpoints": [3,2], "curvature": {"type": "circle", "params": [10, 0, 1]}}, {"endpoints": [3,0]}]},
    "b": {"vertices": [[0,0],[30,0],[30,40],[0,40]], "edges": [{"endpoints": [0,1]}, {"endpoints": [1,2]},
      {"endpoints": [2,3]}, {"endpoints": [3,0]}]}},
    "stitches": [[{"panel": "a", "edge": 2}, {"panel": "b", "edge": 3}], [{"panel": "a", "edge": 3}, {"panel": "b", "edge": 2}, "right_wrong"]]},
    "properties": {"units_in_meter": 100, "curvature_coords": "relative"}})";

struct Case {
    const char* what;
    std::string text;
    MeshOptions mesh = {};
};

std::vector<Case> cases() {
    std::vector<Case> c;
    c.push_back({"empty text", ""});
    c.push_back({"not JSON", "panels: [1, 2"});
    c.push_back({"a JSON array", "[1, 2, 3]"});
    c.push_back({"deep nesting", std::string(10000, '[') + std::string(10000, ']')});
    c.push_back({"deep nesting in a member", weft_pattern(std::string(5000, '[') + std::string(5000, ']'))});
    c.push_back({"NaN literal", weft_pattern(R"([{"name": "a", "vertices": [[NaN,0],[1,0],[1,1]], "edges": []}])")});
    c.push_back({"Infinity literal", weft_pattern(R"([{"name": "a", "vertices": [[Infinity,0],[1,0],[1,1]], "edges": []}])")});
    c.push_back({"1e308 coordinate", weft_pattern(R"([{"name": "a", "vertices": [[1e308,0],[1,0],[1,1]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,0]}]}])")});
    c.push_back({"1e400 coordinate", weft_pattern(R"([{"name": "a", "vertices": [[1e400,0],[1,0],[1,1]], "edges": []}])")});
    c.push_back({"unknown format", R"({"format": "obj", "version": 1})"});
    c.push_back({"missing panels", R"({"format": "weft-pattern", "version": 1})"});
    c.push_back({"missing version", R"({"format": "weft-pattern", "panels": []})"});
    c.push_back({"panels of the wrong type", weft_pattern(R"("front")")});
    c.push_back({"vertex of the wrong type", weft_pattern(R"([{"name": "a", "vertices": [["0", 0],[1,0],[1,1]], "edges": []}])")});
    c.push_back({"unknown key", weft_pattern(kSquare, R"(, "target_edge": 0.02)")});
    c.push_back({"endpoint out of range", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,7]}, {"name": "z", "endpoints": [7,0]}]}])")});
    c.push_back({"negative endpoint", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1]], "edges": [
        {"name": "x", "endpoints": [0,-1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,0]}]}])")});
    c.push_back({"open outline", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1],[0,1]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,3]}]}])")});
    c.push_back({"self-intersecting outline (bow tie)", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,1],[1,0],[0,1]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]}])")});
    c.push_back({"curve crossing the outline", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[1,1],[0,1]], "edges": [
        {"name": "x", "endpoints": [0,1], "curve": {"type": "quadratic", "control": [[0.5, 3]]}}, {"name": "y", "endpoints": [1,2]},
        {"name": "z", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]}])")});
    c.push_back({"zero-area panel", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[2,0]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,0]}]}])")});
    c.push_back({"zero-length edge", weft_pattern(R"([{"name": "a", "vertices": [[0,0],[1,0],[1,0],[1,1]], "edges": [
        {"name": "x", "endpoints": [0,1]}, {"name": "y", "endpoints": [1,2]}, {"name": "z", "endpoints": [2,3]}, {"name": "w", "endpoints": [3,0]}]}])")});
    c.push_back({"unequal seam without gather", weft_pattern(kTwoSquares, R"(, "seams": [{"sides": [{"panel": "a", "edge": "s"}, {"panel": "b", "edge": "s"}]}])")});
    c.push_back({"seam naming a missing panel", weft_pattern(kTwoSquares, R"(, "seams": [{"sides": [{"panel": "a", "edge": "e"}, {"panel": "c", "edge": "w"}]}])")});
    c.push_back({"seam naming a missing edge", weft_pattern(kTwoSquares, R"(, "seams": [{"sides": [{"panel": "a", "edge": "e"}, {"panel": "b", "edge": "q"}]}])")});
    c.push_back({"edge in two seams", weft_pattern(kTwoSquares, R"(, "seams": [{"sides": [{"panel": "a", "edge": "e"}, {"panel": "b", "edge": "w"}]},
        {"sides": [{"panel": "a", "edge": "e"}, {"panel": "b", "edge": "e"}]}])")});
    c.push_back({"seam of one side", weft_pattern(kTwoSquares, R"(, "seams": [{"sides": [{"panel": "a", "edge": "e"}]}])")});
    c.push_back({"pin on a missing edge", weft_pattern(kSquare, R"(, "pins": [{"panel": "a", "edge": "top"}])")});
    c.push_back({"negative density", weft_pattern(kSquare, R"(, "fabric": {"areal_density_kg_m2": -1})")});
    c.push_back({"target edge 0", weft_pattern(kSquare, R"(, "target_edge_m": 0)")});
    c.push_back({"target edge negative", weft_pattern(kSquare, R"(, "target_edge_m": -0.02)")});
    c.push_back({"target edge 1e-9 (billions of particles)", weft_pattern(kSquare, R"(, "target_edge_m": 1e-9)")});
    MeshOptions tiny;
    tiny.target_edge_m = 1e-5;
    c.push_back({"mesh option target edge 1e-5 (past the particle cap)", weft_pattern(kSquare), tiny});
    MeshOptions negative;
    negative.target_edge_m = -1.0;
    c.push_back({"mesh option target edge negative", weft_pattern(kSquare), negative});
    c.push_back({"GarmentCode: stitch to a missing panel", R"({"pattern": {"panels": {"a": {"vertices": [[0,0],[10,0],[10,10]],
        "edges": [{"endpoints": [0,1]}, {"endpoints": [1,2]}, {"endpoints": [2,0]}]}},
        "stitches": [[{"panel": "a", "edge": 0}, {"panel": "b", "edge": 1}]]}})"});
    c.push_back({"GarmentCode: edge index out of range", R"({"pattern": {"panels": {"a": {"vertices": [[0,0],[10,0],[10,10]],
        "edges": [{"endpoints": [0,1]}, {"endpoints": [1,2]}, {"endpoints": [2,0]}]}},
        "stitches": [[{"panel": "a", "edge": 0}, {"panel": "a", "edge": 3}]]}})"});
    c.push_back({"GarmentCode: unknown curve", R"({"pattern": {"panels": {"a": {"vertices": [[0,0],[10,0],[10,10]],
        "edges": [{"endpoints": [0,1], "curvature": {"type": "spline", "params": []}}, {"endpoints": [1,2]}, {"endpoints": [2,0]}]}}}})"});
    c.push_back({"GarmentCode: units_in_meter 0", R"({"properties": {"units_in_meter": 0}, "pattern": {"panels": {}}})"});
    c.push_back({"GarmentCode: no panels", R"({"pattern": {"panels": {}}})"});
    c.push_back({"GarmentCode: vertex used by three edges", R"({"pattern": {"panels": {"a": {"vertices": [[0,0],[10,0],[10,10],[0,10]],
        "edges": [{"endpoints": [0,1]}, {"endpoints": [1,2]}, {"endpoints": [2,0]}, {"endpoints": [0,3]}]}}}})"});
    c.push_back({"GarmentCode: curves that nearly touch (the strip refined without end)", kCurvesNearlyTouch});
    return c;
}

}  // namespace

TEST_CASE("bake: malformed patterns return an error with a message") {
    for (const Case& c : cases()) {
        const std::string what = c.what;
        CAPTURE(what);
        Pattern pattern;
        Status status = parse_pattern(c.text, ParseOptions{}, &pattern);
        if (status.ok()) {
            MeshedGarment garment;
            status = mesh_garment(pattern, c.mesh, &garment);
        }
        CHECK_FALSE(status.ok());
        CHECK_FALSE(status.error.empty());
        MESSAGE(std::string(c.what) << " -> " << status.error);
    }
}

TEST_CASE("bake: curves that nearly touch are refused, naming the panel and both edges") {
    // With the tool's default particle cap: the strip's refinement stops at the panel's own cap.
    Pattern pattern;
    REQUIRE(parse_pattern(kCurvesNearlyTouch, ParseOptions{}, &pattern).ok());
    MeshedGarment garment;
    const Status status = mesh_garment(pattern, MeshOptions{}, &garment);
    CHECK_FALSE(status.ok());
    CAPTURE(status.error);
    CHECK(status.error.find("panel 'a'") != std::string::npos);
    CHECK(status.error.find("nearly touch") != std::string::npos);
    CHECK(status.error.find("edges '2' and '3' come within") != std::string::npos);
}

TEST_CASE("bake: a valid pattern next to the malformed ones bakes") {
    Pattern pattern;
    REQUIRE(parse_pattern(weft_pattern(kSquare, R"(, "target_edge_m": 0.1)"), ParseOptions{}, &pattern).ok());
    MeshedGarment garment;
    const Status status = mesh_garment(pattern, MeshOptions{}, &garment);
    REQUIRE_MESSAGE(status.ok(), status.error);
    CHECK(garment.positions.size() > 100);
}

TEST_CASE("bake: a panel's skin max_distance_scale is read, and a bad one is refused naming the panel") {
    const auto with_skin = [](const std::string& skin) {
        std::string panels = kTwoSquares;
        panels.replace(panels.find(R"("name": "b")"), 11, R"("name": "b", "skin": )" + skin);
        return weft_pattern(panels);
    };
    Pattern pattern;
    REQUIRE(parse_pattern(with_skin(R"({"max_distance_scale": 0})"), ParseOptions{}, &pattern).ok());
    CHECK(!pattern.panels[0].skin_max_distance_scale);  // absent: the baker's default
    CHECK(pattern.panels[1].skin_max_distance_scale == 0.0);
    for (const char* bad : {R"({"max_distance_scale": -0.5})", R"({"max_distance_scale": 1e9})",
                            R"({"max_distance_scale": "far"})", R"({"max_distance": 0.03})"}) {
        CAPTURE(bad);
        const Status s = parse_pattern(with_skin(bad), ParseOptions{}, &pattern);
        REQUIRE_FALSE(s.ok());
        CHECK(s.error.find("panels[1].skin") != std::string::npos);
        MESSAGE(s.error);
    }
    // A pattern built in code is checked too (validate_pattern), naming the panel.
    REQUIRE(parse_pattern(with_skin(R"({"max_distance_scale": 2})"), ParseOptions{}, &pattern).ok());
    pattern.panels[1].skin_max_distance_scale = std::nan("");
    const Status s = validate_pattern(pattern);
    REQUIRE_FALSE(s.ok());
    CHECK(s.error.find("panel \"b\"") != std::string::npos);
    CHECK(s.error.find("skin max_distance_scale") != std::string::npos);
}
