// Meshing one flat panel (seed section 4.1.1, with a regular interior):
//   - the outline, sampled by the caller (equal arc length per edge, equal counts along seams)
//   - a regular grid of spacing h inside it: cells whose corners keep a clearance from the
//     outline, two triangles each with one diagonal direction, left intact so that the runtime can
//     put every grid spring family on contiguous SIMD runs (docs/architecture.md)
//   - the strip between the grid and the outline: CGAL constrained Delaunay triangulation, refined
//     by CGAL's Delaunay mesher to a minimum angle, with the grid as a hole
// mesh_panel.cpp is the only translation unit that includes CGAL (it is slow to compile).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "bake/pattern.h"

namespace weft::bake {

// A panel's sampled outline: a closed polygon (first point not repeated), in loop order.
struct PanelOutline {
    std::vector<Point2> points;
    std::vector<uint32_t> edge_first;  // edge e's points start at edge_first[e]; size = edges + 1, last = points.size()
};

// The grid of one panel: nodes at origin + (col * h, row * h); cell (row, col) has its lower-left
// corner at node (row, col).
struct PanelGrid {
    Point2 origin;
    double h = 0.0;
    uint32_t rows = 0, cols = 0;  // cells
    std::vector<uint8_t> keep;    // [rows * cols] 1 = the cell is meshed as two grid triangles
    uint32_t kept_cells() const;
};

// The grid over a panel's bounding box (fine outline) at spacing h, centred so that the margins
// left and right (and top and bottom) are equal. No cell is kept yet.
PanelGrid grid_frame(const std::vector<Point2>& fine_outline, double h);

// Keeps the cells whose four corners lie inside the outline at least `clearance * h` from it and
// whose side midpoints lie more than 0.55 h from it (the outline then never encroaches a grid side,
// which the mesher would split), except cells in `dropped` (same size as keep, may be empty).
void choose_cells(const std::vector<Point2>& outline, double clearance, const std::vector<uint8_t>& dropped,
                  PanelGrid& grid);

struct PanelMesh {
    std::vector<Point2> points;       // the outline's points first (same indices), then the rest
    std::vector<int32_t> lattice;     // 2 per point: (row, col) of a grid node, (-1, -1) otherwise
    std::vector<uint32_t> triangles;  // 3 per triangle, counter-clockwise in the panel frame
    uint32_t grid_points = 0, grid_triangles = 0;
    // Constraints the mesher split. A split grid side leaves no mesh (points and triangles are
    // empty): the caller drops those cells and meshes again. Points the mesher put on the outline
    // are in the mesh (after its inner points); the caller keeps them or samples the outline there
    // and meshes again.
    struct OutlineSplit {
        uint32_t segment;    // outline segment k (points k -> k + 1)
        double along;        // where the mesher put its point: fraction of the segment from point k, in (0, 1)
        uint32_t point;      // the point's index in `points` (when there is a mesh)
        bool operator<(const OutlineSplit& o) const { return segment != o.segment ? segment < o.segment : along < o.along; }
    };
    std::vector<OutlineSplit> split_outline;  // ordered by segment, then along
    std::vector<uint32_t> split_cells;        // row * cols + col
};

struct StripCriteria {
    double min_angle_deg = 20.0;
    double max_edge_m = 0.0;  // longest edge the mesher leaves in the strip
    size_t max_points = SIZE_MAX;  // past this many points the refinement stops and mesh_panel throws
};

// Thrown when the strip's refinement passes StripCriteria::max_points.
struct StripRefinementCapped : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Meshes the strip and joins it to the grid. Points the mesher put on an outline segment k with
// fixed_segments[k] != 0 are taken out again (the segment stays whole; the triangles around it are
// redone without refinement); fixed_segments may be empty (none fixed). Throws
// StripRefinementCapped past criteria.max_points, std::runtime_error if CGAL fails.
void mesh_panel(const PanelOutline& outline, const PanelGrid& grid, const StripCriteria& criteria,
                const std::vector<uint8_t>& fixed_segments, PanelMesh* out);

}  // namespace weft::bake
