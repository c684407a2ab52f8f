// The render output of the step (WorldDesc::normals): each particle's vertex normal, the sum of its
// triangles' face normals weighted by their areas (cross(b - a, c - a) is twice the area along the
// normal), then normalised. It walks the triangles as the wind pass does (triangle_groups.h), so the
// scalar and SIMD normals are the same bits.
// With WorldDesc::tangents the same walk also sums each triangle's dP/du and dP/dv (Lengyel 2001,
// "Computing tangent space basis vectors for an arbitrary mesh"), weighted by its uv area, into its
// corners; the tangent is dP/du made orthogonal to the normal (Gram-Schmidt) and normalised, its w
// the handedness: -1 where cross(n, t) points away from dP/dv.
#pragma once

#include <cstring>

#include "kernels.h"
#include "simd/float_w.h"
#include "triangle_groups.h"

namespace weft {

// Adds one lane group's face normals to its corners (corner k of lane l at slot corner[k] + l): a run
// touches each vertex at most once, so the vector stores do not collide.
// One lane group's dP/du and dP/dv from its edges and uv gradients (Particles::uv_gradient at `g`).
template <class F>
struct FaceTangents {
    F tx, ty, tz, bx, by, bz;
};
template <class F>
inline FaceTangents<F> face_tangents(const Particles& p, uint32_t g, F e1x, F e1y, F e1z, F e2x, F e2y, F e2z) {
    using namespace simd;
    const F g0 = load(p.uv_gradient[0] + g, F{}), g1 = load(p.uv_gradient[1] + g, F{});
    const F g2 = load(p.uv_gradient[2] + g, F{}), g3 = load(p.uv_gradient[3] + g, F{});
    return {mul_add(g0, e1x, g1 * e2x), mul_add(g0, e1y, g1 * e2y), mul_add(g0, e1z, g1 * e2z),
            mul_add(g2, e1x, g3 * e2x), mul_add(g2, e1y, g3 * e2y), mul_add(g2, e1z, g3 * e2z)};
}

// `g`: the lane group's first entry in Particles::uv_gradient (read only with Tangents).
template <class F, bool Tangents>
inline void add_face_normals(const Particles& p, const uint32_t (&corner)[3], F weight, uint32_t g) {
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
    if constexpr (Tangents) {  // padding lanes have zero gradients
        const FaceTangents<F> f = face_tangents<F>(p, g, e1x, e1y, e1z, e2x, e2y, e2z);
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = corner[k];
            store(p.tangent_x + i, load(p.tangent_x + i, F{}) + f.tx);
            store(p.tangent_y + i, load(p.tangent_y + i, F{}) + f.ty);
            store(p.tangent_z + i, load(p.tangent_z + i, F{}) + f.tz);
            store(p.bitangent_x + i, load(p.bitangent_x + i, F{}) + f.bx);
            store(p.bitangent_y + i, load(p.bitangent_y + i, F{}) + f.by);
            store(p.bitangent_z + i, load(p.bitangent_z + i, F{}) + f.bz);
        }
    }
}

// F::width triangles (3 slots each at `triangle`) with gathered corners; the sums go back lane by
// lane, corner by corner, in triangle order (lanes may share a vertex), as one at a time would.
template <class F, bool Tangents>
inline void add_gathered_face_normals(const Particles& p, const uint32_t* triangle, uint32_t g) {
    using namespace simd;
    constexpr uint32_t W = F::width;
    uint32_t corner[3][W];
    for (uint32_t l = 0; l < W; ++l)
        for (int k = 0; k < 3; ++k) corner[k][l] = triangle[3 * l + uint32_t(k)];
    F x[3], y[3], z[3];
    for (int k = 0; k < 3; ++k)
        x[k] = gather_by_loads(p.x, corner[k], F{}), y[k] = gather_by_loads(p.y, corner[k], F{}), z[k] = gather_by_loads(p.z, corner[k], F{});
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
    if constexpr (Tangents) {
        const FaceTangents<F> f = face_tangents<F>(p, g, e1x, e1y, e1z, e2x, e2y, e2z);
        float tx[W], ty[W], tz[W], bx[W], by[W], bz[W];
        store(tx, f.tx), store(ty, f.ty), store(tz, f.tz), store(bx, f.bx), store(by, f.by), store(bz, f.bz);
        for (uint32_t l = 0; l < W; ++l)
            for (int k = 0; k < 3; ++k) {
                const uint32_t i = corner[k][l];
                p.tangent_x[i] += tx[l], p.tangent_y[i] += ty[l], p.tangent_z[i] += tz[l];
                p.bitangent_x[i] += bx[l], p.bitangent_y[i] += by[l], p.bitangent_z[i] += bz[l];
            }
    }
}

