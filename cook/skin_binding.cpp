// Cooking skin constraints (weft/cook.h: cook_skin_binding): every free particle of a
// dressed garment bound to the closest triangle of the body's offset hull, the way weft-bake binds
// a waistband's attachments (barycentric weights of the closest point), plus its signed distance
// along the interpolated normal there at rest. weft-bake stores the result in the asset; the
// scene builder runs it only for an asset baked without one.
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "error.h"
#include "weft/closest_point.h"
#include "weft/cook.h"

namespace weft {
namespace {

// Double precision throughout: the closest triangle and weights do not depend on rounding order.
struct V3 {
    double x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Closest point of triangle (a, b, c) to p as barycentric weights (Ericson 5.1.5,
// weft/closest_point.h).
void closest_weights(V3 p, V3 a, V3 b, V3 c, double w[3]) {
    const double pp[3] = {p.x, p.y, p.z}, pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
    const BarycentricWeights<double> on = closest_on_triangle(pp, pa, pb, pc);
    w[0] = on.w0, w[1] = on.w1, w[2] = on.w2;
}

// The body's triangles binned by the bounding boxes of their bounding spheres in a uniform grid,
// so that a particle visits the cells around it in growing shells instead of every triangle (the
// times of both on the shared body: docs/garments.md, "Where the binding comes from").
class TriangleGrid {
public:
    TriangleGrid(const std::vector<V3>& centre, const std::vector<double>& radius) {
        V3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (size_t t = 0; t < centre.size(); ++t) {
            lo = {std::min(lo.x, centre[t].x - radius[t]), std::min(lo.y, centre[t].y - radius[t]),
                  std::min(lo.z, centre[t].z - radius[t])};
            hi = {std::max(hi.x, centre[t].x + radius[t]), std::max(hi.y, centre[t].y + radius[t]),
                  std::max(hi.z, centre[t].z + radius[t])};
        }
        origin_ = lo;
        const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
        cell_ = std::max(extent / kMaxCellsPerAxis, 1e-6);
        dims_[0] = cells_along(hi.x - lo.x), dims_[1] = cells_along(hi.y - lo.y), dims_[2] = cells_along(hi.z - lo.z);
        // Counting sort of (cell, triangle) pairs: the triangles of cell c are first_[c]..first_[c+1].
        first_.assign(size_t(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {
            for (uint32_t t = 0; t < centre.size(); ++t) {
                int a[3], b[3];
                cell_of({centre[t].x - radius[t], centre[t].y - radius[t], centre[t].z - radius[t]}, a);
                cell_of({centre[t].x + radius[t], centre[t].y + radius[t], centre[t].z + radius[t]}, b);
                for (int z = a[2]; z <= b[2]; ++z)
                    for (int y = a[1]; y <= b[1]; ++y)
                        for (int x = a[0]; x <= b[0]; ++x) {
                            const size_t c = index(x, y, z);
                            if (pass == 0) ++first_[c + 1];
                            else triangle_[fill_[c]++] = t;
                        }
            }
            if (pass == 0) {
                for (size_t c = 1; c < first_.size(); ++c) first_[c] += first_[c - 1];
                triangle_.resize(first_.back());
                fill_.assign(first_.begin(), first_.end() - 1);
            }
        }
    }

    // Calls visit(t) for the triangles of every cell at Chebyshev distance `shell` from x's cell
    // (clamped into the grid). Returns a lower bound on the distance from x to every triangle not
    // visited yet (they lie in the grid outside the box of shells 0..shell), or -1 once the box
    // holds the whole grid.
    template <class Visit>
    double visit_shell(V3 x, int shell, Visit&& visit) const {
        int c[3], lo[3], hi[3];
        cell_of(x, c);
        for (int a = 0; a < 3; ++a) lo[a] = std::max(c[a] - shell, 0), hi[a] = std::min(c[a] + shell, dims_[a] - 1);
        const auto visit_cell = [&](int i, int y, int z) {
            const size_t cell = index(i, y, z);
            for (uint32_t k = first_[cell]; k < first_[cell + 1]; ++k) visit(triangle_[k]);
        };
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y) {
                if (std::abs(z - c[2]) == shell || std::abs(y - c[1]) == shell) {
                    for (int i = lo[0]; i <= hi[0]; ++i) visit_cell(i, y, z);
                } else {  // inside the shell's faces along z and y: only its two x ends
                    if (c[0] - shell >= 0) visit_cell(c[0] - shell, y, z);
                    if (shell > 0 && c[0] + shell < dims_[0]) visit_cell(c[0] + shell, y, z);
                }
            }
        // The unvisited part of the grid lies beyond a face of the box that the grid extends past.
        const double p[3] = {x.x - origin_.x, x.y - origin_.y, x.z - origin_.z};
        double bound = HUGE_VAL;
        for (int a = 0; a < 3; ++a) {
            if (c[a] - shell > 0) bound = std::min(bound, std::max(p[a] - (c[a] - shell) * cell_, 0.0));
            if (c[a] + shell < dims_[a] - 1) bound = std::min(bound, std::max((c[a] + shell + 1) * cell_ - p[a], 0.0));
        }
        return bound == HUGE_VAL ? -1.0 : bound;
    }

private:
    static constexpr double kMaxCellsPerAxis = 32;  // the sizes tried: docs/garments.md
    int cells_along(double length) const { return std::max(1, std::min(int(kMaxCellsPerAxis), int(std::ceil(length / cell_)))); }
    void cell_of(V3 p, int out[3]) const {
        const double q[3] = {p.x - origin_.x, p.y - origin_.y, p.z - origin_.z};
        for (int a = 0; a < 3; ++a) out[a] = int(std::clamp(std::floor(q[a] / cell_), 0.0, double(dims_[a] - 1)));
    }
    size_t index(int x, int y, int z) const { return (size_t(z) * dims_[1] + y) * dims_[0] + x; }

    V3 origin_{};
    double cell_ = 1.0;
    int dims_[3] = {1, 1, 1};
    std::vector<uint32_t> first_, fill_, triangle_;
};

}  // namespace

ColliderDesc ground_under_body(const Vec3* positions, uint32_t vertex_count, float thickness_m, float friction) {
    ColliderDesc ground;
    ground.shape = ColliderShape::plane;
    ground.p0 = {0.0f, vertex_count > 0 ? positions[0].y : 0.0f, 0.0f};
    for (uint32_t v = 1; v < vertex_count; ++v) ground.p0.y = std::min(ground.p0.y, positions[v].y);
    ground.p1 = {0.0f, 1.0f, 0.0f};
    ground.inflation_m = thickness_m;
    ground.friction = friction;
    return ground;
}

std::vector<float> default_max_distance_scales(const SkinBindingDesc& desc) {
    const uint32_t n = desc.particle_count;
    // Distance from the nearest pin along the edges (Dijkstra; ties popped by particle index, so
    // the same input gives the same answer). Infinite without pins: the body holds it up.
    std::vector<double> from_pin(n, HUGE_VAL);
    using Entry = std::pair<double, uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> front;
    for (uint32_t p = 0; p < n; ++p)
        if (desc.inverse_masses[p] == 0.0f) from_pin[p] = 0.0, front.push({0.0, p});
    if (front.empty()) return std::vector<float>(n, 1.0f);
    std::vector<std::vector<uint32_t>> neighbours(n);
    for (uint32_t t = 0; desc.triangles != nullptr && t < desc.triangle_count; ++t)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t a = desc.triangles[3 * t + k], b = desc.triangles[3 * t + (k + 1) % 3];
            neighbours[a].push_back(b), neighbours[b].push_back(a);
        }
    while (!front.empty()) {
        const auto [d, p] = front.top();
        front.pop();
        if (d > from_pin[p]) continue;
        for (const uint32_t q : neighbours[p]) {
            const Vec3 &u = desc.positions[p], &v = desc.positions[q];
            const double dx = double(v.x) - u.x, dy = double(v.y) - u.y, dz = double(v.z) - u.z;
            const double e = d + std::sqrt(dx * dx + dy * dy + dz * dz);
            if (e < from_pin[q]) from_pin[q] = e, front.push({e, q});
        }
    }
    std::vector<float> scale(n);
    for (uint32_t p = 0; p < n; ++p) scale[p] = from_pin[p] <= double(desc.options.hung_reach_m) ? 1.0f : 0.0f;
    return scale;
}

Result cook_skin_binding(const BodyView& body, const SkinBindingDesc& desc, SkinBinding* out) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (body.triangle_count == 0 || body.hull == nullptr || body.normals == nullptr || body.triangles == nullptr)
        return make_error(ErrorCode::invalid_argument, "the body has no triangles to bind to");
    if (desc.particle_count > 0 && (desc.positions == nullptr || desc.inverse_masses == nullptr))
        return make_error(ErrorCode::invalid_argument, "skin binding without positions or inverse masses");
    const SkinBindingOptions& o = desc.options;
    if (!std::isfinite(o.max_distance_m) || o.max_distance_m < 0.0f || !std::isfinite(o.loose_offset_m) ||
        !std::isfinite(o.backstop_m) || !(o.max_sink_m > 0.0f) || !std::isfinite(o.max_sink_m))
        return make_error(ErrorCode::invalid_argument, "skin binding options must be finite, the max distance >= 0, the max sink > 0");
    for (uint32_t p = 0; p < desc.particle_count; ++p) {
        const Vec3& x = desc.positions[p];
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
            return make_error(ErrorCode::non_finite, "particle %u has a non-finite position", p);
        if (desc.max_distance_scale != nullptr &&
            !(std::isfinite(desc.max_distance_scale[p]) && desc.max_distance_scale[p] >= 0.0f))
            return make_error(ErrorCode::out_of_range, "particle %u: max distance scale %g is not finite and >= 0", p,
                              double(desc.max_distance_scale[p]));
    }

