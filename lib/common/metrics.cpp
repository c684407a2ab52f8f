#include "common/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace weft::metrics {

namespace {

// Strain over the stretch and shear lanes; `at(slot)` gives a slot's position.
template <class PositionOfSlot>
Strain strain_of(const ClothAsset& a, PositionOfSlot at) {
    Strain s;
    uint64_t count = 0;
    for (uint32_t i = 0; i < a.batch_count; ++i) {
        const ConstraintBatch& b = a.batches[i];
        if (b.kind == ConstraintKind::bend) continue;
        for (uint32_t l = b.first_lane; l < b.first_lane + b.lane_count; ++l) {
            if (a.lane_weight[l] == 0.0f || a.rest_length[l] <= 0.0f) continue;
            const Vec3 p = at(a.index_a[l]), q = at(a.index_b[l]);
            const double dx = double(q.x) - p.x, dy = double(q.y) - p.y, dz = double(q.z) - p.z;
            const double strain = std::fabs(std::sqrt(dx * dx + dy * dy + dz * dz) / a.rest_length[l] - 1.0);
            s.mean += strain;
            if (std::isnan(strain) || strain > s.max) s.max_at = {0.5f * (p.x + q.x), 0.5f * (p.y + q.y), 0.5f * (p.z + q.z)};
            s.max = std::isnan(strain) ? strain : std::max(s.max, strain);
            ++count;
        }
    }
    if (count > 0) s.mean /= double(count);
    return s;
}

// Whether segment p-q passes through triangle abc (Moller and Trumbore 1997, in double): a
// crossing point strictly inside the segment and inside or on the triangle. A segment in the
// triangle's plane never crosses it.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double dx = double(q.x) - p.x, dy = double(q.y) - p.y, dz = double(q.z) - p.z;
    const double e1x = double(b.x) - a.x, e1y = double(b.y) - a.y, e1z = double(b.z) - a.z;
    const double e2x = double(c.x) - a.x, e2y = double(c.y) - a.y, e2z = double(c.z) - a.z;
    const double hx = dy * e2z - dz * e2y, hy = dz * e2x - dx * e2z, hz = dx * e2y - dy * e2x;
    const double det = e1x * hx + e1y * hy + e1z * hz;
    if (!(std::fabs(det) > 1e-30)) return false;
    const double inv = 1.0 / det;
    const double sx = double(p.x) - a.x, sy = double(p.y) - a.y, sz = double(p.z) - a.z;
    const double u = (sx * hx + sy * hy + sz * hz) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const double rx = sy * e1z - sz * e1y, ry = sz * e1x - sx * e1z, rz = sx * e1y - sy * e1x;
    const double v = (dx * rx + dy * ry + dz * rz) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = (e2x * rx + e2y * ry + e2z * rz) * inv;
    return t > 0.0 && t < 1.0;
}

}  // namespace

