// weft-bench body: the body-collision pass on the shared mean_all body blended between its A-pose and
// T-pose (issue 13, point 3). Not a timed test: it prints medians per frame.
//   weft-bench body [--frames 60] [--points 10000] [--thickness 0.005] [--fall G] [--random-order] [--scalar]
//                   [--simplify SHARE] [--json]
// Two worlds step the same frames: Weft's pass (its own hierarchy, rays through Embree) and the
// plain pass (add_reference_body: Embree refit + one rtcPointQuery per particle). Per frame:
// set_body_vertices (offset hull of the new pose), then the step's body pass, for points 0 to 3 cm off
// the skin of the torso, hips and upper arms, re-placed on the new pose before every step (a
// garment-like load). The points are ordered as a garment's slots are: neighbours next to each other
// (Morton order of their places on the A-pose), unless --random-order.
#include "bench/body.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <vector>

#include <meshoptimizer.h>

#include "body/body_mesh.h"
#include "weft/weft.h"
#include "weft/cook.h"
#include "weft/debug.h"

namespace weft::bench {
namespace {

struct BodyRun {
    std::unique_ptr<unsigned char[], void (*)(void*)> block{nullptr, std::free};
    World* world = nullptr;
    ClothId cloth;
    BodyId body;
    // pass_us: the step's CPU time on this thread (the body pass and a Verlet pass over the points,
    // about 10 us); wall_pass_us: the body pass's wall time (WorldStats); refit_us is wall time too.
    std::vector<double> hull_us, pass_us, wall_pass_us, refit_us;
    double max_penetration_m = 0.0;
    uint64_t deeper_than_1mm = 0;  // particle-frames left more than 1 mm inside
    uint64_t contacts = 0, rays = 0, queried = 0, embree_refits = 0;
};

bool make_run(const body::BodyMesh& a, const std::vector<uint32_t>& triangles, float thickness_m, const ClothAsset& asset,
              const BodyBenchOptions& o, bool reference, BodyRun* run) {
    WorldDesc desc;
    desc.max_cloths = 0;
    reserve_cloth(desc, asset);
    desc.max_bodies = 1;
    desc.max_body_vertices = a.vertex_count();
    desc.max_body_triangles = a.triangle_count();
    desc.gravity_m_s2 = {0, -o.fall_m_s2, 0};
    desc.simd = o.scalar ? SimdPath::scalar : SimdPath::automatic;
    const MemoryRequirements need = world_memory_requirements(desc);
    run->block.reset(static_cast<unsigned char*>(
        std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment)));
    if (Result r = create_world(desc, run->block.get(), need.bytes, &run->world); !r.ok())
        return std::fprintf(stderr, "%s\n", r.message), false;
    set_profiling(run->world, true);
    ClothDesc cd;
    cd.asset = &asset;
    cd.policy = BudgetPolicy::explicit_split;  // one substep: one body pass per frame
    cd.substeps = 1;
    cd.iterations = 0;
    BodyDesc bd;
    bd.positions = a.positions.data();
    bd.vertex_count = a.vertex_count();
    bd.triangles = triangles.data();
    bd.triangle_count = uint32_t(triangles.size() / 3);
    bd.thickness_m = thickness_m;
    if (!add_cloth(run->world, cd, &run->cloth).ok() ||
        !(reference ? add_reference_body(run->world, bd, &run->body) : add_body(run->world, bd, &run->body)).ok())
        return std::fprintf(stderr, "setup failed\n"), false;
    return true;
}

// This thread's CPU time: the other processes on a shared machine do not count (wall time does).
double thread_cpu_us() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e6 + double(t.tv_nsec) / 1e3;
}

double median(std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
}

uint32_t morton(const float* unit) {
    uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const uint32_t cell = uint32_t(std::min(1023.0f, std::max(0.0f, unit[a] * 1024.0f)));
        for (int bit = 0; bit < 10; ++bit) code |= ((cell >> bit) & 1u) << (3 * bit + a);
    }
    return code;
}

}  // namespace

