// Reading patterns: Weft's own JSON format and GarmentCode's (docs/pattern-format.md), both into
// one Pattern. Every read names its place in the file, so a malformed pattern gets a message that
// points at the fault; exceptions stay inside this file.
#include "bake/pattern.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <stdexcept>

#include "bake/outline.h"

namespace weft::bake {

namespace {

using json = nlohmann::json;

// Limits that keep a hostile file from costing unbounded time or memory.
constexpr size_t kMaxTextBytes = size_t(64) << 20;
constexpr int kMaxNesting = 64;  // the formats nest 6 deep; deeper is not a pattern
constexpr size_t kMaxPanels = 1000;
// Largest per-panel skin max_distance_scale: 100 x the baker's 3 cm is 3 m, looser than any garment needs.
constexpr double kMaxSkinDistanceScale = 100.0;
constexpr size_t kMaxEdgesPerPanel = 10000;
constexpr double kMaxCoordinate_m = 1000.0;  // a panel coordinate past 1 km is not clothing
constexpr double kMinEdgeLength_m = 1e-6;
constexpr double kMinPanelArea_m2 = 1e-6;    // 1 mm^2
constexpr double kSeamLengthTolerance = 0.01;  // Weft seams without a gather: sides within 1%

struct PatternError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& where, const std::string& what) {
    throw PatternError((where.empty() ? std::string("pattern") : where) + ": " + what);
}

std::string at(const std::string& where, const char* key) { return where.empty() ? key : where + "." + key; }
std::string item(const std::string& where, size_t index) { return where + "[" + std::to_string(index) + "]"; }

// Refuses nesting deeper than kMaxNesting before the JSON parser sees the text.
void check_nesting(std::string_view text) {
    int depth = 0;
    bool in_string = false, escaped = false;
    for (char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxNesting) fail("pattern", "nested deeper than " + std::to_string(kMaxNesting) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

const json& member(const json& object, const char* key, const std::string& where) {
    if (!object.is_object()) fail(where, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(where, std::string("missing \"") + key + "\"");
    return *it;
}

const json* optional_member(const json& object, const char* key, const std::string& where) {
    if (!object.is_object()) fail(where, "expected an object");
    const auto it = object.find(key);
    return it == object.end() || it->is_null() ? nullptr : &*it;
}

// Unknown keys in a Weft pattern are errors: a misspelt "target_edge_m" must not pass silently.
void only_keys(const json& object, std::initializer_list<const char*> keys, const std::string& where) {
    for (auto it = object.begin(); it != object.end(); ++it) {
        const std::string& key = it.key();
        if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return key == k; }))
            fail(where, "unknown key \"" + key + "\"");
    }
}

double number(const json& value, const std::string& where) {
    if (!value.is_number()) fail(where, "expected a number");
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(where, "not a finite number");
    return v;
}

double number_in(const json& value, const std::string& where, double lo, double hi) {
    const double v = number(value, where);
    if (v < lo || v > hi) fail(where, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
}

uint32_t index_below(const json& value, const std::string& where, size_t count) {
    if (!value.is_number_integer()) fail(where, "expected an integer index");
    const int64_t v = value.is_number_unsigned() ? int64_t(std::min<uint64_t>(value.get<uint64_t>(), INT64_MAX))
                                                 : value.get<int64_t>();
    if (v < 0 || uint64_t(v) >= count) fail(where, "index " + std::to_string(v) + " out of range (" + std::to_string(count) + ")");
    return uint32_t(v);
}

const std::string& text(const json& value, const std::string& where) {
    if (!value.is_string()) fail(where, "expected a string");
    return value.get_ref<const std::string&>();
}

bool boolean(const json& value, const std::string& where) {
    if (value.is_boolean()) return value.get<bool>();
    if (value.is_number_integer()) return value.get<int64_t>() != 0;  // GarmentCode writes 0/1
    fail(where, "expected true or false");
}

const json& array(const json& value, const std::string& where, size_t min_size, size_t max_size) {
    if (!value.is_array()) fail(where, "expected an array");
    if (value.size() < min_size || value.size() > max_size)
        fail(where, "expected " + std::to_string(min_size) + " to " + std::to_string(max_size) + " elements, got " +
                        std::to_string(value.size()));
    return value;
}

// [x, y] times `scale` (pattern units to metres).
Point2 point(const json& value, const std::string& where, double scale) {
    array(value, where, 2, 2);
    const double x = number(value[0], item(where, 0)) * scale, y = number(value[1], item(where, 1)) * scale;
    if (std::fabs(x) > kMaxCoordinate_m || std::fabs(y) > kMaxCoordinate_m)
        fail(where, "coordinate beyond " + std::to_string(int(kMaxCoordinate_m)) + " m");
    return {x, y};
}

void triple(const json& value, const std::string& where, double scale, double out[3]) {
    array(value, where, 3, 3);
    for (size_t k = 0; k < 3; ++k) out[k] = number_in(value[k], item(where, k), -1e6, 1e6) * scale;
}

// Reverses an edge in place: same curve, drawn from its end to its start.
void reverse_edge(PatternEdge& edge) {
    std::swap(edge.start, edge.end);
    if (edge.shape == EdgeShape::cubic) std::swap(edge.control[0], edge.control[1]);
    if (edge.shape == EdgeShape::arc) edge.arc_right = !edge.arc_right;
}

// Puts a panel's edges in outline order (edge k ends where edge k + 1 starts), reordering edges
// listed out of order and reversing edges drawn against the loop: GarmentCode files without
// "normalized_edge_loops" may have both. The loop keeps the direction of the first listed edge.
// loop_of[e] is the loop position of file edge e; flipped[e] whether it was reversed.
void chain_outline(Panel& panel, std::vector<uint32_t>& loop_of, std::vector<bool>& flipped, const std::string& where) {
    const size_t n = panel.edges.size();
    std::vector<std::vector<uint32_t>> at_vertex(panel.vertices.size());
    for (uint32_t e = 0; e < n; ++e) {
        const PatternEdge& edge = panel.edges[e];
        if (edge.start == edge.end) fail(item(at(where, "edges"), e), "starts and ends at the same vertex");
        at_vertex[edge.start].push_back(e);
        at_vertex[edge.end].push_back(e);
    }
    for (size_t v = 0; v < at_vertex.size(); ++v)
        if (!at_vertex[v].empty() && at_vertex[v].size() != 2)
            fail(item(at(where, "vertices"), v), "is an end of " + std::to_string(at_vertex[v].size()) +
                                                    " edges; an outline is one closed loop (2)");
    loop_of.assign(n, 0);
    flipped.assign(n, false);
    std::vector<bool> used(n, false);
    std::vector<PatternEdge> loop;
    uint32_t e = 0;
    for (size_t k = 0; k < n; ++k) {
        used[e] = true;
        loop_of[e] = uint32_t(k);
        loop.push_back(panel.edges[e]);
        if (k > 0 && loop.back().start != loop[k - 1].end) {
            reverse_edge(loop.back());
            flipped[e] = true;
        }
        const uint32_t end = loop.back().end;
        const std::vector<uint32_t>& next = at_vertex[end];
        const uint32_t candidate = next[0] == e ? next[1] : next[0];
        if (k + 1 < n) {
            if (used[candidate]) fail(at(where, "edges"), "form more than one loop; a panel has one outline");
            e = candidate;
        } else if (end != loop.front().start) {
            fail(at(where, "edges"), "do not close into one loop");
        }
    }
    panel.edges = std::move(loop);
}

// Resolves the file's seam sides, pins and attachments against reordered outlines.
struct EdgeMap {
    std::vector<std::vector<uint32_t>> loop_of;  // per panel, file edge -> loop position
    std::vector<std::vector<bool>> flipped;
};

SeamSide resolve_side(const EdgeMap& map, uint32_t panel, uint32_t file_edge, bool reverse) {
    return {panel, map.loop_of[panel][file_edge], reverse != bool(map.flipped[panel][file_edge])};
}

// ---------------------------------------------------------------------------------------------
// GarmentCode

// A relative control point (u, v) of the edge from p0 to p1: p0 + u*d + v*(-d.y, d.x), d = p1 - p0.
Point2 relative_control(Point2 p0, Point2 p1, Point2 uv) {
    const double dx = p1.x - p0.x, dy = p1.y - p0.y;
    return {p0.x + uv.x * dx - uv.y * dy, p0.y + uv.x * dy + uv.y * dx};
}

void read_garmentcode_curvature(const json& curvature, const std::string& where, bool relative, double scale,
                                const Panel& panel, PatternEdge& edge) {
    const Point2 p0 = panel.vertices[edge.start], p1 = panel.vertices[edge.end];
    auto control = [&](const json& value, const std::string& w) {
        return relative ? relative_control(p0, p1, point(value, w, 1.0)) : point(value, w, scale);
    };
    if (curvature.is_array()) {  // v1: a quadratic's control point
        edge.shape = EdgeShape::quadratic;
        edge.control[0] = control(curvature, where);
        return;
    }
    const std::string& type = text(member(curvature, "type", where), at(where, "type"));
    const json& params = member(curvature, "params", where);
    const std::string pw = at(where, "params");
    if (type == "quadratic") {
        edge.shape = EdgeShape::quadratic;
        edge.control[0] = control(array(params, pw, 1, 1)[0], item(pw, 0));
    } else if (type == "cubic") {
        edge.shape = EdgeShape::cubic;
        array(params, pw, 2, 2);
        edge.control[0] = control(params[0], item(pw, 0));
        edge.control[1] = control(params[1], item(pw, 1));
    } else if (type == "circle") {
        edge.shape = EdgeShape::arc;
        array(params, pw, 3, 3);
        edge.arc_radius_m = number_in(params[0], item(pw, 0), 0.0, 1e9) * scale;
        edge.arc_large = boolean(params[1], item(pw, 1));
        edge.arc_right = boolean(params[2], item(pw, 2));
    } else {
        fail(at(where, "type"), "unknown curve type \"" + type + "\" (quadratic, cubic, circle)");
    }
}

Pattern read_garmentcode(const json& root, const ParseOptions& options) {
    Pattern pattern;
    pattern.format = "garmentcode";
    double units_in_meter = 100.0;
    bool relative = true, normalize_translation = false;
    if (const json* props = optional_member(root, "properties", "")) {
        if (const json* u = optional_member(*props, "units_in_meter", "properties"))
            units_in_meter = number_in(*u, "properties.units_in_meter", 1e-3, 1e9);
        if (const json* c = optional_member(*props, "curvature_coords", "properties")) {
            const std::string& coords = text(*c, "properties.curvature_coords");
            if (coords != "relative" && coords != "absolute")
                fail("properties.curvature_coords", "expected \"relative\" or \"absolute\"");
            relative = coords == "relative";
        }
        if (const json* t = optional_member(*props, "normalize_panel_translation", "properties"))
            normalize_translation = boolean(*t, "properties.normalize_panel_translation");
        // normalized_edge_loops needs no flag: chain_outline orders every panel's loop anyway.
    }
    const double scale = 1.0 / units_in_meter;
    const json& spec = member(root, "pattern", "");
    const json& panels = member(spec, "panels", "pattern");
    if (!panels.is_object() || panels.empty()) fail("pattern.panels", "expected an object of panels");
    if (panels.size() > kMaxPanels) fail("pattern.panels", "more than " + std::to_string(kMaxPanels) + " panels");

    // Panels in "panel_order" when given (the authors' order), else the file's order.
    std::vector<std::string> names;
    if (const json* order = optional_member(spec, "panel_order", "pattern")) {
        array(*order, "pattern.panel_order", 0, kMaxPanels);
        for (size_t k = 0; k < order->size(); ++k) {
            const std::string& name = text((*order)[k], item("pattern.panel_order", k));
            if (!panels.contains(name)) fail(item("pattern.panel_order", k), "no panel \"" + name + "\"");
            if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
        }
    }
    for (auto it = panels.begin(); it != panels.end(); ++it)
        if (std::find(names.begin(), names.end(), it.key()) == names.end()) names.push_back(it.key());

    EdgeMap map;
    std::map<std::string, uint32_t> panel_index;
    struct EdgeLabel {
        uint32_t panel, file_edge;
        std::string label;
    };
    std::vector<EdgeLabel> labels;
    for (const std::string& name : names) {
        const json& p = panels[name];
        const std::string where = "pattern.panels." + name;
        Panel panel;
        panel.name = name;
        const json& vertices = array(member(p, "vertices", where), at(where, "vertices"), 3, kMaxEdgesPerPanel);
        for (size_t k = 0; k < vertices.size(); ++k) panel.vertices.push_back(point(vertices[k], item(at(where, "vertices"), k), scale));
        if (normalize_translation) {  // the template's rule: the panel's origin moves to its vertex mean
            Point2 mean;
            for (const Point2& v : panel.vertices) mean.x += v.x / panel.vertices.size(), mean.y += v.y / panel.vertices.size();
            for (Point2& v : panel.vertices) v.x -= mean.x, v.y -= mean.y;
            panel.placement.translation_m[0] += mean.x;
            panel.placement.translation_m[1] += mean.y;
        }
        const json& edges = array(member(p, "edges", where), at(where, "edges"), 2, kMaxEdgesPerPanel);
        for (size_t k = 0; k < edges.size(); ++k) {
            const std::string ew = item(at(where, "edges"), k);
            const json& ends = array(member(edges[k], "endpoints", ew), at(ew, "endpoints"), 2, 2);
            PatternEdge edge;
            edge.name = std::to_string(k);
            edge.start = index_below(ends[0], item(at(ew, "endpoints"), 0), panel.vertices.size());
            edge.end = index_below(ends[1], item(at(ew, "endpoints"), 1), panel.vertices.size());
            if (const json* c = optional_member(edges[k], "curvature", ew))
                read_garmentcode_curvature(*c, at(ew, "curvature"), relative, scale, panel, edge);
            if (const json* l = optional_member(edges[k], "label", ew)) labels.push_back({uint32_t(pattern.panels.size()), uint32_t(k), text(*l, at(ew, "label"))});
            panel.edges.push_back(edge);
        }
        double translation[3] = {0.0, 0.0, 0.0};
        if (const json* t = optional_member(p, "translation", where)) triple(*t, at(where, "translation"), scale, translation);
        if (const json* r = optional_member(p, "rotation", where))
            triple(*r, at(where, "rotation"), 1.0, panel.placement.rotation_deg);
        for (int k = 0; k < 3; ++k) panel.placement.translation_m[k] += translation[k] + options.placement_offset_m[k];
        map.loop_of.emplace_back();
        map.flipped.emplace_back();
        chain_outline(panel, map.loop_of.back(), map.flipped.back(), where);
        panel_index[name] = uint32_t(pattern.panels.size());
        pattern.panels.push_back(std::move(panel));
    }

    // Stitches: [side, side] or [side, side, "right_wrong"]. Reversed by default: the first edge's
    // start meets the second's end (right side to right side); "right_wrong" keeps the direction.
    if (const json* stitches = optional_member(spec, "stitches", "pattern")) {
        array(*stitches, "pattern.stitches", 0, kMaxPanels * kMaxEdgesPerPanel);
        for (size_t s = 0; s < stitches->size(); ++s) {
            const std::string sw = item("pattern.stitches", s);
            const json& stitch = array((*stitches)[s], sw, 2, 3);
            bool keep_direction = false;
            if (stitch.size() == 3) {
                if (!stitch[2].is_string() || stitch[2].get_ref<const std::string&>() != "right_wrong")
                    fail(item(sw, 2), "a stitch joins two edges; a third element can only be \"right_wrong\"");
                keep_direction = true;
            }
            Seam seam;
            seam.gather = true;  // GarmentCode gathers freely (the dress's waist seams differ by 23%)
            for (size_t k = 0; k < 2; ++k) {
                const std::string w = item(sw, k);
                const std::string& name = text(member(stitch[k], "panel", w), at(w, "panel"));
                const auto found = panel_index.find(name);
                if (found == panel_index.end()) fail(at(w, "panel"), "no panel \"" + name + "\"");
                const uint32_t p = found->second;
                const uint32_t e = index_below(member(stitch[k], "edge", w), at(w, "edge"), map.loop_of[p].size());
                seam.sides.push_back(resolve_side(map, p, e, k == 1 && !keep_direction));
            }
            pattern.seams.push_back(seam);
        }
    }
    // The edges GarmentCode's simulator holds on the body (its attachment_label_names): a lower
    // garment's waistline and a strapless top's upper edge become body attachments.
    pattern.sleeves = false;
    for (const EdgeLabel& l : labels)
        if (l.label == "left_armhole" || l.label == "right_armhole")
            for (const Seam& seam : pattern.seams)
                for (const SeamSide& side : seam.sides)
                    pattern.sleeves = pattern.sleeves || (side.panel == l.panel && side.edge == map.loop_of[l.panel][l.file_edge]);
    for (const EdgeLabel& l : labels)
        if (std::find(std::begin(kGarmentCodeBodyLabels), std::end(kGarmentCodeBodyLabels), l.label) != std::end(kGarmentCodeBodyLabels))
            pattern.attachments.push_back({{l.panel, int32_t(map.loop_of[l.panel][l.file_edge]), {}}, l.label});
    return pattern;
}

// ---------------------------------------------------------------------------------------------
// Weft's own format

double unit_scale(const json& root) {
    const json* units = optional_member(root, "units", "");
    if (units == nullptr) return 1.0;
    const std::string& u = text(*units, "units");
    if (u == "m") return 1.0;
    if (u == "cm") return 0.01;
    if (u == "mm") return 0.001;
    fail("units", "expected \"m\", \"cm\" or \"mm\"");
}

Fabric read_fabric(const json& value) {
    only_keys(value, {"areal_density_kg_m2", "stretch_compliance", "shear_compliance", "bend_compliance",
                      "damping_per_s", "thickness_m", "friction"},
              "fabric");
    Fabric fabric;
    auto read = [&](const char* key, double& field, double lo, double hi) {
        if (const json* v = optional_member(value, key, "fabric")) field = number_in(*v, at("fabric", key), lo, hi);
    };
    read("areal_density_kg_m2", fabric.areal_density_kg_m2, 1e-4, 100.0);
    read("stretch_compliance", fabric.stretch_compliance, 0.0, 1.0);
    read("shear_compliance", fabric.shear_compliance, 0.0, 1.0);
    read("bend_compliance", fabric.bend_compliance, 0.0, 1.0);
    read("damping_per_s", fabric.damping_per_s, 0.0, 1000.0);
    read("thickness_m", fabric.thickness_m, 0.0, 0.1);
    read("friction", fabric.friction, 0.0, 10.0);
    return fabric;
}

struct WeftNames {
    std::map<std::string, uint32_t> panel;
    std::vector<std::map<std::string, uint32_t>> edge;  // per panel: name -> file edge index
};

uint32_t panel_named(const WeftNames& names, const json& object, const std::string& where) {
    const std::string& name = text(member(object, "panel", where), at(where, "panel"));
    const auto it = names.panel.find(name);
    if (it == names.panel.end()) fail(at(where, "panel"), "no panel \"" + name + "\"");
    return it->second;
}

uint32_t edge_named(const WeftNames& names, uint32_t panel, const json& value, const std::string& where) {
    const std::string& name = text(value, where);
    const auto it = names.edge[panel].find(name);
    if (it == names.edge[panel].end()) fail(where, "panel has no edge \"" + name + "\"");
    return it->second;
}

PanelSelector read_selector(const WeftNames& names, const EdgeMap& map, const json& value, double scale,
                            const std::string& where) {
    PanelSelector s;
    s.panel = panel_named(names, value, where);
    const json* edge = optional_member(value, "edge", where);
    const json* point_value = optional_member(value, "point", where);
    if ((edge == nullptr) == (point_value == nullptr)) fail(where, "give exactly one of \"edge\" and \"point\"");
    if (edge) s.edge = int32_t(map.loop_of[s.panel][edge_named(names, s.panel, *edge, at(where, "edge"))]);
    else s.point = point(*point_value, at(where, "point"), scale);
    return s;
}

Pattern read_weft(const json& root) {
    only_keys(root, {"format", "version", "units", "fabric", "target_edge_m", "panels", "seams", "pins", "attachments", "description"}, "");
    Pattern pattern;
    pattern.format = "weft-pattern";
    if (number(member(root, "version", ""), "version") != 1.0) fail("version", "only version 1 is known");
    const double scale = unit_scale(root);
    if (const json* f = optional_member(root, "fabric", "")) pattern.fabric = read_fabric(*f);
    if (const json* h = optional_member(root, "target_edge_m", "")) pattern.target_edge_m = number_in(*h, "target_edge_m", 1e-9, 1e3);

    const json& panels = array(member(root, "panels", ""), "panels", 1, kMaxPanels);
    WeftNames names;
    EdgeMap map;
    for (size_t k = 0; k < panels.size(); ++k) {
        const std::string where = item("panels", k);
        const json& p = panels[k];
        only_keys(p, {"name", "vertices", "edges", "placement", "areal_density_kg_m2", "skin"}, where);
        Panel panel;
        panel.name = text(member(p, "name", where), at(where, "name"));
        if (!names.panel.emplace(panel.name, uint32_t(k)).second) fail(at(where, "name"), "a second panel \"" + panel.name + "\"");
        const json& vertices = array(member(p, "vertices", where), at(where, "vertices"), 2, kMaxEdgesPerPanel);
        for (size_t v = 0; v < vertices.size(); ++v) panel.vertices.push_back(point(vertices[v], item(at(where, "vertices"), v), scale));
        const json& edges = array(member(p, "edges", where), at(where, "edges"), 2, kMaxEdgesPerPanel);
        names.edge.emplace_back();
        for (size_t e = 0; e < edges.size(); ++e) {
            const std::string ew = item(at(where, "edges"), e);
            only_keys(edges[e], {"name", "endpoints", "curve"}, ew);
            PatternEdge edge;
            edge.name = text(member(edges[e], "name", ew), at(ew, "name"));
            if (!names.edge.back().emplace(edge.name, uint32_t(e)).second) fail(at(ew, "name"), "a second edge \"" + edge.name + "\"");
            const json& ends = array(member(edges[e], "endpoints", ew), at(ew, "endpoints"), 2, 2);
            edge.start = index_below(ends[0], item(at(ew, "endpoints"), 0), panel.vertices.size());
            edge.end = index_below(ends[1], item(at(ew, "endpoints"), 1), panel.vertices.size());
            if (const json* curve = optional_member(edges[e], "curve", ew)) {
                const std::string cw = at(ew, "curve");
                only_keys(*curve, {"type", "control", "radius", "large_arc", "right"}, cw);
                const std::string& type = text(member(*curve, "type", cw), at(cw, "type"));
                if (type == "quadratic" || type == "cubic") {
                    const size_t count = type == "quadratic" ? 1 : 2;
                    const json& control = array(member(*curve, "control", cw), at(cw, "control"), count, count);
                    edge.shape = count == 1 ? EdgeShape::quadratic : EdgeShape::cubic;
                    for (size_t c = 0; c < count; ++c) edge.control[c] = point(control[c], item(at(cw, "control"), c), scale);
                } else if (type == "arc") {
                    edge.shape = EdgeShape::arc;
                    edge.arc_radius_m = number_in(member(*curve, "radius", cw), at(cw, "radius"), 0.0, 1e9) * scale;
                    if (const json* l = optional_member(*curve, "large_arc", cw)) edge.arc_large = boolean(*l, at(cw, "large_arc"));
                    if (const json* r = optional_member(*curve, "right", cw)) edge.arc_right = boolean(*r, at(cw, "right"));
                } else {
                    fail(at(cw, "type"), "unknown curve type \"" + type + "\" (quadratic, cubic, arc)");
                }
            }
            panel.edges.push_back(edge);
        }
        if (const json* placement = optional_member(p, "placement", where)) {
            const std::string pw = at(where, "placement");
            only_keys(*placement, {"rotation_deg", "translation"}, pw);
            if (const json* r = optional_member(*placement, "rotation_deg", pw)) triple(*r, at(pw, "rotation_deg"), 1.0, panel.placement.rotation_deg);
            if (const json* t = optional_member(*placement, "translation", pw)) triple(*t, at(pw, "translation"), scale, panel.placement.translation_m);
        }
        if (const json* d = optional_member(p, "areal_density_kg_m2", where))
            panel.areal_density_kg_m2 = number_in(*d, at(where, "areal_density_kg_m2"), 1e-4, 100.0);
        if (const json* skin = optional_member(p, "skin", where)) {
            const std::string sw = at(where, "skin");
            only_keys(*skin, {"max_distance_scale"}, sw);
            if (const json* v = optional_member(*skin, "max_distance_scale", sw))
                panel.skin_max_distance_scale = number_in(
                    *v, at(sw, "max_distance_scale") + " (panel \"" + panel.name + "\")", 0.0, kMaxSkinDistanceScale);
        }
        map.loop_of.emplace_back();
        map.flipped.emplace_back();
        chain_outline(panel, map.loop_of.back(), map.flipped.back(), where);
        pattern.panels.push_back(std::move(panel));
    }

    if (const json* seams = optional_member(root, "seams", "")) {
        array(*seams, "seams", 0, kMaxPanels * kMaxEdgesPerPanel);
        for (size_t s = 0; s < seams->size(); ++s) {
            const std::string sw = item("seams", s);
            only_keys((*seams)[s], {"sides", "gather"}, sw);
            Seam seam;
            if (const json* g = optional_member((*seams)[s], "gather", sw)) seam.gather = boolean(*g, at(sw, "gather"));
            const json& sides = array(member((*seams)[s], "sides", sw), at(sw, "sides"), 2, 3);
            for (size_t k = 0; k < sides.size(); ++k) {
                const std::string w = item(at(sw, "sides"), k);
                only_keys(sides[k], {"panel", "edge", "reverse"}, w);
                const uint32_t p = panel_named(names, sides[k], w);
                const uint32_t e = edge_named(names, p, member(sides[k], "edge", w), at(w, "edge"));
                bool reverse = false;
                if (const json* r = optional_member(sides[k], "reverse", w)) reverse = boolean(*r, at(w, "reverse"));
                seam.sides.push_back(resolve_side(map, p, e, reverse));
            }
            pattern.seams.push_back(seam);
        }
    }
    if (const json* pins = optional_member(root, "pins", "")) {
        array(*pins, "pins", 0, 1u << 20);
        for (size_t k = 0; k < pins->size(); ++k) {
            only_keys((*pins)[k], {"panel", "edge", "point"}, item("pins", k));
            pattern.pins.push_back(read_selector(names, map, (*pins)[k], scale, item("pins", k)));
        }
    }
    if (const json* attachments = optional_member(root, "attachments", "")) {
        array(*attachments, "attachments", 0, 1u << 20);
        for (size_t k = 0; k < attachments->size(); ++k) {
            const std::string w = item("attachments", k);
            only_keys((*attachments)[k], {"panel", "edge", "point", "label"}, w);
            BodyAttachment a;
            a.where = read_selector(names, map, (*attachments)[k], scale, w);
            a.label = text(member((*attachments)[k], "label", w), at(w, "label"));
            pattern.attachments.push_back(a);
        }
    }
    return pattern;
}

bool finite(Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// The edge that fine_outline's segment `segment` belongs to: a straight edge is one segment, a
// curve kFineSegmentsPerCurve.
uint32_t edge_of_segment(const Panel& panel, uint32_t segment) {
    uint32_t first = 0;
    for (uint32_t e = 0; e < panel.edges.size(); ++e) {
        first += panel.edges[e].shape == EdgeShape::straight ? 1 : kFineSegmentsPerCurve;
        if (segment < first) return e;
    }
    return uint32_t(panel.edges.size() - 1);
}

bool outline_crosses(const Panel& panel, uint32_t* edge_a, uint32_t* edge_b, Point2* near) {
    const std::vector<Point2> outline = fine_outline(panel);
    double perimeter = 0.0;
    for (size_t k = 0; k < outline.size(); ++k) {
        const Point2 a = outline[k], b = outline[(k + 1) % outline.size()];
        perimeter += std::hypot(b.x - a.x, b.y - a.y);
    }
    uint32_t segment[2] = {0, 0};
    if (!SegmentIndex(outline, 2.0 * perimeter / double(outline.size())).self_intersects(&segment[0], &segment[1]))
        return false;
    *edge_a = edge_of_segment(panel, segment[0]);
    *edge_b = edge_of_segment(panel, segment[1]);
    *near = outline[segment[0]];
    return true;
}

// The curve with its bulge off the chord scaled by `factor` (< 1: flatter), ends unchanged: a
// Bezier's control points move toward the chord, an arc keeps its ends and takes the radius of
// the lower sagitta.
PatternEdge flattened(const Panel& panel, const PatternEdge& edge, double factor) {
    PatternEdge out = edge;
    const Point2 p0 = panel.vertices[edge.start], p1 = panel.vertices[edge.end];
    const double chord = std::hypot(p1.x - p0.x, p1.y - p0.y);
    if (!(chord > 0.0)) return out;  // a closed curve has no chord to flatten toward
    const double ux = (p1.x - p0.x) / chord, uy = (p1.y - p0.y) / chord;
    if (edge.shape == EdgeShape::quadratic || edge.shape == EdgeShape::cubic) {
        for (Point2& c : out.control) {
            const double along = (c.x - p0.x) * ux + (c.y - p0.y) * uy;
            const double off = factor * ((c.y - p0.y) * ux - (c.x - p0.x) * uy);  // right of the chord
            c = {p0.x + along * ux + off * uy, p0.y + along * uy - off * ux};
        }
    } else if (edge.shape == EdgeShape::arc) {
        const double half = 0.5 * chord, r = std::max(edge.arc_radius_m, half);
        const double s = std::sqrt(std::max(0.0, r * r - half * half));
        const double sagitta = factor * (edge.arc_large ? r + s : r - s);
        if (!(sagitta > 1e-9 * chord)) return out;  // already (numerically) straight
        out.arc_radius_m = (sagitta * sagitta + half * half) / (2.0 * sagitta);
        out.arc_large = sagitta > half;
    }
    return out;
}

// A curve whose end overshoots its corner crosses the next edge right beside their common vertex:
// GarmentCode checks outlines with each curve cut into 10 chords, so an arc leaving its corner a few
// degrees outside it passes (gc_1001_0080's hem, gc_1001_0144's neckline). Such a curve is made
// flatter, by the least factor down to kMostFlattening that clears the crossing and one step more,
// leaving every vertex (and so every seam's ends) where it was; the pattern notes what changed.
// Crossings between edges that do not meet at a vertex are left to check_pattern to refuse.
void flatten_corner_overshoots(Pattern& pattern) {
    constexpr double kStep = 0.01, kMostFlattening = 0.8;
    for (Panel& panel : pattern.panels) {
        const size_t n = panel.edges.size();
        if (n < 2) continue;
        bool valid = true;  // check_pattern reports anything malformed; nothing to repair here
        for (const Point2& v : panel.vertices) valid = valid && finite(v);
        for (size_t e = 0; e < n; ++e)
            valid = valid && panel.edges[e].start < panel.vertices.size() && panel.edges[e].end < panel.vertices.size() &&
                    panel.edges[e].start == panel.edges[(e + n - 1) % n].end &&
                    edge_length(panel, panel.edges[e]) >= kMinEdgeLength_m;
        if (!valid) continue;
        for (size_t round = 0; round < n; ++round) {
            uint32_t a = 0, b = 0;
            Point2 near{};
            if (!outline_crosses(panel, &a, &b, &near)) break;
            if (a == b || ((a + 1) % n != b && (b + 1) % n != a)) break;
            double best_factor = 0.0;
            uint32_t best_edge = a;
            for (uint32_t e : {a, b}) {
                if (panel.edges[e].shape == EdgeShape::straight) continue;
                const PatternEdge original = panel.edges[e];
                for (double f = 1.0 - kStep; f >= kMostFlattening - 1e-9; f -= kStep) {
                    panel.edges[e] = flattened(panel, original, f);
                    uint32_t x, y;
                    Point2 p;
                    if (!outline_crosses(panel, &x, &y, &p) || (x != a && x != b) || (y != a && y != b)) {
                        if (f > best_factor) best_factor = f, best_edge = e;
                        break;
                    }
                }
                panel.edges[e] = original;
            }
            if (best_factor == 0.0) break;
            const double factor = std::max(kMostFlattening - kStep, best_factor - kStep);
            panel.edges[best_edge] = flattened(panel, panel.edges[best_edge], factor);
            const uint32_t other = best_edge == a ? b : a;
            char note[256];
            std::snprintf(note, sizeof note,
                          "panel \"%s\": edge \"%s\" made %.0f%% flatter: its end crossed edge \"%s\" beside their "
                          "corner, near (%.4g, %.4g) m",
                          panel.name.c_str(), panel.edges[best_edge].name.c_str(), 100.0 * (1.0 - factor),
                          panel.edges[other].name.c_str(), near.x, near.y);
            pattern.repairs.push_back(note);
        }
    }
}

void check_pattern(const Pattern& pattern) {
    if (pattern.panels.empty()) fail("pattern", "has no panels");
    const Fabric& f = pattern.fabric;
    if (!(f.areal_density_kg_m2 > 0.0 && f.areal_density_kg_m2 <= 100.0)) fail("fabric.areal_density_kg_m2", "must lie in (0, 100]");
    for (double v : {f.stretch_compliance, f.shear_compliance, f.bend_compliance, f.damping_per_s, f.thickness_m, f.friction})
        if (!(v >= 0.0 && std::isfinite(v))) fail("fabric", "values must be finite and >= 0");
    if (!(pattern.target_edge_m >= 0.0 && std::isfinite(pattern.target_edge_m))) fail("target_edge_m", "must be > 0");
    std::set<std::string> names;
    for (size_t p = 0; p < pattern.panels.size(); ++p) {
        const Panel& panel = pattern.panels[p];
        const std::string where = "panel \"" + panel.name + "\"";
        if (!names.insert(panel.name).second) fail(where, "named twice");
        if (!(panel.areal_density_kg_m2 >= 0.0 && panel.areal_density_kg_m2 <= 100.0)) fail(where, "bad areal density");
        if (const std::optional<double> scale = panel.skin_max_distance_scale;
            scale && !(*scale >= 0.0 && *scale <= kMaxSkinDistanceScale))
            fail(where, "skin max_distance_scale " + std::to_string(*scale) + " must lie in [0, " +
                            std::to_string(kMaxSkinDistanceScale) + "]");
        for (double v : panel.placement.rotation_deg) if (!(std::fabs(v) <= 1e6)) fail(where, "bad rotation");
        for (double v : panel.placement.translation_m) if (!(std::fabs(v) <= 1e6)) fail(where, "bad translation");
        if (panel.edges.size() < 2) fail(where, "an outline needs at least 2 edges");
        for (const Point2& v : panel.vertices)
            if (!finite(v) || std::fabs(v.x) > kMaxCoordinate_m || std::fabs(v.y) > kMaxCoordinate_m) fail(where, "vertex out of range");
        for (size_t e = 0; e < panel.edges.size(); ++e) {
            const PatternEdge& edge = panel.edges[e];
            const std::string ew = where + " edge \"" + edge.name + "\"";
            if (edge.start >= panel.vertices.size() || edge.end >= panel.vertices.size()) fail(ew, "vertex index out of range");
            if (edge.start != panel.edges[(e + panel.edges.size() - 1) % panel.edges.size()].end)
                fail(ew, "does not start where the previous edge ends");
            for (const Point2& c : edge.control)
                if (!finite(c) || std::fabs(c.x) > kMaxCoordinate_m || std::fabs(c.y) > kMaxCoordinate_m) fail(ew, "control point out of range");
            if (!(edge.arc_radius_m >= 0.0 && edge.arc_radius_m <= 1e9)) fail(ew, "bad arc radius");
            const double length = edge_length(panel, edge);
            if (!(length >= kMinEdgeLength_m)) fail(ew, "has zero length");
        }
        if (!(std::fabs(signed_area(fine_outline(panel))) >= kMinPanelArea_m2)) fail(where, "has zero area");
        uint32_t a = 0, b = 0;
        if (Point2 at; outline_crosses(panel, &a, &b, &at)) {
            char place[96];
            std::snprintf(place, sizeof place, " near (%.4g, %.4g) m in the panel's frame", at.x, at.y);
            fail(where, "outline crosses or touches itself: edge \"" + panel.edges[a].name + "\" meets edge \"" +
                            panel.edges[b].name + "\"" + place);
        }
    }
    std::set<std::pair<uint32_t, uint32_t>> sewn;
    for (size_t s = 0; s < pattern.seams.size(); ++s) {
        const Seam& seam = pattern.seams[s];
        const std::string where = "seam " + std::to_string(s);
        if (seam.sides.size() < 2 || seam.sides.size() > 3) fail(where, "joins 2 or 3 edges");
        double shortest = HUGE_VAL, longest = 0.0;
        for (const SeamSide& side : seam.sides) {
            if (side.panel >= pattern.panels.size() || side.edge >= pattern.panels[side.panel].edges.size())
                fail(where, "names a missing panel or edge");
            const Panel& panel = pattern.panels[side.panel];
            if (!sewn.insert({side.panel, side.edge}).second)
                fail(where, "edge \"" + panel.edges[side.edge].name + "\" of panel \"" + panel.name + "\" is sewn twice");
            const double length = edge_length(panel, panel.edges[side.edge]);
            shortest = std::min(shortest, length), longest = std::max(longest, length);
        }
        if (!seam.gather && longest > shortest * (1.0 + kSeamLengthTolerance))
            fail(where, "sides differ in length (" + std::to_string(shortest) + " m vs " + std::to_string(longest) +
                            " m); mark it \"gather\": true if that is meant");
    }
    auto check_selector = [&](const PanelSelector& s, const std::string& where) {
        if (s.panel >= pattern.panels.size()) fail(where, "panel out of range");
        if (s.edge >= int32_t(pattern.panels[s.panel].edges.size())) fail(where, "edge out of range");
        if (s.edge < 0 && !finite(s.point)) fail(where, "point not finite");
    };
    for (size_t k = 0; k < pattern.pins.size(); ++k) check_selector(pattern.pins[k], item("pins", k));
    for (size_t k = 0; k < pattern.attachments.size(); ++k) check_selector(pattern.attachments[k].where, item("attachments", k));
}

}  // namespace

Status parse_pattern(std::string_view json_text, const ParseOptions& options, Pattern* out) {
    try {
        if (out == nullptr) return {"out is null"};
        if (json_text.size() > kMaxTextBytes) return {"pattern: larger than 64 MiB"};
        for (double v : options.placement_offset_m)
            if (!(std::fabs(v) <= 1e6)) return {"placement offset must be finite"};
        check_nesting(json_text);
        const json root = json::parse(json_text.begin(), json_text.end(), nullptr, true, /*ignore_comments=*/true);
        if (!root.is_object()) return {"pattern: expected a JSON object"};
        Pattern pattern;
        if (root.contains("pattern")) {
            pattern = read_garmentcode(root, options);
        } else {
            const json* format = optional_member(root, "format", "");
            if (format == nullptr || !format->is_string() || format->get_ref<const std::string&>() != "weft-pattern")
                return {"pattern: neither a Weft pattern (\"format\": \"weft-pattern\") nor GarmentCode (\"pattern\")"};
            pattern = read_weft(root);
        }
        flatten_corner_overshoots(pattern);
        check_pattern(pattern);
        *out = std::move(pattern);
        return {};
    } catch (const json::exception& e) {
        return {std::string("not valid JSON: ") + e.what()};
    } catch (const std::exception& e) {
        return {e.what()};
    }
}

Status validate_pattern(const Pattern& pattern) {
    try {
        check_pattern(pattern);
        return {};
    } catch (const std::exception& e) {
        return {e.what()};
    }
}

}  // namespace weft::bake
