// weft-bake: sewing patterns -> binary cloth assets the runtime loads in place.
//
//   weft-bake PATTERN.json -o OUT.weft [--target-edge METRES] [--simd-width 8|16] [--json]
//             [--depfile FILE] [--offset X,Y,Z] [--runs] [--body BODY.obj|BODY.gltf|mannequin]
//             [--sweeps N] [--sewing-frames DIR [--sewing-every K]]
//   weft-bake --info FILE.weft [--json]
//
// The pipeline is bake_pattern (bake.h); this file is the command line around it.
// Exit status 0 on success; 1 with the reason on stderr for anything else.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "asset_writer.h"
#include "bake.h"
#include "body_mesh.h"
#include "mannequin.h"
#include "metrics.h"
#include "progress.h"
#include "run_report.h"

namespace {

using namespace weft;
using nlohmann::json;

int fail(const std::string& message) {
    std::fprintf(stderr, "weft-bake: %s\n", message.c_str());
    return 1;
}

bool read_file(const std::string& path, std::string* out) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return false;
    std::ostringstream s;
    s << file.rdbuf();
    *out = s.str();
    return bool(file) || file.eof();
}

// Make/Ninja depfile: the asset depends on the pattern (a pattern names no other file).
std::string depfile_path(const std::string& path) {
    std::string out;
    for (char c : path) {
        if (c == ' ' || c == '#') out += '\\';
        if (c == '$') out += '$';
        out += c;
    }
    return out;
}

json describe(const ClothAsset& a, uint64_t bytes) {
    const LanePadding padding = lane_padding(a);
    const uint32_t total = a.total_constraints();
    const metrics::Strain start = metrics::start_strain(a);  // a dressed garment's stored pose
    return {{"particles", a.particle_count},
            {"slots", a.slot_count},
            {"triangles", a.triangle_count},
            {"stretch_springs", a.constraint_count[0]},
            {"shear_springs", a.constraint_count[1]},
            {"bend_springs", a.constraint_count[2]},
            {"seams", a.seam_point_count},
            {"panels", a.panel_count},
            {"batches", a.batch_count},
            {"colours", a.colour_count},
            {"simd_width", a.simd_width},
            {"padding_ratio", padding.ratio()},
            {"padding_by_pass",
             {{"constraints", padding.constraints.ratio()},
              {"coarse", padding.coarse.ratio()},
              {"tethers", padding.tethers.ratio()},
              {"wind", padding.wind.ratio()}}},
            {"contiguous_fraction", total > 0 ? double(a.constraints_on_runs) / total : 0.0},
            {"start_max_strain", start.max},
            {"start_mean_strain", start.mean},
            {"start_max_strain_at_m", {start.max_at.x, start.max_at.y, start.max_at.z}},
            {"tethered_particles", a.tethered_particles},
            {"coarse_nodes", a.coarse_node_count},
            {"bytes", bytes}};
}

void print_human(const json& j) {
    for (const auto& [key, value] : j.items()) std::printf("  %-22s %s\n", key.c_str(), value.dump().c_str());
}

// The body to sew on: a mesh file, or "mannequin" for the project's own (default measurements).
std::string load_sew_body(const std::string& name, bake::SewBody* out) {
    if (name == "mannequin") {
        body::Mannequin m;
        if (std::string e = body::make_mannequin(body::Measurements{}, body::MannequinOptions{}, &m); !e.empty())
            return "mannequin: " + e;
        out->positions = std::move(m.positions);
        out->triangles = std::move(m.triangles);
        return {};
    }
    body::BodyMesh mesh;
    if (std::string e = body::load_body_mesh(name, &mesh); !e.empty()) return e;
    out->positions = std::move(mesh.positions);
    out->triangles = std::move(mesh.triangles);
    return {};
}

