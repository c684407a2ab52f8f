#include "common/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "body/body_mesh.h"
#include "body/mannequin.h"

namespace weft::scenes {

const char* body_collision_name(BodyCollision c) {
    switch (c) {
        case BodyCollision::cached_planes: return "cached_planes";
        case BodyCollision::skin_constraints: return "skin_constraints";
        default: return "exact";
    }
}

bool body_collision_from_name(const std::string& name, BodyCollision* out) {
    for (BodyCollision c : {BodyCollision::exact, BodyCollision::cached_planes, BodyCollision::skin_constraints})
        if (name == body_collision_name(c)) return *out = c, true;
    return false;
}

ClothMeshDesc GridMesh::desc() const {
    ClothMeshDesc d;
    d.particle_count = uint32_t(positions.size());
    d.positions = positions.data();
    d.triangle_count = uint32_t(triangles.size() / 3);
    d.triangles = triangles.data();
    d.masses = masses.data();
    d.lattice = lattice.data();
    return d;
}

GridMesh make_grid(uint32_t n, float width_m, float length_m, bool vertical, float y_m, float density_kg_m2) {
    GridMesh g;
    g.n = n;
    const float dx = width_m / float(n - 1), dz = length_m / float(n - 1);
    for (uint32_t r = 0; r < n; ++r) {
        for (uint32_t c = 0; c < n; ++c) {
            if (vertical) {  // rows go down from the top, columns out from the pole at x = 0
                g.positions.push_back({float(c) * dx, y_m - float(r) * dz, 0.0f});
            } else {
                g.positions.push_back({-0.5f * width_m + float(c) * dx, y_m, -0.5f * length_m + float(r) * dz});
            }
            g.lattice.push_back(int32_t(r));
            g.lattice.push_back(int32_t(c));
        }
    }
    g.masses.assign(size_t(n) * n, 0.0f);
    const float triangle_mass = density_kg_m2 * 0.5f * dx * dz;
    for (uint32_t r = 0; r + 1 < n; ++r) {
        for (uint32_t c = 0; c + 1 < n; ++c) {
            const uint32_t a = g.index(r, c), b = g.index(r, c + 1), d = g.index(r + 1, c), e = g.index(r + 1, c + 1);
            for (uint32_t v : {a, d, b, b, d, e}) g.triangles.push_back(v);
            for (uint32_t v : {a, d, b, b, d, e}) g.masses[v] += triangle_mass / 3.0f;  // eq. (9)
        }
    }
    return g;
}

namespace {

// A pin index: negative counts from the end. Returns false when out of range.
bool resolve_index(int32_t i, uint32_t n, uint32_t* out) {
    const int64_t v = i < 0 ? int64_t(n) + i : int64_t(i);
    if (v < 0 || v >= int64_t(n)) return false;
    *out = uint32_t(v);
    return true;
}

std::string make_grid_cloth(const GridSource& g, const CookOptions& cook, SceneCloth* out) {
    if (g.n < 2 || g.n > 4096) return "grid n must be in [2, 4096]";
    if (!(g.width_m > 0.0f) || !(g.length_m > 0.0f) || !(g.areal_density_kg_m2 > 0.0f))
        return "grid width, length and areal density must be positive";
    out->mesh = make_grid(g.n, g.width_m, g.length_m, g.vertical, g.y_m, g.areal_density_kg_m2);
    GridMesh& mesh = out->mesh;
    for (Vec3& p : mesh.positions) p = {p.x + g.offset_m.x, p.y + g.offset_m.y, p.z + g.offset_m.z};
    for (const auto& [row, col] : g.pins) {
        uint32_t r, c;
        if (!resolve_index(row, g.n, &r) || !resolve_index(col, g.n, &c)) return "grid pin outside the grid";
        mesh.masses[mesh.index(r, c)] = 0.0f;
    }
    for (int32_t row : g.pin_rows) {
        uint32_t r;
        if (!resolve_index(row, g.n, &r)) return "pinned row outside the grid";
        for (uint32_t c = 0; c < g.n; ++c) mesh.masses[mesh.index(r, c)] = 0.0f;
    }
    for (int32_t col : g.pin_columns) {
        uint32_t c;
        if (!resolve_index(col, g.n, &c)) return "pinned column outside the grid";
        for (uint32_t r = 0; r < g.n; ++r) mesh.masses[mesh.index(r, c)] = 0.0f;
    }
    out->cooked = std::make_unique<CookedCloth>();
    if (Result r = cook_cloth(mesh.desc(), cook, out->cooked.get()); !r.ok()) return r.message;
    out->asset = &out->cooked->asset();
    return {};
}

std::string find_asset(const std::string& path, const std::string& base_dir, const std::vector<std::string>& dirs) {
    namespace fs = std::filesystem;
    if (fs::path(path).is_absolute()) return path;
    std::error_code ec;
    if (fs::exists(fs::path(base_dir) / path, ec)) return (fs::path(base_dir) / path).string();
    for (const std::string& d : dirs)
        if (fs::exists(fs::path(d) / path, ec)) return (fs::path(d) / path).string();
    return (fs::path(base_dir) / path).string();  // the error names where it was expected
}

std::string load_baked_cloth(const std::string& path, SceneCloth* out) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return "cannot open asset '" + path + "'";
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    out->loaded = std::make_unique<assets::LoadedAsset>();
    if (Result r = assets::load_asset_copy(bytes.data(), bytes.size(), out->loaded.get()); !r.ok())
        return path + ": " + r.message;
    out->asset = &out->loaded->asset;
    return {};
}

std::string load_body(const BodySpec& spec, const Scene& scene, const std::vector<std::string>& dirs, SceneBody* out) {
    out->spec = spec;
    if (spec.mannequin) {
        auto m = std::make_shared<body::Mannequin>();
        if (std::string e = body::make_mannequin(body::Measurements{}, body::MannequinOptions{}, m.get()); !e.empty())
            return "mannequin: " + e;
        out->rest = m->positions;
        out->triangles = m->triangles;
        out->mannequin = m;
    } else {
        body::BodyMesh mesh;
        if (std::string e = body::load_body_mesh(find_asset(spec.mesh_path, scene.base_dir, dirs), &mesh); !e.empty())
            return e;
        out->rest = std::move(mesh.positions);
        out->triangles = std::move(mesh.triangles);
    }
    if ((spec.animation == BodyAnimation::walk || spec.animation == BodyAnimation::bend_and_sit) && !spec.mannequin)
        return "only the mannequin walks, bends and sits";
    if (!spec.limb_capsules.empty()) {
        if (!spec.mannequin) return "only the mannequin has the bones limb capsules follow";
        if (std::string e = body::fit_limb_capsules(*static_cast<const body::Mannequin*>(out->mannequin.get()),
                                                    spec.limb_capsules, int(spec.limb_capsule_sections), &out->limb_capsules);
            !e.empty())
            return "limb capsules: " + e;
        out->posed_capsules = out->limb_capsules;
    }
    if (spec.animation == BodyAnimation::blend) {
        body::BodyMesh other;
        if (std::string e = body::load_body_mesh(find_asset(spec.blend_to_path, scene.base_dir, dirs), &other); !e.empty())
            return e;
        if (other.positions.size() != out->rest.size() || other.triangles != out->triangles)
            return "blend_to does not have the body's vertices and faces";
        out->blend_to = std::move(other.positions);
    }
    return {};
}

}  // namespace

