// The health pass's sums over one cloth (step.cpp: find_health; docs/architecture.md, "Health and
// recovery"), one SIMD walk over the movable particles: their box, and the sum of |x - x_prev|^2.
#pragma once

#include <algorithm>
#include <limits>

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Lanes that are summed in the order of their slots within a lane, then lane by lane: a path's
// result is the same bits on every thread count (the paths' sums may differ in the last bits).
template <class F>
void health_sums(const Particles& p, HealthSums* out) {
    using namespace simd;
    const F inf = splat(std::numeric_limits<float>::infinity(), F{}), zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    const F minus_inf = zero - inf;
    F lo[3] = {inf, inf, inf}, hi[3] = {minus_inf, minus_inf, minus_inf};
    F squared = zero, movable = zero;
    const float* const xyz[3] = {p.x, p.y, p.z};
    const float* const previous[3] = {p.previous_x, p.previous_y, p.previous_z};
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const auto moves = load(p.inverse_mass + i, F{}) > zero;
        F d2 = zero;
        for (int k = 0; k < 3; ++k) {
            const F v = load(xyz[k] + i, F{});
            const F d = v - load(previous[k] + i, F{});
            d2 = d2 + d * d;
            lo[k] = min(lo[k], select(moves, v, inf));
            hi[k] = max(hi[k], select(moves, v, minus_inf));
        }
        squared = squared + select(moves, d2, zero);
        movable = movable + select(moves, one, zero);
    }
    float l[3][F::width], h[3][F::width], s[F::width], m[F::width];
    for (int k = 0; k < 3; ++k) store(l[k], lo[k]), store(h[k], hi[k]);
    store(s, squared), store(m, movable);
    HealthSums r{{l[0][0], l[1][0], l[2][0]}, {h[0][0], h[1][0], h[2][0]}, s[0], m[0]};
    float* const box_lo[3] = {&r.lo.x, &r.lo.y, &r.lo.z};
    float* const box_hi[3] = {&r.hi.x, &r.hi.y, &r.hi.z};
    for (uint32_t j = 1; j < F::width; ++j) {
        for (int k = 0; k < 3; ++k) *box_lo[k] = std::min(*box_lo[k], l[k][j]), *box_hi[k] = std::max(*box_hi[k], h[k][j]);
        r.squared_m2 += s[j], r.movable += m[j];
    }
    *out = r;
}

}  // namespace weft
