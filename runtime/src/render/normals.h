// The render output of the step (WorldDesc::normals): each particle's vertex normal, the sum of its
// triangles' face normals weighted by their areas (cross(b - a, c - a) is twice the area along the
// normal), then normalised. It walks the triangles as the wind pass does (triangle_groups.h), so the
// scalar and SIMD normals are the same bits.
#pragma once

#include <cstring>

#include "kernels.h"
#include "simd/float_w.h"
#include "triangle_groups.h"

namespace weft {

// Adds one lane group's face normals to its corners (corner k of lane l at slot corner[k] + l): a run
// touches each vertex at most once, so the vector stores do not collide.
template <class F>
inline void add_face_normals(const Particles& p, const uint32_t (&corner)[3], F weight) {
    using namespace simd;
    F x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = corner[k];
        x[k] = load(p.x + i, F{}), y[k] = load(p.y + i, F{}), z[k] = load(p.z + i, F{});
    }
    const F e1x = x[1] - x[0], e1y = y[1] - y[0], e1z = z[1] - z[0];
    const F e2x = x[2] - x[0], e2y = y[2] - y[0], e2z = z[2] - z[0];
    const F nx = (e1y * e2z - e1z * e2y) * weight, ny = (e1z * e2x - e1x * e2z) * weight, nz = (e1x * e2y - e1y * e2x) * weight;
    for (int k = 0; k < 3; ++k) {
        const uint32_t i = corner[k];
        store(p.normal_x + i, load(p.normal_x + i, F{}) + nx);
        store(p.normal_y + i, load(p.normal_y + i, F{}) + ny);
        store(p.normal_z + i, load(p.normal_z + i, F{}) + nz);
    }
}

// F::width triangles (3 slots each at `triangle`) with gathered corners; the sums go back lane by
// lane, corner by corner, in triangle order (lanes may share a vertex), as one at a time would.
template <class F>
inline void add_gathered_face_normals(const Particles& p, const uint32_t* triangle) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    uint32_t corner[3][W];
    for (uint32_t l = 0; l < W; ++l)
        for (int k = 0; k < 3; ++k) corner[k][l] = triangle[3 * l + uint32_t(k)];
    F x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k)
        x[k] = gather(p.x, corner[k], F{}), y[k] = gather(p.y, corner[k], F{}), z[k] = gather(p.z, corner[k], F{});
    const F e1x = x[1] - x[0], e1y = y[1] - y[0], e1z = z[1] - z[0];
    const F e2x = x[2] - x[0], e2y = y[2] - y[0], e2z = z[2] - z[0];
    float nx[W], ny[W], nz[W];
    store(nx, e1y * e2z - e1z * e2y), store(ny, e1z * e2x - e1x * e2z), store(nz, e1x * e2y - e1y * e2x);
    for (uint32_t l = 0; l < W; ++l)
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = corner[k][l];
            p.normal_x[i] += nx[l];
            p.normal_y[i] += ny[l];
            p.normal_z[i] += nz[l];
        }
}

// Fills p.normal_{x,y,z} for every slot: unit length where the particle has a triangle of non-zero
// area, (0, 0, 0) elsewhere (padding slots, a particle whose triangles all collapsed).
template <class F>
void vertex_normals(const Particles& p, const ClothAsset& a) {
    using namespace simd;
    const size_t bytes = sizeof(float) * p.slot_count;
    std::memset(p.normal_x, 0, bytes);
    std::memset(p.normal_y, 0, bytes);
    std::memset(p.normal_z, 0, bytes);
    for_each_triangle_group<F>(
        a, [&](const uint32_t (&corner)[3], uint32_t lane) { add_face_normals<F>(p, corner, load(a.wind_lane_weight + lane, F{})); },
        [&](uint32_t t) { add_gathered_face_normals<F>(p, a.triangles + 3 * t); },
        [&](const uint32_t (&corner)[3], uint32_t) { add_face_normals<Float1>(p, corner, Float1{1.0f}); });
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{});
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const F nx = load(p.normal_x + i, F{}), ny = load(p.normal_y + i, F{}), nz = load(p.normal_z + i, F{});
        const F length = sqrt(mul_add(nx, nx, mul_add(ny, ny, nz * nz)));
        const auto some = length > zero;
        const F inv = one / max(length, splat(1e-30f, F{}));
        store(p.normal_x + i, keep_if(some, nx * inv));
        store(p.normal_y + i, keep_if(some, ny * inv));
        store(p.normal_z + i, keep_if(some, nz * inv));
    }
}

}  // namespace weft
