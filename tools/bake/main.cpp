// weft-bake: sewing patterns -> binary cloth assets the runtime loads in place.
//
//   weft-bake PATTERN.json -o OUT.weft [--target-edge METRES] [--simd-width 8|16] [--json]
//             [--depfile FILE] [--offset X,Y,Z] [--runs] [--body BODY.obj|BODY.gltf|mannequin]
//             [--sweeps N] [--sewing-frames DIR [--sewing-every K]]
//   weft-bake FOLDER|MANIFEST.json -o OUT_DIR [--jobs N] [--only NAME]... [--depfiles] [the options above]
//   weft-bake --info FILE.weft [--json]
//
// The pipeline is bake_pattern (bake.h); this file is the command line around it, batch.h reads
// folders and manifests (docs/pattern-format.md, "Baking many patterns").
// Exit status 0 on success; 1 with the reason on stderr for anything else (a batch: any asset failed).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/asset_writer.h"
#include "bake/bake.h"
#include "bake/batch.h"
#include "body/body_mesh.h"
#include "common/child_jobs.h"
#include "body/mannequin.h"
#include "common/metrics.h"
#include "common/progress.h"
#include "bake/run_report.h"

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

// A path in a Make/Ninja depfile.
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
            {"attachments", a.attachment_count},
            {"skin_constraints", a.skin.count},
            {"bytes", bytes}};
}

