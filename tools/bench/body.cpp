// weft-bench body: the body-collision pass on the shared mean_all body blended between its A-pose and
// T-pose (issue 13, point 3). Not a timed test: it prints medians per frame.
//   weft-bench body [--frames 60] [--points 10000] [--thickness 0.005]
// Per frame: set_body_vertices (offset hull of the new pose) and the step's body pass (refit,
// rtcPointQuery per particle, tunnelling rays), for 10 000 points 0 to 3 cm off the skin of the
// torso, hips and upper arms, re-placed on the new pose before every step (a garment-like load).
#include "body.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "body_mesh.h"
#include "weft/weft.h"

namespace weft::bench {

int run_body(uint32_t frames, uint32_t point_count, float thickness_m) {
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
    std::vector<uint32_t> vertex(point_count);
    std::vector<float> offset(point_count);
    for (uint32_t k = 0; k < point_count; ++k) {
        vertex[k] = region[uint32_t(uniform() * float(region.size())) % region.size()];
        offset[k] = 0.03f * uniform() - thickness_m;  // 0 to 3 cm off the skin, measured from the hull
    }
    std::vector<Vec3> start(point_count, Vec3{0, 3, 0});
    std::vector<float> masses(point_count, 0.01f);
    ClothMeshDesc mesh;
    mesh.particle_count = point_count;
    mesh.positions = start.data();
    mesh.masses = masses.data();
    CookedCloth cooked;
    if (Result r = cook_cloth(mesh, {}, &cooked); !r.ok()) return std::fprintf(stderr, "%s\n", r.message), 1;

    WorldDesc desc;
    desc.max_cloths = 0;
    reserve_cloth(desc, cooked.asset());
    desc.max_bodies = 1;
    desc.max_body_vertices = a.vertex_count();
    desc.max_body_triangles = a.triangle_count();
    desc.gravity_m_s2 = {0, 0, 0};
    desc.profile = true;
    const MemoryRequirements need = world_memory_requirements(desc);
    std::unique_ptr<unsigned char[], void (*)(void*)> block(
        static_cast<unsigned char*>(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment)),
        std::free);
    World* world = nullptr;
    if (Result r = create_world(desc, block.get(), need.bytes, &world); !r.ok()) return std::fprintf(stderr, "%s\n", r.message), 1;
    ClothDesc cd;
    cd.asset = &cooked.asset();
    cd.policy = BudgetPolicy::explicit_split;  // one substep: one body pass per frame
    cd.substeps = 1;
    cd.iterations = 0;
    ClothId cloth;
    BodyId body;
    BodyDesc bd;
    bd.positions = a.positions.data();
    bd.vertex_count = a.vertex_count();
    bd.triangles = a.triangles.data();
    bd.triangle_count = a.triangle_count();
    bd.thickness_m = thickness_m;
    if (!add_cloth(world, cd, &cloth).ok() || !add_body(world, bd, &body).ok()) return std::fprintf(stderr, "setup failed\n"), 1;

    std::vector<double> hull_us, pass_us, total_us;
    std::vector<Vec3> pose;
    uint64_t contacts = 0, rays = 0;
    for (uint32_t f = 0; f < frames + 5; ++f) {
        const float phase = float(f % 60) / 30.0f;  // A to T in one second, back in the next
        body::blend(a, t, phase <= 1.0f ? phase : 2.0f - phase, &pose);
        const auto t0 = std::chrono::steady_clock::now();
        set_body_vertices(world, body, pose.data(), uint32_t(pose.size()));
        const auto t1 = std::chrono::steady_clock::now();
        BodyView v;
        view_body(world, body, &v);
        for (uint32_t k = 0; k < point_count; ++k) {
            const float* h = v.hull + 4 * vertex[k];
            const float* n = v.normals + 3 * vertex[k];
            set_particle(world, cloth, k, {h[0] + offset[k] * n[0], h[1] + offset[k] * n[1], h[2] + offset[k] * n[2]}, 100.0f);
        }
        const uint64_t before = world_stats(world).pass_ns[int(Pass::body)];
        step(world, 1.0f / 30.0f);
        const WorldStats s = world_stats(world);
        if (f < 5) continue;  // warm-up
        const double hull = std::chrono::duration<double, std::micro>(t1 - t0).count();
        const double pass = double(s.pass_ns[int(Pass::body)] - before) / 1e3;
        hull_us.push_back(hull);
        pass_us.push_back(pass);
        total_us.push_back(hull + pass);
        contacts += s.body_contacts;
        rays += s.body_rays;
    }
    auto median = [](std::vector<double> x) {
        std::sort(x.begin(), x.end());
        return x[x.size() / 2];
    };
    std::printf("weft-bench body: mean_all (%u triangles) blended A<->T, %u points 0-3 cm off torso/hips/upper arms, "
                "thickness %g m, %u frames, 1 substep\n",
                a.triangle_count(), point_count, double(thickness_m), frames);
    std::printf("  median per frame: offset hull (set_body_vertices) %.0f us, body pass (refit + queries + rays) %.0f us, "
                "total %.0f us\n",
                median(hull_us), median(pass_us), median(total_us));
    std::printf("  contacts per frame %.0f, rays per frame %.0f\n", double(contacts) / frames, double(rays) / frames);
    destroy_world(world);
    return 0;
}

}  // namespace weft::bench
