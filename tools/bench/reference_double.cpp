#include "bench/reference_double.h"

#include <chrono>
#include <cstdint>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace weft::bench {

std::string run_drape_double(const scenes::SceneOptions& physics, uint32_t substeps, const Sampling& sampling,
                             Trajectory* out, double perturb_m) {
    *out = Trajectory{};
    if (substeps == 0) return "substeps must be at least 1";
    const scenes::SceneOptions o = plain_split(physics, 1, 1);
    scenes::SeedWorld sw;  // the same asset the float runs use (masses, pins, springs, batch order)
    if (std::string e = scenes::make_seed_world(scenes::SeedScene::drape, o, &sw); !e.empty()) return e;
    const scenes::Scene scene = scenes::seed_scene(scenes::SeedScene::drape, o);
    const ClothAsset& a = sw.asset();
    const uint32_t n = a.particle_count;
    out->start.resize(n);
    if (Result r = read_positions(sw.world, sw.cloth, out->start.data(), n); !r.ok()) return r.message;

    struct D3 {
        double x, y, z;
    };
    std::vector<D3> x(n), previous(n);
    std::vector<double> w(n);
    for (uint32_t p = 0; p < n; ++p) {
        x[p] = previous[p] = {out->start[p].x, out->start[p].y, out->start[p].z};
        w[p] = a.inverse_mass[a.slot_of_particle[p]];
        if (perturb_m != 0.0 && w[p] > 0.0) {  // a fixed pattern in [-1, 1) per coordinate
            uint64_t state = 0x9E3779B97F4A7C15ull * (p + 1);
            auto next = [&] {
                state ^= state >> 31, state *= 0xBF58476D1CE4E5B9ull, state ^= state >> 29;
                return double(state >> 11) / double(1ull << 52) - 1.0;
            };
            x[p].x += perturb_m * next(), x[p].y += perturb_m * next(), x[p].z += perturb_m * next();
            previous[p] = x[p];
        }
    }
    struct Spring {
        uint32_t a, b, kind;
        double rest;
    };
    std::vector<Spring> springs;  // batch by batch, lane by lane: the runtime's order
    for (uint32_t b = 0; b < a.batch_count; ++b) {
        const ConstraintBatch& batch = a.batches[b];
        for (uint32_t l = batch.first_lane; l < batch.first_lane + batch.lane_count; ++l)
            if (a.lane_weight[l] != 0.0f)
                springs.push_back({a.particle_of_slot[a.index_a[l]], a.particle_of_slot[a.index_b[l]],
                                   uint32_t(batch.kind), double(a.rest_length[l])});
    }
    const double compliance[3] = {physics.stretch_compliance_m_per_n, physics.shear_compliance_m_per_n,
                                  physics.bend_compliance_m_per_n};
    const D3 g{scene.gravity_m_s2.x, scene.gravity_m_s2.y, scene.gravity_m_s2.z};
    const double h = double(sw.dt_s) / substeps;
    const double damping = std::exp(-double(physics.damping_per_s) * h);
    bool first = true;
    for (uint32_t frame = 1; frame <= sampling.frames; ++frame) {
        for (uint32_t s = 0; s < substeps; ++s) {
            const double h2 = (first ? 0.5 : 1.0) * h * h;  // the first substep starts at rest
            first = false;
            for (uint32_t p = 0; p < n; ++p) {
                if (!(w[p] > 0.0)) continue;
                const D3 next{x[p].x + (x[p].x - previous[p].x) * damping + g.x * h2,
                              x[p].y + (x[p].y - previous[p].y) * damping + g.y * h2,
                              x[p].z + (x[p].z - previous[p].z) * damping + g.z * h2};
                previous[p] = x[p];
                x[p] = next;
            }
            for (const Spring& c : springs) {
                D3& xa = x[c.a];
                D3& xb = x[c.b];
                const double dx = xb.x - xa.x, dy = xb.y - xa.y, dz = xb.z - xa.z;
                const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
                const double w_sum = w[c.a] + w[c.b] + compliance[c.kind] / (h * h);
                if (!(len > 1e-9) || !(w_sum > 0.0)) continue;
                const double k = (len - c.rest) / (len * w_sum);
                const double sa = w[c.a] * k, sb = w[c.b] * k;
                xa = {xa.x + sa * dx, xa.y + sa * dy, xa.z + sa * dz};
                xb = {xb.x - sb * dx, xb.y - sb * dy, xb.z - sb * dz};
            }
        }
        out->step_us.push_back(0.0);
        out->step_wall_us.push_back(0.0);
        if (!sampling.sampled(frame)) continue;
        std::vector<Vec3> positions(n);
        for (uint32_t p = 0; p < n; ++p) {
            positions[p] = {float(x[p].x), float(x[p].y), float(x[p].z)};
            out->finite = out->finite && std::isfinite(x[p].x + x[p].y + x[p].z);
        }
        out->frames.push_back(std::move(positions));
    }
    return {};
}

}  // namespace weft::bench

