// The order the per-triangle passes (wind, vertex normals) walk a cloth's triangles in: the triangle
// runs F::width at a time (corners at slots a0 + k, b0 + k, c0 + k: plain vector loads), then the
// rest F::width at a time with gathered corners, then the last few one at a time. Every path adds
// its triangles' results to their vertices in this order, so scalar and SIMD sums are the same bits.
#pragma once

#include <cstdint>

#include "weft/cloth_asset.h"

namespace weft {

// run(corner, lane): one run group, corner k of lane l at slot corner[k] + l, its weights and rest
// areas at `lane` of the wind lane arrays. gathered(t): triangles t .. t + F::width - 1 of
// `triangles`. single(corner, t): triangle t alone.
template <class F, class Run, class Gathered, class Single>
inline void for_each_triangle_group(const ClothAsset& a, Run&& run, Gathered&& gathered, Single&& single) {
    for (uint32_t r = 0; r < a.wind_run_count; ++r) {
        const TriangleRun& tr = a.wind_runs[r];
        for (uint32_t k = 0; k < tr.lane_count; k += F::width) {
            const uint32_t corner[3] = {tr.a0 + k, tr.b0 + k, tr.c0 + k};
            run(corner, tr.first_lane + k);
        }
    }
    uint32_t t = a.wind_run_triangles;
    if constexpr (F::width > 1)
        for (; t + F::width <= a.triangle_count; t += F::width) gathered(t);
    for (; t < a.triangle_count; ++t) {
        const uint32_t corner[3] = {a.triangles[3 * t], a.triangles[3 * t + 1], a.triangles[3 * t + 2]};
        single(corner, t);
    }
}

}  // namespace weft
