#include "bake.h"

#include <algorithm>

#include "asset_writer.h"

namespace weft::bake {
namespace {

// The garment as cook_cloth's input, with everything a baked garment carries: pins, UVs, panels,
// seam points and the fabric.
struct GarmentInput {
    std::vector<float> masses;
    std::vector<uint16_t> panel;
    weft::Fabric fabric;
    ClothMeshDesc desc;
};

GarmentInput garment_input(const MeshedGarment& g, const Fabric& f) {
    GarmentInput in;
    in.masses = g.masses;
    for (uint32_t p : g.pinned) in.masses[p] = 0.0f;  // the pattern's pins hold
    in.panel.assign(g.panel.begin(), g.panel.end());
    in.fabric.areal_density_kg_m2 = float(f.areal_density_kg_m2);
    in.fabric.compliance_m_per_n[0] = float(f.stretch_compliance);
    in.fabric.compliance_m_per_n[1] = float(f.shear_compliance);
    in.fabric.compliance_m_per_n[2] = float(f.bend_compliance);
    in.fabric.damping_per_s = float(f.damping_per_s);
    in.fabric.thickness_m = float(f.thickness_m);
    in.fabric.friction = float(f.friction);
    in.desc = cloth_mesh_desc(g);
    in.desc.masses = in.masses.data();
    in.desc.uv = g.uv.data();
    if (!g.seam_first.empty()) {
        in.desc.seam_point_count = uint32_t(g.seam_first.size() - 1);
        in.desc.seam_first = g.seam_first.data();
        in.desc.seam_source = g.seam_source.data();
    }
    in.desc.panel_count = uint32_t(g.panel_names.size());
    in.desc.panel = in.panel.data();
    in.desc.fabric = &in.fabric;
    return in;
}

}  // namespace

double run_cost_ns(const ClothAsset& a) {
    double run = 0.0, indexed = 0.0;
    for (uint32_t b = 0; b < a.batch_count; ++b)
        (a.batches[b].layout == BatchLayout::run ? run : indexed) += a.batches[b].lane_count;
    return kRunLaneNs * run + kIndexedLaneNs * indexed;
}

Result cook_garment(const ClothMeshDesc& mesh, const CookOptions& options, bool choose_runs, CookedCloth* out,
                    CookOptions* chosen) {
    if (chosen != nullptr) *chosen = options;
    if (Result r = cook_cloth(mesh, options, out); !r.ok() || !choose_runs) return r;
    double best = run_cost_ns(out->asset());
    for (const auto& [min_run_lanes, max_run_gap] : kRunChoices) {
        CookOptions cook = options;
        cook.min_run_lanes = min_run_lanes;
        cook.max_run_gap = max_run_gap;
        CookedCloth trial;
        if (Result r = cook_cloth(mesh, cook, &trial); !r.ok()) return r;
        if (const double cost = run_cost_ns(trial.asset()); cost < best) {
            best = cost, *out = std::move(trial);
            if (chosen != nullptr) *chosen = cook;
        }
    }
    return {};
}

Status bake_pattern(std::string_view text, const BakeOptions& options, Baked* out) {
    if (Status s = parse_pattern(text, options.parse, &out->pattern); !s.ok()) return s;
    if (Status s = mesh_garment(out->pattern, options.mesh, &out->garment); !s.ok()) return s;
    const GarmentInput input = garment_input(out->garment, out->pattern.fabric);
    if (options.body != nullptr) {
        std::vector<uint32_t> attached;
        for (const Attachment& a : out->garment.attachments) attached.insert(attached.end(), a.particles.begin(), a.particles.end());
        std::sort(attached.begin(), attached.end());
        attached.erase(std::unique(attached.begin(), attached.end()), attached.end());
        if (Status s = sew_garment(input.desc, attached, *options.body, options.sew, &out->sewn, &out->sew_report); !s.ok())
            return {"sewing: " + s.error};
    }
    const ClothMeshDesc& mesh = options.body != nullptr ? out->sewn.desc : input.desc;
    const CookOptions cook = options.body != nullptr ? sewn_cook_options(options.cook) : options.cook;
    if (Result r = cook_garment(mesh, cook, options.choose_runs, &out->cooked, &out->cook_options); !r.ok()) return {r.message};
    if (Result r = assets::write_asset(out->cooked.asset(), &out->bytes); !r.ok()) return {r.message};
    assets::LoadedAsset check;
    if (Result r = assets::load_asset_copy(out->bytes.data(), out->bytes.size(), &check); !r.ok())
        return {std::string("the written asset does not load: ") + r.message};
    return {};
}

}  // namespace weft::bake
