// Sewing patterns: the 2-D panels, seams and fabric that weft-bake turns into a garment mesh.
//
// Two JSON formats are read (docs/pattern-format.md): Weft's own ("format": "weft-pattern") and
// GarmentCode's specification files (recognised by their top-level "pattern" key). Both become the
// same Pattern: lengths in metres, every panel's outline one closed loop of edges in order, every
// seam a list of panel edges whose points are sewn one to one (seed section 4.1.2).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include "weft/cook.h"

namespace weft::bake {

// The outcome of a baking call: empty `error` = success. Tools report the message as it is, so it
// names the file's element at fault ("panels[2].edges[5].endpoints[1]: ...").
struct Status {
    std::string error;
    bool ok() const { return error.empty(); }
};

// A point in a panel's own 2-D frame, metres (+Y up, as GarmentCode draws panels).
struct Point2 {
    double x = 0.0, y = 0.0;
};

enum class EdgeShape : uint8_t { straight, quadratic, cubic, arc };

// One edge of a panel's outline, from vertex `start` to vertex `end`.
struct PatternEdge {
    std::string name;  // unique within its panel (GarmentCode: the edge's index in the file)
    uint32_t start = 0, end = 0;  // indices into Panel::vertices
    EdgeShape shape = EdgeShape::straight;
    Point2 control[2];  // Bezier control points in panel coordinates (quadratic: control[0] only)
    // Circle arc, SVG style: radius (scaled up to half the chord when shorter), which of the two arcs
    // (large: the one longer than a half circle) and to which side of start-to-end it bulges.
    double arc_radius_m = 0.0;
    bool arc_large = false;
    bool arc_right = false;
};

// Where a flat panel goes in 3-D: world = R * (x, y, 0) + translation, R = Rz * Ry * Rx (angles in
// degrees, XYZ Euler as GarmentCode and Maya use them).
struct Placement {
    double rotation_deg[3] = {0.0, 0.0, 0.0};
    double translation_m[3] = {0.0, 0.0, 0.0};
};

struct Panel {
    std::string name;
    std::vector<Point2> vertices;
    // The outline: edge k ends at the vertex where edge k + 1 starts, the last ends where the first
    // starts. Its winding is the panel's front side (counter-clockwise: the front faces +Z of the
    // panel frame).
    std::vector<PatternEdge> edges;
    Placement placement;
    double areal_density_kg_m2 = 0.0;  // 0: the pattern's fabric
    // Factor on the max distance of this panel's skin constraints (weft-bake --body; weft/attachments.h,
    // SkinBindingOptions::max_distance_m): 1 the baker's 3 cm, 0 none (only the backstop holds them).
    // Absent: the baker's default, 1 for a garment the body holds up, 0 for one hung from attachments
    // (sew.cpp, "Skin constraints").
    std::optional<double> skin_max_distance_scale;
};

// One panel edge of a seam. Its points are taken from start to end, or from end to start when
// `reverse`; the k-th points of all sides of a seam are sewn together.
struct SeamSide {
    uint32_t panel = 0, edge = 0;
    bool reverse = false;
};

struct Seam {
    std::vector<SeamSide> sides;  // 2 or 3
    // Sides of different lengths are gathered (both get the same point count). GarmentCode allows
    // it everywhere; a Weft pattern must say so, else its sides must match within 1%.
    bool gather = false;
};

// A place on a panel: a whole edge, or the particle nearest a 2-D point.
struct PanelSelector {
    uint32_t panel = 0;
    int32_t edge = -1;  // >= 0: every particle of this edge; -1: the particle nearest `point`
    Point2 point;
};

// GarmentCode edge labels read as body attachments (BodyAttachment::label keeps the label), the
// edges GarmentCode's own simulator holds on the body while it dresses a garment: the waistline
// ("lower_interface"), a top's neckline on both sides and a strapless top's upper edge. Without the
// necklines a dress's straps, resting on the shoulders' outer edge, slid off them while it draped.
// (bake_pattern binds a waistline only where nothing above it holds the garment: kWaistHeldBelow_m.)
inline constexpr std::string_view kGarmentCodeBodyLabels[] = {"lower_interface", "right_collar", "left_collar",
                                                              "strapless_top"};

struct BodyAttachment {
    PanelSelector where;
    std::string label;  // stored for the caller (e.g. "waist"); the baker gives it no meaning
};

// The fabric, SI units. Compliances are XPBD's (m/N); 0 is the seed paper's hard correction.
struct Fabric {
    double areal_density_kg_m2 = 0.15;  // Penava et al. 2014, cotton (data/README.md)
    double stretch_compliance = 0.0;
    double shear_compliance = 0.0;
    double bend_compliance = 0.0;
    double damping_per_s = 1.0;  // 1/s, the runtime's ClothDesc default
    double thickness_m = 0.00032;  // cotton, same source
    double friction = 0.3;
};

struct Pattern {
    std::string format;  // "weft-pattern" or "garmentcode"
    Fabric fabric;
    std::vector<Panel> panels;
    std::vector<Seam> seams;
    std::vector<PanelSelector> pins;
    std::vector<BodyAttachment> attachments;
    double target_edge_m = 0.0;  // 0: not given, MeshOptions decides
    // Whether the garment covers the arms (sleeves sewn into armholes). GarmentCode: an edge labelled
    // "left_armhole" or "right_armhole" is stitched. Weft patterns: assumed (the arms stay in the sewing).
    bool sleeves = true;
    // What parse_pattern changed to make the pattern valid, one sentence each (a curve that
    // overshot its corner made flatter); weft-bake prints them.
    std::vector<std::string> repairs;
};

struct ParseOptions {
    // Added to every panel's translation, metres. GarmentCode v1 patterns are placed for another
    // body (origin near the pelvis) and need one to stand on a body with its feet at y = 0.
    double placement_offset_m[3] = {0.0, 0.0, 0.0};
};

// Reads a Weft pattern or a GarmentCode specification. Never throws; on failure *out is unchanged
// and the status names what is wrong and where.
Status parse_pattern(std::string_view json_text, const ParseOptions& options, Pattern* out);

// The checks every Pattern passes before meshing (parse_pattern runs them too): indices in range,
// finite and bounded coordinates, closed non-self-intersecting outlines of non-zero area, seams of
// 2 or 3 distinct edges, no edge in two seams, matching lengths where no gather is allowed.
Status validate_pattern(const Pattern& pattern);

}  // namespace weft::bake
