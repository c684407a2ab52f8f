// mesh_garment: seam-consistent outline sampling, panel meshing with remeshing rounds, lattice
// packing, seams, pins, masses and the quality report. See garment.h.
#include "bake/garment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "bake/mesh_panel.h"
#include "bake/outline.h"

namespace weft::bake {

namespace {

// A panel's strip mesher stops, and the panel is refused, past this many times the panel's
// particle estimate plus a slack: curves that nearly touch would otherwise refine without end.
constexpr double kStripPointsPerEstimate = 8.0, kStripPointsSlack = 1000.0;

struct BakeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Where an outline comes closest to itself: of its segments' pairs, the one whose gap is least
// against the way round the outline between them (so a corner's neighbours do not count), named by
// their edges (for a panel the strip mesher gave up on).
std::string closest_approach(const Panel& panel, const PanelOutline& outline) {
    const std::vector<Point2>& q = outline.points;
    const size_t n = q.size();
    std::vector<double> along(n + 1, 0.0);  // arc length to point k
    for (size_t k = 0; k < n; ++k) along[k + 1] = along[k] + std::hypot(q[(k + 1) % n].x - q[k].x, q[(k + 1) % n].y - q[k].y);
    double best = INFINITY, best_gap = 0.0;
    size_t best_i = 0, best_j = 0;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 2; j < n; ++j) {
            if ((j + 1) % n == i) continue;  // the last segment ends where the first starts
            const Point2 a = q[i], b = q[(i + 1) % n], c = q[j], d = q[(j + 1) % n];
            const double gap = std::min({distance_to_segment(a, c, d), distance_to_segment(b, c, d),
                                         distance_to_segment(c, a, b), distance_to_segment(d, a, b)});
            const double round = std::min(along[j] - along[i + 1], along[n] - along[j + 1] + along[i]);
            if (gap < best * round) best = gap / round, best_gap = gap, best_i = i, best_j = j;
        }
    if (!(best < INFINITY)) return "";
    auto edge_of = [&](size_t k) {
        const size_t e = size_t(std::upper_bound(outline.edge_first.begin(), outline.edge_first.end(), uint32_t(k)) -
                                outline.edge_first.begin()) - 1;
        return "'" + panel.edges[e].name + "'";
    };
    char gap_mm[32];
    std::snprintf(gap_mm, sizeof gap_mm, "%.3g", best_gap * 1e3);
    const std::string a = edge_of(best_i), b = edge_of(best_j);
    return a == b ? "; edge " + a + " comes within " + gap_mm + " mm of itself"
                  : "; edges " + a + " and " + b + " come within " + gap_mm + " mm";
}

struct PanelWork {
    std::vector<Point2> fine;     // the curved outline, finely
    double area_m2 = 0.0;         // signed: > 0 counter-clockwise
    double particle_estimate = 0.0;  // about one particle per h^2 of area and two per h of outline
    std::vector<double> edge_length;
    // Per edge, its outline points as fractions of its arc length, ascending, from 0 to 1.
    std::vector<std::vector<double>> cuts;
    std::vector<uint8_t> dropped; // grid cells the mesher split a side of
    PanelOutline outline;
    PanelGrid grid;
    PanelMesh mesh;
    bool dirty = true;
    // Per edge, its mesh points from start to end (both corners) and their arc-length fractions:
    // the outline's points and those the mesher kept on unsewn edges (finish_edges).
    std::vector<std::vector<uint32_t>> edge_point;
    std::vector<std::vector<double>> edge_fraction;
};

// The seam each panel edge belongs to (-1: none), for cutting every side of a seam at once.
using SeamOf = std::vector<std::vector<int32_t>>;

std::vector<double> uniform_cuts(uint32_t count) {
    std::vector<double> cuts(count + 1);
    for (uint32_t k = 0; k <= count; ++k) cuts[k] = double(k) / count;
    return cuts;
}

// Adds the point at arc-length fraction f of edge e of panel p, and the matching point of every
// other side of its seam (the same fraction along the seam: sewn points stay one to one, gathered
// seams included). A point within 1e-9 of one already there is not added again.
void add_cut(const Pattern& pattern, const SeamOf& seam_of, size_t p, size_t e, double f, std::vector<PanelWork>& work) {
    auto insert = [&](size_t panel, size_t edge, double t) {
        std::vector<double>& cuts = work[panel].cuts[edge];
        const auto at = std::lower_bound(cuts.begin(), cuts.end(), t);
        if ((at != cuts.end() && *at - t < 1e-9) || (at != cuts.begin() && t - *(at - 1) < 1e-9)) return;
        cuts.insert(at, t);
        work[panel].dirty = true;
    };
    if (seam_of[p][e] < 0) return insert(p, e, f);
    const Seam& seam = pattern.seams[size_t(seam_of[p][e])];
    double u = f;  // along the seam: side points are taken end to start when reversed
    for (const SeamSide& side : seam.sides)
        if (side.panel == p && side.edge == e) u = side.reverse ? 1.0 - f : f;
    for (const SeamSide& side : seam.sides) insert(side.panel, side.edge, side.reverse ? 1.0 - u : u);
}

PanelOutline sample_outline(const Panel& panel, const std::vector<std::vector<double>>& cuts) {
    PanelOutline outline;
    for (size_t e = 0; e < panel.edges.size(); ++e) {
        outline.edge_first.push_back(uint32_t(outline.points.size()));
        const std::vector<Point2> points = sample_edge_at(panel, panel.edges[e], cuts[e]);
        outline.points.insert(outline.points.end(), points.begin(), points.end() - 1);  // the end starts the next edge
    }
    outline.edge_first.push_back(uint32_t(outline.points.size()));
    return outline;
}

std::vector<double> corner_angles(const std::vector<Point2>& polygon, bool counter_clockwise);  // below

// True when outline segment k touches a corner sharper than kSharpCornerDeg. CGAL's mesher treats
// the segments at such a corner as a cluster (Shewchuk's concentric shells): a fresh run splits
// them whenever a bad triangle's circumcentre encroaches one, and a point added there as input
// makes a new cluster of the same shape, so sampling the outline finer there never ends (49 of the
// 150 corpus garments stopped at 16 rounds). Its points there are kept on unsewn edges and taken
// out again on sewn ones (mesh_panel's fixed segments).
bool at_sharp_corner(const std::vector<double>& corner, uint32_t k) {
    return corner[k] < kSharpCornerDeg || corner[(k + 1) % corner.size()] < kSharpCornerDeg;
}

// Each edge's mesh points in order: the outline's, and the points the mesher kept on its segments.
void collect_edge_points(PanelWork& w) {
    const PanelOutline& outline = w.outline;
    const uint32_t n = uint32_t(outline.points.size());
    const size_t edges = outline.edge_first.size() - 1;
    w.edge_point.assign(edges, {});
    w.edge_fraction.assign(edges, {});
    size_t s = 0;
    const std::vector<PanelMesh::OutlineSplit>& splits = w.mesh.split_outline;
    for (size_t e = 0; e < edges; ++e) {
        const std::vector<double>& cuts = w.cuts[e];
        for (uint32_t k = outline.edge_first[e]; k < outline.edge_first[e + 1]; ++k) {
            const size_t j = k - outline.edge_first[e];
            w.edge_point[e].push_back(k);
            w.edge_fraction[e].push_back(cuts[j]);
            for (; s < splits.size() && splits[s].segment == k; ++s) {
                w.edge_point[e].push_back(splits[s].point);
                w.edge_fraction[e].push_back(cuts[j] + splits[s].along * (cuts[j + 1] - cuts[j]));
            }
        }
        w.edge_point[e].push_back(outline.edge_first[e + 1] % n);
        w.edge_fraction[e].push_back(1.0);
    }
}

// After the last round: every edge's points in order. Sewn edges keep only their sampled points
// (mesh_panel's fixed segments), so a seam's sides still have one point for one.
void finish_edges(const Pattern& pattern, std::vector<PanelWork>& work) {
    for (PanelWork& w : work) collect_edge_points(w);
    for (const Seam& seam : pattern.seams)
        for (const SeamSide& side : seam.sides)
            if (work[side.panel].edge_point[side.edge].size() != work[seam.sides[0].panel].edge_point[seam.sides[0].edge].size())
                throw BakeError("a seam's sides got different counts (bug)");
}

// Interior angle of the outline polygon at each point, degrees (winding-aware).
std::vector<double> corner_angles(const std::vector<Point2>& polygon, bool counter_clockwise) {
    const size_t n = polygon.size();
    std::vector<double> angle(n);
    for (size_t k = 0; k < n; ++k) {
        const Point2 a = polygon[(k + n - 1) % n], b = polygon[k], c = polygon[(k + 1) % n];
        const double turn = std::atan2((b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x),
                                       (b.x - a.x) * (c.x - b.x) + (b.y - a.y) * (c.y - b.y));
        angle[k] = 180.0 - (counter_clockwise ? turn : -turn) * 180.0 / std::numbers::pi;
    }
    return angle;
}

double triangle_area(Point2 a, Point2 b, Point2 c) { return 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)); }

