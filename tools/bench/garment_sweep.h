// The dressed garment as a `weft-bench sweep` scene (issue 4, point 5): the sample skirt sewn onto
// the project's mannequin (weft-bake --body mannequin), on the mannequin walking in place
// (samples/scenes/skirt-walk.json), run at any explicit split and measured like the seed scenes:
// trajectory against a reference, strain, and the deepest free particle below the body's offset hull.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "bench/accuracy.h"
#include "common/scene.h"

namespace weft::bench {

struct GarmentSweepScene {
    GarmentSweepScene() = default;
    GarmentSweepScene(const GarmentSweepScene&) = delete;
    GarmentSweepScene& operator=(const GarmentSweepScene&) = delete;
    ~GarmentSweepScene();  // removes `dir`

    scenes::Scene scene;             // skirt-walk.json; its asset is written into `dir`
    std::filesystem::path dir;       // this process's own folder (tests run in parallel)
    std::unique_ptr<scenes::SceneWorld> built;  // built once: the asset the strains are measured on
    const ClothAsset& asset() const { return *built->cloths[0].asset; }
};

// Dresses the skirt on the mannequin (a few seconds) and builds the scene once.
std::string make_garment_sweep_scene(GarmentSweepScene* out);

// Builds the garment's world with the split, tethers, coarse level, relaxation and SIMD path of
// `split` (the fabric's own compliance and damping).
std::string build_garment_world(const GarmentSweepScene& garment, const scenes::SceneOptions& split,
                                scenes::SceneWorld* out);

// Runs the garment with the split, tethers, coarse level, relaxation and SIMD path of `split` (the
// fabric's own compliance and damping), the body posed before every step as weft-sim does; the
// scene's dt (1/60 s). Fills the trajectory like run_trajectory, with max_penetration_m the deepest
// free particle below the body's offset hull over the sampled frames.
std::string run_garment_trajectory(const GarmentSweepScene& garment, const scenes::SceneOptions& split,
                                   const Sampling& sampling, Trajectory* out);

}  // namespace weft::bench
