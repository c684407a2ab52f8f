#include "bake/outline.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace weft::bake {

namespace {

Point2 lerp(Point2 a, Point2 b, double t) { return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t}; }
double cross(Point2 o, Point2 a, Point2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }
double length(Point2 a, Point2 b) { return std::hypot(b.x - a.x, b.y - a.y); }

// A circle arc in centre form: start angle and signed sweep (positive = counter-clockwise).
struct Arc {
    Point2 centre;
    double radius, start_angle, sweep;
};

// SVG's endpoint form to centre form. The arc bulges to the right of start-to-end when `right`;
// of the two arcs through both ends on that side, the large one is longer than a half circle.
Arc centre_form(Point2 p0, Point2 p1, const PatternEdge& edge) {
    const double dx = p1.x - p0.x, dy = p1.y - p0.y, chord = std::hypot(dx, dy);
    const double half = 0.5 * chord;
    const double r = std::max(edge.arc_radius_m, half);  // SVG: a radius too short is scaled up
    const double s = std::sqrt(std::max(0.0, r * r - half * half));
    // Unit vector towards the bulge: right of the chord is (dy, -dx).
    const double bx = (edge.arc_right ? dy : -dy) / chord, by = (edge.arc_right ? -dx : dx) / chord;
    const double side = edge.arc_large ? 1.0 : -1.0;  // the centre lies on the bulge side for large arcs
    const Point2 c{0.5 * (p0.x + p1.x) + side * s * bx, 0.5 * (p0.y + p1.y) + side * s * by};
    const double a0 = std::atan2(p0.y - c.y, p0.x - c.x), a1 = std::atan2(p1.y - c.y, p1.x - c.x);
    // Bulging right means travelling counter-clockwise around the centre (and left, clockwise).
    double sweep = a1 - a0;
    if (edge.arc_right) {
        while (sweep <= 0.0) sweep += 2.0 * std::numbers::pi;
    } else {
        while (sweep >= 0.0) sweep -= 2.0 * std::numbers::pi;
    }
    return {c, r, a0, sweep};
}

}  // namespace

Point2 edge_point(const Panel& panel, const PatternEdge& edge, double t) {
    const Point2 p0 = panel.vertices[edge.start], p1 = panel.vertices[edge.end];
    switch (edge.shape) {
        case EdgeShape::straight:
            return lerp(p0, p1, t);
        case EdgeShape::quadratic: {
            const Point2 a = lerp(p0, edge.control[0], t), b = lerp(edge.control[0], p1, t);
            return lerp(a, b, t);
        }
        case EdgeShape::cubic: {
            const Point2 a = lerp(p0, edge.control[0], t), b = lerp(edge.control[0], edge.control[1], t),
                         c = lerp(edge.control[1], p1, t);
            return lerp(lerp(a, b, t), lerp(b, c, t), t);
        }
        case EdgeShape::arc: {
            if (t <= 0.0) return p0;  // the ends exactly, not through sin/cos
            if (t >= 1.0) return p1;
            const Arc arc = centre_form(p0, p1, edge);
            const double a = arc.start_angle + t * arc.sweep;
            return {arc.centre.x + arc.radius * std::cos(a), arc.centre.y + arc.radius * std::sin(a)};
        }
    }
    return p0;
}

std::vector<Point2> edge_polyline(const Panel& panel, const PatternEdge& edge, uint32_t segments) {
    if (edge.shape == EdgeShape::straight) segments = 1;
    std::vector<Point2> points(segments + 1);
    for (uint32_t k = 0; k <= segments; ++k) points[k] = edge_point(panel, edge, double(k) / segments);
    return points;
}

double edge_length(const Panel& panel, const PatternEdge& edge) {
    const std::vector<Point2> line = edge_polyline(panel, edge, kFineSegmentsPerCurve);
    double total = 0.0;
    for (size_t k = 1; k < line.size(); ++k) total += length(line[k - 1], line[k]);
    return total;
}

std::vector<Point2> sample_edge(const Panel& panel, const PatternEdge& edge, uint32_t count) {
    std::vector<double> fractions(count + 1);
    for (uint32_t k = 0; k <= count; ++k) fractions[k] = double(k) / count;
    return sample_edge_at(panel, edge, fractions);
}

std::vector<Point2> sample_edge_at(const Panel& panel, const PatternEdge& edge, const std::vector<double>& fractions) {
    const uint32_t fine = edge.shape == EdgeShape::straight ? 1 : kFineSegmentsPerCurve;
    const std::vector<Point2> line = edge_polyline(panel, edge, fine);
    std::vector<double> run(line.size(), 0.0);  // arc length at each fine point
    for (size_t k = 1; k < line.size(); ++k) run[k] = run[k - 1] + length(line[k - 1], line[k]);
    const size_t last = fractions.size() - 1;
    std::vector<Point2> points(fractions.size());
    points[0] = line.front();
    points[last] = line.back();
    size_t piece = 1;
    for (size_t k = 1; k < last; ++k) {
        const double target = run.back() * fractions[k];
        while (piece + 1 < run.size() && run[piece] < target) ++piece;
        const double span = run[piece] - run[piece - 1];
        const double f = span > 0.0 ? (target - run[piece - 1]) / span : 0.0;
        // Interpolate the curve parameter, then evaluate: the point lies on the curve itself.
        points[k] = edge_point(panel, edge, (double(piece - 1) + f) / fine);
    }
    return points;
}

std::vector<Point2> fine_outline(const Panel& panel) {
    std::vector<Point2> polygon;
    for (const PatternEdge& edge : panel.edges) {
        const std::vector<Point2> line = edge_polyline(panel, edge, kFineSegmentsPerCurve);
        polygon.insert(polygon.end(), line.begin(), line.end() - 1);  // the end is the next edge's start
    }
    return polygon;
}

