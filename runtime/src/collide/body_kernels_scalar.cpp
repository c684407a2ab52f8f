// The body pass's hierarchy search and refit at one lane: the reference the AVX2 path is tested against.
#include "collide/body_query.h"

namespace weft::body_query {

const Path& scalar_path() {
    static constexpr Path path{search_cluster<simd::Float1>, search_again<simd::Float1>, refit_leaves<simd::Float1>,
                                 project_on_planes<simd::Float1>};
    return path;
}

}  // namespace weft::body_query