PanelQuality panel_quality(const std::string& name, const PanelMesh& mesh, const PanelOutline& outline, double h,
                           bool counter_clockwise, double outline_area) {
    PanelQuality q;
    q.name = name;
    q.particles = uint32_t(mesh.points.size());
    q.triangles = uint32_t(mesh.triangles.size() / 3);
    q.grid_particles = mesh.grid_points;
    q.grid_triangles = mesh.grid_triangles;
    q.outline_area_m2 = std::fabs(outline_area);
    const std::vector<double> corner = corner_angles(outline.points, counter_clockwise);
    const uint32_t n_outline = uint32_t(outline.points.size());
    q.min_angle_deg = q.min_angle_deg_smooth = 180.0;
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
        const uint32_t v[3] = {mesh.triangles[t], mesh.triangles[t + 1], mesh.triangles[t + 2]};
        const Point2 p[3] = {mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]]};
        q.mesh_area_m2 += triangle_area(p[0], p[1], p[2]);
        bool sharp = false;
        double smallest = 180.0;
        for (int k = 0; k < 3; ++k) {
            const Point2 a = p[k], b = p[(k + 1) % 3], c = p[(k + 2) % 3];
            const double dot = (b.x - a.x) * (c.x - a.x) + (b.y - a.y) * (c.y - a.y);
            const double cr = std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
            smallest = std::min(smallest, std::atan2(cr, dot) * 180.0 / std::numbers::pi);
            if (v[k] < n_outline && corner[v[k]] < kSharpCornerDeg) sharp = true;
            edges.push_back({std::min(v[k], v[(k + 1) % 3]), std::max(v[k], v[(k + 1) % 3])});
        }
        q.min_angle_deg = std::min(q.min_angle_deg, smallest);
        if (!sharp) q.min_angle_deg_smooth = std::min(q.min_angle_deg_smooth, smallest);
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    q.edge_min_h = HUGE_VAL;
    for (const auto& [a, b] : edges) {
        const double l = std::hypot(mesh.points[b].x - mesh.points[a].x, mesh.points[b].y - mesh.points[a].y) / h;
        q.edge_min_h = std::min(q.edge_min_h, l), q.edge_max_h = std::max(q.edge_max_h, l);
        q.edge_mean_h += l / double(edges.size());
    }
    return q;
}