    auto hull = [&](uint32_t v) { return V3{body.hull[4 * v], body.hull[4 * v + 1], body.hull[4 * v + 2]}; };
    // Each triangle's bounding sphere: a particle skips every triangle whose sphere lies further
    // than the closest triangle found so far, and the grid bins them.
    std::vector<V3> centre(body.triangle_count);
    std::vector<double> radius(body.triangle_count);
    for (uint32_t t = 0; t < body.triangle_count; ++t) {
        const V3 p[3] = {hull(body.triangles[3 * t]), hull(body.triangles[3 * t + 1]), hull(body.triangles[3 * t + 2])};
        centre[t] = (1.0 / 3.0) * (p[0] + p[1] + p[2]);
        radius[t] = 0;
        for (const V3& q : p) radius[t] = std::max(radius[t], std::sqrt(dot(q - centre[t], q - centre[t])));
    }
    const TriangleGrid grid(centre, radius);
    std::vector<uint32_t> seen(body.triangle_count, 0);  // particle + 1 that last considered the triangle
    // The largest max distance (at most `reach`) that keeps a particle bound at hull point q with
    // unit normal n and rest offset o from sinking more than max_sink_m into the hull. It may sit
    // anywhere in the ball of that radius around q + n o in front of its backstop plane, at height
    // b = -backstop_m over the tangent plane; where the hull stands higher than b + max_sink_m it
    // sinks in. Of each nearby hull triangle that part (clipped at that height) is seen from q
    // across the tangent plane: at distance t_min, at most h_max high, it is reached once the
    // radius passes sqrt(t_min^2 + max(o - h_max + max_sink_m, 0)^2) (a lower bound on where the
    // ball first meets it, so the cut errs on the safe side).
    const double b_height = -double(o.backstop_m), sink = double(o.max_sink_m);
    std::vector<uint32_t> reached(body.triangle_count, 0);  // the reach search that last clipped the triangle
    uint32_t search = 0;
    const auto sink_free_reach = [&](V3 q, V3 n, double o_m, double reach) {
        const V3 c = q + o_m * n;
        const double within = reach + std::fabs(o_m);
        // Two directions across n.
        const V3 helper = std::fabs(n.x) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
        V3 u{n.y * helper.z - n.z * helper.y, n.z * helper.x - n.x * helper.z, n.x * helper.y - n.y * helper.x};
        u = (1.0 / std::sqrt(dot(u, u))) * u;
        const V3 v{n.y * u.z - n.z * u.y, n.z * u.x - n.x * u.z, n.x * u.y - n.y * u.x};
        const double level = b_height + sink;
        double best = reach;
        ++search;
        const auto consider = [&](uint32_t t) {
            if (reached[t] == search) return;
            reached[t] = search;
            if (std::sqrt(dot(c - centre[t], c - centre[t])) - radius[t] > within) return;
            // The triangle in (across u, across v, height) about q, clipped to height >= level.
            double in[3][3], out[4][3];
            for (int k = 0; k < 3; ++k) {
                const V3 d = hull(body.triangles[3 * t + uint32_t(k)]) - q;
                in[k][0] = dot(d, u), in[k][1] = dot(d, v), in[k][2] = dot(d, n);
            }
            int m = 0;
            for (int k = 0; k < 3; ++k) {
                const double* a = in[k];
                const double* e = in[(k + 1) % 3];
                if (a[2] >= level) out[m][0] = a[0], out[m][1] = a[1], out[m][2] = a[2], ++m;
                if ((a[2] >= level) != (e[2] >= level)) {
                    const double f = (level - a[2]) / (e[2] - a[2]);
                    out[m][0] = a[0] + f * (e[0] - a[0]), out[m][1] = a[1] + f * (e[1] - a[1]), out[m][2] = level, ++m;
                }
            }
            if (m == 0) return;
            // Distance across the plane from q to the clipped polygon (0 when q lies under it).
            double t_min2 = HUGE_VAL, h_max = -HUGE_VAL;
            int positive = 0, negative = 0;
            for (int k = 0; k < m; ++k) {
                const double* a = out[k];
                const double* e = out[(k + 1) % m];
                h_max = std::max(h_max, a[2]);
                const double ex = e[0] - a[0], ey = e[1] - a[1], len2 = ex * ex + ey * ey;
                const double f = len2 > 0.0 ? std::clamp(-(a[0] * ex + a[1] * ey) / len2, 0.0, 1.0) : 0.0;
                const double px = a[0] + f * ex, py = a[1] + f * ey;
                t_min2 = std::min(t_min2, px * px + py * py);
                const double side = a[0] * ey - a[1] * ex;  // which side of the edge q's foot lies on
                positive += side > 0.0, negative += side < 0.0;
            }
            if (m >= 3 && (positive == 0 || negative == 0)) t_min2 = 0.0;
            const double below = std::max(o_m - h_max + sink, 0.0);
            best = std::min(best, std::sqrt(t_min2 + below * below));
        };
        for (int shell = 0;; ++shell) {
            const double inside = grid.visit_shell(c, shell, consider);
            if (inside < 0.0 || inside > within) break;
        }
        return best;
    };

