// Skin constraints for a cloth dressed on a body (weft/attachments.h: bind_skin_constraints): every
// free particle bound to the closest triangle of the body's offset hull, the way weft-bake binds a
// waistband's attachments (barycentric weights of the closest point), plus its signed distance
// along the interpolated normal there at rest. Computed from a world in which the cloth sits in its
// dressed pose on the body's rest pose (a scene just built).
#pragma once

#include <string>
#include <vector>

#include "weft/attachments.h"
#include "weft/weft.h"

namespace weft::scenes {

struct SkinOptions {
    // Radius of the ball around the particle's skinned rest position, metres (NvCloth's max
    // distance). docs/decisions/2026-11-26-body-collision-models.md, "Skin constraints".
    float max_distance_m = 0.03f;
    // Particles further than this off the hull at rest (a skirt's hem, a loose sleeve) hang free:
    // no max distance (a ball around a point skinned to the thigh drags the hem with the leg).
    float loose_offset_m = 0.02f;
    // How far behind the offset hull a particle may go, metres; negative: that far in front. The
    // backstop plane is tangent at the bound point only, and a particle sliding along it sinks into
    // a concave hull, so it stands 1.5 mm in front (deepest particle on the tee 3.3 -> 1.7 mm).
    float backstop_m = -0.0015f;
};

// The arrays bind_skin_constraints points into: they must outlive the cloth.
struct SkinBinding {
    std::vector<uint32_t> particle, triangle;
    std::vector<float> weight, rest_offset_m, max_distance_m, backstop_m;
    SkinConstraints constraints() const;
};

// Binds every free particle of `cloth` to its closest hull triangle of `body` (by brute force with
// a bounding-sphere cut: offline work) and hands the arrays to bind_skin_constraints. Empty on
// success, else why not.
std::string bind_skin(World* world, ClothId cloth, BodyId body, const SkinOptions& options, SkinBinding* out);

}  // namespace weft::scenes
