// The coarse level of a cooked cloth (see cook/coarse.cpp and ClothAsset::coarse_*).
#pragma once

#include <array>
#include <vector>

#include "weft/cook.h"

namespace weft {

// Where cook_cloth put lattice particles: plane (i & 1, j & 1), row i >> 1, column j >> 1 of the
// lattice coordinates shifted to an even origin. `full`: every particle sits on the lattice and
// every point of its bounding rectangle holds one (the lattice form of the coarse level needs it).
struct LatticeLayout {
    uint32_t plane_rows = 0, plane_cols = 0;  // 0: no lattice
    uint32_t fine_rows = 0, fine_cols = 0;
    bool full = false;
    uint32_t slot(uint32_t i, uint32_t j) const {
        return ((i & 1) * 2 + (j & 1)) * plane_rows * plane_cols + (i >> 1) * plane_cols + (j >> 1);
    }
};

// Fills out.coarse_* for nodes options.coarse_spacing_m apart (the per-slot weight arrays always,
// sized to out.particle_of_slot). `mass` and `inverse_mass` are per caller particle; slots must
// already be assigned.
void build_coarse_level(const ClothMeshDesc& mesh, const LatticeLayout& layout, const std::vector<float>& mass,
                        const std::vector<float>& inverse_mass, const CookOptions& options, CookedCloth& out);

}  // namespace weft
