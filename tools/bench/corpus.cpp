// weft-bench corpus (corpus.h): every pattern of a folder through weft-bake's pipeline, flat and
// sewn, with the figures issue 21 judges a garment by. Each garment bakes in a child process of its
// own (lib/common/child_jobs.h; the result, one JSON line, through a pipe), so a crash, a hang or
// an allocation failure in one garment is that garment's error and the batch goes on.
#include "bench/corpus.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bake/bake.h"
#include "body/body_mesh.h"
#include "common/child_jobs.h"
#include "bench/garment.h"
#include "common/metrics.h"
#include "common/progress.h"
#include "common/scene.h"
#include "weft/cook.h"
#include "weft/debug.h"

namespace weft::bench {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Where the garment is worn, from its panels' names (GarmentCode's: torso, skirt, pant panels):
// "upper", "lower" (skirts, pants, shorts), "full" (dresses, jumpsuits) or "other".
std::string garment_kind(const bake::Pattern& pattern) {
    bool upper = false, lower = false;
    for (const bake::Panel& p : pattern.panels) {
        upper = upper || p.name.find("torso") != std::string::npos;
        lower = lower || p.name.find("skirt") != std::string::npos || p.name.find("pant") != std::string::npos;
    }
    return upper && lower ? "full" : upper ? "upper" : lower ? "lower" : "other";
}

double contiguous_fraction(const ClothAsset& a) {
    const uint32_t total = a.total_constraints();
    return total > 0 ? double(a.constraints_on_runs) / total : 0.0;
}

// The dressed garment in a scene whose body blends from its pose to `o.blend_to` over o.moving_s
// and then stands still: the deepest particle below the moving hull (exact query, every frame),
// whether it stays finite, and its mean speed kMovingRest_s after the body stops.
void run_moving(const std::vector<std::byte>& asset_bytes, const CorpusOptions& o, json& j) {
    const std::string dir = std::filesystem::temp_directory_path() / ("weft_corpus_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/garment.weft", std::ios::binary)
        .write(reinterpret_cast<const char*>(asset_bytes.data()), std::streamsize(asset_bytes.size()));
    scenes::Scene scene = scenes::garment_on_blending_body(
        "garment.weft", std::filesystem::absolute(o.body).string(), std::filesystem::absolute(o.blend_to).string(), o.moving_s);
    scene.cloths[0].desc.self_collision = o.self_collision;
    scenes::SceneWorld sw;
    const std::string e = scenes::build_scene(scene, &sw, {dir});
    std::filesystem::remove_all(dir);
    if (!e.empty()) {
        j["moving_error"] = e;
        return;
    }
    const uint32_t moving = uint32_t(std::lround(o.moving_s / scene.dt_s)), resting = uint32_t(std::lround(kMovingRest_s / scene.dt_s));
    double deepest = 0.0, speed = 0.0, worst_spring = 0.0;
    uint32_t deepest_frame = 0, first_too_deep_frame = 0;
    Vec3 deepest_at{};
    bool finite = true;
    for (uint32_t f = 1; f <= moving + resting && finite; ++f) {
        if (!scenes::animate_body(sw, float(std::min(f, moving)) * scene.dt_s).empty() || !step(sw.world, scene.dt_s).ok()) {
            j["moving_error"] = "the scene did not step";
            return;
        }
        ClothView view;
        view_cloth(sw.world, sw.cloths[0].id, &view);
        finite = metrics::bounds(view).finite;
        Vec3 at{};
        if (const double d = metrics::max_body_penetration_m(sw.world, sw.body->id, view, &at); d > deepest)
            deepest = d, deepest_frame = f, deepest_at = at;
        if (first_too_deep_frame == 0 && deepest > kMovingMaxPenetration_m) first_too_deep_frame = f;
        speed = metrics::mean_speed(view);
        worst_spring = std::max(worst_spring, metrics::stretch_strain(view).max);
    }
    j["moving_finite"] = finite;
    j["moving_max_penetration_m"] = deepest;
    j["moving_deepest_frame"] = deepest_frame;                // 0: none below the hull
    j["moving_first_too_deep_frame"] = first_too_deep_frame;  // 0: none below the bound
    j["moving_deepest_at_m"] = {deepest_at.x, deepest_at.y, deepest_at.z};
    j["moving_final_speed_m_s"] = speed;
    j["moving_max_strain"] = worst_spring;  // the worst spring over the run (start_max_strain: at its start)
    j["moving_self_collision"] = o.self_collision;
    j["moving_ok"] = finite && deepest <= kMovingMaxPenetration_m && speed < kMovingRestSpeed_m_s;
}

