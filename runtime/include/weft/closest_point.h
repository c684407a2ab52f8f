// The closest point of a triangle to a point, as barycentric weights: the one copy the runtime's
// body pass, cooking (render meshes, skin bindings) and the tools (weft-bake's sewing, weft-bench)
// share. Not part of a game's frame (weft/weft.h does not include this header).
#pragma once

#include <cstdint>

namespace weft {

// The Voronoi region of the triangle (a, b, c) the closest point lies in: a vertex, an edge or the face.
enum class TriangleRegion : uint8_t { vertex_a, vertex_b, vertex_c, edge_ab, edge_ac, edge_bc, face };

// Barycentric weights on (a, b, c): the point is w0 a + w1 b + w2 c, w0 + w1 + w2 = 1.
template <typename Scalar>
struct BarycentricWeights {
    Scalar w0, w1, w2;
};

// The closest point of triangle (a, b, c) to p (each three coordinates, x y z), by Ericson,
// Real-Time Collision Detection, 5.1.5: find p's Voronoi region among the vertices, edges and face.
// `region`, when not null, receives that region. A degenerate triangle (no area) whose face
// region is reached gives its first vertex.
template <typename Scalar>
BarycentricWeights<Scalar> closest_on_triangle(const Scalar* p, const Scalar* a, const Scalar* b, const Scalar* c,
                                               TriangleRegion* region = nullptr) {
    const auto sub = [](const Scalar* x, const Scalar* y, Scalar* out) {
        out[0] = x[0] - y[0], out[1] = x[1] - y[1], out[2] = x[2] - y[2];
    };
    const auto dot = [](const Scalar* x, const Scalar* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const auto found = [region](TriangleRegion r, Scalar w0, Scalar w1, Scalar w2) {
        if (region != nullptr) *region = r;
        return BarycentricWeights<Scalar>{w0, w1, w2};
    };
    constexpr Scalar zero = 0, one = 1;
    Scalar ab[3], ac[3], ap[3];
    sub(b, a, ab);
    sub(c, a, ac);
    sub(p, a, ap);
    const Scalar d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= zero && d2 <= zero) return found(TriangleRegion::vertex_a, one, zero, zero);
    Scalar bp[3];
    sub(p, b, bp);
    const Scalar d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= zero && d4 <= d3) return found(TriangleRegion::vertex_b, zero, one, zero);
    const Scalar vc = d1 * d4 - d3 * d2;
    if (vc <= zero && d1 >= zero && d3 <= zero) {
        const Scalar v = d1 / (d1 - d3);
        return found(TriangleRegion::edge_ab, one - v, v, zero);
    }
    Scalar cp[3];
    sub(p, c, cp);
    const Scalar d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= zero && d5 <= d6) return found(TriangleRegion::vertex_c, zero, zero, one);
    const Scalar vb = d5 * d2 - d1 * d6;
    if (vb <= zero && d2 >= zero && d6 <= zero) {
        const Scalar w = d2 / (d2 - d6);
        return found(TriangleRegion::edge_ac, one - w, zero, w);
    }
    const Scalar va = d3 * d6 - d5 * d4;
    if (va <= zero && (d4 - d3) >= zero && (d5 - d6) >= zero) {
        const Scalar w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return found(TriangleRegion::edge_bc, zero, one - w, w);
    }
    const Scalar sum = va + vb + vc;
    if (!(sum > zero)) return found(TriangleRegion::vertex_a, one, zero, zero);
    const Scalar denominator = one / sum;
    const Scalar v = vb * denominator, w = vc * denominator;
    return found(TriangleRegion::face, one - v - w, v, w);
}

}  // namespace weft