// What an asset's report asks a person to look at, on stderr, for one pattern and in a batch alike:
// the repairs made to its pattern, and a worn-over garment dressed through the ones under it.
void warn_from_report(const std::string& name, const json& j) {
    if (j.contains("repairs"))
        for (const json& repair : j["repairs"]) std::fprintf(stderr, "weft-bake: %s: repaired: %s\n", name.c_str(), repair.get<std::string>().c_str());
    if (j.value("layer_crossings", uint64_t(0)) > 0)
        std::fprintf(stderr, "weft-bake: %s: warning: %s edges cross the garments it is worn over\n", name.c_str(),
                     j["layer_crossings"].dump().c_str());
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

// One asset: the entry's pattern baked and written to out_path, and the Make/Ninja depfile (the
// asset depends on the pattern, the body it was sewn on and the manifest that named it; a pattern
// names no other file). A failed bake leaves no asset behind, not even an older one. *j: the
// summary; `configure` may change the options (the sewing frames); *runs: the run report (optional).
std::string bake_asset(const bake::BatchEntry& e, const bake::SewBody* body, const std::string& out_path,
                       const std::string& depfile, const std::function<void(bake::BakeOptions&)>& configure,
                       progress::Bar* bar, json* j, std::string* runs) {
    std::error_code ec;
    std::filesystem::remove(out_path, ec);
    std::string text;
    if (!read_file(e.pattern, &text)) return "cannot read '" + e.pattern + "'";
    bake::BakeOptions options;
    for (size_t k = 0; k < 3; ++k) options.parse.placement_offset_m[k] = e.offset_m[k];
    options.mesh.target_edge_m = e.target_edge_m;
    options.cook.simd_width = e.simd_width;
    options.body = body;
    options.sew.sweeps = e.sweeps;
    for (const std::string& under : e.over) {
        options.over_patterns.emplace_back();
        if (!read_file(under, &options.over_patterns.back())) return "cannot read '" + under + "' (--over)";
    }
    RenderMeshSource render;
    if (!e.render_mesh.empty()) {
        body::BodyMesh m;
        if (std::string error = body::load_body_mesh(e.render_mesh, &m); !error.empty())
            return "--render-mesh " + e.render_mesh + ": " + error;
        render.positions = std::move(m.positions);
        render.triangles = std::move(m.triangles);
        render.uv = std::move(m.uv);
        options.render_mesh = &render;
    }
    options.render_subdivide = e.render_subdivide;
    if (configure) configure(options);
    if (bar != nullptr) options.on_stage = [&](const char* stage, uint32_t index, uint32_t) { bar->update(index, stage); };
    bake::Baked baked;
    const bake::Status baked_status = bake::bake_pattern(text, options, &baked);
    if (bar != nullptr) bar->finish();
    if (!baked_status.ok()) return e.pattern + ": " + baked_status.error;

    // Written under another name first: an asset that exists is whole.
    const std::vector<std::byte>& bytes = baked.bytes;
    const std::string partial = out_path + ".partial";
    std::ofstream out(partial, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (out) std::filesystem::rename(partial, out_path, ec);
    if (!out || ec) {
        std::filesystem::remove(partial, ec);
        return "cannot write '" + out_path + "'";
    }
    if (!depfile.empty()) {
        std::ofstream d(depfile);
        d << depfile_path(out_path) << ": " << depfile_path(e.pattern);
        if (!e.body.empty() && e.body != "mannequin") d << " " << depfile_path(e.body);
        if (!e.render_mesh.empty()) d << " " << depfile_path(e.render_mesh);
        for (const std::string& under : e.over) d << " " << depfile_path(under);
        if (!e.manifest.empty()) d << " " << depfile_path(e.manifest);
        d << "\n";
        if (!d) return "cannot write '" + depfile + "'";
    }

    const bake::MeshedGarment& garment = baked.garment;
    if (runs != nullptr) *runs = bake::format_run_report(bake::run_report(garment, baked.cooked.asset(), options.cook));
    const bake::PanelQuality& q = garment.quality.overall;
    *j = describe(baked.cooked.asset(), bytes.size());
    (*j)["pattern"] = e.pattern;
    (*j)["output"] = out_path;
    (*j)["format"] = baked.pattern.format;
    (*j)["target_edge_m"] = garment.quality.target_edge_m;
    (*j)["min_angle_deg"] = q.min_angle_deg;
    (*j)["min_angle_deg_away_from_sharp_corners"] = q.min_angle_deg_smooth;
    (*j)["edge_min_h"] = q.edge_min_h;  // edge lengths / target_edge_m
    (*j)["edge_mean_h"] = q.edge_mean_h;
    (*j)["edge_max_h"] = q.edge_max_h;
    (*j)["outline_area_m2"] = q.outline_area_m2;  // the exact curved outlines (area_m2: the mesh)
    (*j)["mesh_rounds"] = garment.quality.rounds;
    (*j)["repairs"] = baked.pattern.repairs;  // what parsing changed to make the pattern valid
    (*j)["total_mass_kg"] = garment.total_mass_kg;
    (*j)["area_m2"] = garment.area_m2;
    (*j)["pinned"] = garment.pinned.size();
    (*j)["min_run_lanes"] = baked.cook_options.min_run_lanes;
    (*j)["max_run_gap"] = baked.cook_options.max_run_gap;
    if (const RenderMesh& m = baked.cooked.asset().render; m.vertex_count > 0) {
        (*j)["render_vertices"] = m.vertex_count;
        (*j)["render_triangles"] = m.triangle_count;
        (*j)["render_bind_error_m"] = baked.render_bind_error_m;
    }
    if (body != nullptr) {
        const bake::SewReport& r = baked.sew_report;
        (*j)["body"] = e.body;
        (*j)["body_triangles"] = r.body_triangles;
        (*j)["sewing_s"] = r.sewing_s;
        (*j)["sewing_frames"] = r.sewing_frames;
        (*j)["drape_frames"] = r.drape_frames;
        (*j)["sewn_seam_points"] = r.seam_points;
        (*j)["attached_to_body"] = r.attached;
        (*j)["skin_constraints"] = r.skin_constraints;
        (*j)["skin_binding_s"] = r.skin_binding_s;
        (*j)["particles_before_sewing"] = r.particles_before;
        (*j)["max_seam_gap_m"] = r.max_seam_gap_m;
        (*j)["max_penetration_m"] = r.max_penetration_m;
        (*j)["max_skin_penetration_m"] = r.max_skin_penetration_m;
        (*j)["particles_inside_body"] = r.particles_inside_body;
        (*j)["untangled_particles"] = r.untangled_particles;
        (*j)["layer_crossings"] = r.layer_crossings;
        (*j)["final_mean_speed_m_s"] = r.mean_speed_m_s;
        (*j)["top_drop_m"] = r.top_at_closed_m - r.top_at_rest_m;  // from closed seams to the dressed pose
        (*j)["lowest_m"] = r.lowest_at_rest_m;
    }
    return {};
}

// A folder's or a manifest's assets, each baked in a child process of its own (child_jobs.h), `jobs`
// at a time: a pattern that fails, even by crashing, fails alone. One line per asset in the
// entries' order, then the summary; exit status 1 if any failed.
int bake_batch(const std::vector<bake::BatchEntry>& entries, const std::string& out_dir, uint32_t jobs, bool depfiles,
               bool as_json) {
    const auto start = std::chrono::steady_clock::now();
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) return fail("cannot create '" + out_dir + "': " + ec.message());
    // Each body is read once, here; the children share it.
    std::map<std::string, bake::SewBody> bodies;
    std::map<std::string, std::string> body_errors;
    for (const bake::BatchEntry& e : entries) {
        if (e.body.empty() || bodies.count(e.body) || body_errors.count(e.body)) continue;
        if (std::string error = load_sew_body(e.body, &bodies[e.body]); !error.empty()) {
            bodies.erase(e.body);
            body_errors[e.body] = "body " + e.body + ": " + error;
        }
    }
    const auto output = [&](const bake::BatchEntry& e) { return (std::filesystem::path(out_dir) / (e.name + ".weft")).string(); };
    const auto work = [&](size_t k) {
        const bake::BatchEntry& e = entries[k];
        json j;
        std::string error;
        const auto asset_start = std::chrono::steady_clock::now();
        if (!e.body.empty() && body_errors.count(e.body)) {
            error = body_errors[e.body];
        } else {
            const bake::SewBody* body = e.body.empty() ? nullptr : &bodies.at(e.body);
            error = bake_asset(e, body, output(e), depfiles ? output(e) + ".d" : std::string(), {}, nullptr, &j, nullptr);
        }
        if (!error.empty()) j = json{{"pattern", e.pattern}, {"error", error}};
        j["name"] = e.name;
        j["bake_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - asset_start).count();
        return j.dump();
    };

    std::vector<json> lines(entries.size());
    std::vector<char> done(entries.size(), 0);
    std::vector<std::string> failed;
    size_t printed = 0, finished = 0;
    progress::Bar bar("weft-bake " + std::to_string(entries.size()) + " assets", entries.size(), progress::wanted(as_json));
    const auto print = [&](const json& j) {
        if (!j.contains("error")) warn_from_report(j["name"].get<std::string>(), j);
        if (as_json) {
            std::printf("%s\n", j.dump().c_str());
        } else if (j.contains("error")) {
            std::fprintf(stderr, "weft-bake: %s failed: %s\n", j["name"].get<std::string>().c_str(),
                         j["error"].get<std::string>().c_str());
        } else {
            std::printf("weft-bake: %s (%u particles%s, %.1f s)\n", j["output"].get<std::string>().c_str(),
                        j["particles"].get<uint32_t>(), j.contains("body") ? ", sewn" : "", j["bake_s"].get<double>());
        }
        std::fflush(stdout);
    };
    const auto asset_done = [&](size_t k, jobs::Outcome outcome) {
        json j = outcome.error.empty() ? json::parse(outcome.output, nullptr, false) : json();
        if (!outcome.error.empty() || !j.is_object())
            j = json{{"name", entries[k].name}, {"pattern", entries[k].pattern},
                     {"error", outcome.error.empty() ? std::string("no result") : outcome.error}};
        if (j.contains("error")) {
            std::filesystem::remove(output(entries[k]) + ".partial", ec);  // what a crash left
            std::filesystem::remove(output(entries[k]), ec);
        }
        lines[k] = std::move(j);
        done[k] = 1, ++finished;
        bar.update(finished, entries[k].name);
        for (; printed < entries.size() && done[printed]; ++printed) {
            if (bar.enabled()) bar.finish();
            print(lines[printed]);
        }
    };
    jobs::run_in_children(entries.size(), {jobs, 0.0}, work, asset_done);
    bar.finish();
    for (size_t k = 0; k < entries.size(); ++k)
        if (lines[k].contains("error")) failed.push_back(entries[k].name);

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const uint32_t used_jobs = jobs > 0 ? jobs : jobs::every_core();
    if (as_json) {
        std::printf("%s\n", json{{"summary", true}, {"assets", entries.size()}, {"baked", entries.size() - failed.size()},
                                 {"failed", failed}, {"jobs", used_jobs}, {"seconds", seconds}}
                                .dump()
                                .c_str());
    } else {
        std::string names;
        for (const std::string& name : failed) names += (names.empty() ? "" : ", ") + name;
        std::printf("weft-bake: %zu of %zu assets baked into %s in %.1f s (%u jobs)%s%s\n", entries.size() - failed.size(),
                    entries.size(), out_dir.c_str(), seconds, used_jobs, failed.empty() ? "" : "; failed: ", names.c_str());
    }
    return failed.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-bake: sewing patterns (Weft or GarmentCode JSON) to Weft cloth assets"};
    std::string pattern_path, out_path, depfile, info_path;
    bake::BatchEntry defaults;  // the command line's options: one pattern's, or a batch's defaults
    std::vector<double> offset;
    bool as_json = false;
    bool runs = false;
    app.add_option("pattern", pattern_path,
                   "sewing pattern (docs/pattern-format.md), or a folder of them, or a manifest (\"Baking many patterns\")");
    app.add_option("-o,--output", out_path, "the asset file to write (docs/asset-format.md); a batch's folder");
    app.add_option("--target-edge", defaults.target_edge_m, "mesh edge length, metres (default: the pattern's, else 0.02)")
        ->check(CLI::Range(1e-4, 10.0));
    app.add_option("--simd-width", defaults.simd_width, "pad constraint batches for this SIMD width")
        ->check(CLI::IsMember({8u, 16u}));
    app.add_option("--offset", offset, "added to every panel's placement, metres (GarmentCode v1 patterns)")
        ->expected(3)->delimiter(',');
    app.add_option("--depfile", depfile, "write a Make/Ninja depfile for the output");
    app.add_option("--info", info_path, "describe an asset file (loaded through the runtime's validating loader)");
    app.add_option("--body", defaults.body,
                   "sew the garment onto this body (OBJ, glTF, or 'mannequin': the project's own) and store it dressed");
    app.add_option("--over", defaults.over,
                   "with --body: a pattern worn under this garment (repeat for more, innermost first): it is dressed "
                   "first as weft-bake dresses it alone, and this garment sewn over it (ClothDesc::worn_over)");
    app.add_option("--render-mesh", defaults.render_mesh,
                   "bind this render mesh (OBJ or glTF, authored on the asset's start pose: the flat layout, or the "
                   "dressed pose with --body) to the cloth and store it in the asset (docs/asset-format.md)");
    app.add_option("--render-subdivide", defaults.render_subdivide,
                   "store the cloth's own triangles cut into four N times as its render mesh (0..4; 0: the cloth's mesh)")
        ->check(CLI::Range(0, 4));
    app.add_flag("--json", as_json, "one JSON object instead of the human summary (a batch: one per asset, then the summary)");
    app.add_flag("--runs", runs, "also print where the constraints off SIMD runs and the padding lanes come from (stderr)");
    app.add_option("--sweeps", defaults.sweeps,
                   "with --body: the solver budget the sewing and the drape run at, the garment's in the game "
                   "(ClothDesc::sweeps; default 8)")
        ->check(CLI::Range(1u, 1000u));
    std::string sewing_frames;
    uint32_t sewing_every = 10;
    app.add_option("--sewing-frames", sewing_frames,
                   "with --body: write the sewing world every K frames as OBJ files into this folder "
                   "(body.obj; sewing_NNNNN.obj, the unsewn panels; drape_NNNNN.obj, the sewn garment; figure 13)");
    app.add_option("--sewing-every", sewing_every, "K for --sewing-frames (default 10)")->check(CLI::Range(1u, 100000u));
    uint32_t jobs = 0;
    std::vector<std::string> only;
    bool depfiles = false;
    app.add_option("--jobs", jobs, "a batch: assets baked at once (default: one per core)")->check(CLI::Range(1u, 1024u));
    app.add_option("--only", only, "a batch: bake only the assets of these names");
    app.add_flag("--depfiles", depfiles, "a batch: write OUT_DIR/NAME.weft.d, a Make/Ninja depfile, beside each asset");
    CLI11_PARSE(app, argc, argv);

    if (!info_path.empty()) return info(info_path, as_json);
    if (!defaults.render_mesh.empty() && defaults.render_subdivide >= 0)
        return fail("--render-mesh and --render-subdivide: one render mesh or the other");
    if (pattern_path.empty() || out_path.empty()) return fail("need PATTERN and -o OUT.weft (or --info FILE)");
    for (size_t k = 0; k < offset.size(); ++k) defaults.offset_m[k] = offset[k];

    std::error_code ec;
    const bool folder = std::filesystem::is_directory(pattern_path, ec);
    std::string text;
    if (!folder && !read_file(pattern_path, &text)) return fail("cannot read '" + pattern_path + "'");
    if (folder || bake::is_manifest(text)) {
        if (!depfile.empty()) return fail("--depfile is for one pattern; a batch writes one per asset with --depfiles");
        if (!sewing_frames.empty() || runs) return fail("--sewing-frames and --runs are for one pattern");
        if (!defaults.render_mesh.empty() || defaults.render_subdivide >= 0)
            return fail("--render-mesh and --render-subdivide are for one pattern");
        std::vector<bake::BatchEntry> entries;
        const std::string error = folder ? bake::read_folder(pattern_path, defaults, &entries)
                                         : bake::read_manifest(pattern_path, text, defaults, &entries);
        if (!error.empty()) return fail(error);
        if (!only.empty()) {
            for (const std::string& name : only)
                if (std::none_of(entries.begin(), entries.end(), [&](const bake::BatchEntry& e) { return e.name == name; }))
                    return fail("--only " + name + ": no such asset in " + pattern_path);
            std::erase_if(entries, [&](const bake::BatchEntry& e) { return std::find(only.begin(), only.end(), e.name) == only.end(); });
        }
        return bake_batch(entries, out_path, jobs, depfiles, as_json);
    }
    if (jobs > 0 || !only.empty() || depfiles) return fail("--jobs, --only and --depfiles are for a folder or a manifest");

    defaults.pattern = pattern_path;
    bake::SewBody body;
    if (!defaults.body.empty()) {
        if (std::string e = load_sew_body(defaults.body, &body); !e.empty()) return fail("--body " + defaults.body + ": " + e);
    }
    // Figure 13: the sewing world as OBJ files (frame numbers per stage; the stage's last frame too).
    std::string frames_error;
    uint32_t frames_written = 0;
    std::function<void(bake::BakeOptions&)> configure;
    if (!sewing_frames.empty()) {
        if (defaults.body.empty()) return fail("--sewing-frames needs --body");
        std::filesystem::create_directories(sewing_frames, ec);
        if (ec) return fail("--sewing-frames: cannot create '" + sewing_frames + "': " + ec.message());
        if (std::string e = body::save_obj(sewing_frames + "/body.obj", body.positions, body.triangles); !e.empty())
            return fail("--sewing-frames: " + e);
        configure = [&](bake::BakeOptions& options) {
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
        };
    }
    // On a terminal (and without --json) a bar names the stage; meshing and cooking a garment take seconds.
    progress::Bar bar("weft-bake " + pattern_path, 4, progress::wanted(as_json));
    json j;
    std::string run_text;
    if (std::string e = bake_asset(defaults, defaults.body.empty() ? nullptr : &body, out_path, depfile, configure, &bar, &j,
                                   runs ? &run_text : nullptr);
        !e.empty())
        return fail(e);
    if (!frames_error.empty()) return fail("--sewing-frames: " + frames_error);
    if (runs) std::fprintf(stderr, "%s", run_text.c_str());
    warn_from_report(pattern_path, j);
    if (!sewing_frames.empty()) j["sewing_frames_written"] = frames_written;
    if (as_json) {
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("weft-bake %s -> %s (%s panels, %s)\n", pattern_path.c_str(), out_path.c_str(),
                    j["panels"].dump().c_str(), j["format"].get<std::string>().c_str());
        print_human(j);
    }
    return 0;
}