// Fills p.normal_{x,y,z} for every slot: unit length where the particle has a triangle of non-zero
// area, (0, 0, 0) elsewhere (padding slots, a particle whose triangles all collapsed). With
// Tangents also p.tangent_{x,y,z,w}: unit and orthogonal to the normal, (0, 0, 0, 1) where dP/du
// has nothing across the normal (no triangle with a uv area, or dP/du along the normal).
template <class F, bool Tangents>
void vertex_normals(const Particles& p, const ClothAsset& a) {
    using namespace simd;
    const size_t bytes = sizeof(float) * p.slot_count;
    for (float* sum : {p.normal_x, p.normal_y, p.normal_z}) std::memset(sum, 0, bytes);
    if constexpr (Tangents)
        for (float* sum : {p.tangent_x, p.tangent_y, p.tangent_z, p.bitangent_x, p.bitangent_y, p.bitangent_z})
            std::memset(sum, 0, bytes);
    const uint32_t single = a.wind_lane_count - a.wind_run_triangles;  // + t: triangle t's gradient entry
    for_each_triangle_group<F>(
        a, [&](const uint32_t (&corner)[3], uint32_t lane) { add_face_normals<F, Tangents>(p, corner, load(a.wind_lane_weight + lane, F{}), lane); },
        [&](uint32_t t) { add_gathered_face_normals<F, Tangents>(p, a.triangles + 3 * t, single + t); },
        [&](const uint32_t (&corner)[3], uint32_t t) { add_face_normals<Float1, Tangents>(p, corner, Float1{1.0f}, single + t); });
    const F zero = splat(0.0f, F{}), one = splat(1.0f, F{}), tiny = splat(1e-30f, F{});
    for (uint32_t i = 0; i < p.slot_count; i += F::width) {
        const F sx = load(p.normal_x + i, F{}), sy = load(p.normal_y + i, F{}), sz = load(p.normal_z + i, F{});
        const F length = sqrt(mul_add(sx, sx, mul_add(sy, sy, sz * sz)));
        const auto some = length > zero;
        const F inv = one / max(length, tiny);
        const F nx = keep_if(some, sx * inv), ny = keep_if(some, sy * inv), nz = keep_if(some, sz * inv);
        store(p.normal_x + i, nx);
        store(p.normal_y + i, ny);
        store(p.normal_z + i, nz);
        if constexpr (Tangents) {
            const F ux = load(p.tangent_x + i, F{}), uy = load(p.tangent_y + i, F{}), uz = load(p.tangent_z + i, F{});
            const F along = mul_add(nx, ux, mul_add(ny, uy, nz * uz));  // Gram-Schmidt: t = u - n (n . u)
            const F tx = neg_mul_add(nx, along, ux), ty = neg_mul_add(ny, along, uy), tz = neg_mul_add(nz, along, uz);
            const F t_length = sqrt(mul_add(tx, tx, mul_add(ty, ty, tz * tz)));
            const auto t_some = t_length > zero;
            const F t_inv = one / max(t_length, tiny);
            store(p.tangent_x + i, keep_if(t_some, tx * t_inv));
            store(p.tangent_y + i, keep_if(t_some, ty * t_inv));
            store(p.tangent_z + i, keep_if(t_some, tz * t_inv));
            // Handedness: the side of the (n, t) plane dP/dv lies on; cross(n, t) . b.
            const F bx = load(p.bitangent_x + i, F{}), by = load(p.bitangent_y + i, F{}), bz = load(p.bitangent_z + i, F{});
            const F cx = ny * tz - nz * ty, cy = nz * tx - nx * tz, cz = nx * ty - ny * tx;
            const F side = mul_add(cx, bx, mul_add(cy, by, cz * bz));
            store(p.tangent_w + i, select(side < zero, splat(-1.0f, F{}), one));
        }
    }
}

}  // namespace weft