// Union-find over particles, for seam points: a corner where two seams meet joins both chains.
struct UnionFind {
    std::vector<uint32_t> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void join(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// Strip particles onto free lattice nodes: each takes the free node nearest to it (of the 3 x 3
// around its own position), nearest particles first. The runtime puts lattice particles in its
// parity planes, so a strip spring that joins two nodes like a grid spring (same (di, dj)) joins
// the grid's SIMD runs instead of the one-at-a-time path: this lifts the share of
// springs on runs on the 1 m sheet from 0.92 to 0.97. (cook_cloth calls a strip spring between diagonal
// nodes "shear"; the rest lengths are the true ones either way.)
void snap_strip_to_lattice(const PanelGrid& grid, PanelMesh& mesh) {
    const double h = grid.h;
    std::map<std::pair<int32_t, int32_t>, uint32_t> taken;
    struct Candidate {
        double distance;
        uint32_t point;
    };
    std::vector<Candidate> strip;
    for (uint32_t k = 0; k < mesh.points.size(); ++k) {
        if (mesh.lattice[2 * k] >= 0) {
            taken[{mesh.lattice[2 * k], mesh.lattice[2 * k + 1]}] = k;
            continue;
        }
        const double r = (mesh.points[k].y - grid.origin.y) / h, c = (mesh.points[k].x - grid.origin.x) / h;
        strip.push_back({std::hypot(r - std::round(r), c - std::round(c)), k});
    }
    std::sort(strip.begin(), strip.end(), [](const Candidate& a, const Candidate& b) {
        return a.distance != b.distance ? a.distance < b.distance : a.point < b.point;
    });
    for (const Candidate& s : strip) {
        const double r = (mesh.points[s.point].y - grid.origin.y) / h, c = (mesh.points[s.point].x - grid.origin.x) / h;
        const int32_t r0 = int32_t(std::lround(r)), c0 = int32_t(std::lround(c));
        double best = HUGE_VAL;
        std::pair<int32_t, int32_t> node{0, 0};
        for (int32_t dr = -1; dr <= 1; ++dr)
            for (int32_t dc = -1; dc <= 1; ++dc) {
                const std::pair<int32_t, int32_t> q{r0 + dr, c0 + dc};
                const double d = std::hypot(r - q.first, c - q.second);
                const bool none = q.first == -1 && q.second == -1;  // panel-local (-1, -1) means "off the lattice"
                if (!none && !taken.count(q) && d < best) best = d, node = q;
            }
        if (best == HUGE_VAL) continue;  // stays off the lattice
        taken[node] = s.point;
        mesh.lattice[2 * s.point] = node.first, mesh.lattice[2 * s.point + 1] = node.second;
    }
}

double min_angle_deg(Point2 a, Point2 b, Point2 c) {
    double smallest = 180.0;
    const Point2 p[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        const Point2 u = p[k], v = p[(k + 1) % 3], w = p[(k + 2) % 3];
        const double dot = (v.x - u.x) * (w.x - u.x) + (v.y - u.y) * (w.y - u.y);
        const double cr = std::fabs((v.x - u.x) * (w.y - u.y) - (v.y - u.y) * (w.x - u.x));
        smallest = std::min(smallest, std::atan2(cr, dot) * 180.0 / std::numbers::pi);
    }
    return smallest;
}

// Strip quads onto the grid's diagonal. Two strip triangles that make up one lattice square (their
// four corners snapped to (r, c), (r, c + 1), (r + 1, c), (r + 1, c + 1)) but are cut along the
// other diagonal, (r, c + 1)-(r + 1, c), are flipped to the grid's (r, c)-(r + 1, c + 1) when both
// new triangles keep the strip's minimum angle and no corner is marked in `keep`. The shear spring
// and the bend springs around the square then belong to grid families, which the runtime solves
// on runs; left as they are, they are families of their own (weft-bake --runs: the GarmentCode
// shirt's springs of non-grid families 1259 -> 480 of 9720, the sample skirt 842 -> 334).
// Returns the number of flips.
uint32_t flip_strip_diagonals(const std::vector<uint8_t>& keep, PanelMesh& mesh, double min_angle) {
    uint32_t flips = 0;
    auto node = [&](uint32_t v) { return std::pair{mesh.lattice[2 * v], mesh.lattice[2 * v + 1]}; };
    auto on_lattice = [&](uint32_t v) { return mesh.lattice[2 * v] != -1 || mesh.lattice[2 * v + 1] != -1; };
    for (bool again = true; again;) {
        again = false;
        // (min, max) -> the triangles on that edge and their corners opposite it (an edge has at most two).
        struct Sides {
            uint32_t count = 0, triangle[2] = {0, 0}, corner[2] = {0, 0};
        };
        std::map<std::pair<uint32_t, uint32_t>, Sides> edges;
        const uint32_t triangles = uint32_t(mesh.triangles.size() / 3);
        for (uint32_t t = 0; t < triangles; ++t)
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t u = mesh.triangles[3 * t + (k + 1) % 3], v = mesh.triangles[3 * t + (k + 2) % 3];
                Sides& e = edges[{std::min(u, v), std::max(u, v)}];
                if (e.count < 2) e.triangle[e.count] = t, e.corner[e.count] = k;
                ++e.count;
            }
        std::vector<uint8_t> touched(triangles, 0);
        for (uint32_t t = 0; t < triangles; ++t)
            for (uint32_t k = 0; k < 3 && !touched[t]; ++k) {
                const uint32_t p = mesh.triangles[3 * t + k], u = mesh.triangles[3 * t + (k + 1) % 3],
                               v = mesh.triangles[3 * t + (k + 2) % 3];
                if (!on_lattice(p) || !on_lattice(u) || !on_lattice(v)) continue;
                const auto [ui, uj] = node(u);
                const auto [vi, vj] = node(v);
                if (std::abs(ui - vi) != 1 || (ui - vi) != -(uj - vj)) continue;  // not an anti-diagonal
                const Sides& e = edges[{std::min(u, v), std::max(u, v)}];
                if (e.count != 2) continue;  // on the outline
                const uint32_t side = e.triangle[0] == t ? 1 : 0, s = e.triangle[side], m = e.corner[side];
                if (touched[s]) continue;
                const uint32_t q = mesh.triangles[3 * s + m];
                if (!on_lattice(q) || keep[p] || keep[q] || keep[u] || keep[v]) continue;
                const auto [pi, pj] = node(p);
                const auto [qi, qj] = node(q);
                // p and q: the square's other two corners, on the grid's diagonal.
                if (std::abs(pi - qi) != 1 || (pi - qi) != (pj - qj)) continue;
                if (!((pi == ui && pj == vj) || (pi == vi && pj == uj))) continue;
                // Triangle t is (p, u, v) counter-clockwise; the flipped pair is (p, u, q) and (p, q, v).
                const Point2 P = mesh.points[p], U = mesh.points[u], V = mesh.points[v], Q = mesh.points[q];
                if (triangle_area(P, U, Q) <= 0.0 || triangle_area(P, Q, V) <= 0.0) continue;
                if (min_angle_deg(P, U, Q) < min_angle || min_angle_deg(P, Q, V) < min_angle) continue;
                mesh.triangles[3 * t] = p, mesh.triangles[3 * t + 1] = u, mesh.triangles[3 * t + 2] = q;
                mesh.triangles[3 * s] = p, mesh.triangles[3 * s + 1] = q, mesh.triangles[3 * s + 2] = v;
                touched[t] = touched[s] = 1;
                ++flips;
                again = true;
            }
    }
    return flips;
}

// The points of panel p within `rings` triangle rings of a pinned point (the pattern's pins, chosen
// as assemble() chooses them). Flips are kept away from pins: the baked 2 m sheet's largest strain at
// rest beside its corner pins (tests/test_pipeline.cpp, bound 0.05) came out 0.083, 0.030, 0.059
// with flips up to 0, 1, 2 rings from the pins, and 0.030 (the in-memory grid's figure) from 3 to 8 rings.
std::vector<uint8_t> near_pins(const Pattern& pattern, size_t p, const PanelWork& w, int rings) {
    const PanelMesh& mesh = w.mesh;
    std::vector<uint8_t> near(mesh.points.size(), 0);
    for (const PanelSelector& pin : pattern.pins) {
        if (pin.panel != p) continue;
        if (pin.edge >= 0) {
            for (uint32_t v : w.edge_point[size_t(pin.edge)]) near[v] = 1;
            continue;
        }
        uint32_t best = 0;
        double best_d = HUGE_VAL;
        for (uint32_t v = 0; v < mesh.points.size(); ++v) {
            const double d = std::hypot(mesh.points[v].x - pin.point.x, mesh.points[v].y - pin.point.y);
            if (d < best_d) best_d = d, best = v;
        }
        near[best] = 1;
    }
    for (int r = 0; r < rings; ++r) {
        std::vector<uint8_t> grown = near;
        for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
            const uint32_t a = mesh.triangles[t], b = mesh.triangles[t + 1], c = mesh.triangles[t + 2];
            if (near[a] || near[b] || near[c]) grown[a] = grown[b] = grown[c] = 1;
        }
        near = std::move(grown);
    }
    return near;
}

