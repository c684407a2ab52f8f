#include "bake/batch.h"

#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "bake/bake.h"

namespace weft::bake {
namespace {

using nlohmann::json;

// A manifest path: relative to the manifest's folder ("mannequin" is not a path).
std::string resolve(const std::filesystem::path& folder, const std::string& path) {
    if (path == "mannequin" || std::filesystem::path(path).is_absolute()) return path;
    return (folder / path).lexically_normal().string();
}

// Applies one JSON object's options ("defaults" or an entry) to `e`; `where` names it in errors.
std::string apply_options(const json& j, const std::filesystem::path& folder, bool is_entry, const std::string& where,
                          BatchEntry* e) {
    if (!j.is_object()) return where + ": not a JSON object";
    for (const auto& [key, value] : j.items()) {
        const std::string at = where + "." + key;
        if (is_entry && key == "pattern") {
            if (!value.is_string() || value.get<std::string>().empty()) return at + ": not a file name";
            e->pattern = resolve(folder, value.get<std::string>());
        } else if (is_entry && key == "name") {
            const std::string name = value.is_string() ? value.get<std::string>() : std::string();
            if (name.empty() || name.find_first_of("/\\") != std::string::npos || name == "." || name == "..")
                return at + ": not an asset name (a file name without folders)";
            e->name = name;
        } else if (key == "body") {
            if (value.is_null()) {
                e->body.clear();  // the flat bake, whatever the defaults say
            } else if (value.is_string() && !value.get<std::string>().empty()) {
                e->body = resolve(folder, value.get<std::string>());
            } else {
                return at + ": not a body (a mesh file, \"mannequin\" or null)";
            }
        } else if (key == "over") {
            // A pattern or a list of them, innermost first; relative to the manifest's folder.
            const json list = value.is_string() ? json::array({value}) : value;
            if (!list.is_array() || list.size() > kMaxWornOver) return at + ": not a pattern or a list of at most 4";
            e->over.clear();
            for (const json& p : list) {
                if (!p.is_string() || p.get<std::string>().empty()) return at + ": not a pattern file name";
                e->over.push_back(resolve(folder, p.get<std::string>()));
            }
        } else if (key == "target_edge_m") {
            if (!value.is_number() || value.get<double>() < 1e-4 || value.get<double>() > 10.0)
                return at + ": not a length from 0.0001 to 10 m";
            e->target_edge_m = value.get<double>();
        } else if (key == "simd_width") {
            if (!value.is_number_unsigned() || (value.get<uint32_t>() != 8 && value.get<uint32_t>() != 16))
                return at + ": not 8 or 16";
            e->simd_width = value.get<uint32_t>();
        } else if (key == "sweeps") {
            if (!value.is_number_unsigned() || value.get<uint64_t>() < 1 || value.get<uint64_t>() > 1000)
                return at + ": not a whole number from 1 to 1000";
            e->sweeps = value.get<uint32_t>();
        } else if (key == "offset_m") {
            if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
                !value[2].is_number())
                return at + ": not [x, y, z] in metres";
            for (size_t k = 0; k < 3; ++k) e->offset_m[k] = value[k].get<double>();
        } else {
            return where + ": unknown key '" + key + "'";
        }
    }
    return {};
}

}  // namespace

bool is_manifest(std::string_view text) {
    const json j = json::parse(text, nullptr, false);
    return j.is_object() && j.value("format", json()) == "weft-bake-manifest";
}

std::string read_folder(const std::string& folder, const BatchEntry& defaults, std::vector<BatchEntry>* out) {
    std::string error;
    const std::vector<std::string> files = pattern_files(folder, &error);
    if (!error.empty()) return error;
    if (files.empty()) return "no pattern (*.json) in '" + folder + "'";
    out->clear();
    for (const std::string& file : files) {
        BatchEntry e = defaults;
        e.pattern = file;
        e.name = asset_name(file);
        out->push_back(std::move(e));
    }
    return {};
}

std::string read_manifest(const std::string& path, std::string_view text, const BatchEntry& defaults,
                          std::vector<BatchEntry>* out) {
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return path + ": not a JSON object";
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    BatchEntry shared = defaults;
    shared.manifest = path;
    for (const auto& [key, value] : j.items()) {
        if (key == "format" || key == "assets") continue;
        if (key != "defaults") return path + ": unknown key '" + key + "'";
        if (std::string e = apply_options(value, folder, false, "defaults", &shared); !e.empty()) return path + ": " + e;
    }
    const json assets = j.value("assets", json());
    if (!assets.is_array() || assets.empty()) return path + ": \"assets\" is not a list of patterns";
    out->clear();
    std::set<std::string> names;
    for (size_t k = 0; k < assets.size(); ++k) {
        const std::string where = "assets[" + std::to_string(k) + "]";
        BatchEntry e = shared;
        if (std::string error = apply_options(assets[k], folder, true, where, &e); !error.empty()) return path + ": " + error;
        if (e.pattern.empty()) return path + ": " + where + ": no \"pattern\"";
        if (e.name.empty()) e.name = asset_name(e.pattern);
        if (!names.insert(e.name).second)
            return path + ": " + where + ": a second asset named '" + e.name + "' (give it a \"name\")";
        out->push_back(std::move(e));
    }
    return {};
}

}  // namespace weft::bake
