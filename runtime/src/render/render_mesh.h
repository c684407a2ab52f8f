// The render mesh driven by the cloth (WorldDesc::render_meshes; ClothAsset::render): each render
// vertex is its bound cloth triangle's point at its barycentric weights, moved its offset along the
// normalised interpolated vertex normal (the mesh-to-mesh mapping of APEX clothing and Chaos cloth).
// Runs after the vertex normals. The particles' positions and normals are first packed side by side
// (kRenderCornerFloats a slot), so a corner is two 16-byte loads rather than six scattered ones;
// render vertices then go F::width at a time, the last few one at a time through the same template,
// so the scalar and SIMD paths give the same bits.
#pragma once

#include "kernels.h"
#include "simd/float_w.h"

namespace weft {

// Render vertices v .. v + F::width - 1, their corners read from `corners` (pack_corners).
template <class F>
inline void render_vertices(const ClothAsset& a, const RenderOutput& out, uint32_t v) {
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
    // sum_k w_k a[corner k] for the three values at `at` in each record: the same order of
    // operations on every path.
    auto interpolate = [&](uint32_t at, F* x, F* y, F* z) {
        F cx, cy, cz;
        gather_xyz(out.corners + at, kRenderCornerFloats, corner[0], &cx, &cy, &cz);
        *x = w[0] * cx, *y = w[0] * cy, *z = w[0] * cz;
        for (int k = 1; k < 3; ++k) {
            gather_xyz(out.corners + at, kRenderCornerFloats, corner[k], &cx, &cy, &cz);
            *x = mul_add(w[k], cx, *x), *y = mul_add(w[k], cy, *y), *z = mul_add(w[k], cz, *z);
        }
    };
    F sx, sy, sz, px, py, pz;
    interpolate(4, &sx, &sy, &sz);
    interpolate(0, &px, &py, &pz);
    const F length = sqrt(mul_add(sx, sx, mul_add(sy, sy, sz * sz)));
    const auto some = length > splat(0.0f, F{});
    const F inv = one / max(length, splat(1e-30f, F{}));
    const F nx = keep_if(some, sx * inv), ny = keep_if(some, sy * inv), nz = keep_if(some, sz * inv);
    const F offset = load(m.offset_m + v, F{});
    store(out.x + v, mul_add(offset, nx, px));
    store(out.y + v, mul_add(offset, ny, py));
    store(out.z + v, mul_add(offset, nz, pz));
    store(out.normal_x + v, nx);
    store(out.normal_y + v, ny);
    store(out.normal_z + v, nz);
}

// Each slot's record: x, y, z, 0, normal x, y, z, 0.
inline void pack_corners(const Particles& p, float* corners) {
    for (uint32_t s = 0; s < p.slot_count; ++s) {
        float* r = corners + size_t(kRenderCornerFloats) * s;
        r[0] = p.x[s], r[1] = p.y[s], r[2] = p.z[s], r[3] = 0.0f;
        r[4] = p.normal_x[s], r[5] = p.normal_y[s], r[6] = p.normal_z[s], r[7] = 0.0f;
    }
}

template <class F>
void render_mesh(const Particles& p, const ClothAsset& a, const RenderOutput& out) {
    pack_corners(p, out.corners);
    const uint32_t count = a.render.vertex_count;
    uint32_t v = 0;
    if constexpr (F::width > 1)
        for (; v + F::width <= count; v += F::width) render_vertices<F>(a, out, v);
    for (; v < count; ++v) render_vertices<simd::Float1>(a, out, v);
}

}  // namespace weft
