// Stage 3 of the seed's step (section 2.3): spring-length correction, as XPBD distance constraints.
//
// For a spring a-b with rest length l0, C = |x_b - x_a| - l0 and, with w = inverse mass and
// alpha~ = compliance / h^2 (Macklin, Mueller, Chentanez 2016, eq. 18, one iteration per substep):
//   dlambda = -C / (w_a + w_b + alpha~)
//   x_a += w_a * C / (len * (w_a + w_b + alpha~)) * (x_b - x_a),   x_b -= w_b * (same) * (x_b - x_a)
// With alpha~ = 0 this is the seed's hard correction (figure 2): a stretched spring pulls its ends
// together, split by inverse mass. The multiplier is not accumulated across iterations (as in
// Jolt): exact for one iteration per substep, the seed's projection for more.
//
// No division by zero: a lane whose length is below 1 nm (no direction) or whose ends are both
// pinned with zero compliance gets no correction (keep_if turns its NaN or infinity into 0).
#pragma once

#include <limits>

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

inline constexpr float kMinSpringLength_m = 1e-9f;

// One lane group of distance projections; `weight` is lane_weight * relaxation (0 on padding).
template <class F>
inline void project_distance(F& xa, F& ya, F& za, F wa, F& xb, F& yb, F& zb, F wb, F rest,
                             F weight, F alpha) {
    using namespace simd;
    const F dx = xb - xa, dy = yb - ya, dz = zb - za;
    const F len = sqrt(mul_add(dx, dx, mul_add(dy, dy, dz * dz)));
    const F w_sum = wa + wb + alpha;
    const F zero = splat(0.0f, F{});
    const auto valid = (len > splat(kMinSpringLength_m, F{})) & (w_sum > zero);
    const F s = keep_if(valid, ((len - rest) * weight) / (len * w_sum));
    const F sa = wa * s, sb = wb * s;
    xa = mul_add(sa, dx, xa);
    ya = mul_add(sa, dy, ya);
    za = mul_add(sa, dz, za);
    xb = neg_mul_add(sb, dx, xb);
    yb = neg_mul_add(sb, dy, yb);
    zb = neg_mul_add(sb, dz, zb);
}

// A run: lane k joins slots a0 + k and b0 + k, so every operand is a plain vector load.
template <class F>
void project_run(const Particles& p, const ClothAsset& asset, const ConstraintBatch& batch,
                 const DistanceArgs& args) {
    using namespace simd;
    const F alpha = splat(args.compliance_over_h2, F{});
    const F relaxation = splat(args.relaxation, F{});
    float* const x = p.x;
    float* const y = p.y;
    float* const z = p.z;
    const float* const w = p.inverse_mass;
    const float* const rest = asset.rest_length + batch.first_lane;
    const float* const lane_weight = asset.lane_weight + batch.first_lane;
    for (uint32_t k = 0; k < batch.lane_count; k += F::width) {
        const uint32_t a = batch.a0 + k, b = batch.b0 + k;
        F xa = load(x + a, F{}), ya = load(y + a, F{}), za = load(z + a, F{});
        F xb = load(x + b, F{}), yb = load(y + b, F{}), zb = load(z + b, F{});
        project_distance(xa, ya, za, load(w + a, F{}), xb, yb, zb, load(w + b, F{}),
                         load(rest + k, F{}), load(lane_weight + k, F{}) * relaxation, alpha);
        store(x + a, xa);
        store(y + a, ya);
        store(z + a, za);
        store(x + b, xb);
        store(y + b, yb);
        store(z + b, zb);
    }
}

// The general path: per-lane indices, one lane at a time on every SIMD path (gathers measured
// no faster than scalar on this layout; see docs/architecture.md).
inline void project_indexed(const Particles& p, const ClothAsset& asset, const ConstraintBatch& batch,
                            const DistanceArgs& args) {
    using simd::Float1;
    const Float1 alpha{args.compliance_over_h2};
    const uint32_t end = batch.first_lane + batch.lane_count;
    for (uint32_t lane = batch.first_lane; lane < end; ++lane) {
        const uint32_t a = asset.index_a[lane], b = asset.index_b[lane];
        Float1 xa{p.x[a]}, ya{p.y[a]}, za{p.z[a]}, xb{p.x[b]}, yb{p.y[b]}, zb{p.z[b]};
        project_distance(xa, ya, za, Float1{p.inverse_mass[a]}, xb, yb, zb,
                         Float1{p.inverse_mass[b]}, Float1{asset.rest_length[lane]},
                         Float1{asset.lane_weight[lane] * args.relaxation}, alpha);
        p.x[a] = xa.v;
        p.y[a] = ya.v;
        p.z[a] = za.v;
        p.x[b] = xb.v;
        p.y[b] = yb.v;
        p.z[b] = zb.v;
    }
}

// Tethers (long-range attachments): a unilateral maximum distance from particle particle0 + k to
// the pinned anchor, which is broadcast to every lane. Only free particles move (the anchor has
// inverse mass 0, so the whole correction is the particle's).
template <class F>
void project_tethers(const Particles& p, const ClothAsset& asset, const TetherBatch& batch,
                     float slack) {
    using namespace simd;
    const F ax = splat(p.x[batch.anchor], F{}), ay = splat(p.y[batch.anchor], F{}),
            az = splat(p.z[batch.anchor], F{});
    const F stretch_allowed = splat(1.0f + slack, F{});
    const F zero = splat(0.0f, F{});
    const float* const rest = asset.tether_rest + batch.first_lane;
    for (uint32_t k = 0; k < batch.lane_count; k += F::width) {
        const uint32_t i = batch.particle0 + k;
        F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
        const F dx = x - ax, dy = y - ay, dz = z - az;
        const F len = sqrt(mul_add(dx, dx, mul_add(dy, dy, dz * dz)));
        const F limit = load(rest + k, F{}) * stretch_allowed;  // +inf on padding lanes
        const auto acts = (len > limit) & (load(p.inverse_mass + i, F{}) > zero) &
                          (len > splat(kMinSpringLength_m, F{}));
        const F s = keep_if(acts, (len - limit) / len);
        x = neg_mul_add(s, dx, x);
        y = neg_mul_add(s, dy, y);
        z = neg_mul_add(s, dz, z);
        store(p.x + i, x);
        store(p.y + i, y);
        store(p.z + i, z);
    }
}

}  // namespace weft
