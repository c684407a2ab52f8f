// The Verlet prediction of one lane group (integrate/verlet.h): shared by the integration pass and
// the coarse level's node prediction (constraints/coarse.h), so both give the same bits.
#pragma once

#include "simd/float_w.h"

namespace weft {

template <class F>
inline F verlet_predict(F x, F previous, F acceleration, F velocity_scale, F h2) {
    return simd::mul_add(acceleration, h2, simd::mul_add(x - previous, velocity_scale, x));
}

}  // namespace weft
