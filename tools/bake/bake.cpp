#include "bake/bake.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include "common/asset_writer.h"
#include "common/metrics.h"

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

CookScore cook_score(const ClothAsset& a) {
    const LanePadding padding = lane_padding(a);
    return {padding.constraints.ratio() > kMaxPaddingRatio || padding.ratio() > kMaxPaddingRatio, run_cost_ns(a)};
}

Result cook_garment(const ClothMeshDesc& mesh, const CookOptions& options, bool choose_runs, CookedCloth* out,
                    CookOptions* chosen) {
    if (chosen != nullptr) *chosen = options;
    if (!choose_runs) return cook_cloth(mesh, options, out);
    // The run shapes are scored without the coarse level and tethers (as cook_packings scores
    // packings): their lanes do not change with the run shape, and a sewn garment's tethers,
    // measured along its flat panels by fast marching, were a fifth of its whole bake when every
    // trial cooked them. The winner is then cooked once with everything.
    CookOptions scoring = options;
    scoring.coarse_spacing_m = 0.0f;
    scoring.tethers_per_particle = 0;
    const bool scoring_is_all = scoring.coarse_spacing_m == options.coarse_spacing_m &&
                                scoring.tethers_per_particle == options.tethers_per_particle;
    CookOptions best_options = options;
    CookScore best{true, HUGE_VAL};
    CookedCloth best_trial;
    for (size_t k = 0; k <= std::size(kRunChoices); ++k) {  // the given options first, then each choice
        CookOptions cook = scoring;
        if (k > 0) cook.min_run_lanes = kRunChoices[k - 1][0], cook.max_run_gap = kRunChoices[k - 1][1];
        CookedCloth trial;
        if (Result r = cook_cloth(mesh, cook, &trial); !r.ok()) return r;
        if (const CookScore score = cook_score(trial.asset()); k == 0 || score < best) {
            best = score, best_trial = std::move(trial);
            best_options.min_run_lanes = cook.min_run_lanes, best_options.max_run_gap = cook.max_run_gap;
        }
    }
    if (chosen != nullptr) *chosen = best_options;
    if (scoring_is_all) {
        *out = std::move(best_trial);
        return {};
    }
    return cook_cloth(mesh, best_options, out);
}

Result cook_packings(const ClothMeshDesc& mesh, const MeshedGarment& g, const CookOptions& options, bool choose_runs,
                     CookedCloth* out, CookOptions* chosen, size_t* winner) {
    // Packings and run shapes are scored without the coarse level and tethers, which run_cost_ns
    // does not count (the coarse level's setup was most of the bake time at 48 000 particles);
    // the winner is then cooked once with everything.
    CookOptions scoring = options;
    scoring.coarse_spacing_m = 0.0f;
    scoring.tethers_per_particle = 0;
    CookOptions best_options = options;
    CookScore best{true, HUGE_VAL};
    *winner = 0;
    ClothMeshDesc desc = mesh;
    for (size_t k = 0; k <= g.lattice_alternatives.size(); ++k) {
        desc.lattice = k == 0 ? g.lattice.data() : g.lattice_alternatives[k - 1].lattice.data();
        desc.lattice_plane_stride = k == 0 ? g.lattice_plane_stride : g.lattice_alternatives[k - 1].plane_stride;
        CookedCloth trial;
        CookOptions trial_options;
        if (Result r = cook_garment(desc, scoring, choose_runs, &trial, &trial_options); !r.ok()) return r;
        if (const CookScore score = cook_score(trial.asset()); score < best) best = score, *winner = k, best_options = trial_options;
    }
    best_options.coarse_spacing_m = options.coarse_spacing_m;
    best_options.tethers_per_particle = options.tethers_per_particle;
    desc.lattice = *winner == 0 ? g.lattice.data() : g.lattice_alternatives[*winner - 1].lattice.data();
    desc.lattice_plane_stride = *winner == 0 ? g.lattice_plane_stride : g.lattice_alternatives[*winner - 1].plane_stride;
    if (chosen != nullptr) *chosen = best_options;
    return cook_cloth(desc, best_options, out);
}

