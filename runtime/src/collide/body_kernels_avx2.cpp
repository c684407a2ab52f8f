// The body pass's hierarchy search and refit at eight lanes (AVX2 + FMA).
#include "collide/body_query.h"

#if defined(WEFT_SIMD_REQUIRE_AVX2) && !WEFT_HAVE_AVX2
#error "WEFT_SIMD=avx2 but this file is not compiled for AVX2 + FMA"
#endif

namespace weft::body_query {

#if WEFT_HAVE_AVX2
const Path* avx2_path() {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return nullptr;
    static constexpr Path path{search_cluster<simd::Float8>, search_again<simd::Float8>, refit_leaves<simd::Float8>,
                                 project_on_planes<simd::Float8>};
    return &path;
}
#else
const Path* avx2_path() { return nullptr; }
#endif

}  // namespace weft::body_query
