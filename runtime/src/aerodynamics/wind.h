// Stage 1 of the seed's step (section 2.3), the fluid part of F_external (eq. 4): wind drag and
// lift per triangle (seed section 1.2, eq. 2 and 3), spread to the triangle's vertices as
// accelerations. Runs only in worlds created with the wind feature.
#pragma once

#include "kernels.h"

namespace weft {

struct WindArgs {
    Vec3 wind_m_s;              // u, the air's velocity
    float air_density_kg_m3;    // rho
    float drag_coefficient;     // C_D
    float lift_coefficient;     // C_L
    float previous_substep_s;   // velocity is estimated as (x - x_prev) / this (0: at rest)
    float substep_s;            // the substep the force will act over
};

// Fills p.wind_{x,y,z} for every slot (zero where no triangle pushes).
void apply_wind(const Particles& p, const ClothAsset& asset, const WindArgs& args);

}  // namespace weft
