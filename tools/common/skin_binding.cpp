#include "skin_binding.h"

#include <cmath>
#include <limits>

namespace weft::scenes {
namespace {

constexpr float kNoMaxDistance_m = 1e3f;  // a ball larger than any garment: no limit

struct V3 {
    double x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Closest point of triangle (a, b, c) to p as barycentric weights (Ericson, Real-Time Collision
// Detection, 5.1.5).
void closest_weights(V3 p, V3 a, V3 b, V3 c, double w[3]) {
    const V3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return void((w[0] = 1, w[1] = 0, w[2] = 0));
    const V3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return void((w[0] = 0, w[1] = 1, w[2] = 0));
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return void((w[0] = 1 - v, w[1] = v, w[2] = 0));
    }
    const V3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return void((w[0] = 0, w[1] = 0, w[2] = 1));
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double v = d2 / (d2 - d6);
        return void((w[0] = 1 - v, w[1] = 0, w[2] = v));
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return void((w[0] = 0, w[1] = 1 - v, w[2] = v));
    }
    const double denom = 1 / (va + vb + vc);
    w[1] = vb * denom, w[2] = vc * denom, w[0] = 1 - w[1] - w[2];
}

}  // namespace

SkinConstraints SkinBinding::constraints() const {
    SkinConstraints s;
    s.count = uint32_t(particle.size());
    s.particle = particle.data();
    s.triangle = triangle.data();
    s.weight = weight.data();
    s.rest_offset_m = rest_offset_m.data();
    s.max_distance_m = max_distance_m.data();
    s.backstop_m = backstop_m.data();
    return s;
}

std::string bind_skin(World* world, ClothId cloth, BodyId body, const SkinOptions& options, SkinBinding* out) {
    BodyView b;
    ClothView c;
    if (Result r = view_body(world, body, &b); !r.ok()) return r.message;
    if (Result r = view_cloth(world, cloth, &c); !r.ok()) return r.message;
    auto hull = [&](uint32_t v) { return V3{b.hull[4 * v], b.hull[4 * v + 1], b.hull[4 * v + 2]}; };
    // Each triangle's bounding sphere: a particle skips every triangle whose sphere lies further
    // than the closest triangle found so far.
    std::vector<V3> centre(b.triangle_count);
    std::vector<double> radius(b.triangle_count);
    for (uint32_t t = 0; t < b.triangle_count; ++t) {
        const V3 p[3] = {hull(b.triangles[3 * t]), hull(b.triangles[3 * t + 1]), hull(b.triangles[3 * t + 2])};
        centre[t] = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
        radius[t] = 0;
        for (const V3& q : p) radius[t] = std::max(radius[t], std::sqrt(dot(q - centre[t], q - centre[t])));
    }
    *out = {};
    const ClothAsset& asset = *c.asset;
    for (uint32_t particle = 0; particle < asset.particle_count; ++particle) {
        const uint32_t s = asset.slot_of_particle[particle];
        if (c.inverse_mass[s] == 0.0f) continue;  // pinned: attachments, not skin constraints
        const V3 x{c.x[s], c.y[s], c.z[s]};
        double best = std::numeric_limits<double>::infinity(), best_w[3] = {1, 0, 0};
        uint32_t best_t = 0;
        for (uint32_t t = 0; t < b.triangle_count; ++t) {
            const double reach = std::sqrt(dot(x - centre[t], x - centre[t])) - radius[t];
            if (reach > 0 && reach * reach >= best) continue;
            const uint32_t* v = b.triangles + 3 * t;
            double w[3];
            closest_weights(x, hull(v[0]), hull(v[1]), hull(v[2]), w);
            const V3 q = w[0] * hull(v[0]) + w[1] * hull(v[1]) + w[2] * hull(v[2]);
            const double d2 = dot(x - q, x - q);
            if (d2 < best) best = d2, best_t = t, best_w[0] = w[0], best_w[1] = w[1], best_w[2] = w[2];
        }
        // The rest offset as the runtime will see it: along the normalised interpolated normal.
        const uint32_t* v = b.triangles + 3 * best_t;
        V3 q{0, 0, 0}, n{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            q = q + best_w[k] * hull(v[k]);
            n = n + best_w[k] * V3{b.normals[3 * v[k]], b.normals[3 * v[k] + 1], b.normals[3 * v[k] + 2]};
        }
        n = (1.0 / std::sqrt(dot(n, n))) * n;
        out->particle.push_back(particle);
        out->triangle.push_back(best_t);
        for (double w : best_w) out->weight.push_back(float(w));
        const float offset = float(dot(x - q, n));
        out->rest_offset_m.push_back(offset);
        out->max_distance_m.push_back(std::fabs(offset) > options.loose_offset_m ? kNoMaxDistance_m : options.max_distance_m);
        out->backstop_m.push_back(options.backstop_m);
    }
    if (Result r = bind_skin_constraints(world, cloth, body, out->constraints()); !r.ok()) return r.message;
    return {};
}

}  // namespace weft::scenes