Status bake_pattern(std::string_view text, const BakeOptions& options, Baked* out) {
    const auto stage = [&](const char* name, uint32_t index) {
        if (options.on_stage) options.on_stage(name, index, 4);
    };
    stage("parsing", 0);
    if (Status s = parse_pattern(text, options.parse, &out->pattern); !s.ok()) return s;
    stage("meshing", 1);
    if (Status s = mesh_garment(out->pattern, options.mesh, &out->garment); !s.ok()) return s;
    const GarmentInput input = garment_input(out->garment, out->pattern.fabric);
    stage("cooking", 2);
    MeshedGarment& g = out->garment;
    size_t winner = 0;
    if (Result r = cook_packings(input.desc, g, options.cook, options.choose_runs, &out->cooked, &out->cook_options, &winner);
        !r.ok())
        return {r.message};
    if (winner > 0) {  // the winner becomes the garment's lattice
        std::swap(g.lattice, g.lattice_alternatives[winner - 1].lattice);
        std::swap(g.lattice_plane_stride, g.lattice_alternatives[winner - 1].plane_stride);
    }
    if (!options.over_patterns.empty() && options.body == nullptr)
        return {"a garment worn over others is sewn on a body (--over needs --body)"};
    if (options.body != nullptr) {  // sew the flat panels, packed as the winner, and cook the dressed mesh
        ClothMeshDesc flat = input.desc;
        flat.lattice = g.lattice.data();
        flat.lattice_plane_stride = g.lattice_plane_stride;
        // Attachments are bound to the body for good, except a GarmentCode waistline with more of the
        // garment placed over kWaistHeldBelow_m above it (a dress's bodice, hanging from the
        // shoulders): that one only keeps its height while the seams close (`held`).
        std::vector<uint32_t> attached, held;
        float garment_top = -HUGE_VALF;
        for (const Vec3& p : g.positions) garment_top = std::max(garment_top, p.y);
        for (const Attachment& a : g.attachments) {
            float top = -HUGE_VALF;
            for (uint32_t p : a.particles) top = std::max(top, g.positions[p].y);
            if (a.label != "lower_interface" || garment_top <= top + kWaistHeldBelow_m)
                attached.insert(attached.end(), a.particles.begin(), a.particles.end());
            held.insert(held.end(), a.particles.begin(), a.particles.end());
        }
        for (std::vector<uint32_t>* v : {&attached, &held}) {
            std::sort(v->begin(), v->end());
            v->erase(std::unique(v->begin(), v->end()), v->end());
        }
        SewOptions sew = options.sew;
        // The garments worn under it, dressed first, innermost first (each over those before it).
        std::vector<std::unique_ptr<Baked>> under;
        for (size_t k = 0; k < options.over_patterns.size(); ++k) {
            BakeOptions inner = options;
            inner.on_stage = nullptr;
            inner.render_mesh = nullptr;
            inner.render_subdivide = -1;
            inner.over_patterns.assign(options.over_patterns.begin(), options.over_patterns.begin() + long(k));
            under.push_back(std::make_unique<Baked>());
            if (Status s = bake_pattern(options.over_patterns[k], inner, under.back().get()); !s.ok())
                return {"the garment worn under it (" + std::to_string(k + 1) + "): " + s.error};
            sew.worn_over.push_back(&under.back()->cooked.asset());
        }
        sew.ignore_arm_tips = sew.ignore_arm_tips || !out->pattern.sleeves;
        sew.skin_max_distance_scale.clear();  // each panel's factor on the skin constraints' max distance
        for (const Panel& panel : out->pattern.panels)
            sew.skin_max_distance_scale.push_back(panel.skin_max_distance_scale ? std::optional<float>(float(*panel.skin_max_distance_scale))
                                                                               : std::nullopt);
        // The drape (once or twice) and the asset cook the same sewn mesh, only in other poses: the
        // run shape is chosen once (cook_score reads the lanes, which the pose does not change).
        const CookOptions sewn_cook = sewn_cook_options(options.cook);
        std::optional<CookOptions> sewn_runs;
        const auto cook_sewn = [&](const ClothMeshDesc& desc, CookedCloth* cooked) -> Result {
            if (sewn_runs) return cook_cloth(desc, *sewn_runs, cooked);
            CookOptions chosen;
            const Result r = cook_garment(desc, sewn_cook, options.choose_runs, cooked, &chosen);
            if (r.ok()) sewn_runs = chosen;
            return r;
        };
        sew.cook_sewn = cook_sewn;
        if (Status s = sew_garment(flat, attached, held, *options.body, sew, &out->sewn, &out->sew_report); !s.ok())
            return {"sewing: " + s.error};
        if (Result r = cook_sewn(out->sewn.desc, &out->cooked); !r.ok()) return {r.message};
        out->cook_options = *sewn_runs;
        for (const ClothAsset* inner : sew.worn_over)
            out->sew_report.layer_crossings += metrics::layer_crossings(out->cooked.asset(), *inner);
    }
    if (options.render_mesh != nullptr || options.render_subdivide >= 0) {
        RenderMeshSource subdivided;
        if (options.render_mesh == nullptr)
            if (Result r = subdivide_cloth_mesh(out->cooked.asset(), uint32_t(options.render_subdivide), &subdivided); !r.ok())
                return {std::string("render mesh: ") + r.message};
        const RenderMeshSource& render = options.render_mesh != nullptr ? *options.render_mesh : subdivided;
        if (Result r = bind_render_mesh(render.desc(), &out->cooked, &out->render_bind_error_m); !r.ok())
            return {std::string("render mesh: ") + r.message};
    }
    stage("writing", 3);
    if (Result r = assets::write_asset(out->cooked.asset(), &out->bytes); !r.ok()) return {r.message};
    assets::LoadedAsset check;
    if (Result r = assets::load_asset_copy(out->bytes.data(), out->bytes.size(), &check); !r.ok())
        return {std::string("the written asset does not load: ") + r.message};
    return {};
}

std::vector<std::string> pattern_files(const std::string& folder, std::string* error) {
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path().string());
    }
    if (ec) {
        *error = "cannot read '" + folder + "': " + ec.message();
        return {};
    }
    if (std::any_of(files.begin(), files.end(), [](const std::string& f) { return f.ends_with("_specification.json"); }))
        std::erase_if(files, [](const std::string& f) { return !f.ends_with("_specification.json"); });
    std::sort(files.begin(), files.end());
    return files;
}

std::string asset_name(const std::string& pattern_path) {
    std::string name = std::filesystem::path(pattern_path).filename().string();
    for (const char* suffix : {"_specification.json", ".json"})
        if (name.size() > std::strlen(suffix) && name.ends_with(suffix)) return name.substr(0, name.size() - std::strlen(suffix));
    return name;
}

}  // namespace weft::bake