// One garment, flat then sewn: the corpus line (run in the child).
json bake_one(const std::string& path, const bake::SewBody* body, const CorpusOptions& o) {
    json j;
    j["name"] = bake::asset_name(path);
    j["flat_ok"] = false;
    j["sewn_ok"] = false;
    std::ifstream file(path, std::ios::binary);
    const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    if (!file.good() && !file.eof()) return j["error"] = "cannot read " + path, j;
    bake::BakeOptions options;
    bake::Baked flat;
    const auto flat_start = Clock::now();
    if (bake::Status s = bake::bake_pattern(text, options, &flat); !s.ok()) {
        j["error"] = s.error;
        return j;
    }
    j["kind"] = garment_kind(flat.pattern);
    j["flat_ok"] = true;
    j["flat_s"] = std::chrono::duration<double>(Clock::now() - flat_start).count();
    j["particles"] = flat.cooked.asset().particle_count;
    j["flat_contiguous_fraction"] = contiguous_fraction(flat.cooked.asset());
    j["flat_padding_ratio"] = lane_padding(flat.cooked.asset()).ratio();
    if (body == nullptr) return j;

    options.body = body;
    options.sew.sweeps = o.sweeps;
    bake::Baked sewn;
    if (bake::Status s = bake::bake_pattern(text, options, &sewn); !s.ok()) {
        j["error"] = s.error;
        return j;
    }
    const bake::SewReport& r = sewn.sew_report;
    const ClothAsset& a = sewn.cooked.asset();
    const metrics::Strain start = metrics::start_strain(a);
    const double top_drop = r.top_at_closed_m - r.top_at_rest_m;
    // Sewn: every seam closed (the sewing fails otherwise) and no particle inside the body.
    j["sewn_ok"] = r.particles_inside_body == 0;
    if (r.particles_inside_body > 0) j["error"] = std::to_string(r.particles_inside_body) + " particles inside the body";
    // Stays on: the top stays within kStaysOnMaxTopDrop_m of where the seams closed, nothing below the soles.
    j["stayed_on"] = top_drop < kStaysOnMaxTopDrop_m && r.lowest_at_rest_m >= r.body_lowest_m - kStaysOnBelowSoles_m;
    j["top_drop_m"] = top_drop;
    j["lowest_m"] = r.lowest_at_rest_m;
    j["max_seam_gap_m"] = r.max_seam_gap_m;
    j["particles_inside_body"] = r.particles_inside_body;
    j["max_penetration_m"] = r.max_penetration_m;
    j["start_mean_strain"] = start.mean;
    j["start_max_strain"] = start.max;
    j["start_max_strain_at_m"] = {start.max_at.x, start.max_at.y, start.max_at.z};
    j["contiguous_fraction"] = contiguous_fraction(a);
    j["padding_ratio"] = lane_padding(a).ratio();
    j["attached_to_body"] = r.attached;
    j["drape_frames"] = r.drape_frames;
    j["final_mean_speed_m_s"] = r.mean_speed_m_s;
    j["sew_s"] = r.sewing_s;
    if (!o.blend_to.empty() && j["stayed_on"].get<bool>()) run_moving(sewn.bytes, o, j);
    return j;
}

double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

json summarise(const std::vector<json>& lines, bool sewn) {
    uint32_t flat_ok = 0, sewn_ok = 0, stayed_on = 0, lower = 0, lower_stayed = 0, moving = 0, moving_ok = 0;
    std::vector<double> flat_cf, flat_pad, cf, pad, sew_s, mean_strain, max_strain, moving_strain;
    for (const json& j : lines) {
        if (j.value("flat_ok", false)) {
            ++flat_ok;
            flat_cf.push_back(j["flat_contiguous_fraction"]), flat_pad.push_back(j["flat_padding_ratio"]);
        }
        const bool is_lower = j.value("kind", "") == "lower";
        lower += is_lower;
        if (!j.contains("sew_s")) continue;
        sewn_ok += j.value("sewn_ok", false);
        cf.push_back(j["contiguous_fraction"]), pad.push_back(j["padding_ratio"]), sew_s.push_back(j["sew_s"]);
        if (!j.value("stayed_on", false)) continue;
        if (j.contains("moving_ok") || j.contains("moving_error")) ++moving, moving_ok += j.value("moving_ok", false);
        if (j.contains("moving_max_strain")) moving_strain.push_back(j["moving_max_strain"]);
        ++stayed_on, lower_stayed += is_lower;
        mean_strain.push_back(j["start_mean_strain"]), max_strain.push_back(j["start_max_strain"]);
    }
    json s{{"summary", true}, {"garments", lines.size()}, {"flat_ok", flat_ok},
           {"flat_median_contiguous_fraction", median(flat_cf)}, {"flat_median_padding_ratio", median(flat_pad)}};
    if (!sewn) return s;
    s["sewn_ok"] = sewn_ok;
    s["stayed_on"] = stayed_on;
    s["lower_body"] = lower;
    s["lower_body_stayed_on"] = lower_stayed;
    // Rest strain over the garments that stay on (a garment that fell has no rest on the body).
    s["median_mean_strain"] = median(mean_strain);
    s["p90_mean_strain"] = percentile(mean_strain, 0.9);
    s["median_max_strain"] = median(max_strain);
    s["p90_max_strain"] = percentile(max_strain, 0.9);
    s["worst_max_strain"] = max_strain.empty() ? NAN : *std::max_element(max_strain.begin(), max_strain.end());
    s["median_contiguous_fraction"] = median(cf);
    s["p10_contiguous_fraction"] = percentile(cf, 0.1);
    s["median_padding_ratio"] = median(pad);
    s["median_sew_s"] = median(sew_s);
    if (moving > 0) s["moving"] = moving, s["moving_ok"] = moving_ok;
    if (!moving_strain.empty()) {
        s["moving_median_max_strain"] = median(moving_strain);
        s["moving_worst_max_strain"] = *std::max_element(moving_strain.begin(), moving_strain.end());
    }
    return s;
}