int run_body(const BodyBenchOptions& o) {
    body::BodyMesh a, t;
    for (auto [file, mesh] : {std::pair{"mean_all.obj", &a}, std::pair{"mean_all_tpose.obj", &t}}) {
        const std::string error = body::load_body_mesh(body::shared_body_path(file), mesh);
        if (!error.empty()) {
            std::fprintf(stderr, "weft-bench body: %s\n", error.c_str());
            return 1;
        }
    }
    // Torso, hips and upper arms: skin between hip and shoulder height (y 0.85 to 1.45 m) whose A-to-T
    // motion is under 30 cm (the forearms and hands move further).
    std::vector<uint32_t> region;
    for (uint32_t i = 0; i < a.vertex_count(); ++i) {
        const Vec3 p = a.positions[i], q = t.positions[i];
        const float move = std::sqrt((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) + (q.z - p.z) * (q.z - p.z));
        if (p.y > 0.85f && p.y < 1.45f && move < 0.3f) region.push_back(i);
    }
    uint32_t seed = 7;
    auto uniform = [&] {
        seed = seed * 1664525u + 1013904223u;
        return float(seed >> 8) / float(1u << 24);
    };
    const uint32_t n = o.points;
    std::vector<uint32_t> vertex(n);
    std::vector<float> offset(n);
    for (uint32_t k = 0; k < n; ++k) {
        vertex[k] = region[uint32_t(uniform() * float(region.size())) % region.size()];
        offset[k] = 0.03f * uniform() - o.thickness_m;  // 0 to 3 cm off the skin, measured from the hull
    }
    if (!o.random_order) {
        // A garment's slots run along its lattice rows: neighbours sit next to each other. Morton order
        // of the points' places on the A-pose gives this cloud the same property, for the plain pass
        // too (it queries in slot order). Weft's pass orders by start positions (order_for_body_pass):
        // they are all one place here, so it keeps this order, or --random-order's.
        Vec3 lo{1e9f, 1e9f, 1e9f}, hi{-1e9f, -1e9f, -1e9f};
        for (uint32_t v : vertex) {
            const Vec3 p = a.positions[v];
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        }
        std::vector<std::pair<uint32_t, uint32_t>> keys(n);
        for (uint32_t k = 0; k < n; ++k) {
            const Vec3 p = a.positions[vertex[k]];
            const float unit[3] = {(p.x - lo.x) / (hi.x - lo.x), (p.y - lo.y) / (hi.y - lo.y), (p.z - lo.z) / (hi.z - lo.z)};
            keys[k] = {morton(unit), k};
        }
        std::sort(keys.begin(), keys.end());
        std::vector<uint32_t> v2(n);
        std::vector<float> o2(n);
        for (uint32_t k = 0; k < n; ++k) v2[k] = vertex[keys[k].second], o2[k] = offset[keys[k].second];
        vertex.swap(v2);
        offset.swap(o2);
    }
    std::vector<Vec3> start(n, Vec3{0, 3, 0});
    std::vector<float> masses(n, 0.01f);
    ClothMeshDesc mesh;
    mesh.particle_count = n;
    mesh.positions = start.data();
    mesh.masses = masses.data();
    CookedCloth cooked;
    if (Result r = cook_cloth(mesh, {}, &cooked); !r.ok()) return std::fprintf(stderr, "%s\n", r.message), 1;

    // --simplify: Weft's world collides with fewer triangles over the same vertices (meshoptimizer
    // keeps the vertex indices, so the game's skinned vertices still drive them), its hull pushed out
    // by meshoptimizer's error bound on the A-pose (the penetration below is measured against the
    // full-resolution hull, so it shows whether that bound holds on the moving body).
    std::vector<uint32_t> collision = a.triangles;
    float extra_m = 0.0f;
    if (o.simplify > 0.0f && o.simplify < 1.0f) {
        const float* xyz = &a.positions[0].x;
        const size_t target = size_t(double(a.triangles.size()) * o.simplify) / 3 * 3;
        float relative = 0.0f;
        collision.resize(a.triangles.size());
        collision.resize(meshopt_simplify(collision.data(), a.triangles.data(), a.triangles.size(), xyz,
                                          a.vertex_count(), sizeof(Vec3), target, 1.0f, 0, &relative));
        extra_m = relative * meshopt_simplifyScale(xyz, a.vertex_count(), sizeof(Vec3));
    }
    BodyRun runs[2];  // [0]: Weft's pass, [1]: the plain rtcPointQuery pass
    for (int r = 0; r < 2; ++r)
        if (!make_run(a, r == 0 ? collision : a.triangles, o.thickness_m + (r == 0 ? extra_m : 0.0f), cooked.asset(), o,
                      r == 1, &runs[r]))
            return 1;

    std::vector<Vec3> pose, placed(n), after(n);
    for (uint32_t f = 0; f < o.frames + 5; ++f) {
        const float phase = float(f % 60) / 30.0f;  // A to T in one second, back in the next
        body::blend(a, t, phase <= 1.0f ? phase : 2.0f - phase, &pose);
        // Each world gets the new pose just before its step (its hull still in cache, as in a game
        // that poses the body and steps). The points go on the full-resolution hull of the pose:
        // the world's own, or with --simplify the plain world's, posed first.
        bool posed[2] = {false, false};
        auto pose_world = [&](int r) {
            const auto t0 = std::chrono::steady_clock::now();
            set_body_vertices(runs[r].world, runs[r].body, pose.data(), uint32_t(pose.size()));
            const auto t1 = std::chrono::steady_clock::now();
            if (f >= 5) runs[r].hull_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
            posed[r] = true;
        };
        for (int order = 0; order < 2; ++order) {
            const int r = int((f + order) % 2);  // alternate which runs first
            BodyRun& run = runs[r];
            const bool simplified = collision.size() != a.triangles.size();
            if (r == 0 && simplified && !posed[1]) pose_world(1);
            if (!posed[r]) pose_world(r);
            BodyView v;
            view_body(runs[simplified ? 1 : r].world, runs[simplified ? 1 : r].body, &v);
            for (uint32_t k = 0; k < n; ++k) {
                const float* h = v.hull + 4 * vertex[k];
                const float* nv = v.normals + 3 * vertex[k];
                placed[k] = {h[0] + offset[k] * nv[0], h[1] + offset[k] * nv[1], h[2] + offset[k] * nv[2]};
                set_particle(run.world, run.cloth, k, placed[k], 100.0f);
            }
            const WorldStats before = world_stats(run.world);
            const double cpu0 = thread_cpu_us();
            step(run.world, 1.0f / 30.0f);
            const double cpu1 = thread_cpu_us();
            const WorldStats s = world_stats(run.world);
            if (f < 5) continue;  // warm-up
            run.pass_us.push_back(cpu1 - cpu0);
            run.wall_pass_us.push_back(double(s.pass_ns[int(Pass::body)] - before.pass_ns[int(Pass::body)]) / 1e3);
            run.refit_us.push_back(double(s.body_refit_ns - before.body_refit_ns) / 1e3);
            run.contacts += s.body_contacts;
            run.rays += s.body_rays;
            run.queried += s.body_queried;
            run.embree_refits += s.body_embree_refits;
        }
        if (f < 5) continue;
        // Penetration left by each pass, measured by Embree's full-resolution query of the plain
        // world (both worlds hold the same hull of this pose).
        for (BodyRun& run : runs) {
            read_positions(run.world, run.cloth, after.data(), n);
            for (uint32_t k = 0; k < n; ++k) {
                BodyContact c;
                if (query_body(runs[1].world, runs[1].body, after[k], &c).ok() && c.found)
                    run.max_penetration_m = std::max(run.max_penetration_m, double(c.penetration_m));
                if (c.found && c.penetration_m > 1e-3f) run.deeper_than_1mm += 1;
            }
        }
    }
    const BodyRun &ours = runs[0], &plain = runs[1];
    const double frames = o.frames;
    const double ours_us = median(ours.pass_us), plain_us = median(plain.pass_us);
    const double ours_refit = median(ours.refit_us), plain_refit = median(plain.refit_us);
    if (o.json) {
        std::printf("{\"body_triangles\": %u, \"points\": %u, \"thickness_m\": %g, \"frames\": %u, \"order\": \"%s\", "
                    "\"simd\": \"%s\", \"fall_m_s2\": %g, \"offset_hull_us\": %.1f, \"body_pass_us\": %.1f, "
                    "\"refit_us\": %.1f, \"contacts_rays_us\": %.1f, \"baseline_point_query_us\": %.1f, "
                    "\"baseline_refit_us\": %.1f, \"body_pass_wall_us\": %.1f, \"baseline_wall_us\": %.1f, \"speedup\": %.2f, \"max_penetration_m\": %.6f, "
                    "\"baseline_max_penetration_m\": %.6f, \"deeper_than_1mm_per_frame\": %.2f, \"bvh_query_ratio\": %.4f, \"contacts_per_frame\": %.0f, "
                    "\"rays_per_frame\": %.0f, \"embree_refits_per_frame\": %.2f, \"collision_triangles\": %zu, \"collision_offset_m\": %.6f}\n",
                    a.triangle_count(), n, double(o.thickness_m), o.frames, o.random_order ? "random" : "neighbours",
                    o.scalar ? "scalar" : "auto", double(o.fall_m_s2), median(ours.hull_us), ours_us, ours_refit,
                    median(ours.pass_us) - ours_refit, plain_us, plain_refit, median(ours.wall_pass_us),
                    median(plain.wall_pass_us), plain_us / ours_us,
                    ours.max_penetration_m, plain.max_penetration_m, double(ours.deeper_than_1mm) / frames, double(ours.queried) / (frames * n),
                    double(ours.contacts) / frames, double(ours.rays) / frames, double(ours.embree_refits) / frames,
                    collision.size() / 3, double(extra_m));
        for (BodyRun& run : runs) destroy_world(run.world);
        return 0;
    }
    std::printf("weft-bench body: mean_all (%u triangles) blended A<->T, %u points 0-3 cm off torso/hips/upper arms "
                "(%s), thickness %g m, %u frames, 1 substep, %s path%s\n",
                a.triangle_count(), n, o.random_order ? "random order" : "neighbours next to each other",
                double(o.thickness_m), o.frames, o.scalar ? "scalar" : "default SIMD",
                o.fall_m_s2 > 0.0f ? ", points falling" : "");
    if (collision.size() != a.triangles.size())
        std::printf("  Weft collides with %zu triangles (meshoptimizer), its hull %.2f mm further out\n", collision.size() / 3,
                    1e3 * double(extra_m));
    std::printf("  median per frame (us)           offset hull   body pass (CPU)   refit   contacts+rays   body pass (wall)\n");
    std::printf("  Weft (own hierarchy)            %11.0f %17.0f %7.0f %15.0f %18.0f\n", median(ours.hull_us), ours_us,
                ours_refit, ours_us - ours_refit, median(ours.wall_pass_us));
    std::printf("  plain (refit + rtcPointQuery)   %11.0f %17.0f %7.0f %15.0f %18.0f\n", median(plain.hull_us), plain_us,
                plain_refit, plain_us - plain_refit, median(plain.wall_pass_us));
    std::printf("  speed-up of the body pass: %.2fx; the plain pass's contacts and rays per particle queried: %.0f ns\n",
                plain_us / ours_us, 1e3 * (plain_us - plain_refit) / (double(plain.queried) / frames));
    std::printf("  max penetration after the pass: Weft %.3f mm, plain %.3f mm (Embree's full-resolution query); "
                "particles left deeper than 1 mm per frame: Weft %.2f, plain %.2f\n",
                1e3 * ours.max_penetration_m, 1e3 * plain.max_penetration_m, double(ours.deeper_than_1mm) / frames,
                double(plain.deeper_than_1mm) / frames);
    std::printf("  per frame: contacts %.0f (plain %.0f), rays %.0f, Embree refits %.2f; particles that needed "
                "triangle tests %.1f%%\n",
                double(ours.contacts) / frames, double(plain.contacts) / frames, double(ours.rays) / frames,
                double(ours.embree_refits) / frames, 100.0 * double(ours.queried) / (frames * n));
    for (BodyRun& run : runs) destroy_world(run.world);
    return 0;
}

}  // namespace weft::bench
