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
// Two ways to evaluate it (ClothDesc::projection):
//   exact:     as above; one square root and one division per spring.
//   sqrt_free: Jakobsen's first-order square-root approximation (Advanced Character Physics,
//              2001), rest / len ~ 2 l0^2 / (len^2 + l0^2), so that
//                C * n = (x_b - x_a) * (1 - l0 / len) ~ (x_b - x_a) * (len^2 - l0^2) / (len^2 + l0^2).
//              The same fixed point (len = l0) with one division and no square root: the square root
//              costs as much as the rest of the projection on this class of CPU. It over-corrects a
//              stretched spring slightly (4.5% at 10% strain) and under-corrects a compressed one.
//
// With kWeakCompression (the coarse level only) a compressed constraint's correction is scaled by
// DistanceArgs::compression_weight: see constraints/coarse.h.
//
// No division by zero: a lane whose length is below 1 nm (no direction) or whose ends are both
// pinned with zero compliance gets no correction (keep_if turns its NaN or infinity into 0).
#pragma once

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

inline constexpr float kMinSpringLength_m = 1e-9f;

// One lane group of distance projections; `weight` is lane_weight * relaxation (0 on padding).
template <class F, bool kExact, bool kWeakCompression = false>
inline void project_distance(F& xa, F& ya, F& za, F wa, F& xb, F& yb, F& zb, F wb, F rest,
                             F weight, F alpha, F compression_weight = F{}) {
    using namespace simd;
    const F dx = xb - xa, dy = yb - ya, dz = zb - za;
    const F len2 = mul_add(dx, dx, mul_add(dy, dy, dz * dz));
    const F w_sum = wa + wb + alpha;
    const F zero = splat(0.0f, F{});
    F s;
    if constexpr (kExact) {
        const F len = sqrt(len2);
        const auto valid = (len > splat(kMinSpringLength_m, F{})) & (w_sum > zero);
        s = keep_if(valid, ((len - rest) * weight) / (len * w_sum));
    } else {
        const F rest2 = rest * rest;
        const F den = (len2 + rest2) * w_sum;
        s = keep_if(den > zero, ((len2 - rest2) * weight) / den);
    }
    if constexpr (kWeakCompression) s = select(s < zero, s * compression_weight, s);
    const F sa = wa * s, sb = wb * s;
    xa = mul_add(sa, dx, xa);
    ya = mul_add(sa, dy, ya);
    za = mul_add(sa, dz, za);
    xb = neg_mul_add(sb, dx, xb);
    yb = neg_mul_add(sb, dy, yb);
    zb = neg_mul_add(sb, dz, zb);
}

// A run: lane k joins slots a0 + k and b0 + k, so every operand is a plain vector load.
template <class F, bool kExact, bool kWeakCompression = false>
void project_run(const PointSet& p, const ConstraintLanes& constraints, const ConstraintBatch& batch,
                 const DistanceArgs& args) {
    using namespace simd;
    const F alpha = splat(args.compliance_over_h2, F{});
    const F relaxation = splat(args.relaxation, F{});
    const F compression_weight = splat(args.compression_weight, F{});
    // One base pointer per stream, so each load is a single base + k addressing mode (index
    // arithmetic per load measured as the bottleneck, not sqrt or divide).
    float* const xa_base = p.x + batch.a0;
    float* const ya_base = p.y + batch.a0;
    float* const za_base = p.z + batch.a0;
    float* const xb_base = p.x + batch.b0;
    float* const yb_base = p.y + batch.b0;
    float* const zb_base = p.z + batch.b0;
    const float* const wa_base = p.inverse_mass + batch.a0;
    const float* const wb_base = p.inverse_mass + batch.b0;
    const float* const rest = constraints.rest_length + batch.first_lane;
    const float* const lane_weight = constraints.lane_weight + batch.first_lane;
    const size_t lanes = batch.lane_count;  // size_t: no zero-extension per iteration
    for (size_t k = 0; k < lanes; k += F::width) {
        F xa = load(xa_base + k, F{}), ya = load(ya_base + k, F{}), za = load(za_base + k, F{});
        F xb = load(xb_base + k, F{}), yb = load(yb_base + k, F{}), zb = load(zb_base + k, F{});
        project_distance<F, kExact, kWeakCompression>(xa, ya, za, load(wa_base + k, F{}), xb, yb, zb,
                                                      load(wb_base + k, F{}), load(rest + k, F{}),
                                                      load(lane_weight + k, F{}) * relaxation, alpha, compression_weight);
        store(xa_base + k, xa);
        store(ya_base + k, ya);
        store(za_base + k, za);
        store(xb_base + k, xb);
        store(yb_base + k, yb);
        store(zb_base + k, zb);
    }
}

