// Panel meshing: the grid (no CGAL) and the strip around it (CGAL's constrained Delaunay
// triangulation and Delaunay mesher). See mesh_panel.h.
#include "bake/mesh_panel.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "bake/outline.h"

namespace weft::bake {

namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;
// A grid side is split by the mesher when an outline point lies inside its diametral circle
// (radius h / 2 around its midpoint); 0.55 h keeps every outline point out of it with a margin.
constexpr double kSideMidpointClearance = 0.55;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo {
    uint32_t id = kNone;  // < outline size: outline point; else outline size + grid node; kNone: added by the mesher
};
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using SizeCriteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;

// CGAL's angle and size criteria with a cap on the points: past max_points no face is bad any
// more, so the refinement drains its queue and ends. Curves that nearly touch (a pattern the
// fuzzer made) otherwise refine into hundreds of thousands of points; the panel is then refused.
class CappedCriteria : public SizeCriteria {
public:
    CappedCriteria(double squared_min_sine, double max_edge, const Cdt& cdt, size_t max_points)
        : SizeCriteria(squared_min_sine, max_edge), cdt_(&cdt), max_points_(max_points) {}

    class Is_bad : public SizeCriteria::Is_bad {
    public:
        Is_bad(const SizeCriteria::Is_bad& size, const Cdt* cdt, size_t max_points)
            : SizeCriteria::Is_bad(size), cdt_(cdt), max_points_(max_points) {}
        CGAL::Mesh_2::Face_badness operator()(const Quality q) const {
            return capped() ? CGAL::Mesh_2::NOT_BAD : SizeCriteria::Is_bad::operator()(q);
        }
        CGAL::Mesh_2::Face_badness operator()(const Cdt::Face_handle& f, Quality& q) const {
            return capped() ? CGAL::Mesh_2::NOT_BAD : SizeCriteria::Is_bad::operator()(f, q);
        }

    private:
        bool capped() const { return cdt_->number_of_vertices() > max_points_; }
        const Cdt* cdt_;
        size_t max_points_;
    };
    Is_bad is_bad_object() const { return Is_bad(SizeCriteria::is_bad_object(), cdt_, max_points_); }

private:
    const Cdt* cdt_;
    size_t max_points_;
};
using Mesher = CGAL::Delaunay_mesher_2<Cdt, CappedCriteria>;

// The inside intervals of the outline along one horizontal line: sorted crossing abscissae.
std::vector<double> crossings(const std::vector<Point2>& polygon, double y) {
    std::vector<double> xs;
    for (size_t k = 0, n = polygon.size(), j = n - 1; k < n; j = k++) {
        const Point2 a = polygon[k], b = polygon[j];
        if ((a.y > y) != (b.y > y)) xs.push_back(a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y));
    }
    std::sort(xs.begin(), xs.end());
    return xs;
}

bool inside(const std::vector<double>& xs, double x) {
    return (std::lower_bound(xs.begin(), xs.end(), x) - xs.begin()) % 2 == 1;
}

}  // namespace

uint32_t PanelGrid::kept_cells() const { return uint32_t(std::count(keep.begin(), keep.end(), uint8_t(1))); }

PanelGrid grid_frame(const std::vector<Point2>& fine_outline, double h) {
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    for (const Point2& p : fine_outline) x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    PanelGrid grid;
    grid.h = h;
    grid.cols = uint32_t(std::floor((x1 - x0) / h));
    grid.rows = uint32_t(std::floor((y1 - y0) / h));
    grid.origin = {x0 + 0.5 * ((x1 - x0) - grid.cols * h), y0 + 0.5 * ((y1 - y0) - grid.rows * h)};
    grid.keep.assign(size_t(grid.rows) * grid.cols, 0);
    return grid;
}

