#include "bench/levers.h"

#include <cmath>
#include <cstdio>

namespace weft::bench {

SphereOutcome sphere_outcome(const Measurement& m, uint32_t n, float inflation_m) {
    SphereOutcome out;
    const uint32_t middle = (n / 2) * n + n / 2;  // the grid particle nearest the centre
    if (middle >= m.final_positions.size()) return out;
    out.middle = m.final_positions[middle];
    const double r = std::sqrt(double(out.middle.x) * out.middle.x + double(out.middle.y) * out.middle.y +
                               double(out.middle.z) * out.middle.z);
    out.middle_gap_m = r - (0.5 + inflation_m);
    out.stays = m.finite && m.rest_speed < 0.01 && m.bounds.min.y > -1.0f && out.middle_gap_m > -0.001 &&
                out.middle_gap_m < 0.02;
    return out;
}

std::vector<Lever> levers(uint32_t sweeps) {
    auto split = [&](const char* name, uint32_t substeps, float relaxation, bool tethers, bool coarse) {
        Lever l;
        l.name = name;
        scenes::apply_config(scenes::Config::plain, sweeps, l.options);
        l.options.explicit_split = true;
        l.options.substeps = substeps;
        l.options.iterations = sweeps / substeps;
        l.options.relaxation = relaxation;
        l.options.tethers = tethers;
        l.options.coarse_level = coarse ? CoarseLevel::on : CoarseLevel::off;
        l.options.contact_tethers = false;
        return l;
    };
    std::vector<Lever> out;
    out.push_back(split("plain: 1 substep x all iterations", 1, 1.0f, false, false));
    out.push_back(split("substeps instead of iterations", sweeps, 1.0f, false, false));
    out.push_back(split("substeps, under-relaxed 0.8", sweeps, 0.8f, false, false));
    out.push_back(split("iterations, under-relaxed 0.8", 1, 0.8f, false, false));
    out.push_back(split("tethers (iterations)", 1, 1.0f, true, false));
    Lever both = split("tethers before and after sweeps", 1, 1.0f, true, false);
    both.options.tethers_before_sweeps = true;
    out.push_back(both);
    out.push_back(split("tethers (substeps, 0.8)", sweeps, 0.8f, true, false));
    out.push_back(split("coarse level (iterations)", 1, 1.0f, false, true));
    out.push_back(split("coarse level (substeps, 0.8)", sweeps, 0.8f, false, true));
    out.push_back(split("coarse level + tethers (substeps, 0.8)", sweeps, 0.8f, true, true));
    Lever contact = split("coarse + contact tethers (substeps, 0.8)", sweeps, 0.8f, false, true);
    contact.options.contact_tethers = true;
    out.push_back(contact);
    // Fewer substeps, the coarse level solved 3 times a substep (ClothDesc::coarse_iterations).
    const uint32_t two = sweeps < 2 ? sweeps : 2;
    Lever coarse3 = split("2 substeps, coarse level x3 (0.8)", two, 0.8f, false, true);
    coarse3.options.coarse_iterations = 3;
    out.push_back(coarse3);
    Lever coarse3_contact = coarse3;
    coarse3_contact.name = "2 substeps, coarse x3 + contact tethers";
    coarse3_contact.options.contact_tethers = true;
    out.push_back(coarse3_contact);
    Lever d;
    d.name = "default (automatic policy)";
    scenes::apply_config(scenes::Config::default_config, sweeps, d.options);
    out.push_back(d);
    return out;
}

int run_levers(uint32_t n, uint32_t sweeps, uint32_t steps, bool json) {
    const SimdPath path = simd_path_available(SimdPath::avx2) ? SimdPath::avx2 : SimdPath::scalar;
    for (scenes::SeedScene scene : {scenes::SeedScene::drape, scenes::SeedScene::sphere}) {
        if (!json)
            std::printf("\n%s, n = %u, %u sweeps per step, %s path, %u frames (median us per step)\n",
                        scenes::scene_name(scene), n, sweeps, simd_path_name(path), steps + 30);
        if (!json)
            std::printf("%-40s %7s %9s %6s %10s %9s %9s %s\n", "lever", "split", "us/step", "ratio",
                        "mean str%", "max str%", "rest m/s", scene == scenes::SeedScene::sphere ? "stays" : "");
        double plain_us = 0.0;
        for (const Lever& lever : levers(sweeps)) {
            RunOptions ro;
            ro.scene = scene;
            ro.scene_options = lever.options;
            ro.scene_options.sphere_friction = 0.5f;
            ro.steps = steps;
            ro.passes = false;
            ro.repeats = 3;
            Measurement m;
            if (std::string err = measure(ro, n, path, &m); !err.empty()) {
                std::fprintf(stderr, "weft-bench levers: %s\n", err.c_str());
                return 1;
            }
            if (plain_us == 0.0) plain_us = m.total_us.median;
            const SphereOutcome s = sphere_outcome(m, n, ro.scene_options.sphere_inflation_m);
            const double ratio = m.total_us.median / plain_us;
            if (json) {
                std::printf("{\"bench\":\"levers\",\"scene\":\"%s\",\"n\":%u,\"sweeps\":%u,\"lever\":\"%s\","
                            "\"substeps\":%u,\"iterations\":%u,\"relaxation\":%g,\"tethers\":%s,\"coarse_level\":%s,"
                            "\"us_per_step\":%.2f,\"ratio_to_plain\":%.3f,\"mean_strain\":%.6f,\"max_strain\":%.6f,"
                            "\"rest_speed\":%.6f,\"middle_y\":%.4f,\"min_y\":%.4f,\"stays\":%s}\n",
                            scenes::scene_name(scene), n, sweeps, lever.name.c_str(), m.split.substeps,
                            m.split.iterations, double(m.split.relaxation), m.split.tethers ? "true" : "false",
                            m.split.coarse_level ? "true" : "false", m.total_us.median, ratio, m.strain.mean,
                            m.strain.max, m.rest_speed, double(s.middle.y), double(m.bounds.min.y),
                            s.stays ? "true" : "false");
            } else {
                char split[16];
                std::snprintf(split, sizeof(split), "%ux%u", m.split.substeps, m.split.iterations);
                std::printf("%-40s %7s %9.1f %6.2f %10.3f %9.2f %9.4f %s\n", lever.name.c_str(), split,
                            m.total_us.median, ratio, 100.0 * m.strain.mean, 100.0 * m.strain.max, m.rest_speed,
                            scene == scenes::SeedScene::sphere ? (s.stays ? "yes" : "no") : "");
            }
        }
    }
    return 0;
}

}  // namespace weft::bench
