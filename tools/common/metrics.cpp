#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace weft::metrics {

Strain stretch_strain(const ClothView& c) {
    const ClothAsset& a = *c.asset;
    Strain s;
    uint64_t count = 0;
    for (uint32_t i = 0; i < a.batch_count; ++i) {
        const ConstraintBatch& b = a.batches[i];
        if (b.kind == ConstraintKind::bend) continue;
        for (uint32_t l = b.first_lane; l < b.first_lane + b.lane_count; ++l) {
            if (a.lane_weight[l] == 0.0f || a.rest_length[l] <= 0.0f) continue;
            const uint32_t p = a.index_a[l], q = a.index_b[l];
            const double dx = double(c.x[q]) - c.x[p], dy = double(c.y[q]) - c.y[p], dz = double(c.z[q]) - c.z[p];
            const double strain = std::fabs(std::sqrt(dx * dx + dy * dy + dz * dz) / a.rest_length[l] - 1.0);
            s.mean += strain;
            s.max = std::isnan(strain) ? strain : std::max(s.max, strain);
            ++count;
        }
    }
    if (count > 0) s.mean /= double(count);
    return s;
}

double mean_speed(const ClothView& c) {
    const ClothAsset& a = *c.asset;
    if (!(c.last_substep_s > 0.0f)) return 0.0;
    double sum = 0.0;
    uint32_t count = 0;
    for (uint32_t s = 0; s < a.slot_count; ++s) {
        if (a.particle_of_slot[s] == kNoParticle || c.inverse_mass[s] == 0.0f) continue;
        const double dx = double(c.x[s]) - c.previous_x[s], dy = double(c.y[s]) - c.previous_y[s],
                     dz = double(c.z[s]) - c.previous_z[s];
        sum += std::sqrt(dx * dx + dy * dy + dz * dz) / c.last_substep_s;
        ++count;
    }
    return count > 0 ? sum / count : 0.0;
}

Bounds bounds(const ClothView& c) {
    const ClothAsset& a = *c.asset;
    Bounds b;
    const float inf = std::numeric_limits<float>::infinity();
    b.min = {inf, inf, inf};
    b.max = {-inf, -inf, -inf};
    for (uint32_t s = 0; s < a.slot_count; ++s) {
        if (a.particle_of_slot[s] == kNoParticle) continue;
        if (!std::isfinite(c.x[s]) || !std::isfinite(c.y[s]) || !std::isfinite(c.z[s])) b.finite = false;
        b.min = {std::min(b.min.x, c.x[s]), std::min(b.min.y, c.y[s]), std::min(b.min.z, c.z[s])};
        b.max = {std::max(b.max.x, c.x[s]), std::max(b.max.y, c.y[s]), std::max(b.max.z, c.z[s])};
    }
    return b;
}

double max_tether_excess(const ClothView& c) {
    const ClothAsset& a = *c.asset;
    double worst = 0.0;
    for (uint32_t i = 0; i < a.tether_batch_count; ++i) {
        const TetherBatch& t = a.tether_batches[i];
        for (uint32_t k = 0; k < t.lane_count; ++k) {
            const uint32_t p = t.particle0 + k;
            for (int side = 0; side < 2; ++side) {
                const float rest = a.tether_rest[side][t.first_lane + k];
                if (std::isinf(rest) || rest <= 0.0f) continue;
                const uint32_t q = t.anchor[side];
                const double dx = double(c.x[p]) - c.x[q], dy = double(c.y[p]) - c.y[q], dz = double(c.z[p]) - c.z[q];
                worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz) / rest - 1.0);
            }
        }
    }
    return worst;
}

namespace {

// Depth of point q below the collision surface of c (negative outside).
double depth_inside(const ColliderDesc& c, double qx, double qy, double qz) {
    const double rx = qx - c.p0.x, ry = qy - c.p0.y, rz = qz - c.p0.z;
    if (c.shape == ColliderShape::plane) return c.inflation_m - (rx * c.p1.x + ry * c.p1.y + rz * c.p1.z);
    double dx = rx, dy = ry, dz = rz;
    if (c.shape != ColliderShape::sphere) {
        const double ax = double(c.p1.x) - c.p0.x, ay = double(c.p1.y) - c.p0.y, az = double(c.p1.z) - c.p0.z;
        const double len2 = ax * ax + ay * ay + az * az;
        double t = len2 > 0.0 ? (rx * ax + ry * ay + rz * az) / len2 : 0.0;
        if (c.shape == ColliderShape::cylinder && (t <= 0.0 || t >= 1.0)) return -1.0;  // no caps (seed eq. 6)
        t = std::clamp(t, 0.0, 1.0);
        dx -= t * ax, dy -= t * ay, dz -= t * az;
    }
    return double(c.radius_m) + c.inflation_m - std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

double max_penetration_m(const ClothView& c, const ColliderDesc* colliders, uint32_t count) {
    const ClothAsset& a = *c.asset;
    double worst = 0.0;
    for (uint32_t s = 0; s < a.slot_count; ++s) {
        if (a.particle_of_slot[s] == kNoParticle || c.inverse_mass[s] == 0.0f) continue;
        for (uint32_t k = 0; k < count; ++k) worst = std::max(worst, depth_inside(colliders[k], c.x[s], c.y[s], c.z[s]));
    }
    return worst;
}

Vec3 particle_position(const ClothView& c, uint32_t particle) {
    const uint32_t s = c.asset->slot_of_particle[particle];
    return {c.x[s], c.y[s], c.z[s]};
}

}  // namespace weft::metrics
