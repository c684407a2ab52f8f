// The seed paper's experiments (section 3) as in-memory meshes and ready-to-step worlds, shared by
// weft-bench, weft-sim and the tests. Defaults reproduce the paper: a 2 m square cloth, dt 0.033 s,
// 3 correction iterations.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/scene.h"
#include "weft/cook.h"

namespace weft::scenes {

// Made-up garment data on a grid (tests, the fuzz corpus): texture coordinates from the flat
// grid, two panels (the left and the right half of the columns), seam points that join each
// row's first and last particle (and three-source points at the corners), and a linen-like fabric.
struct GridGarment {
    std::vector<float> uv;
    std::vector<uint32_t> seam_first, seam_source;
    std::vector<uint16_t> panel;
    Fabric fabric;
    // Points `desc`'s optional garment inputs at this data.
    void apply(ClothMeshDesc& desc) const;
};
GridGarment make_grid_garment(const GridMesh& grid);

enum class SeedScene { drape, flag, sphere };
const char* scene_name(SeedScene scene);

struct SceneOptions {
    uint32_t n = 100;
    SimdPath simd = SimdPath::automatic;
    // The budget: `sweeps` with the automatic policy (config "default"), or an explicit split.
    uint32_t sweeps = 3;
    bool explicit_split = false;
    uint32_t substeps = 1;
    uint32_t iterations = 3;
    bool tethers = true;
    bool tethers_before_sweeps = false;
    CoarseLevel coarse_level = CoarseLevel::automatic;  // explicit split (ClothDesc::coarse_level)
    uint32_t coarse_iterations = 1;  // coarse sweeps per substep (explicit split)
    bool contact_tethers = ClothDesc{}.contact_tethers;  // ClothDesc::contact_tethers
    float coarse_spacing_m = CookOptions{}.coarse_spacing_m;
    uint32_t tethers_per_particle = 2;  // nearest pinned particles each particle is tethered to
    float relaxation = 1.0f;
    float damping_per_s = ClothDesc{}.damping_per_s;
    SpringProjection projection = SpringProjection::exact;
    // XPBD compliance per spring kind, m/N (ClothDesc::compliance_m_per_n; 0 = hard).
    float stretch_compliance_m_per_n = ClothDesc{}.compliance_m_per_n[0];
    float shear_compliance_m_per_n = ClothDesc{}.compliance_m_per_n[1];
    float bend_compliance_m_per_n = ClothDesc{}.compliance_m_per_n[2];
    // The flag's fabric: heavy (a canvas banner), so that the seed's 10 to 40 m/s span drooping to
    // streaming; at cotton's 0.15 kg/m2 the wind of eq. (2)-(3) holds it fully out from 10 m/s on.
    float flag_density_kg_m2 = 2.0f;
    float wind_m_s = 20.0f;        // flag only: along +x, 10 degrees off the flag's plane
    float sphere_inflation_m = 0.01f;
    float sphere_friction = 0.0f;
    float sphere_offset_m = 0.0f;  // drop point off the sphere's top, along x
    bool profile = false;
    bool normals = false;  // WorldDesc::normals: the step ends with vertex normals
};

// The two configurations every figure compares (docs/solver.md):
//   plain:   the seed's method, 1 substep x `sweeps` iterations, no tethers, no coarse level,
//            relaxation 1 (the baseline);
//   default: ClothDesc's defaults, the automatic budget policy at `sweeps`.
enum class Config { plain, default_config };
const char* config_name(Config config);
void apply_config(Config config, uint32_t sweeps, SceneOptions& options);

// A world holding one seed scene, with the block it lives in.
struct SeedWorld {
    SeedScene scene{};
    GridMesh mesh;
    std::unique_ptr<CookedCloth> cooked;  // behind a pointer: the world points at its asset
    std::unique_ptr<unsigned char[], void (*)(void*)> memory{nullptr, nullptr};
    World* world = nullptr;
    ClothId cloth{};
    float dt_s = kSeedTimeStep_s;
    const ClothAsset& asset() const { return cooked->asset(); }
};

// The experiment as a scene (what samples/scenes/*.json also describe).
Scene seed_scene(SeedScene scene, const SceneOptions& options);

// Self-collision's heap (weft-bench self, tests/test_self_collision.cpp): a 50 x 50 sheet, 1 m
// square, hanging in the x-y plane and let go 4 cm over a bar (a capsule of 5 cm radius lying on a
// ground with friction, its axis 3 cm behind the sheet's plane): the lower edge lands on the bar's
// side and is thrown back, and the rest of the sheet folds down onto itself. 8 substeps of one sweep
// a frame of 1/60 s: at one substep the sheet, landing at 4-5 m/s, crumples within its own plane
// (overlapping triangles of one layer) before any layer lies on another.
Scene heap_scene();

// Builds the scene; returns the failure message (empty on success).
std::string make_seed_world(SeedScene scene, const SceneOptions& options, SeedWorld* out);

}  // namespace weft::scenes
