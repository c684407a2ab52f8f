// Stage 2 of the seed's step (section 2.3): position Verlet with damping.
//   x(t+h) = x(t) + (x(t) - x(t-h)) * (h / h_prev) * exp(-damping h) + (g + a_wind) h^2
// The h / h_prev factor keeps the implied velocity right when the frame time changes; exp(-d h)
// makes damping a rate in 1/s, independent of how the budget is split into substeps.
#pragma once

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

template <class F, bool kWind>
void integrate_verlet_pass(const Particles& p, const IntegrateArgs& args) {
    using namespace simd;
    const F h2 = splat(args.h_s * args.h_s, F{});
    const F velocity_scale = splat(args.velocity_scale, F{});
    const F gx = splat(args.gravity.x, F{}), gy = splat(args.gravity.y, F{}), gz = splat(args.gravity.z, F{});
    const F zero = splat(0.0f, F{});
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const auto is_free = load(p.inverse_mass + i, F{}) > zero;  // pinned particles stay put
        F ax = gx, ay = gy, az = gz;
        if constexpr (kWind) {
            ax = ax + load(p.wind_x + i, F{});
            ay = ay + load(p.wind_y + i, F{});
            az = az + load(p.wind_z + i, F{});
        }
        const F x = load(p.x + i, F{}), y = load(p.y + i, F{}), z = load(p.z + i, F{});
        const F nx = mul_add(ax, h2, mul_add(x - load(p.previous_x + i, F{}), velocity_scale, x));
        const F ny = mul_add(ay, h2, mul_add(y - load(p.previous_y + i, F{}), velocity_scale, y));
        const F nz = mul_add(az, h2, mul_add(z - load(p.previous_z + i, F{}), velocity_scale, z));
        store(p.previous_x + i, x);
        store(p.previous_y + i, y);
        store(p.previous_z + i, z);
        store(p.x + i, select(is_free, nx, x));
        store(p.y + i, select(is_free, ny, y));
        store(p.z + i, select(is_free, nz, z));
    }
}

template <class F>
void integrate_verlet(const Particles& p, const IntegrateArgs& args) {
    if (args.wind) {
        integrate_verlet_pass<F, true>(p, args);
    } else {
        integrate_verlet_pass<F, false>(p, args);
    }
}

}  // namespace weft
