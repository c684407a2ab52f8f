// weft-bench self: self-collision's cost and what it prevents (issue 25, point 2).
#pragma once

#include <cstdint>

namespace weft::bench {

struct SelfBenchOptions {
    uint32_t frames = 300;  // steps per scene (the skirt's after the walk's 1 s ramp)
    bool json = false;
    float thickness_m = 0.004f;  // ClothDesc::self_thickness_m of the worlds with self-collision
    float friction = 0.2f;       // ClothDesc::self_friction
};

// Per scene (the seed's 100 x 100 drape, a 50 x 50 sheet dropped in a heap on the ground, the
// sample skirt on the walking mannequin) two worlds stepped in turn, without and with
// ClothDesc::self_collision: the median step and the frames in which the cloth passes through
// itself (metrics::self_crossings). Returns the process exit code.
int run_self(const SelfBenchOptions& options);

}  // namespace weft::bench