void choose_cells(const std::vector<Point2>& outline, double clearance, const std::vector<uint8_t>& dropped,
                  PanelGrid& grid) {
    const double h = grid.h;
    const SegmentIndex index(outline, h);
    const uint32_t node_cols = grid.cols + 1;
    auto node_point = [&](uint32_t r, uint32_t c) { return Point2{grid.origin.x + c * h, grid.origin.y + r * h}; };
    // Good nodes: inside, and far enough from the outline.
    std::vector<uint8_t> good(size_t(grid.rows + 1) * node_cols, 0);
    for (uint32_t r = 0; r <= grid.rows; ++r) {
        const std::vector<double> xs = crossings(outline, node_point(r, 0).y);
        for (uint32_t c = 0; c <= grid.cols; ++c) {
            const Point2 p = node_point(r, c);
            good[size_t(r) * node_cols + c] = inside(xs, p.x) && index.distance(p, clearance * h) >= clearance * h;
        }
    }
    auto far = [&](Point2 p) { return index.distance(p, h) > kSideMidpointClearance * h; };
    for (uint32_t r = 0; r < grid.rows; ++r)
        for (uint32_t c = 0; c < grid.cols; ++c) {
            const size_t cell = size_t(r) * grid.cols + c;
            const Point2 p = node_point(r, c);
            grid.keep[cell] = (dropped.empty() || !dropped[cell]) && good[size_t(r) * node_cols + c] &&
                              good[size_t(r) * node_cols + c + 1] && good[size_t(r + 1) * node_cols + c] &&
                              good[size_t(r + 1) * node_cols + c + 1] && far({p.x + 0.5 * h, p.y}) &&
                              far({p.x, p.y + 0.5 * h}) && far({p.x + h, p.y + 0.5 * h}) && far({p.x + 0.5 * h, p.y + h});
        }
}

