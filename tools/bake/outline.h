// Panel outlines as geometry: points on curved edges, arc lengths, equal-arc-length sampling (seed
// section 4.1.1: "sample the panel outline at a fixed spacing"), areas, and a segment index for
// distance and intersection queries. No CGAL here (mesh_panel.cpp is the only CGAL translation unit).
#pragma once

#include <cstdint>
#include <vector>

#include "bake/pattern.h"

namespace weft::bake {

// Segments per curved edge for lengths, areas and intersection tests: the chord error of a
// Bezier falls as 1/n^2, so 512 segments put lengths and areas within about 1e-6 of the curve.
inline constexpr uint32_t kFineSegmentsPerCurve = 512;

// The point at parameter t in [0, 1] along an edge (Bezier parameter; angle fraction for arcs).
Point2 edge_point(const Panel& panel, const PatternEdge& edge, double t);

// The edge as a polyline of `segments` pieces (one piece when straight): segments + 1 points.
std::vector<Point2> edge_polyline(const Panel& panel, const PatternEdge& edge, uint32_t segments);

// Arc length of an edge (fine polyline).
double edge_length(const Panel& panel, const PatternEdge& edge);

// count + 1 points along the edge at equal arc length, both ends included, exactly on the curve.
std::vector<Point2> sample_edge(const Panel& panel, const PatternEdge& edge, uint32_t count);

// The points at the given fractions of the edge's arc length (ascending, first 0, last 1; both
// ends are the edge's end points exactly), on the curve.
std::vector<Point2> sample_edge_at(const Panel& panel, const PatternEdge& edge, const std::vector<double>& fractions);

// The outline as one closed polygon (no repeated first point), curves fine.
std::vector<Point2> fine_outline(const Panel& panel);

// Signed area (shoelace), positive for counter-clockwise polygons.
double signed_area(const std::vector<Point2>& polygon);

// Even-odd rule.
bool point_in_polygon(const std::vector<Point2>& polygon, Point2 p);

double distance_to_segment(Point2 p, Point2 a, Point2 b);

// The segments of a closed polygon in a uniform grid of buckets, for distance queries near the
// outline and the self-intersection test, in time linear in the polygon's size for sane outlines.
class SegmentIndex {
public:
    SegmentIndex(const std::vector<Point2>& polygon, double bucket_size);

    // The distance from p to the nearest segment, or `limit` when none is nearer than `limit`.
    double distance(Point2 p, double limit) const;

    // True when two segments that are not neighbours touch or cross, or two neighbours fold back
    // over each other. Sets *first and *second (may be null) to the two offending segments.
    bool self_intersects(uint32_t* first, uint32_t* second = nullptr) const;

private:
    template <class Visit>
    void visit_buckets(double x0, double y0, double x1, double y1, Visit&& visit) const;

    const std::vector<Point2>& polygon_;
    double min_x_ = 0.0, min_y_ = 0.0, bucket_ = 1.0;
    uint32_t columns_ = 1, rows_ = 1;
    std::vector<uint32_t> first_, segments_;  // CSR: bucket -> segment indices
};

}  // namespace weft::bake
