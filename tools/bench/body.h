// weft-bench body: the body-collision pass on the animated shared body (tools/bench/body.cpp).
#pragma once

#include <cstdint>

namespace weft::bench {

int run_body(uint32_t frames, uint32_t point_count, float thickness_m);

}  // namespace weft::bench
