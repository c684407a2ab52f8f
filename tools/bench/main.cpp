#include <chrono>
#include <cstdio>
#include "seed_scenes.h"
#include "metrics.h"
using namespace weft;
int main(int argc, char** argv) {
    uint32_t n = argc > 1 ? atoi(argv[1]) : 100;
    for (SimdPath path : {SimdPath::scalar, SimdPath::avx2}) {
        scenes::SceneOptions o; o.n = n; o.simd = path; o.profile = true;
        scenes::SeedWorld sw;
        std::string err = scenes::make_seed_world(scenes::SeedScene::drape, o, &sw);
        if (!err.empty()) { printf("error %s\n", err.c_str()); return 1; }
        const auto& a = sw.cooked.asset();
        printf("slots %u lanes %u batches %u colours %u on_runs %u/%u tethers %u\n", a.slot_count, a.lane_count, a.batch_count, a.colour_count, a.constraints_on_runs, a.total_constraints(), a.tether_count);
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < 330; ++i) step(sw.world, sw.dt_s);
        auto t1 = std::chrono::steady_clock::now();
        { auto st = world_stats(sw.world); for (int p = 0; p < 5; ++p) printf("  %s %.1f us\n", pass_name(Pass(p)), st.pass_ns[p] / 330e3); }
        ClothView v; view_cloth(sw.world, sw.cloth, &v);
        auto s = metrics::stretch_strain(v);
        printf("%s: %.1f us/step mean strain %.4f max %.4f speed %.4f tether %.4f\n", simd_path_name(path), std::chrono::duration<double, std::micro>(t1 - t0).count() / 330, s.mean, s.max, metrics::mean_speed(v), metrics::max_tether_excess(v));
    }
}
