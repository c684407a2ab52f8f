// The AVX2 + FMA path: the same kernel templates at eight lanes.
#include "aerodynamics/wind.h"
#include "collide/colliders.h"
#include "constraints/coarse.h"
#include "constraints/distance.h"
#include "constraints/skin.h"
#include "constraints/tethers.h"
#include "health.h"
#include "integrate/verlet.h"
#include "kernels.h"
#include "render/normals.h"
#include "render/render_mesh.h"

#if defined(WEFT_SIMD_REQUIRE_AVX2) && !WEFT_HAVE_AVX2
#error "WEFT_SIMD=avx2 but this file is not compiled for AVX2 + FMA"
#endif

namespace weft {

#if WEFT_HAVE_AVX2
const Kernels* avx2_kernels() {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return nullptr;
    using F = simd::Float8;
    static constexpr Kernels kernels{SimdPath::avx2, integrate_verlet<F>, solve_coarse_level<F>,
                                     {project_springs<F, true>, project_springs<F, false>},
                                     project_tethers<F>, collide<F>, apply_wind<F>, particle_bounds<F>, health_sums<F>, skin_frames<F>, project_skin<F>,
                                     vertex_normals<F, false>, vertex_normals<F, true>, render_mesh<F>};
    return &kernels;
}
#else
const Kernels* avx2_kernels() { return nullptr; }
#endif

}  // namespace weft
