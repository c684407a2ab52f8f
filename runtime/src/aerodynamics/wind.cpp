#include "aerodynamics/wind.h"

#include <cmath>
#include <cstring>

namespace weft {
namespace {

struct V3 {
    float x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

}  // namespace

void apply_wind(const Particles& p, const ClothAsset& asset, const WindArgs& args) {
    const size_t bytes = sizeof(float) * p.slot_count;
    std::memset(p.wind_x, 0, bytes);
    std::memset(p.wind_y, 0, bytes);
    std::memset(p.wind_z, 0, bytes);
    const float inv_h = args.previous_substep_s > 0.0f ? 1.0f / args.previous_substep_s : 0.0f;
    const V3 wind{args.wind_m_s.x, args.wind_m_s.y, args.wind_m_s.z};
    // 1/2 rho C S |v|^2, with S = |n| / 2 folded in below.
    const float half_rho = 0.5f * args.air_density_kg_m3;
    for (uint32_t t = 0; t < asset.triangle_count; ++t) {
        const uint32_t* tri = asset.triangles + 3 * t;
        V3 x[3], v{0.0f, 0.0f, 0.0f};
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[k];
            x[k] = {p.x[i], p.y[i], p.z[i]};
            v = v + (x[k] - V3{p.previous_x[i], p.previous_y[i], p.previous_z[i]}) * inv_h;
        }
        const V3 relative = v * (1.0f / 3.0f) - wind;  // v_relative = v_object - u
        const float speed2 = dot(relative, relative);
        const V3 area_normal = cross(x[1] - x[0], x[2] - x[0]);  // |area_normal| = 2 S
        const float twice_area = std::sqrt(dot(area_normal, area_normal));
        if (!(speed2 > 1e-12f) || !(twice_area > 1e-12f)) continue;
        const float speed = std::sqrt(speed2);
        const V3 v_hat = relative * (1.0f / speed);
        const V3 n_hat = area_normal * (1.0f / twice_area);
        const float area = 0.5f * twice_area;
        // theta is the angle between v_relative and the surface: sin(theta) = |n . v_hat|.
        const float n_dot_v = dot(n_hat, v_hat);
        const float sin_theta = std::fabs(n_dot_v);
        // Drag (2): opposite v_relative.
        const V3 drag = v_hat * (-half_rho * args.drag_coefficient * speed2 * area * sin_theta);
        // Lift (3): perpendicular to v_relative, towards the downwind side of the surface. The
        // unnormalised direction n_d - (n_d . v_hat) v_hat already has length cos(theta). The side
        // flips when the flow crosses the surface; a linear ramp over |n . v_hat| < 0.05 keeps the
        // force continuous there instead of switching sign in one step.
        const float ramp = -n_dot_v * 20.0f;  // / 0.05
        const float side = ramp > 1.0f ? 1.0f : (ramp < -1.0f ? -1.0f : ramp);
        const V3 n_down = n_hat * side;
        const V3 lift_dir = n_down - v_hat * dot(n_down, v_hat);
        const V3 lift = lift_dir * (half_rho * args.lift_coefficient * speed2 * area);
        // Stability: the force grows with |v_rel|^2, so an explicit step overshoots once
        // h * d|a|/d|v| = h * 2|a| / |v_rel| exceeds 1 (1.06 for the seed's flag at 40 m/s and
        // dt 0.033 s). Dividing by 1 + that is the backward-Euler (linearised implicit) response:
        // the same force where it is small, never an overshoot where it is not.
        const V3 force = drag + lift;
        float w_max = 0.0f;
        for (int k = 0; k < 3; ++k) w_max = p.inverse_mass[tri[k]] > w_max ? p.inverse_mass[tri[k]] : w_max;
        const float accel = std::sqrt(dot(force, force)) * (1.0f / 3.0f) * w_max;
        const float implicit = 1.0f / (1.0f + args.substep_s * 2.0f * accel / speed);
        const V3 force_per_vertex = force * ((1.0f / 3.0f) * implicit);
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[k];
            const float w = p.inverse_mass[i];
            p.wind_x[i] += force_per_vertex.x * w;
            p.wind_y[i] += force_per_vertex.y * w;
            p.wind_z[i] += force_per_vertex.z * w;
        }
    }
}

}  // namespace weft