double signed_area(const std::vector<Point2>& polygon) {
    double twice = 0.0;
    for (size_t k = 0, n = polygon.size(); k < n; ++k) {
        const Point2 a = polygon[k], b = polygon[(k + 1) % n];
        twice += a.x * b.y - b.x * a.y;
    }
    return 0.5 * twice;
}

bool point_in_polygon(const std::vector<Point2>& polygon, Point2 p) {
    bool inside = false;
    for (size_t k = 0, n = polygon.size(), j = n - 1; k < n; j = k++) {
        const Point2 a = polygon[k], b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (b.x - a.x) * (p.y - a.y) / (b.y - a.y)) inside = !inside;
    }
    return inside;
}

double distance_to_segment(Point2 p, Point2 a, Point2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y, ll = dx * dx + dy * dy;
    const double t = ll > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / ll, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

SegmentIndex::SegmentIndex(const std::vector<Point2>& polygon, double bucket_size) : polygon_(polygon) {
    const size_t n = polygon.size();
    double max_x = -HUGE_VAL, max_y = -HUGE_VAL;
    min_x_ = HUGE_VAL, min_y_ = HUGE_VAL;
    for (const Point2& p : polygon) {
        min_x_ = std::min(min_x_, p.x), min_y_ = std::min(min_y_, p.y);
        max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
    }
    if (n == 0) min_x_ = min_y_ = max_x = max_y = 0.0;
    // At most about 4 buckets per segment: a bucket finer than that only costs memory.
    bucket_ = std::max(bucket_size, 1e-9);
    const double cells = ((max_x - min_x_) / bucket_ + 1.0) * ((max_y - min_y_) / bucket_ + 1.0);
    if (cells > 4.0 * double(n) + 16.0) bucket_ *= std::sqrt(cells / (4.0 * double(n) + 16.0));
    columns_ = uint32_t((max_x - min_x_) / bucket_) + 1;
    rows_ = uint32_t((max_y - min_y_) / bucket_) + 1;
    std::vector<uint32_t> count(size_t(columns_) * rows_ + 1, 0);
    auto each_segment = [&](auto&& visit) {
        for (uint32_t k = 0; k < n; ++k) {
            const Point2 a = polygon[k], b = polygon[(k + 1) % n];
            visit_buckets(std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y),
                          [&](uint32_t bucket) { visit(bucket, k); });
        }
    };
    each_segment([&](uint32_t bucket, uint32_t) { ++count[bucket + 1]; });
    for (size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
    first_ = count;
    segments_.resize(count.back());
    each_segment([&](uint32_t bucket, uint32_t k) { segments_[count[bucket]++] = k; });
}

template <class Visit>
void SegmentIndex::visit_buckets(double x0, double y0, double x1, double y1, Visit&& visit) const {
    auto column = [&](double x) { return uint32_t(std::clamp((x - min_x_) / bucket_, 0.0, double(columns_ - 1))); };
    auto row = [&](double y) { return uint32_t(std::clamp((y - min_y_) / bucket_, 0.0, double(rows_ - 1))); };
    for (uint32_t r = row(y0), r1 = row(y1); r <= r1; ++r)
        for (uint32_t c = column(x0), c1 = column(x1); c <= c1; ++c) visit(r * columns_ + c);
}

double SegmentIndex::distance(Point2 p, double limit) const {
    double best = limit;
    const size_t n = polygon_.size();
    visit_buckets(p.x - limit, p.y - limit, p.x + limit, p.y + limit, [&](uint32_t bucket) {
        for (uint32_t s = first_[bucket]; s < first_[bucket + 1]; ++s) {
            const uint32_t k = segments_[s];
            best = std::min(best, distance_to_segment(p, polygon_[k], polygon_[(k + 1) % n]));
        }
    });
    return best;
}

bool SegmentIndex::self_intersects(uint32_t* first, uint32_t* second) const {
    const size_t n = polygon_.size();
    auto touches = [&](uint32_t i, uint32_t j) {
        const Point2 a = polygon_[i], b = polygon_[(i + 1) % n], c = polygon_[j], d = polygon_[(j + 1) % n];
        const bool neighbours = (i + 1) % n == j || (j + 1) % n == i;
        if (neighbours) {  // share one end: wrong only when they fold back onto each other
            const Point2 shared = (i + 1) % n == j ? b : a;
            const Point2 u = (i + 1) % n == j ? a : b, v = (i + 1) % n == j ? d : c;
            const double along = (u.x - shared.x) * (v.x - shared.x) + (u.y - shared.y) * (v.y - shared.y);
            return n > 2 && std::fabs(cross(shared, u, v)) <= 1e-12 * (length(shared, u) * length(shared, v)) &&
                   along > 0.0;
        }
        const double d1 = cross(a, b, c), d2 = cross(a, b, d), d3 = cross(c, d, a), d4 = cross(c, d, b);
        if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
        // Touching: an end lies on the other segment.
        const double eps = 1e-12 * std::max({length(a, b), length(c, d), 1e-9});
        return distance_to_segment(c, a, b) <= eps || distance_to_segment(d, a, b) <= eps ||
               distance_to_segment(a, c, d) <= eps || distance_to_segment(b, c, d) <= eps;
    };
    for (uint32_t bucket = 0; bucket + 1 < first_.size(); ++bucket)
        for (uint32_t s = first_[bucket]; s < first_[bucket + 1]; ++s)
            for (uint32_t t = s + 1; t < first_[bucket + 1]; ++t)
                if (segments_[s] != segments_[t] && touches(segments_[s], segments_[t])) {
                    *first = segments_[s];
                    if (second != nullptr) *second = segments_[t];
                    return true;
                }
    return false;
}

}  // namespace weft::bake
