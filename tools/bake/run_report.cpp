#include "bake/run_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace weft::bake {

namespace {

// The grid's spring families (mesh_panel.cpp: one diagonal, lower left to upper right), as
// (di, dj) with di > 0 or (di == 0 and dj > 0).
bool grid_family(ConstraintKind kind, int32_t di, int32_t dj) {
    if (di < 0 || (di == 0 && dj < 0)) di = -di, dj = -dj;
    switch (kind) {
        case ConstraintKind::stretch: return (di == 0 && dj == 1) || (di == 1 && dj == 0);
        case ConstraintKind::shear: return di == 1 && dj == 1;
        case ConstraintKind::bend: return (di == 1 && dj == -1) || (di == 2 && dj == 1) || (di == 1 && dj == 2);
    }
    return false;
}

}  // namespace

RunReport run_report(const MeshedGarment& g, const ClothAsset& a, const CookOptions& options) {
    RunReport r;
    struct Off {
        uint32_t kind, offset, a;
    };
    std::vector<Off> family_off;  // grid-family constraints off runs
    // The lattice box as the runtime's assign_slots sees it: slots past its four planes are off it.
    int32_t i0 = INT32_MAX, j0 = INT32_MAX, i1 = -1, j1 = -1;
    for (size_t k = 0; k < g.lattice.size(); k += 2)
        if (g.lattice[k] >= 0 && g.lattice[k + 1] >= 0)
            i0 = std::min(i0, g.lattice[k]), i1 = std::max(i1, g.lattice[k]), j0 = std::min(j0, g.lattice[k + 1]),
            j1 = std::max(j1, g.lattice[k + 1]);
    i0 &= ~1, j0 &= ~1;
    uint64_t box = i1 < 0 ? 0 : uint64_t((i1 - i0) / 2 + 1) * uint64_t((j1 - j0) / 2 + 1) * 4;
    if (const uint64_t stride = g.lattice_plane_stride; i1 >= 0 && stride != 0 && stride != uint64_t((j1 - j0) / 2 + 1)) {
        uint64_t first = ~uint64_t(0), last = 0;  // the helix, as assign_slots lays it out
        for (size_t k = 0; k < g.lattice.size(); k += 2)
            if (g.lattice[k] >= 0 && g.lattice[k + 1] >= 0) {
                const uint64_t at = uint64_t(g.lattice[k] - i0) / 2 * stride + uint64_t(g.lattice[k + 1] - j0) / 2;
                first = std::min(first, at), last = std::max(last, at);
            }
        box = (last - first + 1) * 4;
    }
    const bool lattice_used = box > 0 && box <= uint64_t(a.particle_count) * 8 + 64;  // assign_slots' density check
    r.lattice_box = box;
    r.lattice_used = lattice_used;
    for (uint32_t bi = 0; bi < a.batch_count; ++bi) {
        const ConstraintBatch& b = a.batches[bi];
        if (b.layout == BatchLayout::run) {
            ++r.runs;
            uint32_t last_real = 0;
            for (uint32_t k = 0; k < b.lane_count; ++k)
                if (a.lane_weight[b.first_lane + k] != 0.0f) last_real = k;
            uint32_t prev_real = 0;
            for (uint32_t k = 0; k < b.lane_count; ++k) {
                if (a.lane_weight[b.first_lane + k] != 0.0f) {
                    if (k > prev_real + 1) {  // a gap between lanes prev_real and k
                        const uint32_t pa = a.particle_of_slot[b.a0 + prev_real], pb = a.particle_of_slot[b.a0 + k];
                        const bool across = pa == kNoParticle || pb == kNoParticle || g.panel[pa] != g.panel[pb];
                        (across ? r.gaps_between_panels : r.gaps_inside_panels)[k - prev_real - 1] += k - prev_real - 1;
                    }
                    prev_real = k;
                    ++r.run_lanes;
                    ++r.kinds[uint32_t(b.kind)].on_runs;
                } else if (k < last_real) {
                    ++r.gap_lanes;
                } else {
                    ++r.tail_lanes;
                }
            }
            continue;
        }
        for (uint32_t k = 0; k < b.lane_count; ++k) {
            ++r.indexed_lanes;
            const uint32_t sa = a.index_a[b.first_lane + k], sb = a.index_b[b.first_lane + k];
            const uint32_t pa = a.particle_of_slot[sa], pb = a.particle_of_slot[sb];
            RunReport::Kind& kind = r.kinds[uint32_t(b.kind)];
            const int32_t ai = g.lattice[2 * pa], aj = g.lattice[2 * pa + 1], bi2 = g.lattice[2 * pb], bj = g.lattice[2 * pb + 1];
            if (!lattice_used || ai < 0 || bi2 < 0 || sa >= box || sb >= box) {
                ++kind.off_lattice;
            } else if (!grid_family(b.kind, bi2 - ai, bj - aj)) {
                ++kind.odd_family;
                int32_t di = bi2 - ai, dj = bj - aj;
                if (di < 0 || (di == 0 && dj < 0)) di = -di, dj = -dj;
                char key[48];
                std::snprintf(key, sizeof key, "%s(%d,%d)", b.kind == ConstraintKind::stretch ? "stretch" : b.kind == ConstraintKind::shear ? "shear" : "bend", di, dj);
                r.odd_families[key] += 1;
            } else {
                ++kind.short_run;
                family_off.push_back({uint32_t(b.kind), sb - sa, sa});
            }
        }
    }
    // Lengths of the maximal sequences the grid-family constraints off runs form.
    std::sort(family_off.begin(), family_off.end(), [](const Off& l, const Off& q) {
        return l.kind != q.kind ? l.kind < q.kind : l.offset != q.offset ? l.offset < q.offset : l.a < q.a;
    });
    for (size_t i = 0; i < family_off.size();) {
        size_t j = i + 1;
        while (j < family_off.size() && family_off[j].kind == family_off[i].kind &&
               family_off[j].offset == family_off[i].offset && family_off[j].a - family_off[j - 1].a <= options.max_run_gap + 1)
            ++j;
        r.short_run_lengths[uint32_t(j - i)] += j - i;
        i = j;
    }
    r.wind_run_triangles = a.wind_run_triangles;
    r.wind_single_triangles = a.triangle_count - a.wind_run_triangles;
    r.wind_lanes = a.wind_lane_count;
    for (uint32_t l = 0; l < a.wind_lane_count; ++l) r.wind_padding_lanes += a.wind_lane_weight[l] == 0.0f;
    r.coarse_lanes = a.coarse_lane_count;
    for (uint32_t l = 0; l < a.coarse_lane_count; ++l) r.coarse_padding_lanes += a.coarse_lane_weight[l] == 0.0f;
    r.tether_lanes = a.tether_lane_count;
    for (uint32_t l = 0; l < a.tether_lane_count; ++l)
        r.tether_padding_lanes += std::isinf(a.tether_rest[0][l]) && std::isinf(a.tether_rest[1][l]);
    return r;
}

