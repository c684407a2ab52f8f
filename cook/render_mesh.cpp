// Render meshes (weft/cook.h): the cloth's mesh subdivided, and any render mesh bound to the cloth's
// triangles by barycentric coordinates and an offset along the interpolated normal (the mapping
// APEX and Chaos use to drive a fine render mesh from a coarse simulation mesh).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>
#include <vector>

#include "asset/garment_checks.h"
#include "error.h"
#include "weft/closest_point.h"
#include "weft/cook.h"

namespace weft {
namespace {

struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(double s, D3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 normalised(D3 a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0 ? (1.0 / l) * a : D3{};
}
D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }

// The closest point of triangle (a, b, c) to p as barycentric weights (Ericson 5.1.5,
// weft/closest_point.h).
D3 closest_weights(D3 p, D3 a, D3 b, D3 c) {
    const double pp[3] = {p.x, p.y, p.z}, pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
    const BarycentricWeights<double> w = closest_on_triangle(pp, pa, pb, pc);
    return {w.w0, w.w1, w.w2};
}

// Uniform grid over the triangles' boxes, cells of `cell` metres.
struct TriangleGrid {
    double cell = 1.0;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
    static uint64_t key(int64_t i, int64_t j, int64_t k) {
        return (uint64_t(i & 0x1FFFFF) << 42) | (uint64_t(j & 0x1FFFFF) << 21) | uint64_t(k & 0x1FFFFF);
    }
    int64_t index(double v) const { return int64_t(std::floor(v / cell)); }
};

// A render vertex further than this from its reconstruction at rest is refused, m.
constexpr double kMaxRenderBindError_m = 1e-3;

}  // namespace

Result subdivide_cloth_mesh(const ClothAsset& a, uint32_t levels, RenderMeshSource* out) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (a.triangle_count == 0) return make_error(ErrorCode::invalid_argument, "the cloth has no triangles");
    if (levels > 4) return make_error(ErrorCode::out_of_range, "%u subdivision levels (at most 4: 256 times the triangles)", levels);
    std::vector<Vec3> x(a.particle_count);
    std::vector<uint32_t> tri(3 * size_t(a.triangle_count));
    if (Result r = read_start_positions(a, x.data(), a.particle_count); !r.ok()) return r;
    if (Result r = read_triangles(a, tri.data(), uint32_t(tri.size())); !r.ok()) return r;
    std::vector<int64_t> sewn_of(a.particle_count, -1);
    for (uint32_t k = 0; k < a.sewn_point_count; ++k) sewn_of[a.sewn_particle[k]] = k;

    RenderMeshSource m;
    std::unordered_map<uint64_t, uint32_t> vertex_of;  // (particle, uv choice) -> render vertex
    for (uint32_t t = 0; t < a.triangle_count; ++t) {
        const uint32_t* v = &tri[3 * size_t(t)];
        // Each corner's uv choices: the particle's, or every source's of a sewn seam particle; the
        // triangle takes the ones whose uv edge lengths best match its start pose (its own panel's).
        const float* option[3];
        uint32_t count[3];
        for (int k = 0; k < 3; ++k) {
            static const float kZero[2] = {0.0f, 0.0f};
            const int64_t s = sewn_of[v[k]];
            if (a.uv == nullptr) option[k] = kZero, count[k] = 1;
            else if (s < 0) option[k] = a.uv + 2 * size_t(v[k]), count[k] = 1;
            else option[k] = a.sewn_uv + 2 * size_t(a.sewn_uv_first[s]), count[k] = a.sewn_uv_first[s + 1] - a.sewn_uv_first[s];
        }
        uint32_t pick[3] = {0, 0, 0};
        double best = std::numeric_limits<double>::infinity();
        for (uint32_t i0 = 0; i0 < count[0]; ++i0)
            for (uint32_t i1 = 0; i1 < count[1]; ++i1)
                for (uint32_t i2 = 0; i2 < count[2]; ++i2) {
                    const uint32_t c[3] = {i0, i1, i2};
                    double misfit = 0;
                    for (int k = 0; k < 3; ++k) {
                        const int l = (k + 1) % 3;
                        const float* u = option[k] + 2 * c[k];
                        const float* w = option[l] + 2 * c[l];
                        const double d = std::hypot(double(w[0]) - u[0], double(w[1]) - u[1]) -
                                         std::sqrt(dot(d3(x[v[l]]) - d3(x[v[k]]), d3(x[v[l]]) - d3(x[v[k]])));
                        misfit += d * d;
                    }
                    if (misfit < best) best = misfit, pick[0] = i0, pick[1] = i1, pick[2] = i2;
                }
        for (int k = 0; k < 3; ++k) {
            const uint64_t key = (uint64_t(v[k]) << 4) | pick[k];
            auto [it, added] = vertex_of.try_emplace(key, uint32_t(m.positions.size()));
            if (added) {
                m.positions.push_back(x[v[k]]);
                const float* u = option[k] + 2 * pick[k];
                m.uv.insert(m.uv.end(), {u[0], u[1]});
            }
            m.triangles.push_back(it->second);
        }
    }
    for (uint32_t level = 0; level < levels; ++level) {
        std::unordered_map<uint64_t, uint32_t> midpoint;  // edge (low, high vertex) -> its midpoint
        auto middle = [&](uint32_t i, uint32_t j) {
            const uint64_t key = (uint64_t(std::min(i, j)) << 32) | std::max(i, j);
            auto [it, added] = midpoint.try_emplace(key, uint32_t(m.positions.size()));
            if (added) {
                const Vec3 p = m.positions[i], q = m.positions[j];
                m.positions.push_back({0.5f * (p.x + q.x), 0.5f * (p.y + q.y), 0.5f * (p.z + q.z)});
                const float u = 0.5f * (m.uv[2 * i] + m.uv[2 * j]), w = 0.5f * (m.uv[2 * i + 1] + m.uv[2 * j + 1]);
                m.uv.insert(m.uv.end(), {u, w});
            }
            return it->second;
        };
        std::vector<uint32_t> finer;
        finer.reserve(4 * m.triangles.size());
        for (size_t t = 0; t < m.triangles.size(); t += 3) {
            const uint32_t p = m.triangles[t], q = m.triangles[t + 1], r = m.triangles[t + 2];
            const uint32_t pq = middle(p, q), qr = middle(q, r), rp = middle(r, p);
            finer.insert(finer.end(), {p, pq, rp, pq, q, qr, rp, qr, r, pq, qr, rp});  // the winding kept
        }
        m.triangles = std::move(finer);
    }
    *out = std::move(m);
    return {};
}

