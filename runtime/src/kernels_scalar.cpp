// The scalar path: every kernel template at one lane. Always compiled; the reference the SIMD
// path is tested against.
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

namespace weft {

const Kernels& scalar_kernels() {
    using F = simd::Float1;
    static constexpr Kernels kernels{SimdPath::scalar, integrate_verlet<F>, solve_coarse_level<F>,
                                     {project_springs<F, true>, project_springs<F, false>},
                                     project_tethers<F>, collide<F>, apply_wind<F>, particle_bounds<F>, health_sums<F>, skin_frames<F>, project_skin<F>,
                                     vertex_normals<F, false>, vertex_normals<F, true>, render_mesh<F>};
    return kernels;
}

}  // namespace weft