std::string format_run_report(const RunReport& r) {
    std::string s;
    char line[256];
    const char* names[] = {"stretch", "shear", "bend"};
    uint64_t total = 0, on = 0;
    for (const RunReport::Kind& k : r.kinds) total += k.on_runs + k.off_lattice + k.odd_family + k.short_run, on += k.on_runs;
    std::snprintf(line, sizeof line, "lattice box %llu slots (%s)\n", (unsigned long long)r.lattice_box,
                  r.lattice_used ? "used" : "refused by the runtime's density check");
    s += line;
    std::snprintf(line, sizeof line, "constraints %llu, on runs %llu (%.3f)\n", (unsigned long long)total,
                  (unsigned long long)on, total ? double(on) / double(total) : 0.0);
    s += line;
    for (uint32_t k = 0; k < kConstraintKindCount; ++k) {
        const RunReport::Kind& q = r.kinds[k];
        std::snprintf(line, sizeof line, "  %-8s on runs %6llu  off: off_lattice %5llu  odd_family %5llu  short_run %5llu\n",
                      names[k], (unsigned long long)q.on_runs, (unsigned long long)q.off_lattice,
                      (unsigned long long)q.odd_family, (unsigned long long)q.short_run);
        s += line;
    }
    s += "  gap lanes inside a panel (size: lanes):";
    for (const auto& [size, count] : r.gaps_inside_panels) {
        std::snprintf(line, sizeof line, " %u:%llu", size, (unsigned long long)count);
        s += line;
    }
    s += "\n  gap lanes between panels (size: lanes):";
    for (const auto& [size, count] : r.gaps_between_panels) {
        std::snprintf(line, sizeof line, " %u:%llu", size, (unsigned long long)count);
        s += line;
    }
    s += "\n  odd families:";
    for (const auto& [key, count] : r.odd_families) {
        std::snprintf(line, sizeof line, " %s:%llu", key.c_str(), (unsigned long long)count);
        s += line;
    }
    s += "\n  short sequences (length: constraints):";
    for (const auto& [length, count] : r.short_run_lengths) {
        std::snprintf(line, sizeof line, " %u:%llu", length, (unsigned long long)count);
        s += line;
    }
    const uint64_t lanes = r.run_lanes + r.gap_lanes + r.tail_lanes + r.indexed_lanes;
    const uint64_t wind = r.wind_lanes + r.wind_single_triangles;
    const uint64_t all = lanes + r.coarse_lanes + r.tether_lanes + wind;
    const uint64_t padding = r.gap_lanes + r.tail_lanes + r.coarse_padding_lanes + r.tether_padding_lanes + r.wind_padding_lanes;
    std::snprintf(line, sizeof line,
                  "\nlanes %llu (constraints %llu, coarse %llu, tethers %llu, wind %llu), padding %llu (%.3f): run gaps %llu, "
                  "run tails %llu, coarse %llu, tethers %llu, wind %llu; %llu runs\n",
                  (unsigned long long)all, (unsigned long long)lanes, (unsigned long long)r.coarse_lanes,
                  (unsigned long long)r.tether_lanes, (unsigned long long)wind, (unsigned long long)padding,
                  all ? double(padding) / double(all) : 0.0, (unsigned long long)r.gap_lanes,
                  (unsigned long long)r.tail_lanes, (unsigned long long)r.coarse_padding_lanes,
                  (unsigned long long)r.tether_padding_lanes, (unsigned long long)r.wind_padding_lanes,
                  (unsigned long long)r.runs);
    s += line;
    std::snprintf(line, sizeof line, "wind triangles on runs %llu, gathered or one at a time %llu\n",
                  (unsigned long long)r.wind_run_triangles, (unsigned long long)r.wind_single_triangles);
    s += line;
    return s;
}

}  // namespace weft::bake