// The two ends of F::width indexed lanes (per-lane slots index_a, index_b), loaded lane by lane
// from the particle arrays (scalar loads and inserts: faster than vgatherdps on Zen 4, as for the
// coarse level), projected, and stored back lane by lane.
template <class F>
struct IndexedEnds {
    F xa, ya, za, wa, xb, yb, zb, wb;
};
template <class F>
[[gnu::always_inline]] inline IndexedEnds<F> gather_ends(const PointSet& p, const uint32_t* a, const uint32_t* b) {
    using namespace simd;
    return {gather_by_loads(p.x, a, F{}), gather_by_loads(p.y, a, F{}), gather_by_loads(p.z, a, F{}), gather_by_loads(p.inverse_mass, a, F{}),
            gather_by_loads(p.x, b, F{}), gather_by_loads(p.y, b, F{}), gather_by_loads(p.z, b, F{}), gather_by_loads(p.inverse_mass, b, F{})};
}
template <class F, bool kExact, bool kWeakCompression>
[[gnu::always_inline]] inline void project_ends(IndexedEnds<F>& e, const ConstraintLanes& constraints, uint32_t lane, const DistanceArgs& args) {
    using namespace simd;
    project_distance<F, kExact, kWeakCompression>(
        e.xa, e.ya, e.za, e.wa, e.xb, e.yb, e.zb, e.wb, load(constraints.rest_length + lane, F{}),
        load(constraints.lane_weight + lane, F{}) * splat(args.relaxation, F{}), splat(args.compliance_over_h2, F{}),
        splat(args.compression_weight, F{}));
}
template <class F>
[[gnu::always_inline]] inline void scatter_ends(const PointSet& p, const uint32_t* a, const uint32_t* b, const IndexedEnds<F>& e) {
    using namespace simd;
    scatter_by_stores(p.x, a, e.xa);
    scatter_by_stores(p.y, a, e.ya);
    scatter_by_stores(p.z, a, e.za);
    scatter_by_stores(p.x, b, e.xb);
    scatter_by_stores(p.y, b, e.yb);
    scatter_by_stores(p.z, b, e.zb);
}

// The general path: per-lane indices. Lanes of one colour touch disjoint particles (validate_asset
// checks it), so on a SIMD path they are projected F::width at a time; each lane's arithmetic is
// the same as one at a time, so every path gives the same bits. The overflow colour shares
// particles, and the tail of a batch goes one lane at a time. Measured on the sewn garments:
// docs/decisions/2026-11-26-exact-pass-speed.md.
template <class F, bool kExact, bool kWeakCompression = false>
void project_indexed(const PointSet& p, const ConstraintLanes& constraints, const ConstraintBatch& batch,
                     const DistanceArgs& args) {
    const uint32_t* a = constraints.index_a;
    const uint32_t* b = constraints.index_b;
    uint32_t lane = batch.first_lane;
    const uint32_t end = batch.first_lane + batch.lane_count;
    if (F::width > 1 && batch.colour != kOverflowColour) {
        // Two groups at once: each group is one long chain (gathers, square root, division,
        // stores), and two side by side let the processor overlap them (an array of four groups
        // measured no better than two).
        for (; lane + 2 * F::width <= end; lane += 2 * F::width) {
            const uint32_t next = lane + F::width;
            IndexedEnds<F> e0 = gather_ends<F>(p, a + lane, b + lane), e1 = gather_ends<F>(p, a + next, b + next);
            project_ends<F, kExact, kWeakCompression>(e0, constraints, lane, args);
            project_ends<F, kExact, kWeakCompression>(e1, constraints, next, args);
            scatter_ends(p, a + lane, b + lane, e0);
            scatter_ends(p, a + next, b + next, e1);
        }
        for (; lane + F::width <= end; lane += F::width) {
            IndexedEnds<F> e = gather_ends<F>(p, a + lane, b + lane);
            project_ends<F, kExact, kWeakCompression>(e, constraints, lane, args);
            scatter_ends(p, a + lane, b + lane, e);
        }
    }
    for (; lane < end; ++lane) {
        IndexedEnds<simd::Float1> e = gather_ends<simd::Float1>(p, a + lane, b + lane);
        project_ends<simd::Float1, kExact, kWeakCompression>(e, constraints, lane, args);
        scatter_ends(p, a + lane, b + lane, e);
    }
}

// One sweep: every batch in array order (Gauss-Seidel across batches), `args` by constraint kind.
// One call a sweep rather than one a batch: a sewn garment has hundreds of short batches, and the
// call and the loops' set-up per batch cost a tenth of its pass.
template <class F, bool kExact>
void project_springs(const PointSet& p, const ConstraintLanes& constraints, const ConstraintBatch* batches,
                     uint32_t batch_count, const DistanceArgs* args) {
    for (uint32_t b = 0; b < batch_count; ++b) {
        const ConstraintBatch& batch = batches[b];
        const DistanceArgs& a = args[static_cast<uint32_t>(batch.kind)];
        if (batch.layout == BatchLayout::run)
            project_run<F, kExact>(p, constraints, batch, a);
        else
            project_indexed<F, kExact>(p, constraints, batch, a);
    }
}

}  // namespace weft
