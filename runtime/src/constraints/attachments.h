// Body attachments (weft/attachments.h): attached particles placed on their body triangle's offset
// hull at their barycentric weights, the hull interpolated between the previous step's pose and
// this step's (`t` = how far this substep ends into the step, 0..1). Pinned particles: the
// integration keeps them where this puts them; their previous position keeps the motion.
#pragma once

#include <cmath>

#include "collide/body.h"
#include "world_internal.h"

namespace weft {

inline void follow_attachments(const BodyState& body, const ClothAsset& asset, const Particles& p, float t) {
    for (uint32_t k = 0; k < asset.attachment_count; ++k) {
        const uint32_t s = asset.slot_of_particle[asset.attached_particle[k]];
        const uint32_t* tri = body.triangles + 3 * asset.attached_triangle[k];
        const float* w = asset.attached_weight + 3 * k;
        float x[3] = {0.0f, 0.0f, 0.0f};
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 3; ++i) {
                const float now = body.hull[4 * tri[c] + i], before = body.previous_hull[4 * tri[c] + i];
                x[i] = std::fma(w[c], std::fma(t, now - before, before), x[i]);
            }
        p.previous_x[s] = p.x[s], p.previous_y[s] = p.y[s], p.previous_z[s] = p.z[s];
        p.x[s] = x[0], p.y[s] = x[1], p.z[s] = x[2];
    }
}

}  // namespace weft