// A panel's lattice nodes, normalised to >= 0 (even shifts keep every node in its parity plane),
// upright or turned by 180 degrees (which keeps the grid's diagonal family), and per parity plane
// the intervals of plane columns each of its plane rows holds.
struct Footprint {
    std::vector<std::pair<int32_t, int32_t>> cells;  // lattice (i, j), in the order given
    struct Span {
        int32_t row, lo, hi;  // plane row, first and last plane column
    };
    std::vector<Span> spans[4];  // per parity plane (i & 1) * 2 + (j & 1)
    int32_t cols = 0;            // plane columns spanned
    size_t nodes() const { return cells.size(); }
};
Footprint footprint(const std::vector<std::pair<int32_t, int32_t>>& in, bool turned) {
    auto even_up = [](int32_t v) { return (v + 1) & ~1; };
    Footprint f;
    int32_t r0 = INT32_MAX, c0 = INT32_MAX, r1 = INT32_MIN, c1 = INT32_MIN;
    for (const auto& [r, c] : in) r0 = std::min(r0, r), c0 = std::min(c0, c), r1 = std::max(r1, r), c1 = std::max(c1, c);
    r0 &= ~1, c0 &= ~1;  // even shifts keep parity
    const int32_t R = even_up(r1 - r0), C = even_up(c1 - c0);
    for (const auto& [r, c] : in)
        f.cells.push_back(turned ? std::pair{R - (r - r0), C - (c - c0)} : std::pair{r - r0, c - c0});
    std::vector<std::pair<int32_t, int32_t>> plane[4];
    for (const auto& [i, j] : f.cells) plane[(i & 1) * 2 + (j & 1)].push_back({i >> 1, j >> 1});
    for (int q = 0; q < 4; ++q) {
        std::sort(plane[q].begin(), plane[q].end());
        for (size_t k = 0; k < plane[q].size(); ++k) {
            const auto [r, c] = plane[q][k];
            f.cols = std::max(f.cols, c + 1);
            if (k > 0 && plane[q][k - 1].first == r && plane[q][k - 1].second + 1 >= c) f.spans[q].back().hi = c;
            else f.spans[q].push_back({r, c, c});
        }
    }
    return f;
}

// Parity planes laid out as a helix (ClothMeshDesc::lattice_plane_stride): plane node (r, c) at
// position r * stride + c. A panel placed at offset o (o = R * stride + C: the panel moved by
// (2R, 2C) lattice nodes) covers o + r * stride + [lo, hi] for each of its spans, in all four
// planes alike.
class Helix {
public:
    explicit Helix(int32_t stride) : stride_(stride) {}

