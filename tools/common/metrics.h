// Measurements of a cloth's state that tests and benchmarks share. Defined in docs/accuracy.md.
#pragma once

#include "weft/weft.h"

namespace weft::metrics {

struct Strain {
    double mean = 0.0;  // mean |l / l0 - 1| over stretch and shear springs
    double max = 0.0;
};
Strain stretch_strain(const ClothView& cloth);

// Mean particle speed over the last substep, m/s (real, free particles only).
double mean_speed(const ClothView& cloth);

struct Bounds {
    Vec3 min{}, max{};
    bool finite = true;
};
Bounds bounds(const ClothView& cloth);

// Largest distance of a tethered particle beyond its tether length, as a fraction of that length.
double max_tether_excess(const ClothView& cloth);

// Deepest a particle lies inside any collider's collision surface (the shape grown by its
// inflation: the surface the solver enforces), metres; 0 when none is inside.
double max_penetration_m(const ClothView& cloth, const ColliderDesc* colliders, uint32_t count);

// Position of the real particle with this caller index.
Vec3 particle_position(const ClothView& cloth, uint32_t particle);

}  // namespace weft::metrics