namespace weft::bench {

int run_reference_study(const ReferenceStudyOptions& o) {
    for (uint32_t n : o.sizes) {
        scenes::SceneOptions physics;
        physics.n = n;
        physics.stretch_compliance_m_per_n = o.compliance_m_per_n[0];
        physics.shear_compliance_m_per_n = o.compliance_m_per_n[1];
        physics.bend_compliance_m_per_n = o.compliance_m_per_n[2];
        Trajectory previous;
        double diagonal = 0.0;
        if (!o.json)
            std::printf("drape n=%u, %u frames: substeps x 1 | double: change from half the substeps | float (runtime) "
                        "vs double at the same split | float: change from half | double with its start moved\n",
                        n, o.sampling.frames);
        Trajectory previous_float;
        for (uint32_t s = 1; s <= o.cap; s *= 2) {
            Trajectory d;
            const auto t0 = std::chrono::steady_clock::now();
            if (std::string e = run_drape_double(physics, s, o.sampling, &d); !e.empty())
                return std::fprintf(stderr, "weft-bench reference: %s\n", e.c_str()), 1;
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (diagonal == 0.0) diagonal = metrics::diagonal_m(d.start);
            const double inf = std::numeric_limits<double>::infinity();
            const double change = previous.frames.empty() ? inf : metrics::trajectory_error(d.frames, previous.frames, diagonal);
            Trajectory moved;
            if (std::string e = run_drape_double(physics, s, o.sampling, &moved, o.perturb_m); !e.empty())
                return std::fprintf(stderr, "weft-bench reference: %s\n", e.c_str()), 1;
            const double sensitivity = metrics::trajectory_error(moved.frames, d.frames, diagonal);
            // The same on the last frame only (the drape at rest).
            const double rest_change = previous.frames.empty() ? inf : metrics::rest_state_error(d.frames, previous.frames, diagonal);
            const double rest_sensitivity = metrics::rest_state_error(moved.frames, d.frames, diagonal);
            double float_vs_double = inf, float_change = inf;
            if (s <= 64) {
                Trajectory f;
                if (std::string e = run_trajectory(scenes::SeedScene::drape, plain_split(physics, s, 1), o.sampling, &f);
                    !e.empty())
                    return std::fprintf(stderr, "weft-bench reference: %s\n", e.c_str()), 1;
                float_vs_double = metrics::trajectory_error(f.frames, d.frames, diagonal);
                if (!previous_float.frames.empty())
                    float_change = metrics::trajectory_error(f.frames, previous_float.frames, diagonal);
                previous_float = std::move(f);
            }
            if (o.json) {
                std::printf("{\"bench\":\"reference\",\"scene\":\"drape\",\"n\":%u,\"substeps\":%u,\"double_change\":%.4g,"
                            "\"float_vs_double\":%.4g,\"float_change\":%.4g,\"perturbed\":%.4g,\"rest_change\":%.4g,"
                            "\"rest_perturbed\":%.4g,\"seconds\":%.2f}\n",
                            n, s, std::isfinite(change) ? change : -1.0, std::isfinite(float_vs_double) ? float_vs_double : -1.0,
                            std::isfinite(float_change) ? float_change : -1.0, sensitivity,
                            std::isfinite(rest_change) ? rest_change : -1.0, rest_sensitivity, seconds);
            } else {
                std::printf("  %5ux1  double change %10.3g   float vs double %10.3g   float change %10.3g   "
                            "double moved %g m vs not %10.3g | at rest: change %10.3g  moved %10.3g   (%.1f s)\n",
                            s, change, float_vs_double, float_change, o.perturb_m, sensitivity, rest_change,
                            rest_sensitivity, seconds);
            }
            std::fflush(stdout);
            previous = std::move(d);
        }
    }
    return 0;
}

int run_sphere_sensitivity(const ReferenceStudyOptions& o, float offset_m) {
    for (uint32_t n : o.sizes) {
        scenes::SceneOptions physics;
        physics.n = n;
        physics.sphere_friction = 0.5f;  // the sweep's
        std::printf("sphere n=%u, %u frames, float runtime: substeps x 1 | change from half | dropped %g m off-centre vs "
                    "not | at rest: change, moved\n",
                    n, o.sampling.frames, double(offset_m));
        Trajectory previous;
        double diagonal = 0.0;
        for (uint32_t s = 1; s <= std::min(o.cap, 64u); s *= 2) {
            Trajectory t, moved;
            scenes::SceneOptions off = physics;
            off.sphere_offset_m = offset_m;
            if (std::string e = run_trajectory(scenes::SeedScene::sphere, plain_split(physics, s, 1), o.sampling, &t); !e.empty())
                return std::fprintf(stderr, "weft-bench reference: %s\n", e.c_str()), 1;
            if (std::string e = run_trajectory(scenes::SeedScene::sphere, plain_split(off, s, 1), o.sampling, &moved); !e.empty())
                return std::fprintf(stderr, "weft-bench reference: %s\n", e.c_str()), 1;
            if (diagonal == 0.0) diagonal = metrics::diagonal_m(t.start);
            const double inf = std::numeric_limits<double>::infinity();
            const double change = previous.frames.empty() ? inf : metrics::trajectory_error(t.frames, previous.frames, diagonal);
            const double rest_change = previous.frames.empty() ? inf : metrics::rest_state_error(t.frames, previous.frames, diagonal);
            std::printf("  %5ux1  change %10.3g   moved vs not %10.3g | at rest: change %10.3g  moved %10.3g\n", s, change,
                        metrics::trajectory_error(moved.frames, t.frames, diagonal), rest_change,
                        metrics::rest_state_error(moved.frames, t.frames, diagonal));
            std::fflush(stdout);
            previous = std::move(t);
        }
    }
    return 0;
}

}  // namespace weft::bench