    // Whether the footprint alone maps its nodes to distinct positions.
    bool holds(const Footprint& f) const {
        for (int q = 0; q < 4; ++q) {
            std::vector<std::pair<int64_t, int64_t>> at;
            for (const Footprint::Span& s : f.spans[q]) at.push_back({int64_t(s.row) * stride_ + s.lo, int64_t(s.row) * stride_ + s.hi});
            std::sort(at.begin(), at.end());
            for (size_t k = 1; k < at.size(); ++k)
                if (at[k].first <= at[k - 1].second) return false;
        }
        return true;
    }
    // How many nodes of f at offset o meet placed nodes (stops counting past `limit`).
    uint32_t collisions(const Footprint& f, int64_t o, uint32_t limit) const {
        uint32_t met = 0;
        for (int q = 0; q < 4; ++q)
            for (const Footprint::Span& s : f.spans[q]) {
                const int64_t a = o + int64_t(s.row) * stride_ + s.lo, b = std::min(o + int64_t(s.row) * stride_ + s.hi, end_ - 1);
                if (a <= b && (met += filled_[q][size_t(b + 1)] - filled_[q][size_t(a)]) > limit) return met;
            }
        return met;
    }
    // The lowest offset >= `from` where f meets at most `limit` placed nodes (there is always one:
    // past the last placed node). `from`: an offset below which none fits (a stricter limit's
    // search may start at a looser one's answer).
    int64_t first_fit(const Footprint& f, uint32_t limit, int64_t from = 0) const {
        int64_t o = from;
        while (collisions(f, o, limit) > limit) ++o;
        return o;
    }
    // Places f at o; its nodes that meet placed ones stay off the lattice: *dropped[k] = 1 for cell k.
    void place(const Footprint& f, int64_t o, uint32_t panel, std::vector<uint8_t>* dropped) {
        waste_ = waste_if_placed(f, o, panel);
        int64_t end = end_;
        for (int q = 0; q < 4; ++q)
            for (const Footprint::Span& s : f.spans[q]) end = std::max(end, o + int64_t(s.row) * stride_ + s.hi + 1);
        for (int q = 0; q < 4; ++q) owner_[q].resize(size_t(end), 0);
        dropped->assign(f.cells.size(), 0);
        size_t placed[4];
        int64_t first = end_;  // the first position whose prefix sum changes (those past end_ are new)
        for (int q = 0; q < 4; ++q) placed[q] = occupied_[q].size();
        for (size_t k = 0; k < f.cells.size(); ++k) {
            const auto [i, j] = f.cells[k];
            const int q = (i & 1) * 2 + (j & 1);
            const int64_t at = o + int64_t(i >> 1) * stride_ + (j >> 1);
            uint32_t& owner = owner_[q][size_t(at)];
            if (owner != 0) (*dropped)[k] = 1, ++dropped_;
            else owner = panel + 1, occupied_[q].push_back(at), first = std::min(first, at);
        }
        for (int q = 0; q < 4; ++q) {
            std::vector<int64_t>& occupied = occupied_[q];
            std::sort(occupied.begin() + std::ptrdiff_t(placed[q]), occupied.end());
            std::inplace_merge(occupied.begin(), occupied.begin() + std::ptrdiff_t(placed[q]), occupied.end());
            filled_[q].resize(size_t(end) + 1, 0);
            for (size_t k = size_t(first); k < size_t(end); ++k) filled_[q][k + 1] = filled_[q][k] + (owner_[q][k] != 0);
        }
        end_ = end;
    }
    // The padding lanes this layout costs the runtime's runs, estimated from the nodes alone
    // (measured with weft-bake --runs on the sample tee): along each plane, a hole of up to
    // kBridged slots between two nodes is bridged by a padding lane in every family that passes
    // over it (about 12 lanes per hole slot); a longer one ends those runs (about 12 tails of half a
    // SIMD width); two neighbours from different panels miss the springs between them (about 1
    // lane). A node left off the lattice sends its springs (about 6) to the indexed path, 7.6 run
    // lanes each: about 46 lanes' worth of time.
    double waste() const { return waste_; }
    // waste() after placing f at o as `panel`, the layout unchanged: only the gaps between placed
    // nodes that f's nodes fall into change (every term is a whole number: the sum is exact in any
    // order, so this equals the sum over the whole layout).
    double waste_if_placed(const Footprint& f, int64_t o, uint32_t panel) const {
        constexpr int64_t kBridged = 4;
        constexpr double kHoleSlot = 12.0, kRunEnd = 42.0, kPanelBoundary = 1.0, kDroppedNode = 46.0;
        const auto owner_at = [&](int q, int64_t at) { return at < end_ ? owner_[q][size_t(at)] : 0u; };
        const auto gap = [&](int64_t a, uint32_t owner_a, int64_t b, uint32_t owner_b) {
            const int64_t hole = b - a - 1;
            return hole > kBridged ? kRunEnd : kHoleSlot * double(hole) + (owner_a != owner_b ? kPanelBoundary : 0.0);
        };
        double waste = waste_;
        std::vector<int64_t> added;
        for (int q = 0; q < 4; ++q) {
            added.clear();
            for (const auto& [i, j] : f.cells) {
                if ((i & 1) * 2 + (j & 1) != q) continue;
                const int64_t at = o + int64_t(i >> 1) * stride_ + (j >> 1);
                if (owner_at(q, at) != 0) waste += kDroppedNode;  // stays off the lattice
                else added.push_back(at);
            }
            std::sort(added.begin(), added.end());
            const std::vector<int64_t>& placed = occupied_[q];
            for (size_t k = 0; k < added.size();) {
                // The run of added nodes in one gap between placed nodes a < ... < b.
                const auto next = std::lower_bound(placed.begin(), placed.end(), added[k]);
                const bool has_a = next != placed.begin(), has_b = next != placed.end();
                const int64_t a = has_a ? *(next - 1) : 0, b = has_b ? *next : 0;
                size_t m = k + 1;
                while (m < added.size() && (!has_b || added[m] < b)) ++m;
                if (has_a && has_b) waste -= gap(a, owner_at(q, a), b, owner_at(q, b));
                if (has_a) waste += gap(a, owner_at(q, a), added[k], panel + 1);
                for (size_t n = k + 1; n < m; ++n) waste += gap(added[n - 1], panel + 1, added[n], panel + 1);
                if (has_b) waste += gap(added[m - 1], panel + 1, b, owner_at(q, b));
                k = m;
            }
        }
        return waste;
    }
    int64_t end() const { return end_; }
    int32_t stride() const { return stride_; }

private:
    int32_t stride_;
    int64_t end_ = 0;
    uint32_t dropped_ = 0;  // nodes left off the lattice where panels met
    std::vector<uint32_t> owner_[4];  // panel + 1 per position, 0 where free
    std::vector<uint32_t> filled_[4];  // prefix sums of occupied positions
    std::vector<int64_t> occupied_[4];  // occupied positions, sorted
    double waste_ = 0.0;                // waste() of the layout as placed
};

struct PackedLattice {
    std::vector<std::vector<std::pair<int32_t, int32_t>>> nodes;  // per panel: placed (i, j) of each node
    uint32_t plane_stride = 0;                                    // ClothMeshDesc::lattice_plane_stride
};