// The walk is entered from the rest pose, on which the garment was dressed.
float walk_entry(const BodySpec& spec, float t_s) {
    const float u = spec.ramp_s > 0.0f ? std::min(1.0f, t_s / spec.ramp_s) : 1.0f;
    return u * u * (3.0f - 2.0f * u);
}

ColliderDesc limb_collider(const BodySpec& spec, const body::LimbCapsule& c) {
    ColliderDesc d;
    d.shape = ColliderShape::capsule;
    d.p0 = c.p0;
    d.p1 = c.p1;
    d.radius_m = c.radius_m;
    d.inflation_m = spec.thickness_m;
    d.friction = spec.friction;
    return d;
}

std::string create_world_in_block(const WorldDesc& desc, WorldBlock* memory, World** out) {
    const MemoryRequirements need = world_memory_requirements(desc);
    if (need.bytes == 0) return "bad world description";
    const size_t bytes = (need.bytes + need.alignment - 1) / need.alignment * need.alignment;
    *memory = {static_cast<unsigned char*>(std::aligned_alloc(need.alignment, bytes)), std::free};
    if (!*memory) return "out of memory";
    if (Result r = create_world(desc, memory->get(), bytes, out); !r.ok()) return r.message;
    return {};
}

SceneWorld& SceneWorld::operator=(SceneWorld&& other) noexcept {
    if (this == &other) return *this;
    destroy_world(world);  // before `memory`, which holds it, is replaced
    cloths = std::move(other.cloths);
    body = std::move(other.body);
    memory = std::move(other.memory);
    memory_bytes = other.memory_bytes;
    world = std::exchange(other.world, nullptr);
    colliders = std::move(other.colliders);
    dt_s = other.dt_s;
    return *this;
}