    SkinBinding b;
    const std::vector<float> default_scale = desc.max_distance_scale == nullptr ? default_max_distance_scales(desc) : std::vector<float>();
    for (uint32_t particle = 0; particle < desc.particle_count; ++particle) {
        if (desc.inverse_masses[particle] == 0.0f) continue;  // pinned: attachments, not skin constraints
        const Vec3& p = desc.positions[particle];
        const V3 x{p.x, p.y, p.z};
        // The closest triangle; of equally close ones (a point nearest a shared edge) the lowest
        // index, so the answer does not depend on the order the grid visits them in.
        double best = std::numeric_limits<double>::infinity(), best_w[3] = {1, 0, 0};
        uint32_t best_t = ~0u;
        const auto consider = [&](uint32_t t) {
            if (seen[t] == particle + 1) return;  // a triangle spans several cells
            seen[t] = particle + 1;
            const double reach = std::sqrt(dot(x - centre[t], x - centre[t])) - radius[t];
            if (reach > 0 && reach * reach > best) return;
            const uint32_t* v = body.triangles + 3 * t;
            double w[3];
            closest_weights(x, hull(v[0]), hull(v[1]), hull(v[2]), w);
            const V3 q = w[0] * hull(v[0]) + w[1] * hull(v[1]) + w[2] * hull(v[2]);
            const double d2 = dot(x - q, x - q);
            if (d2 < best || (d2 == best && t < best_t))
                best = d2, best_t = t, best_w[0] = w[0], best_w[1] = w[1], best_w[2] = w[2];
        };
        for (int shell = 0;; ++shell) {
            const double inside = grid.visit_shell(x, shell, consider);
            if (inside < 0.0 || (best_t != ~0u && inside * inside > best)) break;
        }
        // The rest offset as the step will see it: along the normalised interpolated normal.
        const uint32_t* v = body.triangles + 3 * best_t;
        V3 q{0, 0, 0}, n{0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            q = q + best_w[k] * hull(v[k]);
            n = n + best_w[k] * V3{body.normals[3 * v[k]], body.normals[3 * v[k] + 1], body.normals[3 * v[k] + 2]};
        }
        n = (1.0 / std::sqrt(dot(n, n))) * n;
        b.particle.push_back(particle);
        b.triangle.push_back(best_t);
        for (double w : best_w) b.weight.push_back(float(w));
        const float offset = float(dot(x - q, n));
        b.rest_offset_m.push_back(offset);
        const float scale = desc.max_distance_scale != nullptr ? desc.max_distance_scale[particle] : default_scale[particle];
        const bool free = std::fabs(offset) > o.loose_offset_m || scale == 0.0f;
        float max_distance = std::min(scale * o.max_distance_m, kSkinNoMaxDistance_m);
        if (!free) max_distance = std::min(max_distance, float(sink_free_reach(q, n, double(offset), double(max_distance))));
        b.max_distance_m.push_back(free ? kSkinNoMaxDistance_m : max_distance);
        b.backstop_m.push_back(o.backstop_m);
    }
    *out = std::move(b);
    return {};
}

}  // namespace weft