// Packs the panels' lattice nodes into one coordinate space for the runtime's parity planes laid out
// as a helix: a plane row runs on into the next, so two slanted panels side by side (a skirt's
// front beside its back turned by 180 degrees: a parallelogram) fill their rows end to end with
// no holes at the row ends, where a box of the widest row would leave a triangle of holes on each
// side. Largest panel first, upright or turned, at the lowest free offset (panels touch: no spring
// joins two panels, so runs go on from one into the next); every stride from the narrowest a panel
// allows to all panels side by side is tried and the least estimated waste (Helix::waste) wins.
std::vector<PackedLattice> pack_lattice(const std::vector<std::vector<std::pair<int32_t, int32_t>>>& nodes, size_t keep) {
    std::vector<size_t> order;
    std::vector<Footprint> upright(nodes.size()), turned(nodes.size());
    int32_t total_cols = 1;
    for (size_t p = 0; p < nodes.size(); ++p) {
        if (nodes[p].empty()) continue;
        order.push_back(p);
        upright[p] = footprint(nodes[p], false);
        turned[p] = footprint(nodes[p], true);
        total_cols += upright[p].cols + 1;
    }
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return nodes[a].size() > nodes[b].size(); });
    struct Choice {
        bool turned = false;
        int64_t offset = 0;
        std::vector<uint8_t> dropped;  // per cell: left off the lattice
    };
    struct Packing {
        double waste;
        int64_t end;
        int32_t stride;
        std::vector<Choice> choices;
    };
    std::vector<Packing> packings;
    std::vector<Choice> trial(nodes.size());
    for (int32_t stride = 1; stride <= total_cols; ++stride) {
        Helix helix(stride);
        bool ok = true;
        for (size_t p : order) {
            const bool up = helix.holds(upright[p]), down = helix.holds(turned[p]);
            if (!up && !down) {
                ok = false;
                break;
            }
            // Each orientation at its lowest offset meeting at most `limit` placed nodes (a node
            // sticking out of an outline would otherwise keep a whole column of holes between two
            // panels); the one that leaves the least waste.
            double pick_waste = HUGE_VAL;
            for (const bool turn : {false, true}) {
                if (!(turn ? down : up)) continue;
                const Footprint& f = turn ? turned[p] : upright[p];
                // A stricter limit never fits lower than a looser one: searched loosest first.
                constexpr uint32_t kLimits[5] = {0u, 2u, 4u, 8u, 16u};
                int64_t fit[5];
                for (int k = 4; k >= 0; --k) fit[k] = helix.first_fit(f, kLimits[k], k < 4 ? fit[k + 1] : 0);
                int64_t tried[5];  // offsets placed already: the same offset leaves the same waste
                uint32_t tries = 0;
                for (int k = 0; k < 5; ++k) {
                    const int64_t offset = fit[k];
                    if (std::find(tried, tried + tries, offset) != tried + tries) continue;
                    tried[tries++] = offset;
                    if (const double w = helix.waste_if_placed(f, offset, uint32_t(p)); w < pick_waste)
                        pick_waste = w, trial[p] = Choice{turn, offset, {}};
                }
            }
            helix.place(trial[p].turned ? turned[p] : upright[p], trial[p].offset, uint32_t(p), &trial[p].dropped);
        }
        if (!ok) continue;
        const double waste = helix.waste();
        packings.push_back({waste, helix.end(), stride, trial});
    }
    std::stable_sort(packings.begin(), packings.end(), [](const Packing& a, const Packing& b) {
        return a.waste != b.waste ? a.waste < b.waste : a.end < b.end;
    });
    packings.resize(std::min(packings.size(), std::max<size_t>(keep, 1)));
    std::vector<PackedLattice> result;
    for (const Packing& best : packings) {
        PackedLattice packed;
        packed.nodes.resize(nodes.size());
        packed.plane_stride = uint32_t(best.stride);
        for (size_t p : order) {
            const Choice& c = best.choices[p];
            const Footprint& f = c.turned ? turned[p] : upright[p];
            const int64_t rows = c.offset / best.stride, cols = c.offset % best.stride;
            for (size_t k = 0; k < f.cells.size(); ++k)
                packed.nodes[p].push_back(c.dropped[k] ? std::pair{-1, -1}
                                                       : std::pair{f.cells[k].first + int32_t(2 * rows),
                                                                   f.cells[k].second + int32_t(2 * cols)});
        }
        result.push_back(std::move(packed));
    }
    return result;
}

void rotate(const Placement& placement, double x, double y, Vec3* out) {
    const double rx = placement.rotation_deg[0] * std::numbers::pi / 180.0, ry = placement.rotation_deg[1] * std::numbers::pi / 180.0,
                 rz = placement.rotation_deg[2] * std::numbers::pi / 180.0;
    // R = Rz * Ry * Rx applied to (x, y, 0).
    double px = x, py = y * std::cos(rx), pz = y * std::sin(rx);                       // Rx
    const double qx = px * std::cos(ry) + pz * std::sin(ry), qz = -px * std::sin(ry) + pz * std::cos(ry);  // Ry
    px = qx, pz = qz;
    const double sx = px * std::cos(rz) - py * std::sin(rz), sy = px * std::sin(rz) + py * std::cos(rz);  // Rz
    out->x = float(sx + placement.translation_m[0]);
    out->y = float(sy + placement.translation_m[1]);
    out->z = float(pz + placement.translation_m[2]);
}

