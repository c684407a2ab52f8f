// The render mesh driven by the cloth (WorldDesc::render_meshes; ClothAsset::render): each render
// vertex is its bound cloth triangle's point at its barycentric weights, moved its offset along the
// normalised interpolated vertex normal (the mesh-to-mesh mapping of APEX clothing and Chaos cloth).
// Runs after the vertex normals. Render vertices go F::width at a time with gathered corners, the
// last few one at a time through the same template, so the scalar and SIMD paths give the same bits.
#pragma once

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Render vertices v .. v + F::width - 1.
template <class F>
inline void render_vertices(const Particles& p, const ClothAsset& a, const RenderOutput& out, uint32_t v) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    const RenderMesh& m = a.render;
    uint32_t corner[3][W];
    for (uint32_t l = 0; l < W; ++l) {
        const uint32_t* t = a.triangles + 3 * size_t(m.cloth_triangle[v + l]);
        for (int k = 0; k < 3; ++k) corner[k][l] = t[k];
    }
    const F one = splat(1.0f, F{});
    const F w1 = load(m.weight_1 + v, F{}), w2 = load(m.weight_2 + v, F{});
    const F w[3] = {(one - w1) - w2, w1, w2};
    // sum_k w_k a[corner k]: the same order of operations on every path.
    auto interpolate = [&](const float* array) {
        F sum = w[0] * gather_by_loads(array, corner[0], F{});
        sum = mul_add(w[1], gather_by_loads(array, corner[1], F{}), sum);
        return mul_add(w[2], gather_by_loads(array, corner[2], F{}), sum);
    };
    const F sx = interpolate(p.normal_x), sy = interpolate(p.normal_y), sz = interpolate(p.normal_z);
    const F length = sqrt(mul_add(sx, sx, mul_add(sy, sy, sz * sz)));
    const auto some = length > splat(0.0f, F{});
    const F inv = one / max(length, splat(1e-30f, F{}));
    const F nx = keep_if(some, sx * inv), ny = keep_if(some, sy * inv), nz = keep_if(some, sz * inv);
    const F offset = load(m.offset_m + v, F{});
    store(out.x + v, mul_add(offset, nx, interpolate(p.x)));
    store(out.y + v, mul_add(offset, ny, interpolate(p.y)));
    store(out.z + v, mul_add(offset, nz, interpolate(p.z)));
    store(out.normal_x + v, nx);
    store(out.normal_y + v, ny);
    store(out.normal_z + v, nz);
}

template <class F>
void render_mesh(const Particles& p, const ClothAsset& a, const RenderOutput& out) {
    const uint32_t count = a.render.vertex_count;
    uint32_t v = 0;
    if constexpr (F::width > 1)
        for (; v + F::width <= count; v += F::width) render_vertices<F>(p, a, out, v);
    for (; v < count; ++v) render_vertices<simd::Float1>(p, a, out, v);
}

}  // namespace weft
