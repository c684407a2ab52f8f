// weft-bench body: the body-collision pass on the animated shared body (tools/bench/body.cpp).
#pragma once

#include <cstdint>

namespace weft::bench {

struct BodyBenchOptions {
    uint32_t frames = 60, points = 10000;
    float thickness_m = 0.005f;
    float fall_m_s2 = 0.0f;      // gravity on the points: > 5.4 m/s^2 moves every point past 5 mm a step (rays)
    bool random_order = false;   // points in random order instead of neighbours next to each other
    bool scalar = false;         // the scalar path instead of AVX2
    bool json = false;           // one JSON object instead of the table
    // Weft's world collides with the body's triangles simplified by meshoptimizer to this share
    // (0: the full body), its hull pushed out by meshoptimizer's error bound on top of the thickness.
    float simplify = 0.0f;
};
int run_body(const BodyBenchOptions& options);

}  // namespace weft::bench
