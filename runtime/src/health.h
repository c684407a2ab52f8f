// The health pass's sums over one cloth (step.cpp: find_health; docs/architecture.md, "Health and
// recovery"), one SIMD walk over the movable particles: their box, and the sum of |x - x_prev|^2.
#pragma once

#include <algorithm>
#include <limits>

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Summed in kSimdWidth lanes on every path (the scalar path keeps one accumulator per lane, slot i
// in lane i % kSimdWidth), the lanes then in order: the scalar and SIMD paths give the same bits,
// so both flag (and recover) the same cloths.
template <class F>
void health_sums(const Particles& p, HealthSums* out) {
    using namespace simd;
    constexpr uint32_t W = F::width, G = kSimdWidth / W;  // G accumulators of W lanes
    static_assert(kSimdWidth % W == 0);
    const F inf = splat(std::numeric_limits<float>::infinity(), F{}), zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    const F minus_inf = zero - inf;
    F lo[G][3], hi[G][3], squared[G], movable[G];
    for (uint32_t g = 0; g < G; ++g) {
        for (int k = 0; k < 3; ++k) lo[g][k] = inf, hi[g][k] = minus_inf;
        squared[g] = zero, movable[g] = zero;
    }
    const float* const xyz[3] = {p.x, p.y, p.z};
    const float* const previous[3] = {p.previous_x, p.previous_y, p.previous_z};
    for (uint32_t i = 0; i < p.slot_count; i += kSimdWidth)  // slot_count is a multiple of kSimdWidth
        for (uint32_t g = 0; g < G; ++g) {
            const uint32_t at = i + g * W;
            const auto moves = load(p.inverse_mass + at, F{}) > zero;
            F d2 = zero;
            for (int k = 0; k < 3; ++k) {
                const F v = load(xyz[k] + at, F{});
                const F d = v - load(previous[k] + at, F{});
                d2 = d2 + d * d;
                lo[g][k] = min(lo[g][k], select(moves, v, inf));
                hi[g][k] = max(hi[g][k], select(moves, v, minus_inf));
            }
            squared[g] = squared[g] + select(moves, d2, zero);
            movable[g] = movable[g] + select(moves, one, zero);
        }
    float l[3][kSimdWidth], h[3][kSimdWidth], s[kSimdWidth], m[kSimdWidth];
    for (uint32_t g = 0; g < G; ++g) {
        for (int k = 0; k < 3; ++k) store(l[k] + g * W, lo[g][k]), store(h[k] + g * W, hi[g][k]);
        store(s + g * W, squared[g]), store(m + g * W, movable[g]);
    }
    HealthSums r{{l[0][0], l[1][0], l[2][0]}, {h[0][0], h[1][0], h[2][0]}, s[0], m[0]};
    float* const box_lo[3] = {&r.lo.x, &r.lo.y, &r.lo.z};
    float* const box_hi[3] = {&r.hi.x, &r.hi.y, &r.hi.z};
    for (uint32_t j = 1; j < kSimdWidth; ++j) {
        for (int k = 0; k < 3; ++k) *box_lo[k] = std::min(*box_lo[k], l[k][j]), *box_hi[k] = std::max(*box_hi[k], h[k][j]);
        r.squared_m2 += s[j], r.movable += m[j];
    }
    *out = r;
}

}  // namespace weft