void print_line(const json& j, bool as_json) {
    if (as_json) {
        std::printf("%s\n", j.dump().c_str());
    } else if (j.value("summary", false)) {
        std::printf("\n");
        for (const auto& [key, value] : j.items())
            if (key != "summary") std::printf("  %-34s %s\n", key.c_str(), value.dump().c_str());
    } else {
        const auto num = [&](const char* key, double scale) { return j.contains(key) ? j[key].get<double>() * scale : NAN; };
        std::printf("%-16s %-5s flat %-3s sewn %-3s on %-3s drop %6.1f cm  strain %5.1f%% / %6.1f%%  runs %.2f  pad %4.1f%%  %5.1f s%s%s\n",
                    j.value("name", "?").c_str(), j.value("kind", "").c_str(), j.value("flat_ok", false) ? "ok" : "-",
                    j.value("sewn_ok", false) ? "ok" : "-", j.value("stayed_on", false) ? "yes" : "-", num("top_drop_m", 100),
                    num("start_mean_strain", 100), num("start_max_strain", 100), num("contiguous_fraction", 1),
                    num("padding_ratio", 100), num("sew_s", 1), j.contains("error") ? "  " : "",
                    j.value("error", "").c_str());
    }
    std::fflush(stdout);
}

}  // namespace

int run_corpus(const CorpusOptions& o) {
    std::string error;
    std::vector<std::string> files = bake::pattern_files(o.dir, &error);
    if (!error.empty()) {
        std::fprintf(stderr, "weft-bench corpus: %s\n", error.c_str());
        return 1;
    }
    std::erase_if(files, [&](const std::string& path) {  // --filter: comma-separated parts, any of them
        const std::string name = std::filesystem::path(path).filename().string();
        bool wanted = o.filter.empty();
        for (size_t at = 0; !wanted && at <= o.filter.size();) {
            const size_t comma = std::min(o.filter.find(',', at), o.filter.size());
            wanted = comma > at && name.find(o.filter.substr(at, comma - at)) != std::string::npos;
            at = comma + 1;
        }
        return !wanted;
    });
    if (files.empty()) {
        std::fprintf(stderr, "weft-bench corpus: no pattern (*.json) in '%s'\n", o.dir.c_str());
        return 1;
    }
    bake::SewBody body;
    if (!o.body.empty()) {
        if (o.body == "mannequin") {
            if (std::string e = mannequin_sew_body(&body); !e.empty()) return std::fprintf(stderr, "weft-bench corpus: %s\n", e.c_str()), 1;
        } else {
            body::BodyMesh mesh;
            if (std::string e = body::load_body_mesh(o.body, &mesh); !e.empty())
                return std::fprintf(stderr, "weft-bench corpus: --body %s: %s\n", o.body.c_str(), e.c_str()), 1;
            body.positions = std::move(mesh.positions), body.triangles = std::move(mesh.triangles);
        }
    }
    const bake::SewBody* sew_body = o.body.empty() ? nullptr : &body;
    // One child per garment, --jobs at a time; lines are printed in file order as soon as all
    // before them are in.
    std::vector<json> lines(files.size());
    std::vector<char> done(files.size(), 0);
    size_t printed = 0, finished = 0;
    progress::Bar bar("weft-bench corpus", files.size(), progress::wanted(o.json));
    const auto work = [&](size_t k) {
        try {
            return bake_one(files[k], sew_body, o).dump();
        } catch (const std::exception& e) {
            return json{{"name", bake::asset_name(files[k])}, {"error", std::string("exception: ") + e.what()}}.dump();
        }
    };
    const auto garment_done = [&](size_t k, jobs::Outcome outcome) {
        json j = outcome.error.empty() ? json::parse(outcome.output, nullptr, false) : json();
        if (!outcome.error.empty() || j.is_discarded() || !j.is_object()) {
            j = json{{"name", bake::asset_name(files[k])}, {"flat_ok", false}, {"sewn_ok", false},
                     {"error", outcome.error.empty() ? std::string("no result") : outcome.error}};
        }
        lines[k] = std::move(j);
        done[k] = 1, ++finished;
        bar.update(finished, bake::asset_name(files[k]));
        for (; printed < files.size() && done[printed]; ++printed) {
            if (bar.enabled()) bar.finish();
            print_line(lines[printed], o.json);
        }
    };
    jobs::run_in_children(files.size(), {o.jobs, o.timeout_s}, work, garment_done);
    bar.finish();
    print_line(summarise(lines, sew_body != nullptr), o.json);
    return 0;
}

}  // namespace weft::bench
