// weft-bench garment: the dressed garments on their animated bodies (issue 13, point 8).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bake/bake.h"
#include "common/scene.h"

namespace weft::bench {

// Bakes the sample skirt and tee onto the mannequin (and the shared pencil dress onto mean_all when
// ../shared/data is there), runs their scene files and prints per-pass costs per step, the plain
// Embree point-query baseline measured in the same run, and the deepest penetration.
// A row's body collision: the model, and whether the mannequin's limb capsules stand beside it (the
// scene file's, or else the thighs'; scenes on another body skip such a row).
struct GarmentModel {
    BodyCollision collision = BodyCollision::exact;
    bool limb_capsules = false;
};
// "exact", "cached_planes", "skin_constraints", each optionally followed by "+limb_capsules".
// False for an unknown name.
bool garment_model_from_name(const std::string& name, GarmentModel* out);
std::string garment_model_name(const GarmentModel& model);

// One row per scene and body collision model in `models` (the first also times the plain pass).
// `simd`: the path every scene runs on (automatic: the widest this CPU has).
int run_garment(uint32_t steps, bool as_json, const std::vector<GarmentModel>& models,
                SimdPath simd = SimdPath::automatic);

// The project's mannequin (default measurements, rest pose) as a body to sew onto.
std::string mannequin_sew_body(bake::SewBody* out);

// Loads `scene_file`, dresses `pattern` on `body` (weft-bake --body) and writes the asset the scene
// names into `dir` (build the scene with `dir` among its asset folders). Returns the failure message.
std::string dress_scene(const std::string& scene_file, const std::string& pattern, const bake::SewBody& body,
                        const std::filesystem::path& dir, scenes::Scene* scene, bake::Baked* baked);

}  // namespace weft::bench