MeshedGarment assemble(const Pattern& pattern, const MeshOptions& options, double h, std::vector<PanelWork>& work) {
    MeshedGarment g;
    g.fabric = pattern.fabric;
    const size_t panels = pattern.panels.size();
    // Strip particles onto the lattice, then all panels' lattices into one coordinate space.
    std::vector<std::vector<std::pair<int32_t, int32_t>>> nodes(panels);
    for (size_t p = 0; p < panels; ++p) {
        snap_strip_to_lattice(work[p].grid, work[p].mesh);
        flip_strip_diagonals(near_pins(pattern, p, work[p], 3), work[p].mesh, options.min_angle_deg);
        const std::vector<int32_t>& l = work[p].mesh.lattice;
        for (size_t k = 0; k < l.size(); k += 2)
            if (l[k] != -1 || l[k + 1] != -1) nodes[p].push_back({l[k], l[k + 1]});
    }
    const std::vector<PackedLattice> packed = pack_lattice(nodes, options.lattice_candidates);
    std::vector<std::pair<uint32_t, int64_t>> node_of;  // per particle: (panel, its lattice node) or (panel, -1)

    double table_x = 0.0;  // the cutting table: panels side by side along x, 5 cm apart
    std::vector<uint32_t> base(panels + 1, 0);
    for (size_t p = 0; p < panels; ++p) {
        const Panel& panel = pattern.panels[p];
        const PanelMesh& mesh = work[p].mesh;
        base[p] = uint32_t(g.positions.size());
        const double density = panel.areal_density_kg_m2 > 0.0 ? panel.areal_density_kg_m2 : pattern.fabric.areal_density_kg_m2;
        double min_x = HUGE_VAL, max_x = -HUGE_VAL;
        for (const Point2& q : mesh.points) min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
        std::vector<double> mass(mesh.points.size(), 0.0);
        size_t next_node = 0;
        for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
            const uint32_t a = mesh.triangles[t], b = mesh.triangles[t + 1], c = mesh.triangles[t + 2];
            const double area = std::fabs(triangle_area(mesh.points[a], mesh.points[b], mesh.points[c]));
            for (uint32_t v : {a, b, c}) mass[v] += density * area / 3.0;  // seed eq. (9)
            g.area_m2 += area;
            g.total_mass_kg += density * area;
            // Wound like the outline: its winding is the panel's front side.
            if (work[p].area_m2 > 0.0) g.triangles.insert(g.triangles.end(), {base[p] + a, base[p] + b, base[p] + c});
            else g.triangles.insert(g.triangles.end(), {base[p] + a, base[p] + c, base[p] + b});
        }
        for (size_t k = 0; k < mesh.points.size(); ++k) {
            const Point2 q = mesh.points[k];
            Vec3 placed;
            rotate(panel.placement, q.x, q.y, &placed);
            g.positions.push_back(placed);
            g.rest_positions.push_back({float(table_x + q.x - min_x), float(q.y), 0.0f});
            g.masses.push_back(float(mass[k]));
            g.uv.insert(g.uv.end(), {float(q.x), float(q.y)});
            g.panel.push_back(uint32_t(p));
            const bool on_lattice = mesh.lattice[2 * k] != -1 || mesh.lattice[2 * k + 1] != -1;
            node_of.push_back({uint32_t(p), on_lattice ? int64_t(next_node++) : -1});
        }
        table_x += (max_x - min_x) + 0.05;
        g.edge_particles.emplace_back();
        for (size_t e = 0; e < panel.edges.size(); ++e) {
            std::vector<uint32_t> points = work[p].edge_point[e];
            for (uint32_t& v : points) v += base[p];
            g.edge_particles.back().push_back(std::move(points));
        }
        g.panel_names.push_back(panel.name);
        g.quality.panels.push_back(panel_quality(panel.name, mesh, work[p].outline, h, work[p].area_m2 > 0.0, work[p].area_m2));
    }
    base[panels] = uint32_t(g.positions.size());
    for (size_t c = 0; c < packed.size(); ++c) {
        std::vector<int32_t> lattice;
        for (const auto& [p, node] : node_of) {
            const auto [i, j] = node < 0 ? std::pair{-1, -1} : packed[c].nodes[p][size_t(node)];
            lattice.insert(lattice.end(), {i, j});
        }
        if (c == 0) g.lattice = std::move(lattice), g.lattice_plane_stride = packed[c].plane_stride;
        else g.lattice_alternatives.push_back({std::move(lattice), packed[c].plane_stride});
    }

    // Seams: the k-th points of a seam's sides are one seam point; chains through corners merge.
    UnionFind sets(g.positions.size());
    std::vector<uint8_t> sewn(g.positions.size(), 0);
    for (const Seam& seam : pattern.seams) {
        std::vector<std::vector<uint32_t>> sides;
        for (const SeamSide& s : seam.sides) {
            std::vector<uint32_t> points = g.edge_particles[s.panel][s.edge];
            if (s.reverse) std::reverse(points.begin(), points.end());
            sides.push_back(std::move(points));
        }
        for (size_t k = 0; k < sides[0].size(); ++k)
            for (size_t s = 0; s < sides.size(); ++s) {
                if (sides[s].size() != sides[0].size()) throw BakeError("a seam's sides got different counts (bug)");
                sewn[sides[s][k]] = 1;
                sets.join(sides[0][k], sides[s][k]);
            }
    }
    std::map<uint32_t, std::vector<uint32_t>> members;  // root -> particles, ordered by root
    for (uint32_t v = 0; v < g.positions.size(); ++v)
        if (sewn[v]) members[sets.find(v)].push_back(v);
    g.seam_first.push_back(0);
    for (const auto& [root, particles] : members) {
        if (particles.size() < 2) continue;  // a dart's tip is sewn to itself
        g.seam_source.insert(g.seam_source.end(), particles.begin(), particles.end());
        g.seam_first.push_back(uint32_t(g.seam_source.size()));
    }

    auto select = [&](const PanelSelector& s) {
        if (s.edge >= 0) return g.edge_particles[s.panel][size_t(s.edge)];
        uint32_t best = base[s.panel];
        double best_d = HUGE_VAL;
        for (uint32_t v = base[s.panel]; v < base[s.panel + 1]; ++v) {
            const double d = std::hypot(g.uv[2 * v] - s.point.x, g.uv[2 * v + 1] - s.point.y);
            if (d < best_d) best_d = d, best = v;
        }
        return std::vector<uint32_t>{best};
    };
    for (const PanelSelector& pin : pattern.pins)
        for (uint32_t v : select(pin)) g.pinned.push_back(v);
    std::sort(g.pinned.begin(), g.pinned.end());
    g.pinned.erase(std::unique(g.pinned.begin(), g.pinned.end()), g.pinned.end());
    for (const BodyAttachment& a : pattern.attachments) g.attachments.push_back({a.label, select(a.where)});

    // The garment's quality: the panels' figures combined.
    PanelQuality& all = g.quality.overall;
    all.name = "garment";
    all.min_angle_deg = all.min_angle_deg_smooth = 180.0;
    all.edge_min_h = HUGE_VAL;
    uint32_t triangles = 0;
    for (const PanelQuality& q : g.quality.panels) {
        all.particles += q.particles, all.triangles += q.triangles;
        all.grid_particles += q.grid_particles, all.grid_triangles += q.grid_triangles;
        all.min_angle_deg = std::min(all.min_angle_deg, q.min_angle_deg);
        all.min_angle_deg_smooth = std::min(all.min_angle_deg_smooth, q.min_angle_deg_smooth);
        all.edge_min_h = std::min(all.edge_min_h, q.edge_min_h), all.edge_max_h = std::max(all.edge_max_h, q.edge_max_h);
        all.edge_mean_h += q.edge_mean_h * q.triangles;
        triangles += q.triangles;
        all.mesh_area_m2 += q.mesh_area_m2 < 0 ? -q.mesh_area_m2 : q.mesh_area_m2;
        all.outline_area_m2 += q.outline_area_m2;
    }
    if (triangles > 0) all.edge_mean_h /= triangles;  // weighted by triangles: close to the edge mean
    g.quality.target_edge_m = h;
    return g;
}

}  // namespace

ClothMeshDesc cloth_mesh_desc(const MeshedGarment& garment) {
    ClothMeshDesc desc;
    desc.particle_count = uint32_t(garment.positions.size());
    desc.positions = garment.positions.data();
    desc.rest_positions = garment.rest_positions.data();
    desc.triangle_count = uint32_t(garment.triangles.size() / 3);
    desc.triangles = garment.triangles.data();
    desc.masses = garment.masses.data();
    desc.lattice = garment.lattice.data();
    desc.lattice_plane_stride = garment.lattice_plane_stride;
    return desc;
}