int info(const std::string& path, bool as_json) {
    std::string file;
    if (!read_file(path, &file)) return fail("cannot read '" + path + "'");
    assets::LoadedAsset loaded;
    if (Result r = assets::load_asset_copy(file.data(), file.size(), &loaded); !r.ok())
        return fail(path + ": " + r.message);
    AssetFileInfo header;
    read_asset_header(loaded.bytes.data(), loaded.bytes.size(), &header);
    json j = describe(loaded.asset, file.size());
    j["file"] = path;
    j["format_version"] = std::to_string(header.version_major) + "." + std::to_string(header.version_minor);
    char checksum[24];
    std::snprintf(checksum, sizeof checksum, "%016llx", static_cast<unsigned long long>(header.checksum));
    j["checksum_xxh64"] = checksum;
    j["sections"] = header.section_count;
    if (as_json) {
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("%s: Weft asset, format %s\n", path.c_str(), j["format_version"].get<std::string>().c_str());
        print_human(j);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-bake: sewing patterns (Weft or GarmentCode JSON) to Weft cloth assets"};
    std::string pattern_path, out_path, depfile, info_path, body_name;
    double target_edge = 0.0;
    uint32_t simd_width = kSimdWidth;
    std::vector<double> offset;
    bool as_json = false;
    bool runs = false;
    app.add_option("pattern", pattern_path, "sewing pattern (docs/pattern-format.md)");
    app.add_option("-o,--output", out_path, "the asset file to write (docs/asset-format.md)");
    app.add_option("--target-edge", target_edge, "mesh edge length, metres (default: the pattern's, else 0.02)")
        ->check(CLI::Range(1e-4, 10.0));
    app.add_option("--simd-width", simd_width, "pad constraint batches for this SIMD width")
        ->check(CLI::IsMember({8u, 16u}));
    app.add_option("--offset", offset, "added to every panel's placement, metres (GarmentCode v1 patterns)")
        ->expected(3)->delimiter(',');
    app.add_option("--depfile", depfile, "write a Make/Ninja depfile for the output");
    app.add_option("--info", info_path, "describe an asset file (loaded through the runtime's validating loader)");
    app.add_option("--body", body_name,
                   "sew the garment onto this body (OBJ, glTF, or 'mannequin': the project's own) and store it dressed");
    app.add_flag("--json", as_json, "one JSON object instead of the human summary");
    app.add_flag("--runs", runs, "also print where the constraints off SIMD runs and the padding lanes come from (stderr)");
    uint32_t sweeps = bake::SewOptions{}.sweeps;
    app.add_option("--sweeps", sweeps,
                   "with --body: the solver budget the sewing and the drape run at, the garment's in the game "
                   "(ClothDesc::sweeps; default 8)")
        ->check(CLI::Range(1u, 1000u));
    std::string sewing_frames;
    uint32_t sewing_every = 10;
    app.add_option("--sewing-frames", sewing_frames,
                   "with --body: write the sewing world every K frames as OBJ files into this folder "
                   "(body.obj; sewing_NNNNN.obj, the unsewn panels; drape_NNNNN.obj, the sewn garment; figure 13)");
    app.add_option("--sewing-every", sewing_every, "K for --sewing-frames (default 10)")->check(CLI::Range(1u, 100000u));
    CLI11_PARSE(app, argc, argv);

    if (!info_path.empty()) return info(info_path, as_json);
    if (pattern_path.empty() || out_path.empty()) return fail("need PATTERN and -o OUT.weft (or --info FILE)");

    std::string text;
    if (!read_file(pattern_path, &text)) return fail("cannot read '" + pattern_path + "'");
    bake::BakeOptions options;
    for (size_t k = 0; k < offset.size(); ++k) options.parse.placement_offset_m[k] = offset[k];
    options.mesh.target_edge_m = target_edge;
    options.cook.simd_width = simd_width;
    bake::SewBody body;
    if (!body_name.empty()) {
        if (std::string e = load_sew_body(body_name, &body); !e.empty()) return fail("--body " + body_name + ": " + e);
        options.body = &body;
    }
    options.sew.sweeps = sweeps;
    // Figure 13: the sewing world as OBJ files (frame numbers per stage; the stage's last frame too).
    std::string frames_error;
    uint32_t frames_written = 0;
    if (!sewing_frames.empty()) {
        if (body_name.empty()) return fail("--sewing-frames needs --body");
        std::error_code ec;
        std::filesystem::create_directories(sewing_frames, ec);
        if (ec) return fail("--sewing-frames: cannot create '" + sewing_frames + "': " + ec.message());
        if (std::string e = body::save_obj(sewing_frames + "/body.obj", body.positions, body.triangles); !e.empty())
            return fail("--sewing-frames: " + e);
        options.sew.frame_every = sewing_every;
        options.sew.on_frame = [&](const bake::SewFrame& f) {
            char name[64];
            std::snprintf(name, sizeof name, "/%s_%05u.obj", f.stage, f.frame);
            const std::vector<Vec3> positions(f.positions, f.positions + f.particle_count);
            const std::vector<uint32_t> triangles(f.triangles, f.triangles + 3 * size_t(f.triangle_count));
            std::vector<float> uv;
            if (f.uv != nullptr) uv.assign(f.uv, f.uv + 2 * size_t(f.particle_count));
            if (std::string e = body::save_obj(sewing_frames + name, positions, triangles, uv); !e.empty() && frames_error.empty())
                frames_error = e;
            ++frames_written;
        };
    }
    // On a terminal (and without --json) a bar names the stage; meshing and cooking a garment take seconds.
    progress::Bar bar("weft-bake " + pattern_path, 4, progress::wanted(as_json));
    options.on_stage = [&](const char* stage, uint32_t index, uint32_t) { bar.update(index, stage); };
    bake::Baked baked;
    const bake::Status baked_status = bake::bake_pattern(text, options, &baked);
    bar.finish();
    if (!baked_status.ok()) return fail(pattern_path + ": " + baked_status.error);
    if (!frames_error.empty()) return fail("--sewing-frames: " + frames_error);
    const std::vector<std::byte>& bytes = baked.bytes;
    const bake::MeshedGarment& garment = baked.garment;

    std::ofstream out(out_path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) return fail("cannot write '" + out_path + "'");
    if (!depfile.empty()) {
        std::ofstream d(depfile);
        d << depfile_path(out_path) << ": " << depfile_path(pattern_path);
        if (!body_name.empty() && body_name != "mannequin") d << " " << depfile_path(body_name);
        d << "\n";
        if (!d) return fail("cannot write '" + depfile + "'");
    }

    if (runs)
        std::fprintf(stderr, "%s", bake::format_run_report(bake::run_report(garment, baked.cooked.asset(), options.cook)).c_str());
    const bake::PanelQuality& q = garment.quality.overall;
    json j = describe(baked.cooked.asset(), bytes.size());
    j["pattern"] = pattern_path;
    j["output"] = out_path;
    j["format"] = baked.pattern.format;
    j["target_edge_m"] = garment.quality.target_edge_m;
    j["min_angle_deg"] = q.min_angle_deg;
    j["min_angle_deg_away_from_sharp_corners"] = q.min_angle_deg_smooth;
    j["edge_min_h"] = q.edge_min_h;  // edge lengths / target_edge_m
    j["edge_mean_h"] = q.edge_mean_h;
    j["edge_max_h"] = q.edge_max_h;
    j["outline_area_m2"] = q.outline_area_m2;  // the exact curved outlines (area_m2: the mesh)
    j["mesh_rounds"] = garment.quality.rounds;
    j["total_mass_kg"] = garment.total_mass_kg;
    j["area_m2"] = garment.area_m2;
    j["pinned"] = garment.pinned.size();
    j["min_run_lanes"] = baked.cook_options.min_run_lanes;
    j["max_run_gap"] = baked.cook_options.max_run_gap;
    if (options.body != nullptr) {
        const bake::SewReport& r = baked.sew_report;
        j["body"] = body_name;
        j["body_triangles"] = r.body_triangles;
        j["sewing_s"] = r.sewing_s;
        j["sewing_frames"] = r.sewing_frames;
        j["drape_frames"] = r.drape_frames;
        j["sewn_seam_points"] = r.seam_points;
        j["attached_to_body"] = r.attached;
        j["particles_before_sewing"] = r.particles_before;
        j["max_seam_gap_m"] = r.max_seam_gap_m;
        j["max_penetration_m"] = r.max_penetration_m;
        j["max_skin_penetration_m"] = r.max_skin_penetration_m;
        j["particles_inside_body"] = r.particles_inside_body;
        j["untangled_particles"] = r.untangled_particles;
        j["final_mean_speed_m_s"] = r.mean_speed_m_s;
        j["top_drop_m"] = r.top_at_closed_m - r.top_at_rest_m;  // from closed seams to the dressed pose
        j["lowest_m"] = r.lowest_at_rest_m;
        if (!sewing_frames.empty()) j["sewing_frames_written"] = frames_written;
    }
    if (as_json) {
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("weft-bake %s -> %s (%zu panels, %s)\n", pattern_path.c_str(), out_path.c_str(),
                    garment.panel_names.size(), baked.pattern.format.c_str());
        print_human(j);
    }
    return 0;
}
