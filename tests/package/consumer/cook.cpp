// A tool outside Weft's tree that cooks its own cloth with Weft::cook (weft/cook.h), then steps it
// with the runtime it brings (Weft::weft): a 10 x 10 sheet pinned along one edge.
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "weft/cook.h"
#include "weft/weft.h"

int main() {
    constexpr uint32_t n = 10;
    std::vector<weft::Vec3> positions;
    std::vector<float> masses;
    std::vector<uint32_t> triangles;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) {
            positions.push_back({0.1f * float(j), 1.0f, 0.1f * float(i)});
            masses.push_back(i == 0 ? 0.0f : 0.01f);  // mass 0 pins the first row
        }
    for (uint32_t i = 0; i + 1 < n; ++i)
        for (uint32_t j = 0; j + 1 < n; ++j) {
            const uint32_t a = i * n + j;
            triangles.insert(triangles.end(), {a, a + n, a + 1, a + 1, a + n, a + n + 1});
        }
    weft::ClothMeshDesc mesh;
    mesh.particle_count = n * n;
    mesh.positions = positions.data();
    mesh.masses = masses.data();
    mesh.triangle_count = uint32_t(triangles.size() / 3);
    mesh.triangles = triangles.data();
    weft::CookedCloth cooked;
    if (weft::Result r = weft::cook_cloth(mesh, weft::CookOptions{}, &cooked); !r.ok()) {
        std::printf("cook_cloth: %s\n", r.message);
        return 1;
    }
    weft::WorldDesc desc;
    desc.max_cloths = 0;
    weft::reserve_cloth(desc, cooked.asset());
    const weft::MemoryRequirements need = weft::world_memory_requirements(desc);
    void* block = std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment);
    weft::World* world = nullptr;
    weft::ClothDesc cloth;
    cloth.asset = &cooked.asset();
    weft::ClothId id;
    if (!weft::create_world(desc, block, need.bytes, &world).ok() || !weft::add_cloth(world, cloth, &id).ok()) return 1;
    for (int frame = 0; frame < 30; ++frame)
        if (!weft::step(world, 1.0f / 60.0f).ok()) return 1;
    std::vector<weft::Vec3> now(n * n);
    if (!weft::read_positions(world, id, now.data(), n * n).ok()) return 1;
    weft::destroy_world(world);
    std::free(block);
    // The pinned row stays; the far edge has fallen.
    const bool ok = now[0].y == 1.0f && now[n * n - 1].y < 0.99f;
    std::printf(ok ? "OK\n" : "the sheet did not hang\n");
    return ok ? 0 : 1;
}