uint64_t self_crossings(const uint32_t* triangles, uint32_t triangle_count, const std::vector<Vec3>& x) {
    // The mesh's edges, once each.
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    edges.reserve(3 * size_t(triangle_count));
    for (uint32_t t = 0; t < triangle_count; ++t)
        for (uint32_t e = 0; e < 3; ++e) {
            const uint32_t a = triangles[3 * t + e], b = triangles[3 * t + (e + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    if (edges.empty()) return 0;
    for (const auto& [a, b] : edges)
        if (a >= x.size() || b >= x.size() || !std::isfinite(x[a].x + x[a].y + x[a].z + x[b].x + x[b].y + x[b].z))
            return 0;  // not a cloth's positions: nothing to count
    // A uniform grid over the triangles' boxes, cells twice the mean edge long (so an edge's box
    // meets a few cells) and no shorter than an eighth of the longest edge (so no box meets more
    // than 9 cells an axis).
    double length = 0.0, longest = 0.0;
    for (const auto& [a, b] : edges) {
        const double dx = double(x[b].x) - x[a].x, dy = double(x[b].y) - x[a].y, dz = double(x[b].z) - x[a].z;
        const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
        length += l, longest = std::max(longest, l);
    }
    const double cell = std::max({2.0 * length / double(edges.size()), longest / 8.0, 1e-4});
    const auto cell_of = [&](float v) { return int64_t(std::clamp(std::floor(double(v) / cell), -1e15, 1e15)); };
    const auto key = [](int64_t i, int64_t j, int64_t k) {
        return (uint64_t(i & 0x1FFFFF) << 42) | (uint64_t(j & 0x1FFFFF) << 21) | uint64_t(k & 0x1FFFFF);
    };
    struct Box {
        int64_t lo[3], hi[3];
    };
    const auto box_of = [&](std::initializer_list<uint32_t> corners) {
        Box box{};
        bool first = true;
        for (uint32_t p : corners) {
            const int64_t c[3] = {cell_of(x[p].x), cell_of(x[p].y), cell_of(x[p].z)};
            for (int d = 0; d < 3; ++d) {
                box.lo[d] = first ? c[d] : std::min(box.lo[d], c[d]);
                box.hi[d] = first ? c[d] : std::max(box.hi[d], c[d]);
            }
            first = false;
        }
        return box;
    };
    std::vector<std::pair<uint64_t, uint32_t>> cells;  // (cell key, triangle), sorted by key
    for (uint32_t t = 0; t < triangle_count; ++t) {
        const Box b = box_of({triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]});
        for (int64_t i = b.lo[0]; i <= b.hi[0]; ++i)
            for (int64_t j = b.lo[1]; j <= b.hi[1]; ++j)
                for (int64_t k = b.lo[2]; k <= b.hi[2]; ++k) cells.push_back({key(i, j, k), t});
    }
    std::sort(cells.begin(), cells.end());
    std::vector<uint32_t> seen(triangle_count, ~0u);  // the last edge that tested each triangle
    uint64_t crossings = 0;
    for (uint32_t e = 0; e < edges.size(); ++e) {
        const auto [a, b] = edges[e];
        const Box box = box_of({a, b});
        for (int64_t i = box.lo[0]; i <= box.hi[0]; ++i)
            for (int64_t j = box.lo[1]; j <= box.hi[1]; ++j)
                for (int64_t k = box.lo[2]; k <= box.hi[2]; ++k) {
                    auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key(i, j, k), 0u));
                    for (; it != cells.end() && it->first == key(i, j, k); ++it) {
                        const uint32_t t = it->second;
                        if (seen[t] == e) continue;
                        seen[t] = e;
                        const uint32_t* v = triangles + 3 * t;
                        if (v[0] == a || v[1] == a || v[2] == a || v[0] == b || v[1] == b || v[2] == b) continue;
                        crossings += segment_crosses_triangle(x[a], x[b], x[v[0]], x[v[1]], x[v[2]]);
                    }
                }
    }
    return crossings;
}

namespace {

// Both meshes as one (b's slots after a's): no triangle shares a particle with the other cloth's
// edges, so the crossings between them are the union's less each cloth's own.
uint64_t layer_crossings(const ClothAsset& aa, const std::vector<Vec3>& xa, const ClothAsset& ab, const std::vector<Vec3>& xb) {
    std::vector<Vec3> x = xa;
    x.insert(x.end(), xb.begin(), xb.end());
    std::vector<uint32_t> triangles(aa.triangles, aa.triangles + 3 * size_t(aa.triangle_count));
    for (uint32_t k = 0; k < 3 * ab.triangle_count; ++k) triangles.push_back(aa.slot_count + ab.triangles[k]);
    const uint64_t both = self_crossings(triangles.data(), uint32_t(triangles.size() / 3), x);
    return both - self_crossings(aa.triangles, aa.triangle_count, xa) - self_crossings(ab.triangles, ab.triangle_count, xb);
}

std::vector<Vec3> by_slot(const ClothView& c) {
    std::vector<Vec3> x(c.asset->slot_count);
    for (uint32_t s = 0; s < c.asset->slot_count; ++s) x[s] = {c.x[s], c.y[s], c.z[s]};
    return x;
}

std::vector<Vec3> start_by_slot(const ClothAsset& a) {
    std::vector<Vec3> x(a.slot_count);
    for (uint32_t s = 0; s < a.slot_count; ++s) x[s] = {a.start_x[s], a.start_y[s], a.start_z[s]};
    return x;
}

}  // namespace

uint64_t self_crossings(const ClothView& c) { return self_crossings(c.asset->triangles, c.asset->triangle_count, by_slot(c)); }

uint64_t layer_crossings(const ClothView& a, const ClothView& b) {
    return layer_crossings(*a.asset, by_slot(a), *b.asset, by_slot(b));
}

uint64_t layer_crossings(const ClothAsset& a, const ClothAsset& b) {
    return layer_crossings(a, start_by_slot(a), b, start_by_slot(b));
}

Strain stretch_strain(const ClothView& c) {
    return strain_of(*c.asset, [&](uint32_t s) { return Vec3{c.x[s], c.y[s], c.z[s]}; });
}

Strain stretch_strain(const ClothAsset& a, const std::vector<Vec3>& positions) {
    if (positions.size() != a.particle_count) return {};
    return strain_of(a, [&](uint32_t s) { return positions[a.particle_of_slot[s]]; });
}

