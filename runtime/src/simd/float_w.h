// One wide float type per target (the Box2D v3 habit): kernels are templates over `F`, written once,
// and instantiated for Float1 (the scalar path) and Float8 (AVX2 + FMA). Lanes run across
// constraints or particles. Each operation maps to one IEEE-exact instruction on both paths
// (add, sub, mul, div, sqrt, fused multiply-add), so the two paths give bit-identical results for
// the same order of work; the build disables implicit contraction (-ffp-contract=off).
#pragma once

#include <cmath>
#include <cstring>
#include <cstdint>

#if defined(__AVX2__) && defined(__FMA__) && !defined(WEFT_SIMD_SCALAR_ONLY)
#define WEFT_HAVE_AVX2 1
#include <immintrin.h>
#else
#define WEFT_HAVE_AVX2 0
#endif

#if !defined(WEFT_SCALAR_FMA)
#if defined(__FMA__)
#define WEFT_SCALAR_FMA 1
#else
#define WEFT_SCALAR_FMA 0
#endif
#endif

namespace weft::simd {

// --- scalar: one lane ---------------------------------------------------------------------------
struct Float1 {
    static constexpr uint32_t width = 1;
    float v;
};
struct Mask1 {
    bool v;
};

inline Float1 load(const float* p, Float1) { return {*p}; }
inline void store(float* p, Float1 a) { *p = a.v; }
// The first n lanes at p (n >= 1): the tail of a row. Other lanes read as 0 and are not written.
// base[index[k]] for every lane k.
inline Float1 gather(const float* base, const uint32_t* index, Float1) { return {base[*index]}; }
// The same, as one scalar load per lane (see the Float8 form).
inline Float1 gather_by_loads(const float* base, const uint32_t* index, Float1) { return {base[*index]}; }
// base[index[k]] = a[k] for every lane: the inverse of gather_by_loads (the indices must differ).
inline void scatter_by_stores(float* base, const uint32_t* index, Float1 a) { base[*index] = a.v; }
// The first three floats of records of `stride` floats: x, y, z of record index[k] for every lane.
// The records must be readable 16 bytes from their start (the wide form loads four floats).
inline void gather_xyz(const float* base, uint32_t stride, const uint32_t* index, Float1* x, Float1* y, Float1* z) {
    const float* r = base + size_t(stride) * *index;
    *x = {r[0]}, *y = {r[1]}, *z = {r[2]};
}
// table[index[k]] for every lane k, where the lanes' indices lie within 8 of the first lane's
// (index[k] - index[0] in [0, 7]; the table is readable up to entry index[0] + 7).
inline Float1 gather_near(const float* table, const uint32_t* index, Float1) { return {table[*index]}; }
inline Float1 splat(float s, Float1) { return {s}; }
inline Float1 operator+(Float1 a, Float1 b) { return {a.v + b.v}; }
inline Float1 operator-(Float1 a, Float1 b) { return {a.v - b.v}; }
inline Float1 operator*(Float1 a, Float1 b) { return {a.v * b.v}; }
inline Float1 operator/(Float1 a, Float1 b) { return {a.v / b.v}; }
inline Float1 sqrt(Float1 a) { return {std::sqrt(a.v)}; }
// a * b + c, rounded once. WEFT_SCALAR_FMA is set for the whole library by the build (not per
// file), so every translation unit agrees: with a SIMD path the scalar path fuses too (std::fma is
// one instruction on FMA targets, a correctly rounded library call elsewhere) and stays bit-identical
// to it; a scalar-only build rounds twice.
inline Float1 mul_add(Float1 a, Float1 b, Float1 c) {
#if WEFT_SCALAR_FMA
    return {std::fma(a.v, b.v, c.v)};
#else
    return {a.v * b.v + c.v};
#endif
}
// c - a * b, rounded once (see mul_add).
inline Float1 neg_mul_add(Float1 a, Float1 b, Float1 c) {
#if WEFT_SCALAR_FMA
    return {std::fma(-a.v, b.v, c.v)};
#else
    return {c.v - a.v * b.v};
#endif
}
inline Float1 min(Float1 a, Float1 b) { return {a.v < b.v ? a.v : b.v}; }
inline Float1 abs(Float1 a) { return {std::fabs(a.v)}; }
inline Float1 max(Float1 a, Float1 b) { return {a.v > b.v ? a.v : b.v}; }
inline Mask1 operator>(Float1 a, Float1 b) { return {a.v > b.v}; }
inline Mask1 operator<(Float1 a, Float1 b) { return {a.v < b.v}; }
inline Mask1 operator&(Mask1 a, Mask1 b) { return {a.v && b.v}; }
inline Mask1 operator|(Mask1 a, Mask1 b) { return {a.v || b.v}; }
// The value where the mask holds, +0 elsewhere (also when the value is NaN or infinite).
inline Float1 keep_if(Mask1 m, Float1 a) { return {m.v ? a.v : 0.0f}; }
// a where the mask holds, b elsewhere.
inline Float1 select(Mask1 m, Float1 a, Float1 b) { return {m.v ? a.v : b.v}; }
inline bool any(Mask1 m) { return m.v; }
// Lanes k >= n (the one lane is lane 0).
inline Mask1 lanes_from(uint32_t n, Float1) { return {n == 0}; }
inline bool all(Mask1 m) { return m.v; }

#if WEFT_HAVE_AVX2
// --- AVX2 + FMA: eight lanes --------------------------------------------------------------------
struct Float8 {
    static constexpr uint32_t width = 8;
    __m256 v;
};
struct Mask8 {
    __m256 v;
};

// Unaligned loads: a run starts at any particle slot. On AVX2 hardware they cost the same as
// aligned ones when the data happens to be aligned.
inline Float8 load(const float* p, Float8) { return {_mm256_loadu_ps(p)}; }
inline void store(float* p, Float8 a) { _mm256_storeu_ps(p, a.v); }
// Lanes k >= n.
inline Mask8 lanes_from(uint32_t n, Float8) {
    return {_mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 8), _mm256_set1_epi32(int(n))))};
}
inline Float8 gather(const float* base, const uint32_t* index, Float8) {
    return {_mm256_i32gather_ps(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index)), 4)};
}
// Eight scalar loads and inserts instead of vgatherdps: measured faster on this Zen 4 for the
// coarse level's few, scattered nodes (its pass 1.20 -> 0.94 us a substep at n = 50, docs/solver.md).
inline Float8 gather_by_loads(const float* base, const uint32_t* index, Float8) {
    return {_mm256_setr_ps(base[index[0]], base[index[1]], base[index[2]], base[index[3]], base[index[4]], base[index[5]],
                           base[index[6]], base[index[7]])};
}
// One 16-byte load per lane and a 4 x 8 transpose (NvCloth's particle records): a third of the
// instructions of three gather_by_loads.
inline void gather_xyz(const float* base, uint32_t stride, const uint32_t* index, Float8* x, Float8* y, Float8* z) {
    auto row = [&](int k) { return _mm_loadu_ps(base + size_t(stride) * index[k]); };
    // Lanes k and k + 4 share a 256-bit register, so one set of shuffles transposes both halves.
    const __m256 r0 = _mm256_set_m128(row(4), row(0)), r1 = _mm256_set_m128(row(5), row(1));
    const __m256 r2 = _mm256_set_m128(row(6), row(2)), r3 = _mm256_set_m128(row(7), row(3));
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);  // x0 x1 y0 y1 | z0 z1 w0 w1
    const __m256 t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
    x->v = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
    y->v = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
    z->v = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t1), _mm256_castps_pd(t3)));
}
// Eight scalar stores straight from the register (vmovss, vextractps): AVX2 has no scatter.
inline void scatter_by_stores(float* base, const uint32_t* index, Float8 a) {
    const __m128 low = _mm256_castps256_ps128(a.v), high = _mm256_extractf128_ps(a.v, 1);
    auto put = [&](uint32_t slot, int bits) { std::memcpy(base + slot, &bits, sizeof(float)); };
    _mm_store_ss(base + index[0], low);
    put(index[1], _mm_extract_ps(low, 1));
    put(index[2], _mm_extract_ps(low, 2));
    put(index[3], _mm_extract_ps(low, 3));
    _mm_store_ss(base + index[4], high);
    put(index[5], _mm_extract_ps(high, 1));
    put(index[6], _mm_extract_ps(high, 2));
    put(index[7], _mm_extract_ps(high, 3));
}
// table[index[k]] with index[k] - index[0] in [0, 7]: one load of the eight entries from
// table[index[0]] and one vpermps (a gather, or a lookup from registers over a whole coarse row,
// measured slower).
inline Float8 gather_near(const float* table, const uint32_t* index, Float8) {
    const __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index));
    const __m256i local = _mm256_sub_epi32(i, _mm256_set1_epi32(int(index[0])));
    return {_mm256_permutevar8x32_ps(_mm256_loadu_ps(table + index[0]), local)};
}
inline Float8 splat(float s, Float8) { return {_mm256_set1_ps(s)}; }
inline Float8 operator+(Float8 a, Float8 b) { return {_mm256_add_ps(a.v, b.v)}; }
inline Float8 operator-(Float8 a, Float8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline Float8 operator*(Float8 a, Float8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline Float8 operator/(Float8 a, Float8 b) { return {_mm256_div_ps(a.v, b.v)}; }
inline Float8 sqrt(Float8 a) { return {_mm256_sqrt_ps(a.v)}; }
inline Float8 mul_add(Float8 a, Float8 b, Float8 c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
inline Float8 neg_mul_add(Float8 a, Float8 b, Float8 c) { return {_mm256_fnmadd_ps(a.v, b.v, c.v)}; }
// Operand order matches Float1's `a < b ? a : b` for NaN inputs (minps returns the second).
inline Float8 min(Float8 a, Float8 b) { return {_mm256_min_ps(a.v, b.v)}; }
inline Float8 abs(Float8 a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
inline Float8 max(Float8 a, Float8 b) { return {_mm256_max_ps(a.v, b.v)}; }
inline Mask8 operator>(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
inline Mask8 operator<(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
inline Mask8 operator&(Mask8 a, Mask8 b) { return {_mm256_and_ps(a.v, b.v)}; }
inline Mask8 operator|(Mask8 a, Mask8 b) { return {_mm256_or_ps(a.v, b.v)}; }
inline Float8 keep_if(Mask8 m, Float8 a) { return {_mm256_and_ps(m.v, a.v)}; }
inline Float8 select(Mask8 m, Float8 a, Float8 b) { return {_mm256_blendv_ps(b.v, a.v, m.v)}; }
inline bool any(Mask8 m) { return _mm256_movemask_ps(m.v) != 0; }
inline bool all(Mask8 m) { return _mm256_movemask_ps(m.v) == 0xFF; }
#endif

}  // namespace weft::simd