Status mesh_garment(const Pattern& pattern, const MeshOptions& options, MeshedGarment* out) {
    try {
        if (out == nullptr) return {"out is null"};
        if (Status s = validate_pattern(pattern); !s.ok()) return s;
        const double h = options.target_edge_m != 0.0 ? options.target_edge_m
                         : pattern.target_edge_m > 0.0 ? pattern.target_edge_m
                                                        : kDefaultTargetEdge_m;
        if (!(h > 0.0 && h <= 10.0)) return {"target edge length must lie in (0, 10] m, got " + std::to_string(h)};
        if (!(options.grid_clearance >= 0.5 && options.grid_clearance <= 4.0)) return {"grid_clearance must lie in [0.5, 4]"};
        if (!(options.min_angle_deg >= 0.0 && options.min_angle_deg <= 20.7))
            return {"min_angle_deg must lie in [0, 20.7] (Delaunay refinement may not terminate above)"};

        const size_t panels = pattern.panels.size();
        std::vector<PanelWork> work(panels);
        // About one particle per h^2 of area and one per h of outline (a triangle mesh of spacing h
        // has 2 / sqrt(3) particles per h^2; the strip adds a few): refuse what would exceed the cap.
        double estimate = 0.0;
        for (size_t p = 0; p < panels; ++p) {
            PanelWork& w = work[p];
            w.fine = fine_outline(pattern.panels[p]);
            w.area_m2 = signed_area(w.fine);
            for (const PatternEdge& edge : pattern.panels[p].edges) {
                w.edge_length.push_back(edge_length(pattern.panels[p], edge));
                w.particle_estimate += 2.0 * w.edge_length.back() / h;
            }
            w.particle_estimate += 1.2 * std::fabs(w.area_m2) / (h * h);
            estimate += w.particle_estimate;
        }
        if (!(estimate <= options.max_particles))
            return {"target edge " + std::to_string(h) + " m would give about " + std::to_string(estimate) +
                    " particles, more than the cap of " + std::to_string(options.max_particles)};

        // Segments per edge: ceil(length / h), the same on every side of a seam (the longest side's),
        // at equal arc length.
        std::vector<std::vector<uint32_t>> count(panels);
        for (size_t p = 0; p < panels; ++p)
            for (double length : work[p].edge_length) count[p].push_back(uint32_t(std::max(1.0, std::ceil(length / h - 1e-9))));
        SeamOf seam_of(panels);
        for (size_t p = 0; p < panels; ++p) seam_of[p].assign(pattern.panels[p].edges.size(), -1);
        for (size_t s = 0; s < pattern.seams.size(); ++s) {
            uint32_t most = 0;
            for (const SeamSide& side : pattern.seams[s].sides) {
                seam_of[side.panel][side.edge] = int32_t(s);
                most = std::max(most, count[side.panel][side.edge]);
            }
            for (const SeamSide& side : pattern.seams[s].sides) count[side.panel][side.edge] = most;
        }
        for (size_t p = 0; p < panels; ++p)
            for (uint32_t c : count[p]) work[p].cuts.push_back(uniform_cuts(c));

        StripCriteria criteria;
        criteria.min_angle_deg = options.min_angle_deg;
        // Longer than the grid's own diagonal (sqrt(2) h): a strip of squares like the grid's must not be
        // refined (the midpoint of a diagonal would encroach the outline and a grid side).
        criteria.max_edge_m = 1.5 * h;
        uint32_t round = 0;
        for (;; ++round) {
            // Before the last round, a split outline segment away from sharp corners is sampled finer
            // there; at sharp corners (at_sharp_corner) and in the last round the mesher's points stay
            // on unsewn edges and go again on sewn ones.
            const bool last = round + 1 >= options.max_rounds;
            bool again = false;
            for (size_t p = 0; p < panels; ++p) {
                PanelWork& w = work[p];
                if (!w.dirty) continue;
                w.dirty = false;
                w.outline = sample_outline(pattern.panels[p], w.cuts);
                PanelGrid& grid = w.grid;
                grid = grid_frame(w.fine, h);
                if (w.dropped.empty()) w.dropped.assign(grid.keep.size(), 0);
                choose_cells(w.outline.points, options.grid_clearance, w.dropped, grid);
                // Sewn segments at sharp corners (and every sewn segment in the last round) keep no
                // point the mesher adds: the seam's other sides would need the same points.
                const std::vector<double> corner = corner_angles(w.outline.points, w.area_m2 > 0.0);
                std::vector<uint8_t> fixed(w.outline.points.size(), 0);
                for (size_t e = 0; e < pattern.panels[p].edges.size(); ++e)
                    if (seam_of[p][e] >= 0)
                        for (uint32_t k = w.outline.edge_first[e]; k < w.outline.edge_first[e + 1]; ++k)
                            fixed[k] = last || at_sharp_corner(corner, k);
                criteria.max_points = size_t(std::min(double(options.max_particles),
                                                      kStripPointsPerEstimate * w.particle_estimate + kStripPointsSlack));
                try {
                    mesh_panel(w.outline, grid, criteria, fixed, &w.mesh);
                } catch (const StripRefinementCapped& e) {
                    throw BakeError("panel '" + pattern.panels[p].name + "': " + e.what() +
                                    closest_approach(pattern.panels[p], w.outline));
                }
                // Split outline segments: sampled there in the next round (the seam's other sides
                // too), except at sharp corners and in the last round, where the mesher's points
                // stay; split grid sides: their cells go to the strip.
                std::vector<std::pair<size_t, double>> added;  // (edge, fraction), against the cuts this mesh had
                for (const PanelMesh::OutlineSplit& split : w.mesh.split_outline) {
                    if (last || at_sharp_corner(corner, split.segment)) continue;
                    const uint32_t k = split.segment;
                    const size_t e = size_t(std::upper_bound(w.outline.edge_first.begin(), w.outline.edge_first.end(), k) -
                                            w.outline.edge_first.begin()) - 1;
                    const std::vector<double>& cuts = w.cuts[e];
                    const size_t j = k - w.outline.edge_first[e];
                    const double f = cuts[j] + split.along * (cuts[j + 1] - cuts[j]);
                    added.push_back({e, f});
                }
                for (const auto& [e, f] : added) add_cut(pattern, seam_of, p, e, f, work);
                for (uint32_t cell : w.mesh.split_cells) w.dropped[cell] = 1;
                if (!w.mesh.split_cells.empty()) w.dirty = true;
                again = again || w.dirty;
            }
            for (const PanelWork& w : work) again = again || w.dirty;
            if (!again) break;
            if (last) {
                std::string names;
                for (size_t p = 0; p < panels; ++p)
                    if (work[p].dirty) names += (names.empty() ? "\"" : ", \"") + pattern.panels[p].name + "\"";
                return {"the strip mesher still split grid sides of panel " + names + " after " +
                        std::to_string(round + 1) + " rounds"};
            }
            double particles = 0.0;
            for (const PanelWork& w : work)
                for (const std::vector<double>& c : w.cuts) particles += double(c.size() - 1);
            if (particles > options.max_particles) return {"outline sampling exceeded the particle cap while remeshing"};
        }
        finish_edges(pattern, work);
        MeshedGarment garment = assemble(pattern, options, h, work);
        garment.quality.rounds = round + 1;
        if (garment.positions.size() > options.max_particles)
            return {"the garment has " + std::to_string(garment.positions.size()) + " particles, more than the cap of " +
                    std::to_string(options.max_particles)};
        *out = std::move(garment);
        return {};
    } catch (const std::exception& e) {
        return {std::string("meshing failed: ") + e.what()};
    }
}

}  // namespace weft::bake