Result bind_render_mesh(const RenderMeshDesc& mesh, CookedCloth* cloth, double* max_error_m) {
    if (cloth == nullptr) return make_error(ErrorCode::invalid_argument, "cloth is null");
    if (mesh.vertex_count == 0 || mesh.positions == nullptr || (mesh.triangle_count > 0 && mesh.triangles == nullptr))
        return make_error(ErrorCode::invalid_argument, "render mesh has no vertices or is missing an array");
    const ClothAsset& a = cloth->asset();
    if (a.triangle_count == 0) return make_error(ErrorCode::invalid_argument, "the cloth has no triangles");
    for (uint32_t v = 0; v < mesh.vertex_count; ++v) {
        const Vec3 p = mesh.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return make_error(ErrorCode::non_finite, "render vertex %u is not finite", v);
    }
    for (uint64_t k = 0; k < 3 * uint64_t(mesh.triangle_count); ++k)
        if (mesh.triangles[k] >= mesh.vertex_count)
            return make_error(ErrorCode::out_of_range, "render triangle %llu names vertex %u of %u",
                              (unsigned long long)(k / 3), mesh.triangles[k], mesh.vertex_count);

    // The start pose by slot and its area-weighted vertex normals (the normals pass's).
    const uint32_t n = a.slot_count, T = a.triangle_count;
    std::vector<D3> x(n), normal(n);
    for (uint32_t s = 0; s < n; ++s) x[s] = {a.start_x[s], a.start_y[s], a.start_z[s]};
    double edge_sum = 0;
    for (uint32_t t = 0; t < T; ++t) {
        const uint32_t* c = a.triangles + 3 * size_t(t);
        const D3 face = cross(x[c[1]] - x[c[0]], x[c[2]] - x[c[0]]);
        for (int k = 0; k < 3; ++k) normal[c[k]] = normal[c[k]] + face;
        edge_sum += std::sqrt(dot(x[c[1]] - x[c[0]], x[c[1]] - x[c[0]]));
    }
    for (D3& v : normal) v = normalised(v);

    TriangleGrid grid;
    grid.cell = std::max(2.0 * edge_sum / T, 1e-4);
    for (uint32_t t = 0; t < T; ++t) {
        const uint32_t* c = a.triangles + 3 * size_t(t);
        D3 lo = x[c[0]], hi = x[c[0]];
        for (int k = 1; k < 3; ++k) {
            lo = {std::min(lo.x, x[c[k]].x), std::min(lo.y, x[c[k]].y), std::min(lo.z, x[c[k]].z)};
            hi = {std::max(hi.x, x[c[k]].x), std::max(hi.y, x[c[k]].y), std::max(hi.z, x[c[k]].z)};
        }
        for (int64_t i = grid.index(lo.x); i <= grid.index(hi.x); ++i)
            for (int64_t j = grid.index(lo.y); j <= grid.index(hi.y); ++j)
                for (int64_t k = grid.index(lo.z); k <= grid.index(hi.z); ++k) grid.cells[TriangleGrid::key(i, j, k)].push_back(t);
    }

    auto point = [&](uint32_t t, D3 b) {
        const uint32_t* c = a.triangles + 3 * size_t(t);
        return b.x * x[c[0]] + b.y * x[c[1]] + b.z * x[c[2]];
    };
    auto normal_at = [&](uint32_t t, D3 b) {
        const uint32_t* c = a.triangles + 3 * size_t(t);
        return normalised(b.x * normal[c[0]] + b.y * normal[c[1]] + b.z * normal[c[2]]);
    };
    std::vector<uint32_t> bound(mesh.vertex_count);
    std::vector<float> w1(mesh.vertex_count), w2(mesh.vertex_count), offset(mesh.vertex_count);
    double worst = 0;
    for (uint32_t v = 0; v < mesh.vertex_count; ++v) {
        const D3 p = d3(mesh.positions[v]);
        uint32_t best_t = 0;
        D3 best_b{1, 0, 0};
        double best = std::numeric_limits<double>::infinity();
        auto consider = [&](uint32_t t) {
            const uint32_t* c = a.triangles + 3 * size_t(t);
            const D3 b = closest_weights(p, x[c[0]], x[c[1]], x[c[2]]);
            const D3 d = p - point(t, b);
            const double d2 = dot(d, d);
            if (d2 < best || (d2 == best && t < best_t)) best = d2, best_t = t, best_b = b;
        };
        // Rings of cells around p until the best distance is inside the searched cube.
        const int64_t ci = grid.index(p.x), cj = grid.index(p.y), ck = grid.index(p.z);
        bool found = false;
        for (int64_t r = 0; r <= 8 && !found; ++r) {
            for (int64_t i = ci - r; i <= ci + r; ++i)
                for (int64_t j = cj - r; j <= cj + r; ++j)
                    for (int64_t k = ck - r; k <= ck + r; ++k) {
                        if (std::max({std::abs(i - ci), std::abs(j - cj), std::abs(k - ck)}) != r) continue;  // the shell
                        auto it = grid.cells.find(TriangleGrid::key(i, j, k));
                        if (it != grid.cells.end())
                            for (uint32_t t : it->second) consider(t);
                    }
            found = best <= double(r) * grid.cell * double(r) * grid.cell;
        }
        if (!found)  // far from every cell searched: all the triangles
            for (uint32_t t = 0; t < T; ++t) consider(t);
        // p = X(b) + d N(b): the closest point's b first, then twice b of p - d N on the triangle.
        D3 b = best_b;
        double d = dot(p - point(best_t, b), normal_at(best_t, b));
        for (int refine = 0; refine < 2; ++refine) {
            const uint32_t* c = a.triangles + 3 * size_t(best_t);
            b = closest_weights(p - d * normal_at(best_t, b), x[c[0]], x[c[1]], x[c[2]]);
            d = dot(p - point(best_t, b), normal_at(best_t, b));
        }
        if (std::fabs(d) > 1.0)
            return make_error(ErrorCode::out_of_range, "render vertex %u lies %.3f m off the cloth (is it authored on the start pose?)", v, d);
        const D3 back = point(best_t, b) + d * normal_at(best_t, b);
        const double error = std::sqrt(dot(back - p, back - p));
        if (error > kMaxRenderBindError_m)  // past the cloth's edge: weights on the triangle cannot reach it
            return make_error(ErrorCode::out_of_range,
                              "render vertex %u cannot be bound: %.4f m from where its triangle puts it (past the cloth's edge? "
                              "authored on another pose?)", v, error);
        worst = std::max(worst, error);
        bound[v] = best_t, w1[v] = float(b.y), w2[v] = float(b.z), offset[v] = float(d);
    }

    cloth->render_cloth_triangle = std::move(bound);
    cloth->render_weight_1 = std::move(w1);
    cloth->render_weight_2 = std::move(w2);
    cloth->render_offset = std::move(offset);
    cloth->render_triangles.assign(mesh.triangles, mesh.triangles + 3 * size_t(mesh.triangle_count));
    if (mesh.uv != nullptr)
        cloth->render_uv.assign(mesh.uv, mesh.uv + 2 * size_t(mesh.vertex_count));
    else
        cloth->render_uv.assign(2 * size_t(mesh.vertex_count), 0.0f);
    cloth->refresh_asset();
    if (Result r = check_render_mesh(cloth->asset().render, cloth->asset().triangle_count); !r.ok()) return r;
    if (max_error_m != nullptr) *max_error_m = worst;
    return {};
}

}  // namespace weft