void mesh_panel(const PanelOutline& outline, const PanelGrid& grid, const StripCriteria& criteria,
                const std::vector<uint8_t>& fixed_segments, PanelMesh* out) {
    const uint32_t n_outline = uint32_t(outline.points.size());
    const uint32_t node_cols = grid.cols + 1;
    auto kept = [&](int64_t r, int64_t c) {
        return r >= 0 && c >= 0 && r < grid.rows && c < grid.cols && grid.keep[size_t(r) * grid.cols + c];
    };
    auto node_point = [&](uint32_t node) {
        return Point2{grid.origin.x + (node % node_cols) * grid.h, grid.origin.y + (node / node_cols) * grid.h};
    };

    // The strip's constraints: the outline, and every side between a kept and a dropped cell.
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> outline_vertex(n_outline);
    for (uint32_t k = 0; k < n_outline; ++k) {
        outline_vertex[k] = cdt.insert(Kernel::Point_2(outline.points[k].x, outline.points[k].y));
        outline_vertex[k]->info().id = k;
    }
    for (uint32_t k = 0; k < n_outline; ++k) cdt.insert_constraint(outline_vertex[k], outline_vertex[(k + 1) % n_outline]);

    std::vector<Cdt::Vertex_handle> node_vertex(size_t(grid.rows + 1) * node_cols);
    auto grid_vertex = [&](uint32_t node) {
        if (node_vertex[node] == Cdt::Vertex_handle()) {
            const Point2 p = node_point(node);
            node_vertex[node] = cdt.insert(Kernel::Point_2(p.x, p.y));
            node_vertex[node]->info().id = n_outline + node;
        }
        return node_vertex[node];
    };
    std::vector<Kernel::Point_2> seeds;  // one per connected piece of the grid: the holes of the strip
    std::vector<uint8_t> seeded(grid.keep.size(), 0);
    for (uint32_t r = 0; r < grid.rows; ++r)
        for (uint32_t c = 0; c < grid.cols; ++c) {
            if (!kept(r, c)) continue;
            const uint32_t n00 = r * node_cols + c, n01 = n00 + 1, n10 = n00 + node_cols, n11 = n10 + 1;
            // One statement per vertex: grid_vertex inserts into the triangulation, and the order
            // in which a call's arguments are evaluated is unspecified (GCC: last first, Clang:
            // first first); the insertion order changes the mesh, so the baker wrote other bytes
            // when built by the other compiler. b before a: the order GCC took, its meshes unchanged.
            auto constrain = [&](uint32_t a, uint32_t b) {
                const Cdt::Vertex_handle vb = grid_vertex(b);
                const Cdt::Vertex_handle va = grid_vertex(a);
                cdt.insert_constraint(va, vb);
            };
            if (!kept(r - 1, c)) constrain(n00, n01);
            if (!kept(r + 1, c)) constrain(n10, n11);
            if (!kept(r, int64_t(c) - 1)) constrain(n00, n10);
            if (!kept(r, c + 1)) constrain(n01, n11);
            if (seeded[size_t(r) * grid.cols + c]) continue;
            // A new piece: flood it (4-neighbours share an unconstrained side) and seed its first cell.
            const Point2 centre = node_point(n00);
            seeds.emplace_back(centre.x + 0.5 * grid.h, centre.y + 0.5 * grid.h);
            std::vector<uint32_t> stack{r * grid.cols + c};
            seeded[stack.back()] = 1;
            while (!stack.empty()) {
                const uint32_t cell = stack.back();
                stack.pop_back();
                const int64_t cr = cell / grid.cols, cc = cell % grid.cols;
                for (auto [dr, dc] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
                    if (kept(cr + dr, cc + dc) && !seeded[size_t(cr + dr) * grid.cols + size_t(cc + dc)]) {
                        seeded[size_t(cr + dr) * grid.cols + size_t(cc + dc)] = 1;
                        stack.push_back(uint32_t((cr + dr) * grid.cols + cc + dc));
                    }
            }
        }

    // Refine the strip only (seeds mark the grid as outside the domain; CGAL also leaves out every
    // face reachable from infinity without crossing a constraint: the outside of the outline).
    // The first criterion is sin^2 of the minimum angle (docs: dependencies.md).
    const double sin_min = std::sin(criteria.min_angle_deg * std::numbers::pi / 180.0);
    Mesher mesher(cdt, CappedCriteria(sin_min * sin_min, criteria.max_edge_m, cdt, criteria.max_points));
    mesher.set_seeds(seeds.begin(), seeds.end(), false);
    mesher.refine_mesh();
    if (cdt.number_of_vertices() > criteria.max_points)
        throw StripRefinementCapped("the strip mesher passed " + std::to_string(criteria.max_points) +
                                    " points without meeting its angle bound: the outline's curves nearly touch");

    // Constraints the mesher split: walk along the constraint from each added vertex to the
    // original points at both ends.
    out->split_outline.clear();
    out->split_cells.clear();
    out->points.clear();
    out->lattice.clear();
    out->triangles.clear();
    auto constrained_neighbours = [&](Cdt::Vertex_handle v) {
        std::vector<Cdt::Vertex_handle> result;
        Cdt::Edge_circulator e = cdt.incident_edges(v), end = e;
        if (e != nullptr) do {
                if (!cdt.is_infinite(*e) && cdt.is_constrained(*e)) {
                    const Cdt::Face_handle f = e->first;
                    const Cdt::Vertex_handle a = f->vertex(Cdt::cw(e->second)), b = f->vertex(Cdt::ccw(e->second));
                    result.push_back(a == v ? b : a);
                }
            } while (++e != end);
        return result;
    };
    auto walk_to_original = [&](Cdt::Vertex_handle from, Cdt::Vertex_handle next) {
        for (size_t guard = 0; next->info().id == kNone && guard < cdt.number_of_vertices(); ++guard) {
            const std::vector<Cdt::Vertex_handle> around = constrained_neighbours(next);
            if (around.size() != 2) break;
            const Cdt::Vertex_handle step = around[0] == from ? around[1] : around[0];
            from = next, next = step;
        }
        return next->info().id;
    };
    std::vector<Cdt::Vertex_handle> added;       // the mesher's points inside the strip
    std::vector<Cdt::Vertex_handle> on_outline;  // its points on the outline, as split_outline
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
        if (v->info().id != kNone) continue;
        const std::vector<Cdt::Vertex_handle> around = constrained_neighbours(v);
        if (around.size() < 2) {
            added.push_back(v);
            continue;
        }
        const uint32_t a = walk_to_original(v, around[0]), b = walk_to_original(v, around[1]);
        if (a == kNone || b == kNone) throw std::runtime_error("mesh_panel: a split constraint has no original ends");
        if (a < n_outline && b < n_outline) {
            const uint32_t k = (a + 1) % n_outline == b ? a : b;
            const Point2 p0 = outline.points[k], p1 = outline.points[(k + 1) % n_outline];
            const double dx = p1.x - p0.x, dy = p1.y - p0.y;
            const double along = ((v->point().x() - p0.x) * dx + (v->point().y() - p0.y) * dy) / (dx * dx + dy * dy);
            out->split_outline.push_back({k, std::clamp(along, 0.0, 1.0), 0});
            on_outline.push_back(v);
        } else if (a >= n_outline && b >= n_outline) {
            const uint32_t na = a - n_outline, nb = b - n_outline, lo = std::min(na, nb), hi = std::max(na, nb);
            const int64_t r = lo / node_cols, c = lo % node_cols;
            // The side lo -> hi is horizontal (hi = lo + 1) or vertical (hi = lo + node_cols); the
            // kept cell is the one on either side of it.
            const bool horizontal = hi == lo + 1;
            const int64_t r2 = horizontal ? r - 1 : r, c2 = horizontal ? c : c - 1;
            if (kept(r, c)) out->split_cells.push_back(uint32_t(r * grid.cols + c));
            if (kept(r2, c2)) out->split_cells.push_back(uint32_t(r2 * grid.cols + c2));
        } else {
            throw std::runtime_error("mesh_panel: a constraint joins the outline to the grid");
        }
    }
    auto unique = [](std::vector<uint32_t>& v) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
    };
    unique(out->split_cells);
    if (!out->split_cells.empty()) return;
    // The mesher's points on fixed segments go again (the triangulation around them is redone,
    // without refinement), as GarmentCode's own mesher does with every point it adds to an outline.
    std::vector<uint32_t> restored;  // segments whose points are all gone, constrained again after
    for (size_t k = 0; k < on_outline.size(); ++k) {
        if (fixed_segments.empty() || !fixed_segments[out->split_outline[k].segment]) continue;
        cdt.remove_incident_constraints(on_outline[k]);
        cdt.remove(on_outline[k]);
        restored.push_back(out->split_outline[k].segment);
        on_outline[k] = Cdt::Vertex_handle();
    }
    for (uint32_t a : restored) cdt.insert_constraint(outline_vertex[a], outline_vertex[(a + 1) % n_outline]);
    // The mesher's inner points inside a restored segment's diametral circle would leave slivers on it.
    for (uint32_t a : restored) {
        const Point2 p0 = outline.points[a], p1 = outline.points[(a + 1) % n_outline];
        const double mx = 0.5 * (p0.x + p1.x), my = 0.5 * (p0.y + p1.y);
        const double r2 = 0.25 * ((p1.x - p0.x) * (p1.x - p0.x) + (p1.y - p0.y) * (p1.y - p0.y));
        for (Cdt::Vertex_handle& v : added)
            if (v != Cdt::Vertex_handle() &&
                (v->point().x() - mx) * (v->point().x() - mx) + (v->point().y() - my) * (v->point().y() - my) < r2) {
                cdt.remove(v);
                v = Cdt::Vertex_handle();
            }
    }
    added.erase(std::remove(added.begin(), added.end(), Cdt::Vertex_handle()), added.end());
    if (!restored.empty()) {
        mesher.mark_facets();
        size_t kept = 0;
        for (size_t k = 0; k < on_outline.size(); ++k)
            if (on_outline[k] != Cdt::Vertex_handle()) on_outline[kept] = on_outline[k], out->split_outline[kept++] = out->split_outline[k];
        on_outline.resize(kept);
        out->split_outline.resize(kept);
    }
    // Points on the outline join the mesh after the mesher's inner points, ordered along the outline.
    std::vector<uint32_t> order(out->split_outline.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return out->split_outline[a] < out->split_outline[b]; });
    std::vector<PanelMesh::OutlineSplit> splits;
    for (uint32_t k : order) {
        splits.push_back(out->split_outline[k]);
        added.push_back(on_outline[k]);
    }
    out->split_outline = std::move(splits);

    // The mesh: outline points, grid nodes (row-major), the mesher's points; strip and grid triangles.
    out->points = outline.points;
    out->lattice.assign(2 * size_t(n_outline), -1);
    out->triangles.clear();
    std::vector<uint32_t> index_of_node(node_vertex.size(), kNone);
    for (uint32_t r = 0; r <= grid.rows; ++r)
        for (uint32_t c = 0; c <= grid.cols; ++c)
            if (kept(r, c) || kept(int64_t(r) - 1, c) || kept(r, int64_t(c) - 1) || kept(int64_t(r) - 1, int64_t(c) - 1)) {
                index_of_node[size_t(r) * node_cols + c] = uint32_t(out->points.size());
                out->points.push_back(node_point(r * node_cols + c));
                out->lattice.insert(out->lattice.end(), {int32_t(r), int32_t(c)});
            }
    out->grid_points = uint32_t(out->points.size()) - n_outline;
    // Ids past the grid's nodes number the mesher's points, in the order they are appended.
    const uint32_t first_added_id = n_outline + uint32_t(node_vertex.size()), first_added = uint32_t(out->points.size());
    const uint32_t first_on_outline = first_added + uint32_t(added.size() - out->split_outline.size());
    for (size_t k = 0; k < out->split_outline.size(); ++k) out->split_outline[k].point = first_on_outline + uint32_t(k);
    for (size_t k = 0; k < added.size(); ++k) {
        added[k]->info().id = first_added_id + uint32_t(k);
        out->points.push_back({added[k]->point().x(), added[k]->point().y()});
        out->lattice.insert(out->lattice.end(), {-1, -1});
    }
    auto index_of = [&](Cdt::Vertex_handle v) {
        const uint32_t id = v->info().id;
        if (id < n_outline) return id;
        if (id < first_added_id) return index_of_node[id - n_outline];
        return first_added + (id - first_added_id);
    };
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) continue;
        out->triangles.insert(out->triangles.end(), {index_of(f->vertex(0)), index_of(f->vertex(1)), index_of(f->vertex(2))});
    }
    const uint32_t strip_triangles = uint32_t(out->triangles.size() / 3);
    for (uint32_t r = 0; r < grid.rows; ++r)
        for (uint32_t c = 0; c < grid.cols; ++c) {
            if (!kept(r, c)) continue;
            const uint32_t n00 = r * node_cols + c;
            const uint32_t a = index_of_node[n00], b = index_of_node[n00 + 1], d = index_of_node[n00 + node_cols],
                           e = index_of_node[n00 + node_cols + 1];
            // One diagonal everywhere (a to e), counter-clockwise.
            out->triangles.insert(out->triangles.end(), {a, b, e, a, e, d});
        }
    out->grid_triangles = uint32_t(out->triangles.size() / 3) - strip_triangles;
    for (uint32_t v : out->triangles)
        if (v >= out->points.size()) throw std::runtime_error("mesh_panel: a triangle lost a vertex");
}

}  // namespace weft::bake