Scene garment_on_blending_body(const std::string& asset_path, const std::string& body_path,
                               const std::string& blend_to_path, float blend_s) {
    Scene scene;
    scene.name = "garment-on-blending-body";
    scene.dt_s = 1.0f / 60.0f;
    BodySpec body;
    body.mesh_path = body_path;
    body.blend_to_path = blend_to_path;
    body.animation = BodyAnimation::blend;
    body.period_s = 2.0f * blend_s;  // rest -> blend_to in blend_s
    body.ground = true;               // the floor it was dressed on
    scene.body = body;
    ClothSpec cloth;
    cloth.name = "garment";
    cloth.asset_path = asset_path;
    scene.cloths.push_back(cloth);
    return scene;
}

std::string animate_body(SceneWorld& w, float t_s) {
    if (!w.body || w.body->spec.animation == BodyAnimation::still) return {};
    SceneBody& b = *w.body;
    const size_t n = b.rest.size();
    const bool clip = b.spec.animation == BodyAnimation::walk || b.spec.animation == BodyAnimation::bend_and_sit;
    const body::Clip which = b.spec.animation == BodyAnimation::walk ? body::Clip::walk : body::Clip::bend_and_sit;
    if (clip) {
        const auto& m = *static_cast<const body::Mannequin*>(b.mannequin.get());
        body::clip_pose(m, which, t_s, &b.pose);
        const float k = walk_entry(b.spec, t_s);
        for (size_t v = 0; v < n; ++v)
            b.pose[v] = {b.rest[v].x + (b.pose[v].x - b.rest[v].x) * k, b.rest[v].y + (b.pose[v].y - b.rest[v].y) * k,
                         b.rest[v].z + (b.pose[v].z - b.rest[v].z) * k};
    } else {
        const float k = 0.5f - 0.5f * std::cos(6.2831853f * t_s / b.spec.period_s);
        b.pose.resize(n);
        for (size_t v = 0; v < n; ++v)
            b.pose[v] = {b.rest[v].x + (b.blend_to[v].x - b.rest[v].x) * k, b.rest[v].y + (b.blend_to[v].y - b.rest[v].y) * k,
                         b.rest[v].z + (b.blend_to[v].z - b.rest[v].z) * k};
    }
    if (Result r = set_body_vertices(w.world, b.id, b.pose.data(), uint32_t(n)); !r.ok()) return r.message;
    if (!b.limb_capsules.empty()) {
        const auto& m = *static_cast<const body::Mannequin*>(b.mannequin.get());
        body::clip_capsules(m, which, b.limb_capsules, clip ? t_s : 0.0f, &b.posed_capsules);
        const float k = walk_entry(b.spec, t_s);
        for (size_t i = 0; i < b.posed_capsules.size(); ++i) {
            body::LimbCapsule& c = b.posed_capsules[i];
            const body::LimbCapsule& r = b.limb_capsules[i];
            const auto enter = [k](Vec3 rest, Vec3 walk) {  // from the rest pose, as the vertices above
                return Vec3{rest.x + (walk.x - rest.x) * k, rest.y + (walk.y - rest.y) * k, rest.z + (walk.z - rest.z) * k};
            };
            c.p0 = enter(r.p0, c.p0);
            c.p1 = enter(r.p1, c.p1);
            if (Result res = set_collider(w.world, b.limb_colliders[i], limb_collider(b.spec, c)); !res.ok())
                return res.message;
        }
    }
    return {};
}

