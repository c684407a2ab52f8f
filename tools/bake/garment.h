// A sewing pattern meshed into one garment: the front half of weft-bake.
//
//   Pattern (pattern.h) --mesh_garment--> MeshedGarment --cloth_mesh_desc--> weft::cook_cloth
//
// Per panel the outline is sampled at equal arc length, every seam's edges with the same count
// (seed 4.1.1-4.1.2), the interior is a regular grid and the strip around it a CGAL mesh
// (mesh_panel.h). The panels' grids share one lattice coordinate space so that the runtime's
// parity planes hold all of them (cook/cook.cpp, assign_slots).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bake/pattern.h"
#include "weft/cloth_asset.h"
#include "weft/cook.h"

namespace weft::bake {

// Default target edge length. 2 cm gives a T-shirt about 2 000 particles and a dress about
// 3 500: the seed's real-time range (10 000 particles at 20 fps on a 2008 PC), and fine enough
// for the patterns' smallest features (darts about 3 cm wide, necklines of 8 cm radius).
inline constexpr double kDefaultTargetEdge_m = 0.02;

struct MeshOptions {
    double target_edge_m = 0.0;  // h; 0: the pattern's target_edge_m, or kDefaultTargetEdge_m
    // Grid cells keep their corners at least this many h inside the outline. 0.6 measured best:
    // smaller leaves slivers between grid and outline that the mesher refines (and splits grid
    // sides); larger widens the strip, whose springs are not on SIMD runs (docs/pattern-format.md).
    double grid_clearance = 0.6;
    double min_angle_deg = 20.0;  // the strip mesher's bound (Delaunay refinement terminates up to 20.7)
    uint32_t max_particles = 2'000'000;  // refuse patterns that would mesh into more
    uint32_t max_rounds = 16;            // remeshing rounds after the mesher split a constraint
    // Lattice packings kept (the best by the packer's estimate first): bake_pattern cooks each and
    // keeps the fastest by run_cost_ns, since the estimate misjudges some garments.
    uint32_t lattice_candidates = 4;
};

struct PanelQuality {
    std::string name;
    uint32_t particles = 0, triangles = 0, grid_particles = 0, grid_triangles = 0;
    double min_angle_deg = 0.0;           // over all triangles
    double min_angle_deg_smooth = 0.0;    // over triangles not touching a sharp outline corner
    double edge_min_h = 0.0, edge_mean_h = 0.0, edge_max_h = 0.0;  // edge lengths / h
    double mesh_area_m2 = 0.0;     // sum of the triangles
    double outline_area_m2 = 0.0;  // the exact curved outline (fine polygon)
};

struct Quality {
    double target_edge_m = 0.0;
    uint32_t rounds = 0;  // meshing rounds (1 = the mesher split nothing)
    std::vector<PanelQuality> panels;
    PanelQuality overall;  // name "garment"
};

// An outline corner is "sharp" below this interior angle: Delaunay refinement cannot promise the
// minimum angle next to input angles under 60 degrees (Shewchuk), and CGAL does not try.
inline constexpr double kSharpCornerDeg = 60.0;

struct Attachment {
    std::string label;
    std::vector<uint32_t> particles;
};

struct MeshedGarment {
    std::vector<Vec3> positions;       // placed in 3-D (panel placement), metres
    std::vector<Vec3> rest_positions;  // flat: each panel's 2-D frame side by side along x, z = 0
    std::vector<float> masses;         // kg, seed eq. (9): rho * sum of adjacent triangle areas / 3
    std::vector<int32_t> lattice;      // 2 per particle: (i, j) for grid particles, (-1, -1) otherwise
    uint32_t lattice_plane_stride = 0; // ClothMeshDesc::lattice_plane_stride the panels were packed for
    struct Lattice {
        std::vector<int32_t> lattice;
        uint32_t plane_stride = 0;
    };
    std::vector<Lattice> lattice_alternatives;  // other packings (MeshOptions::lattice_candidates)
    std::vector<float> uv;             // 2 per particle: the panel's own 2-D coordinates, metres
    std::vector<uint32_t> panel;       // panel index per particle
    std::vector<uint32_t> triangles;   // 3 per triangle, wound like the panel outline (front side)
    // Seam points (seed 4.2, eq. 10), CSR: point s joins particles seam_source[seam_first[s] ..
    // seam_first[s + 1]] (2 on a plain seam, 3 or 4 where seams meet; chains merged).
    std::vector<uint32_t> seam_first, seam_source;
    std::vector<uint32_t> pinned;      // particles the pattern pins (their masses are kept)
    std::vector<Attachment> attachments;
    // Per panel edge, its particles from start to end (outline points, both corners included).
    std::vector<std::vector<std::vector<uint32_t>>> edge_particles;
    Fabric fabric;
    std::vector<std::string> panel_names;
    Quality quality;
    double area_m2 = 0.0, total_mass_kg = 0.0;
};

// Meshes and assembles a validated pattern. Never throws; on failure *out is unchanged.
Status mesh_garment(const Pattern& pattern, const MeshOptions& options, MeshedGarment* out);

// The garment as cook_cloth's input (pointers into `garment`; nothing is pinned: the caller sets
// the masses of garment.pinned to 0 in a copy if the pins should hold).
ClothMeshDesc cloth_mesh_desc(const MeshedGarment& garment);

}  // namespace weft::bake