Strain start_strain(const ClothAsset& a) {
    return strain_of(a, [&](uint32_t s) { return Vec3{a.start_x[s], a.start_y[s], a.start_z[s]}; });
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
                const uint32_t q = tether_anchor(a, t, k, uint32_t(side));
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

double max_penetration_m(const ClothAsset& a, const std::vector<Vec3>& positions, const ColliderDesc* colliders,
                         uint32_t count) {
    double worst = 0.0;
    for (uint32_t p = 0; p < a.particle_count && p < positions.size(); ++p) {
        if (a.inverse_mass[a.slot_of_particle[p]] == 0.0f) continue;
        const Vec3 q = positions[p];
        for (uint32_t k = 0; k < count; ++k) worst = std::max(worst, depth_inside(colliders[k], q.x, q.y, q.z));
    }
    return worst;
}

double rms_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    if (a.size() != b.size() || a.empty()) return std::numeric_limits<double>::infinity();
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double dx = double(a[i].x) - b[i].x, dy = double(a[i].y) - b[i].y, dz = double(a[i].z) - b[i].z;
        sum += dx * dx + dy * dy + dz * dz;
    }
    // A NaN anywhere makes the run infinitely wrong, not "unordered".
    return std::isfinite(sum) ? std::sqrt(sum / double(a.size())) : std::numeric_limits<double>::infinity();
}

double trajectory_error(const Frames& run, const Frames& reference, double diagonal) {
    if (run.size() != reference.size() || run.empty() || !(diagonal > 0.0))
        return std::numeric_limits<double>::infinity();
    double sum = 0.0;  // of squared RMS distances: every frame has the same particle count
    for (size_t f = 0; f < run.size(); ++f) {
        const double d = rms_distance(run[f], reference[f]);
        sum += d * d;
    }
    return std::isfinite(sum) ? std::sqrt(sum / double(run.size())) / diagonal
                              : std::numeric_limits<double>::infinity();
}

double rest_state_error(const Frames& run, const Frames& reference, double diagonal) {
    if (run.empty() || reference.empty() || !(diagonal > 0.0)) return std::numeric_limits<double>::infinity();
    return rms_distance(run.back(), reference.back()) / diagonal;
}

double diagonal_m(const std::vector<Vec3>& positions) {
    if (positions.empty()) return 0.0;
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3& p : positions) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const double dx = double(hi.x) - lo.x, dy = double(hi.y) - lo.y, dz = double(hi.z) - lo.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

Vec3 particle_position(const ClothView& c, uint32_t particle) {
    const uint32_t s = c.asset->slot_of_particle[particle];
    return {c.x[s], c.y[s], c.z[s]};
}

namespace {
// How deep `point` is inside the body's hull: the step's query, then, for a point it does not reach,
// a query kDeepReach_m wide (a particle that went deeper than the step's reach is out of its sight,
// and must not be out of the metric's).
constexpr float kDeepReach_m = 0.25f;
double body_depth_m(const World* world, BodyId body, Vec3 point) {
    BodyContact c;
    if (!query_body(world, body, point, &c).ok()) return 0.0;
    if (!c.found && !(query_body(world, body, point, &c, kDeepReach_m).ok() && c.found)) return 0.0;
    return std::max(0.0, double(c.penetration_m));
}
}  // namespace

double max_body_penetration_m(const World* world, BodyId body, const ClothView& cloth, Vec3* deepest_at) {
    double deepest = 0.0;
    for (uint32_t s = 0; s < cloth.asset->slot_count; ++s) {
        if (!(cloth.inverse_mass[s] > 0.0f)) continue;  // pinned (attached) and padding slots
        const Vec3 x{cloth.x[s], cloth.y[s], cloth.z[s]};
        const double depth = body_depth_m(world, body, x);
        if (depth > deepest) deepest = depth, *deepest_at = x;
    }
    return deepest;
}

double max_body_penetration_m(const World* world, BodyId body, const ClothView& cloth) {
    Vec3 unused{};
    return max_body_penetration_m(world, body, cloth, &unused);
}

double max_body_penetration_m(const World* world, BodyId body, const ClothAsset& asset,
                              const std::vector<Vec3>& positions) {
    double deepest = 0.0;
    for (uint32_t p = 0; p < asset.particle_count && p < positions.size(); ++p)
        if (asset.inverse_mass[asset.slot_of_particle[p]] > 0.0f)
            deepest = std::max(deepest, body_depth_m(world, body, positions[p]));
    return deepest;
}

}  // namespace weft::metrics