std::string build_scene(const Scene& scene, SceneWorld* out, const std::vector<std::string>& asset_dirs) {
    if (scene.cloths.empty()) return "the scene has no cloth";
    out->dt_s = scene.dt_s;
    out->cloths.clear();
    out->cloths.resize(scene.cloths.size());
    WorldDesc wd;
    wd.max_cloths = 0;
    for (size_t i = 0; i < scene.cloths.size(); ++i) {
        const ClothSpec& spec = scene.cloths[i];
        SceneCloth& cloth = out->cloths[i];
        std::string error;
        if (spec.grid) {
            error = make_grid_cloth(*spec.grid, spec.cook, &cloth);
        } else {
            error = load_baked_cloth(find_asset(spec.asset_path, scene.base_dir, asset_dirs), &cloth);
        }
        if (!error.empty()) return "cloth '" + spec.name + "': " + error;
        ClothDesc reserved = spec.desc;
        reserved.asset = cloth.asset;
        reserve_cloth(wd, reserved);
        // Layers: the cloths it is worn over come before it.
        const ClothAsset* largest_inner = nullptr;
        for (const std::string& name : spec.worn_over) {
            size_t j = 0;
            while (j < i && scene.cloths[j].name != name) ++j;
            if (j == i) return "cloth '" + spec.name + "': worn over '" + name + "', which is not a cloth listed before it";
            if (largest_inner == nullptr || out->cloths[j].asset->slot_count > largest_inner->slot_count)
                largest_inner = out->cloths[j].asset;
        }
        if (largest_inner != nullptr) reserve_layer(wd, *cloth.asset, *largest_inner);
    }
    if (scene.body) {
        out->body = std::make_unique<SceneBody>();
        if (std::string e = load_body(*scene.body, scene, asset_dirs, out->body.get()); !e.empty()) return "body: " + e;
        wd.max_bodies = 1;
        wd.max_cached_plane_bodies = scene.body->collision == BodyCollision::cached_planes ? 1 : 0;  // 76 B a slot
        wd.max_body_vertices = uint32_t(out->body->rest.size());
        wd.max_body_triangles = uint32_t(out->body->triangles.size() / 3);
    }
    // Skin constraints are bound below only under the skin_constraints model: the asset's, or for
    // an asset without them at most one a particle. Other scenes reserve none (reserve_cloth's count
    // is for a game that binds them).
    wd.max_skin_constraints = 0;
    if (scene.body && scene.body->collision == BodyCollision::skin_constraints)
        for (const auto& c : out->cloths)
            wd.max_skin_constraints += c.asset->skin.count > 0 ? c.asset->skin.count : c.asset->particle_count;
    wd.max_colliders = uint32_t(scene.colliders.size());
    if (out->body) wd.max_colliders += uint32_t(out->body->limb_capsules.size()) + (scene.body->ground ? 1 : 0);
    wd.wind = scene.wind_m_s.has_value();
    wd.gravity_m_s2 = scene.gravity_m_s2;
    wd.air_density_kg_m3 = scene.air_density_kg_m3;
    wd.simd = scene.simd;
    wd.normals = scene.normals;
    wd.tangents = scene.tangents;
    wd.render_meshes = scene.render_meshes;
    wd.scheduler = scene.scheduler;
    if (std::string e = create_world_in_block(wd, &out->memory, &out->world); !e.empty()) return e;
    out->memory_bytes = world_memory_requirements(wd).bytes;
    if (scene.profile) set_profiling(out->world, true);

    if (out->body) {
        const BodySpec& b = out->body->spec;
        BodyDesc bd;
        bd.positions = out->body->rest.data();
        bd.vertex_count = uint32_t(out->body->rest.size());
        bd.triangles = out->body->triangles.data();
        bd.triangle_count = uint32_t(out->body->triangles.size() / 3);
        bd.thickness_m = b.thickness_m;
        bd.margin_m = b.margin_m;
        bd.friction = b.friction;
        bd.collision = b.collision;
        if (Result r = add_body(out->world, bd, &out->body->id); !r.ok()) return std::string("body: ") + r.message;
        out->body->limb_colliders.resize(out->body->limb_capsules.size());
        for (size_t i = 0; i < out->body->limb_capsules.size(); ++i)
            if (Result r = add_collider(out->world, limb_collider(b, out->body->limb_capsules[i]), &out->body->limb_colliders[i]); !r.ok())
                return std::string("body: limb capsule: ") + r.message;
        if (b.ground) {
            const ColliderDesc ground =
                ground_under_body(out->body->rest.data(), uint32_t(out->body->rest.size()), b.thickness_m, b.friction);
            if (Result r = add_collider(out->world, ground, &out->body->ground); !r.ok()) return std::string("body: ground: ") + r.message;
        }
    }
    for (size_t i = 0; i < scene.cloths.size(); ++i) {
        const ClothSpec& spec = scene.cloths[i];
        ClothDesc cd = spec.desc;
        cd.asset = out->cloths[i].asset;
        if (cd.asset->has_fabric) {  // the fabric the pattern named, unless the scene overrides it
            const Fabric& f = cd.asset->fabric;
            if (!spec.compliance_given)
                for (uint32_t k = 0; k < kConstraintKindCount; ++k) cd.compliance_m_per_n[k] = f.compliance_m_per_n[k];
            if (!spec.damping_given) cd.damping_per_s = f.damping_per_s;
        }
        cd.worn_over_count = uint32_t(spec.worn_over.size());
        for (uint32_t k = 0; k < cd.worn_over_count; ++k)
            for (size_t j = 0; j < i; ++j)
                if (scene.cloths[j].name == spec.worn_over[k]) cd.worn_over[k] = out->cloths[j].id;
        out->cloths[i].desc = cd;
        if (Result r = add_cloth(out->world, cd, &out->cloths[i].id); !r.ok())
            return "cloth '" + scene.cloths[i].name + "': " + r.message;
        if (out->body && cd.asset->attachment_count > 0)  // a garment dressed on this body (weft-bake --body)
            if (Result r = attach_cloth_to_body(out->world, out->cloths[i].id, out->body->id); !r.ok())
                return "cloth '" + scene.cloths[i].name + "': attachments: " + r.message;
        if (out->body && scene.body->collision == BodyCollision::skin_constraints) {
            // The binding weft-bake --body baked; an asset without one is bound here, on the
            // dressed pose it starts in against the body's rest pose (the same cook_skin_binding).
            std::string e;
            if (cd.asset->skin.count > 0) {
                if (Result r = bind_asset_skin_constraints(out->world, out->cloths[i].id, out->body->id); !r.ok())
                    e = r.message;
            } else {
                out->cloths[i].skin = std::make_unique<SkinBinding>();
                e = bind_skin(out->world, out->cloths[i].id, out->body->id, SkinBindingOptions{}, out->cloths[i].skin.get());
            }
            if (!e.empty()) return "cloth '" + scene.cloths[i].name + "': skin constraints: " + e;
        }
    }
    out->colliders.resize(scene.colliders.size());
    for (size_t i = 0; i < scene.colliders.size(); ++i)
        if (Result r = add_collider(out->world, scene.colliders[i], &out->colliders[i]); !r.ok())
            return std::string("collider: ") + r.message;
    if (scene.wind_m_s)
        if (Result r = set_wind(out->world, *scene.wind_m_s); !r.ok()) return std::string("wind: ") + r.message;
    return {};
}

std::vector<uint32_t> caller_triangles(const ClothAsset& asset) {
    std::vector<uint32_t> t(3 * size_t(asset.triangle_count));
    read_triangles(asset, t.data(), uint32_t(t.size()));  // the count is the asset's: it cannot fail
    return t;
}

std::vector<std::vector<Vec3>> cloth_positions(const SceneWorld& world) {
    std::vector<std::vector<Vec3>> positions;
    for (const SceneCloth& c : world.cloths) {
        std::vector<Vec3>& p = positions.emplace_back(c.asset->particle_count);
        read_positions(world.world, c.id, p.data(), uint32_t(p.size()));
    }
    return positions;
}

}  // namespace weft::scenes
