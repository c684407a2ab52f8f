// Virtual sewing (sew.h): sew, merge, drape, all stepped by the runtime in a world with the body.
#include "bake/sew.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <numeric>

#include "weft/body.h"
#include "weft/closest_point.h"
#include "weft/world.h"

namespace weft::bake {
namespace {

Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float length(Vec3 a) { return std::sqrt(dot(a, a)); }
Vec3 normalize(Vec3 a) { const float l = length(a); return {a.x / l, a.y / l, a.z / l}; }
Vec3 add(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 scale(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }

// How far in front of a hull triangle its outside is probed (buried_hull_triangles), metres.
constexpr float kBuriedProbe_m = 0.001f;
// How far from the body the sewing looks for a particle's closest hull point (query_body's reach).
constexpr float kProbeReach_m = 0.5f;

// Seam points as sets of particles joined transitively (a particle in two seam points, where
// seams meet, joins them): root of every particle.
std::vector<uint32_t> seam_groups(const ClothMeshDesc& m) {
    std::vector<uint32_t> parent(m.particle_count);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t p) {
        while (parent[p] != p) p = parent[p] = parent[parent[p]];
        return p;
    };
    for (uint32_t s = 0; s < m.seam_point_count; ++s)
        for (uint32_t i = m.seam_first[s] + 1; i < m.seam_first[s + 1]; ++i) {
            const uint32_t a = find(m.seam_source[m.seam_first[s]]), b = find(m.seam_source[i]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    for (uint32_t p = 0; p < m.particle_count; ++p) parent[p] = find(p);
    return parent;
}

// Moves every open seam group's sources toward their target by at most `step_m` (eq. 10: the
// sources move geometrically, not by physics; they are held kinematic, inverse mass 0, while they
// move; `index` maps them to the sewing world's particles), marks a group whose sources have met
// as closed, and returns the largest distance of a source to its target before the move.
float close_seams(World* world, ClothId cloth, const BodyWorld& probe, const std::vector<std::vector<uint32_t>>& groups,
                  const std::vector<Vec3>& target, const std::vector<uint32_t>& index, std::vector<char>& closed,
                  std::vector<Vec3>& x, float step_m) {
    float gap = 0.0f;
    for (size_t k = 0; k < groups.size(); ++k) {
        if (closed[k]) continue;
        float group_gap = 0.0f;
        for (uint32_t p : groups[k]) {
            const Vec3 d = sub(target[k], x[p]);
            const float l = length(d);
            group_gap = std::max(group_gap, l);
            const float t = l > step_m ? step_m / l : 1.0f;
            x[p] = {x[p].x + d.x * t, x[p].y + d.y * t, x[p].z + d.z * t};
            // Held kinematic, a source meets no collider: one that stepped into the body's hull
            // goes to its closest hull point, so it slides over the body instead of through it,
            // unless that leaves it no nearer its target by half a step (a limb in its way: it
            // passes through, as GarmentCode's sources do, rather than stay caught behind an arm).
            BodyContact c;
            if (query_body(probe.world, probe.body, x[p], &c, kProbeReach_m).ok() && c.found && c.penetration_m > 0.0f &&
                length(sub(target[k], c.hull_point)) < l - 0.5f * step_m)
                x[p] = c.hull_point;
            set_particle(world, cloth, index[p], x[p], 0.0f);
        }
        gap = std::max(gap, group_gap);
        closed[k] = group_gap <= step_m;  // every source is on the target now
    }
    return gap;
}

// The garment with the seam groups `merged` marks each made one particle (the first source's
// index order) at the mean of its sources in `x`, with the summed mass (0 when `mass` pins any
// source), every source's uv kept; triangles keep their flat corners (rest_corners) so rest
// lengths still come from the flat panels. The other particles are copied as they are.
void merge_seams(const ClothMeshDesc& unsewn, const std::vector<uint32_t>& root,
                 const std::vector<std::vector<uint32_t>>& groups, const std::vector<char>& merged,
                 const std::vector<Vec3>& x, const float* mass, SewnGarment* out) {
    const uint32_t n = unsewn.particle_count;
    std::vector<uint32_t> merge_root(n);
    std::iota(merge_root.begin(), merge_root.end(), 0u);
    for (size_t k = 0; k < groups.size(); ++k)
        if (merged[k])
            for (uint32_t p : groups[k]) merge_root[p] = root[p];
    SewnGarment g;
    g.new_of_old.assign(n, ~0u);
    std::vector<uint32_t> first_of_new;
    for (uint32_t p = 0; p < n; ++p) {
        if (merge_root[p] != p) continue;
        g.new_of_old[p] = uint32_t(first_of_new.size());
        first_of_new.push_back(p);
    }
    for (uint32_t p = 0; p < n; ++p) g.new_of_old[p] = g.new_of_old[merge_root[p]];
    const uint32_t m = uint32_t(first_of_new.size());
    g.positions.assign(m, Vec3{});
    g.masses.assign(m, 0.0f);
    std::vector<uint32_t> count(m, 0);
    std::vector<bool> pinned(m, false);
    for (uint32_t p = 0; p < n; ++p) {
        const uint32_t q = g.new_of_old[p];
        g.positions[q] = {g.positions[q].x + x[p].x, g.positions[q].y + x[p].y, g.positions[q].z + x[p].z};
        g.masses[q] += unsewn.masses[p];
        pinned[q] = pinned[q] || mass[p] == 0.0f;
        ++count[q];
    }
    for (uint32_t q = 0; q < m; ++q) {
        const float inv = 1.0f / float(count[q]);
        g.positions[q] = {g.positions[q].x * inv, g.positions[q].y * inv, g.positions[q].z * inv};
        if (pinned[q]) g.masses[q] = 0.0f;  // a pin on any source holds the sewn particle
    }
    if (unsewn.uv != nullptr) {
        g.uv.resize(2 * size_t(m));
        for (uint32_t q = 0; q < m; ++q) g.uv[2 * q] = unsewn.uv[2 * first_of_new[q]], g.uv[2 * q + 1] = unsewn.uv[2 * first_of_new[q] + 1];
        g.sewn_uv_first.push_back(0);
        for (size_t k = 0; k < groups.size(); ++k) {
            if (!merged[k]) continue;
            g.sewn_particle.push_back(g.new_of_old[groups[k][0]]);
            for (uint32_t p : groups[k]) g.sewn_uv.push_back(unsewn.uv[2 * p]), g.sewn_uv.push_back(unsewn.uv[2 * p + 1]);
            g.sewn_uv_first.push_back(uint32_t(g.sewn_uv.size() / 2));
        }
    }
    if (unsewn.lattice != nullptr) {
        // A seam particle keeps the lattice node of its first source that has one: its springs into
        // that source's panel (and along the seam) then join the panel's runs; off the lattice all
        // of them went one lane at a time (sewn contiguous_fraction 0.70 against 0.88 flat).
        g.lattice.assign(2 * size_t(m), -1);
        for (uint32_t p = 0; p < n; ++p) {
            const uint32_t q = g.new_of_old[p];
            if (g.lattice[2 * q] >= 0 || unsewn.lattice[2 * p] < 0 || unsewn.lattice[2 * p + 1] < 0) continue;
            g.lattice[2 * q] = unsewn.lattice[2 * p], g.lattice[2 * q + 1] = unsewn.lattice[2 * p + 1];
        }
    }
    if (unsewn.panel != nullptr) {
        g.panel.resize(m);
        for (uint32_t q = 0; q < m; ++q) g.panel[q] = unsewn.panel[first_of_new[q]];
    }
    for (uint32_t t = 0; t < unsewn.triangle_count; ++t) {
        const uint32_t* v = unsewn.triangles + 3 * t;
        const uint32_t a = g.new_of_old[v[0]], b = g.new_of_old[v[1]], c = g.new_of_old[v[2]];
        if (a == b || b == c || a == c) continue;  // a corner sewn onto its own triangle's edge
        g.triangles.insert(g.triangles.end(), {a, b, c});
        for (int k = 0; k < 3; ++k) g.rest_corners.push_back(unsewn.rest_positions[v[k]]);
    }
    ClothMeshDesc& d = g.desc;
    d.particle_count = m;
    d.positions = g.positions.data();
    d.triangle_count = uint32_t(g.triangles.size() / 3);
    d.triangles = g.triangles.data();
    d.masses = g.masses.data();
    d.rest_corners = g.rest_corners.data();
    d.lattice = g.lattice.empty() ? nullptr : g.lattice.data();
    d.lattice_plane_stride = unsewn.lattice_plane_stride;
    d.uv = g.uv.empty() ? nullptr : g.uv.data();
    d.panel_count = unsewn.panel_count;
    d.panel = g.panel.empty() ? nullptr : g.panel.data();
    d.fabric = unsewn.fabric;
    if (!g.sewn_particle.empty()) {
        d.sewn_point_count = uint32_t(g.sewn_particle.size());
        d.sewn_particle = g.sewn_particle.data();
        d.sewn_uv_first = g.sewn_uv_first.data();
        d.sewn_uv = g.sewn_uv.data();
    }
    *out = std::move(g);  // the vectors move with their buffers: desc's pointers stay valid
}

}  // namespace

BodyWorld::~BodyWorld() { destroy_world(world); }

namespace {

// The sewing's cloth: `asset` at the options' sweeps, with its fabric's compliance (as a scene
// gives the loaded asset: the stored pose is that solver's rest).
ClothDesc sewing_cloth(const ClothAsset& asset, const SewOptions& o, float damping_per_s) {
    ClothDesc c;
    c.asset = &asset;
    c.sweeps = o.sweeps;
    c.damping_per_s = damping_per_s;
    for (uint32_t k = 0; k < kConstraintKindCount; ++k) c.compliance_m_per_n[k] = asset.fabric.compliance_m_per_n[k];
    return c;
}

// `p` moved in front of the nearest face of the garments it is worn over (SewOptions::worn_over)
// within kWornOverReach_m, by their layer thickness, when it is behind or closer (their faces point
// away from the body: collide/layers.h); else as it is.
constexpr float kWornOverReach_m = 0.05f;
Vec3 in_front_of_worn_over(Vec3 p, const SewOptions& o) {
    float nearest2 = kWornOverReach_m * kWornOverReach_m;
    Vec3 closest{}, normal{};
    for (const ClothAsset* a : o.worn_over)
        for (uint32_t t = 0; t < a->triangle_count; ++t) {
            float corner[3][3];
            for (int c = 0; c < 3; ++c) {
                const uint32_t s = a->triangles[3 * t + c];
                corner[c][0] = a->start_x[s], corner[c][1] = a->start_y[s], corner[c][2] = a->start_z[s];
            }
            const float q[3] = {p.x, p.y, p.z};
            const BarycentricWeights<float> w = closest_on_triangle(q, corner[0], corner[1], corner[2]);
            const Vec3 on{w.w0 * corner[0][0] + w.w1 * corner[1][0] + w.w2 * corner[2][0],
                          w.w0 * corner[0][1] + w.w1 * corner[1][1] + w.w2 * corner[2][1],
                          w.w0 * corner[0][2] + w.w1 * corner[1][2] + w.w2 * corner[2][2]};
            const float d2 = dot(sub(p, on), sub(p, on));
            if (!(d2 < nearest2)) continue;
            const Vec3 e1 = sub(Vec3{corner[1][0], corner[1][1], corner[1][2]}, Vec3{corner[0][0], corner[0][1], corner[0][2]});
            const Vec3 e2 = sub(Vec3{corner[2][0], corner[2][1], corner[2][2]}, Vec3{corner[0][0], corner[0][1], corner[0][2]});
            const Vec3 n = cross(e1, e2);
            const float n_length = length(n);
            if (!(n_length > 0.0f)) continue;
            nearest2 = d2, closest = on, normal = {n.x / n_length, n.y / n_length, n.z / n_length};
        }
    if (nearest2 >= kWornOverReach_m * kWornOverReach_m || dot(sub(p, closest), normal) >= o.layer_thickness_m) return p;
    return {closest.x + o.layer_thickness_m * normal.x, closest.y + o.layer_thickness_m * normal.y,
            closest.z + o.layer_thickness_m * normal.z};
}

// The garment's cloth worn over the world's inner garments (SewOptions::worn_over).
ClothDesc worn_over_inner(const BodyWorld& w, const SewOptions& o, ClothDesc c) {
    c.worn_over_count = uint32_t(w.inner.size());
    for (size_t k = 0; k < w.inner.size(); ++k) c.worn_over[k] = w.inner[k];
    c.layer_thickness_m = o.layer_thickness_m;
    return c;
}

// open_body_world, or without `asset` (null) the body (and floor) alone; `room_for_another`: a
// second cloth as large fits (the sewing replaces its cloth at each merge). With
// SewOptions::worn_over the inner garments come first, held on the body by their own attachments
// (they start at rest on the still body, and sleep once calm: no cost then), and the garment is worn
// over them.
Status open_world(const ClothAsset* asset, const SewBody& body, const SewOptions& o, float gravity,
                  float damping_per_s, BodyWorld* w, float margin_m, bool room_for_another = false) {
    WorldDesc desc;
    desc.max_cloths = 0;
    if (asset != nullptr) reserve_cloth(desc, *asset);
    if (asset != nullptr && room_for_another) reserve_cloth(desc, *asset);
    const bool layered = asset != nullptr && !o.worn_over.empty();
    if (layered) {
        if (o.worn_over.size() > kMaxWornOver) return {"worn over more garments than a cloth can be"};
        const ClothAsset* largest = o.worn_over[0];
        for (const ClothAsset* inner : o.worn_over) {
            reserve_cloth(desc, *inner);
            if (inner->slot_count > largest->slot_count) largest = inner;
        }
        for (int k = 0; k < (room_for_another ? 2 : 1); ++k) reserve_layer(desc, *asset, *largest);
    }
    desc.max_cloths = std::max(desc.max_cloths, 1u);  // a world holds at least one cloth, even unused
    desc.max_bodies = 1;
    desc.max_colliders = o.floor ? 1 : 0;
    desc.max_body_vertices = uint32_t(body.positions.size());
    desc.max_body_triangles = uint32_t(body.triangles.size() / 3);
    desc.gravity_m_s2 = {0.0f, -gravity, 0.0f};
    const MemoryRequirements need = world_memory_requirements(desc);
    if (need.alignment == 0) return {"the sewing world's capacities are refused"};
    w->block.reset(std::aligned_alloc(need.alignment, (need.bytes + need.alignment - 1) / need.alignment * need.alignment));
    if (!w->block) return {"cannot allocate the sewing world"};
    if (Result r = create_world(desc, w->block.get(), need.bytes, &w->world); !r.ok()) return {r.message};
    BodyDesc b;
    b.positions = body.positions.data();
    b.vertex_count = uint32_t(body.positions.size());
    b.triangles = body.triangles.data();
    b.triangle_count = uint32_t(body.triangles.size() / 3);
    b.thickness_m = o.body_thickness_m;
    b.friction = o.body_friction;
    b.margin_m = margin_m;
    if (Result r = add_body(w->world, b, &w->body); !r.ok()) return {std::string("body: ") + r.message};
    if (o.floor) {
        const ColliderDesc ground =
            ground_under_body(body.positions.data(), uint32_t(body.positions.size()), o.body_thickness_m, o.body_friction);
        ColliderId id;
        if (Result r = add_collider(w->world, ground, &id); !r.ok()) return {std::string("floor: ") + r.message};
    }
    if (asset == nullptr) return {};
    for (size_t k = 0; layered && k < o.worn_over.size(); ++k) {
        ClothDesc inner = sewing_cloth(*o.worn_over[k], o, damping_per_s);
        inner.sleep_speed_m_s = o.rest_speed_m_s;
        if (k > 0) inner = worn_over_inner(*w, o, inner);  // each over those before it, as it was baked
        ClothId id;
        if (Result r = add_cloth(w->world, inner, &id); !r.ok()) return {std::string("inner garment: ") + r.message};
        // Its attachments name the whole body's triangles: not those of a body without its arm tips.
        if (o.worn_over[k]->attachment_count > 0 && !o.ignore_arm_tips)
            if (Result r = attach_cloth_to_body(w->world, id, w->body); !r.ok())
                return {std::string("inner garment: attachments: ") + r.message};
        w->inner.push_back(id);
    }
    if (Result r = add_cloth(w->world, worn_over_inner(*w, o, sewing_cloth(*asset, o, damping_per_s)), &w->cloth); !r.ok())
        return {std::string("garment: ") + r.message};
    return {};
}

}  // namespace

Status open_body_world(const ClothAsset& asset, const SewBody& body, const SewOptions& o, float gravity,
                       float damping_per_s, BodyWorld* w, float margin_m) {
    return open_world(&asset, body, o, gravity, damping_per_s, w, margin_m);
}

// Where a sewn garment hangs from, m: the height of its highest attachment, or without any, of its
// highest opening (waist, neckline, shoulders: particles on an edge of one triangle). Loose cloth
// bunched above it while the seams close falls into place in the drape; a top that sinks is the
// garment sliding off.
double top_of_openings(const std::vector<uint32_t>& triangles, const std::vector<Vec3>& positions,
                       const std::vector<uint32_t>& attached) {
    if (!attached.empty()) {  // it hangs from them: the highest attachment
        double top = -HUGE_VAL;
        for (uint32_t p : attached) top = std::max(top, double(positions[p].y));
        return top;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = triangles[t + e], b = triangles[t + (e + 1) % 3];
            edges[{std::min(a, b), std::max(a, b)}] += 1;
        }
    double top = -HUGE_VAL;
    for (const auto& [edge, count] : edges)
        if (count == 1) top = std::max({top, double(positions[edge.first].y), double(positions[edge.second].y)});
    if (top == -HUGE_VAL)  // closed all round: its highest particle
        for (const Vec3& p : positions) top = std::max(top, double(p.y));
    return top;
}

// The boundary loops of a triangle mesh, each in the direction its triangles run along it.
std::vector<std::vector<uint32_t>> boundary_loops(const std::vector<uint32_t>& triangles) {
    std::map<std::pair<uint32_t, uint32_t>, int> half_edges;  // (a, b) -> how often, minus (b, a)
    for (size_t t = 0; t + 2 < triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) half_edges[{triangles[t + e], triangles[t + (e + 1) % 3]}] += 1;
    std::map<uint32_t, uint32_t> next;  // boundary edge a -> b: no triangle has b -> a
    for (const auto& [edge, count] : half_edges)
        if (!half_edges.contains({edge.second, edge.first})) next[edge.first] = edge.second;
    std::vector<std::vector<uint32_t>> loops;
    while (!next.empty()) {
        std::vector<uint32_t> loop;
        for (auto it = next.begin(); it != next.end(); it = next.find(loop.back())) {
            loop.push_back(it->first);
            const uint32_t b = it->second;
            next.erase(it);
            if (b == loop.front()) break;
            if (!next.contains(b)) break;  // not a simple loop: keep what was found
        }
        if (loop.size() >= 3) loops.push_back(std::move(loop));
    }
    return loops;
}

namespace {

// The body's offset hull: every vertex out by thickness_m along its area-weighted normal, as
// add_body makes it.
SewBody offset_hull(const SewBody& body, float thickness_m) {
    std::vector<Vec3> normal(body.positions.size(), Vec3{0.0f, 0.0f, 0.0f});
    for (size_t t = 0; t + 2 < body.triangles.size(); t += 3) {
        const Vec3 a = body.positions[body.triangles[t]], b = body.positions[body.triangles[t + 1]],
                   c = body.positions[body.triangles[t + 2]];
        const Vec3 area = cross(sub(b, a), sub(c, a));  // twice the area, along the face normal
        for (int k = 0; k < 3; ++k) {
            Vec3& n = normal[body.triangles[t + k]];
            n = {n.x + area.x, n.y + area.y, n.z + area.z};
        }
    }
    SewBody hull = body;
    for (size_t v = 0; v < hull.positions.size(); ++v) {
        const float l = length(normal[v]);
        if (l > 0.0f) hull.positions[v] = add(hull.positions[v], scale(normal[v], thickness_m / l));
    }
    return hull;
}

}  // namespace

std::vector<bool> buried_hull_triangles(const SewBody& body, float thickness_m) {
    const SewBody hull = offset_hull(body, thickness_m);
    const BodyInsideTest inside(hull);
    std::vector<bool> buried(body.triangles.size() / 3, false);
    for (size_t t = 0; t < buried.size(); ++t) {
        const Vec3 a = hull.positions[hull.triangles[3 * t]], b = hull.positions[hull.triangles[3 * t + 1]],
                   c = hull.positions[hull.triangles[3 * t + 2]];
        const Vec3 n = cross(sub(b, a), sub(c, a));
        const float l = length(n);
        if (!(l > 0.0f)) continue;
        const Vec3 middle{(a.x + b.x + c.x) / 3.0f, (a.y + b.y + c.y) / 3.0f, (a.z + b.z + c.z) / 3.0f};
        buried[t] = inside.contains(add(middle, scale(n, kBuriedProbe_m / l)));
    }
    return buried;
}

namespace {

// The body without its buried hull triangles: what the garment collides with while it is sewn and
// draped. `whole_triangle` (the whole body's triangle of each of body's) is kept in step.
SewBody exterior_of(const SewBody& body, float thickness_m, std::vector<uint32_t>* whole_triangle) {
    const std::vector<bool> buried = buried_hull_triangles(body, thickness_m);
    SewBody out;
    out.positions = body.positions;
    std::vector<uint32_t> kept;
    for (size_t t = 0; t < buried.size(); ++t) {
        if (buried[t]) continue;
        out.triangles.insert(out.triangles.end(), body.triangles.begin() + 3 * t, body.triangles.begin() + 3 * t + 3);
        if (whole_triangle != nullptr) kept.push_back((*whole_triangle)[t]);
    }
    if (whole_triangle != nullptr) *whole_triangle = std::move(kept);
    return out;
}

// The closest point of triangle abc to p (Ericson 5.1.5, weft/closest_point.h), built from its
// weights on the feature of its region (a vertex itself, a + ab t on an edge), as the bakes'
// bytes were made.
Vec3 closest_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    const float pp[3] = {p.x, p.y, p.z}, pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
    TriangleRegion region = TriangleRegion::face;
    const BarycentricWeights<float> w = weft::closest_on_triangle(pp, pa, pb, pc, &region);
    switch (region) {
        case TriangleRegion::vertex_a: return a;
        case TriangleRegion::vertex_b: return b;
        case TriangleRegion::vertex_c: return c;
        case TriangleRegion::edge_ab: return add(a, scale(sub(b, a), w.w1));
        case TriangleRegion::edge_ac: return add(a, scale(sub(c, a), w.w2));
        case TriangleRegion::edge_bc: return add(b, scale(sub(c, b), w.w2));
        case TriangleRegion::face: break;
    }
    return add(a, add(scale(sub(b, a), w.w1), scale(sub(c, a), w.w2)));
}

// Where the runtime's hull leaves a particle in a crease: the hull there is two parts' offset hulls
// overlapping (the arm's underside and the torso's side in the armpit), and the closest hull triangle
// to a particle between them can be one buried under the other part, in front of the particle, and a
// start state left there puts it where the game's first step can draw it into the skin. A particle is clear of the
// body when it is outside the skin and at least kClearanceShare of the hull's thickness from every
// part of it: half, because in a concave spot (the small of the back) the hull itself, offset along
// vertex normals, lies nearer the skin than its thickness, and a stricter clearance sent particles
// held there to a hull point centimetres away, which the game's first step snapped back through it.
class BodyClearance {
public:
    static constexpr float kClearanceShare = 0.5f;

    BodyClearance(const SewBody& skin, const BodyInsideTest& inside, const SewOptions& o) : inside_(inside) {
        clearance_m_ = kClearanceShare * o.body_thickness_m;
        SewOptions bare = o;  // a world of the skin itself (no hull, no floor), for distances to it
        bare.body_thickness_m = 0.0f;
        bare.floor = false;
        status_ = open_world(nullptr, skin, bare, 0.0f, 1.0f, &skin_, clearance_m_);
    }
    const Status& status() const { return status_; }

    // Inside the skin (ray parity), or outside it but nearer than the clearance.
    bool violated(Vec3 p) const {
        if (inside_.contains(p)) return true;
        BodyContact c;
        return clearance_m_ > 0.0f && query_body(skin_.world, skin_.body, p, &c, clearance_m_).ok() && c.found &&
               length(sub(p, c.hull_point)) < clearance_m_;
    }

private:
    const BodyInsideTest& inside_;
    float clearance_m_ = 0.0f;
    BodyWorld skin_;
    Status status_;
};

// Where a particle found inside the skin by ray parity, or in a crease nearer the skin than the
// hull (BodyClearance), goes: the closest point of the collided hull (the buried triangles left out)
// that is itself clear of the body. The closest hull point alone is often another body part's,
// facing the particle: one 27 mm inside the arm by the armpit is 22 mm in front of the torso's
// hull, and that point lies inside the arm too.
class OutsideHull {
public:
    // How far past the closest candidate a particle's own candidates are kept, metres: a particle
    // held outside is searched again every frame, among the triangles near it only.
    static constexpr float kNear_m = 0.05f;

    OutsideHull(const SewBody& collided, float thickness_m, const BodyClearance& clear)
        : hull_(offset_hull(collided, thickness_m)), clear_(clear) {}

    // The outside hull point closest to p among `near` (all triangles when empty; then `near`
    // becomes the triangles within kNear_m of the closest candidate). False when there is none.
    bool find(Vec3 p, std::vector<uint32_t>* near, Vec3* out) const {
        const bool all = near->empty();
        const size_t count = all ? hull_.triangles.size() / 3 : near->size();
        // The candidates in increasing (distance squared, triangle), the order a full sort gives,
        // taken from a heap only as far as the answer and its near list need.
        std::vector<std::pair<float, uint32_t>> heap(count);
        for (size_t i = 0; i < count; ++i) {
            const uint32_t t = all ? uint32_t(i) : (*near)[i];
            heap[i] = {dot_self(sub(point(t, p), p)), t};
        }
        const auto later = std::greater<>();
        std::make_heap(heap.begin(), heap.end(), later);
        const auto next = [&] {
            std::pop_heap(heap.begin(), heap.end(), later);
            const std::pair<float, uint32_t> closest = heap.back();
            heap.pop_back();
            return closest;
        };
        std::vector<uint32_t> taken;  // the candidates so far, nearest first (all within the answer's distance)
        while (!heap.empty()) {
            const auto [d2, t] = next();
            if (all) taken.push_back(t);
            const Vec3 q = point(t, p);
            if (clear_.violated(q)) continue;
            if (all) {  // the triangles near enough to be the answer in later frames
                const float reach = std::sqrt(d2) + kNear_m;
                while (!heap.empty() && !(heap.front().first > reach * reach)) taken.push_back(next().second);
                *near = std::move(taken);
            }
            *out = q;
            return true;
        }
        return false;
    }

private:
    static float dot_self(Vec3 a) { return dot(a, a); }
    Vec3 point(uint32_t t, Vec3 p) const {
        const uint32_t* v = &hull_.triangles[3 * t];
        return closest_on_triangle(p, hull_.positions[v[0]], hull_.positions[v[1]], hull_.positions[v[2]]);
    }
    SewBody hull_;
    const BodyClearance& clear_;
};

}  // namespace

std::vector<bool> arm_tip_triangles(const SewBody& body) {
    const uint32_t n = uint32_t(body.positions.size());
    std::vector<bool> tip(body.triangles.size() / 3, false);
    if (n == 0) return tip;
    // Surface distances (Dijkstra along the triangles' edges) from both fingertips at once.
    std::vector<std::vector<std::pair<uint32_t, float>>> next(n);
    for (size_t t = 0; t + 2 < body.triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = body.triangles[t + e], b = body.triangles[t + (e + 1) % 3];
            const float l = length(sub(body.positions[a], body.positions[b]));
            next[a].push_back({b, l}), next[b].push_back({a, l});
        }
    uint32_t left = 0, right = 0;
    float low = HUGE_VALF, high = -HUGE_VALF;
    for (uint32_t v = 0; v < n; ++v) {
        low = std::min(low, body.positions[v].y), high = std::max(high, body.positions[v].y);
        if (body.positions[v].x < body.positions[left].x) left = v;
        if (body.positions[v].x > body.positions[right].x) right = v;
    }
    const float reach = kArmTipReach * (high - low);
    std::vector<float> distance(n, HUGE_VALF);
    using Entry = std::pair<float, uint32_t>;
    std::vector<Entry> heap{{0.0f, left}, {0.0f, right}};
    distance[left] = distance[right] = 0.0f;
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), std::greater<>());
        const auto [d, v] = heap.back();
        heap.pop_back();
        if (d > distance[v]) continue;
        for (const auto& [w, l] : next[v])
            if (d + l < distance[w] && d + l < reach) {
                distance[w] = d + l;
                heap.push_back({d + l, w}), std::push_heap(heap.begin(), heap.end(), std::greater<>());
            }
    }
    for (size_t t = 0; t < tip.size(); ++t)
        for (int k = 0; k < 3; ++k) tip[t] = tip[t] || distance[body.triangles[3 * t + k]] < reach;
    return tip;
}

namespace {

constexpr Vec3 kInsideRay{0.5773f, 0.5774f, 0.5773f};  // a direction no mesh axis shares

// Moeller-Trumbore: whether the ray from p along kInsideRay crosses triangle t ahead of p.
bool ray_crosses(const SewBody& body, size_t t, Vec3 p) {
    const Vec3 a = body.positions[body.triangles[3 * t]], b = body.positions[body.triangles[3 * t + 1]],
               c = body.positions[body.triangles[3 * t + 2]];
    const Vec3 e1 = sub(b, a), e2 = sub(c, a), h = cross(kInsideRay, e2);
    const float det = dot(e1, h);
    if (std::fabs(det) < 1e-12f) return false;
    const Vec3 s = sub(p, a);
    const float u = dot(s, h) / det;
    if (u < 0.0f || u > 1.0f) return false;
    const Vec3 q = cross(s, e1);
    const float v = dot(kInsideRay, q) / det;
    if (v < 0.0f || u + v > 1.0f) return false;
    return dot(e2, q) / det > 0.0f;
}

// A point's shadow along the ray: its coordinates on two axes across it.
void shadow(Vec3 p, float out[2]) {
    static const Vec3 u = normalize(cross(kInsideRay, Vec3{0.0f, 0.0f, 1.0f})), v = normalize(cross(kInsideRay, u));
    out[0] = dot(p, u), out[1] = dot(p, v);
}

}  // namespace

bool inside_body(const SewBody& body, Vec3 p) {
    uint32_t crossings = 0;
    for (size_t t = 0; 3 * t + 2 < body.triangles.size(); ++t) crossings += ray_crosses(body, t, p);
    return crossings % 2 == 1;
}

BodyInsideTest::BodyInsideTest(const SewBody& body) : body_(body) {
    const size_t count = body.triangles.size() / 3;
    std::vector<float> box(4 * count);  // per triangle: its shadow's min u, min v, max u, max v
    float lo[2] = {HUGE_VALF, HUGE_VALF}, hi[2] = {-HUGE_VALF, -HUGE_VALF};
    for (size_t t = 0; t < count; ++t) {
        float* b = &box[4 * t];
        b[0] = b[1] = HUGE_VALF, b[2] = b[3] = -HUGE_VALF;
        for (int k = 0; k < 3; ++k) {
            float s[2];
            shadow(body.positions[body.triangles[3 * t + k]], s);
            b[0] = std::min(b[0], s[0]), b[1] = std::min(b[1], s[1]), b[2] = std::max(b[2], s[0]), b[3] = std::max(b[3], s[1]);
        }
        lo[0] = std::min(lo[0], b[0]), lo[1] = std::min(lo[1], b[1]), hi[0] = std::max(hi[0], b[2]), hi[1] = std::max(hi[1], b[3]);
    }
    if (count == 0) {
        first_.assign(2, 0);
        return;
    }
    // About one triangle a cell; the shadows grow by a margin, so a point on a shadow's edge
    // (rounded differently in the projection than in the ray test) still finds its triangle.
    cells_ = std::clamp(uint32_t(std::sqrt(double(count))), 1u, 1024u);
    const float margin = 1e-3f;
    origin_[0] = lo[0] - margin, origin_[1] = lo[1] - margin;
    cell_ = std::max(hi[0] - lo[0], hi[1] - lo[1]) / float(cells_) + 4.0f * margin / float(cells_);
    const auto cell_of = [&](float x, float o) { return uint32_t(std::clamp((x - o) / cell_, 0.0f, float(cells_ - 1))); };
    first_.assign(size_t(cells_) * cells_ + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {  // count, then fill
        std::vector<uint32_t> fill(first_.begin(), first_.end() - 1);
        for (size_t t = 0; t < count; ++t) {
            const float* b = &box[4 * t];
            for (uint32_t j = cell_of(b[1] - margin, origin_[1]); j <= cell_of(b[3] + margin, origin_[1]); ++j)
                for (uint32_t i = cell_of(b[0] - margin, origin_[0]); i <= cell_of(b[2] + margin, origin_[0]); ++i) {
                    if (pass == 0) ++first_[size_t(j) * cells_ + i + 1];
                    else triangle_[fill[size_t(j) * cells_ + i]++] = uint32_t(t);
                }
        }
        if (pass == 0) {
            for (size_t c = 0; c + 1 < first_.size(); ++c) first_[c + 1] += first_[c];
            triangle_.resize(first_.back());
        }
    }
}

bool BodyInsideTest::contains(Vec3 p) const {
    float s[2];
    shadow(p, s);
    if (!(s[0] >= origin_[0] && s[1] >= origin_[1]) || s[0] >= origin_[0] + cell_ * cells_ || s[1] >= origin_[1] + cell_ * cells_)
        return false;  // (NaN too) no triangle's shadow reaches it
    const size_t c = size_t(uint32_t((s[1] - origin_[1]) / cell_)) * cells_ + uint32_t((s[0] - origin_[0]) / cell_);
    uint32_t crossings = 0;
    for (uint32_t k = first_[c]; k < first_[c + 1]; ++k) crossings += ray_crosses(body_, triangle_[k], p);
    return crossings % 2 == 1;
}

Status sew_garment(const ClothMeshDesc& unsewn, const std::vector<uint32_t>& attached, const std::vector<uint32_t>& held,
                   const SewBody& whole_body,
                   const SewOptions& o, SewnGarment* out, SewReport* report) {
    // The body the garment collides with while it is sewn and draped (SewOptions::ignore_arm_tips),
    // and the whole body's triangle of each of its own.
    SewBody body;
    std::vector<uint32_t> whole_triangle;
    if (o.ignore_arm_tips) {
        const std::vector<bool> tip = arm_tip_triangles(whole_body);
        body.positions = whole_body.positions;
        for (uint32_t t = 0; t < tip.size(); ++t)
            if (!tip[t]) {
                body.triangles.insert(body.triangles.end(), whole_body.triangles.begin() + 3 * t, whole_body.triangles.begin() + 3 * t + 3);
                whole_triangle.push_back(t);
            }
        // Each cut closed by a fan around its middle: an open hull's inside test fails near the
        // hole, and a seam target found "inside" there was pushed onto its rim again and again.
        const size_t kept = whole_triangle.size();
        for (const std::vector<uint32_t>& loop : boundary_loops(body.triangles)) {
            Vec3 middle{};
            for (uint32_t v : loop) middle = {middle.x + body.positions[v].x, middle.y + body.positions[v].y, middle.z + body.positions[v].z};
            const float inv = 1.0f / float(loop.size());
            body.positions.push_back({middle.x * inv, middle.y * inv, middle.z * inv});
            const uint32_t c = uint32_t(body.positions.size() - 1);
            for (size_t k = 0; k < loop.size(); ++k)  // the loop runs along its triangles' edges: the cap runs against it
                body.triangles.insert(body.triangles.end(), {loop[(k + 1) % loop.size()], loop[k], c});
        }
        // A binding on a cap (a garment without sleeves does not reach one) would name no triangle of the whole body.
        whole_triangle.resize(body.triangles.size() / 3, whole_triangle.empty() ? 0u : whole_triangle[kept - 1]);
    } else {
        body = whole_body;
        whole_triangle.resize(body.triangles.size() / 3);
        std::iota(whole_triangle.begin(), whole_triangle.end(), 0u);
    }
    // Collisions skip the hull's buried triangles (buried_hull_triangles); the inside tests take
    // the closed body.
    const SewBody closed_body = body;
    body = exterior_of(closed_body, o.body_thickness_m, &whole_triangle);
    const SewBody whole_exterior = o.ignore_arm_tips ? exterior_of(whole_body, o.body_thickness_m, nullptr) : SewBody{};
    SewOptions sewing = o;  // frictionless while the seams close (SewOptions::sewing_friction)
    sewing.body_friction = o.sewing_friction;
    const auto start = std::chrono::steady_clock::now();
    if (body.positions.empty() || body.triangles.size() < 3) return {"the body has no triangles"};
    if (unsewn.seam_point_count == 0) return {"the pattern has no seams to sew"};
    if (unsewn.rest_positions == nullptr || unsewn.masses == nullptr) return {"sewing needs flat rest positions and masses"};
    const uint32_t n = unsewn.particle_count;
    SewReport rep;
    rep.particles_before = n;
    rep.body_triangles = uint32_t(whole_body.triangles.size() / 3);

    // 1. Sewing: the unsewn garment under a small gravity, seams closing geometrically.
    CookOptions cook;
    CookedCloth cooked;
    if (Result r = cook_cloth(unsewn, cook, &cooked); !r.ok()) return {std::string("unsewn garment: ") + r.message};
    const std::vector<uint32_t> root = seam_groups(unsewn);
    std::vector<std::vector<uint32_t>> groups;
    {
        std::vector<uint32_t> group_of(n, ~0u), members(n, 0);
        for (uint32_t p = 0; p < n; ++p) ++members[root[p]];
        for (uint32_t p = 0; p < n; ++p) {
            if (members[root[p]] < 2) continue;
            if (group_of[root[p]] == ~0u) group_of[root[p]] = uint32_t(groups.size()), groups.emplace_back();
            groups[group_of[root[p]]].push_back(p);
        }
    }
    std::vector<Vec3> x(unsewn.positions, unsewn.positions + n), target(groups.size());
    // Queried up to kProbeReach_m away: the closest hull point of any garment particle. The reach is
    // the query's, not the body's margin: a body whose step reached 0.5 m would mark every triangle
    // as in a crease (another part faces it within reach) at add_body, a third of a bake's time.
    BodyWorld probe;
    if (Status s = open_body_world(cooked.asset(), body, o, 0.0f, 1.0f, &probe); !s.ok()) return s;
    for (size_t k = 0; k < groups.size(); ++k) {  // eq. (10): the mean of the sources as placed
        Vec3 sum{};
        for (uint32_t p : groups[k]) sum = {sum.x + x[p].x, sum.y + x[p].y, sum.z + x[p].z};
        const float inv = 1.0f / float(groups[k].size());
        target[k] = {sum.x * inv, sum.y * inv, sum.z * inv};
        // A target inside the body (the mean of a front and a back source placed around an arm
        // lies in it) goes to the closest hull point: the sources are held kinematic while they
        // move, so nothing else would stop them there, and the merged particle would start too
        // deep for the drape's contacts to find (the pencil dress: 4 particles in mean_all's arms).
        BodyContact c;
        if (query_body(probe.world, probe.body, target[k], &c, kProbeReach_m).ok() && c.found && c.penetration_m > 0.0f)
            target[k] = c.hull_point;
        // Likewise a target behind a garment it is worn over (the mean of a front and a back source
        // placed around a sleeve lies inside the inner sleeve) goes in front of the nearest inner face.
        target[k] = in_front_of_worn_over(target[k], o);
    }
    // The attachments (the skirt's waistband) move with the cloth while the seams close; then,
    // while the cloth settles, each (a seam point among them as one, its sources at their mean) is
    // pulled every frame toward the closest hull point by at most a sewing step and left dynamic,
    // so the band slides along the body to where its springs and the cloth below balance, and is
    // bound where it is. Snapped to the hull only after the merge (the band 7 cm in at the side
    // seams, the waist corners, held at their seam targets, 1.7 cm above the band beside them, which
    // had slid down) the skirt kept a spring stretched 142% at the waist through its drape.
    std::vector<std::vector<uint32_t>> attached_sets;
    for (const std::vector<uint32_t>& group : groups)
        if (std::any_of(group.begin(), group.end(), [&](uint32_t p) { return std::find(attached.begin(), attached.end(), p) != attached.end(); }))
            attached_sets.push_back(group);
    for (uint32_t p : attached)
        if (std::count(root.begin(), root.end(), root[p]) == 1) attached_sets.push_back({p});
    // How far the sources are from closing: from their target until the attachments slide, then
    // (a seam point on the band slides with it) from the first source of their own seam point.
    bool attaching = false;
    const auto seam_gap = [&] {
        float gap = 0.0f;
        for (size_t k = 0; k < groups.size(); ++k)
            for (uint32_t p : groups[k]) gap = std::max(gap, length(sub(x[p], attaching ? x[groups[k][0]] : target[k])));
        return gap;
    };
    // The sewing world: the garment with the seam points closed so far merged (merge_seams), so a
    // closed seam point is one dynamic particle that follows the cloth while the open ones close.
    // Held where they closed until every seam was closed, the pencil dress's waist seam points
    // beside the back's side seam stayed behind the body while the side seam's corner, its
    // neighbour 1.4 cm away on the same panel, moved 25 cm to its target at the side (7.2x its
    // rest length at the start state).
    // One world for the whole sewing: a merge replaces its cloth (room for two was reserved for
    // the unsewn one; a merged garment has fewer particles), so the body is added, and its crease
    // triangles marked, once.
    struct Stage {
        SewnGarment garment;  // garment.new_of_old: the sewing world's particle of each unsewn one
        CookedCloth cooked;
    };
    std::unique_ptr<Stage> stage;
    std::unique_ptr<BodyWorld> sewing_world;
    std::vector<char> closed(groups.size(), 0), merged(groups.size(), 0);
    std::vector<Vec3> now;
    uint32_t merged_at = 0;  // the frame of the last merge
    const auto merge_closed = [&]() -> Status {
        auto next = std::make_unique<Stage>();
        merged = closed;
        merge_seams(unsewn, root, groups, merged, x, unsewn.masses, &next->garment);
        if (Result r = cook_cloth(next->garment.desc, sewn_cook_options(cook), &next->cooked); !r.ok())
            return {std::string("garment being sewn: ") + r.message};
        const ClothDesc cloth = sewing_cloth(next->cooked.asset(), sewing, o.sewing_damping_per_s);
        bool replaced = false;
        if (sewing_world != nullptr && remove_cloth(sewing_world->world, sewing_world->cloth).ok())
            replaced = add_cloth(sewing_world->world, worn_over_inner(*sewing_world, sewing, cloth), &sewing_world->cloth).ok();
        if (!replaced) {  // the first stage, or a merged garment the world has no room for
            auto w = std::make_unique<BodyWorld>();
            if (Status s = open_world(&next->cooked.asset(), body, sewing, o.sewing_gravity_m_s2, o.sewing_damping_per_s,
                                      w.get(), BodyDesc{}.margin_m, true);
                !s.ok())
                return s;
            sewing_world = std::move(w);
        }
        stage = std::move(next);
        now.resize(stage->garment.desc.particle_count);
        merged_at = rep.sewing_frames;
        return {};
    };
    const auto read_sewing = [&]() -> Status {  // the sewing world's positions, as unsewn particles
        if (Result r = read_positions(sewing_world->world, sewing_world->cloth, now.data(), uint32_t(now.size())); !r.ok()) return {r.message};
        for (uint32_t p = 0; p < n; ++p) x[p] = now[stage->garment.new_of_old[p]];
        return {};
    };
    const auto slide_attachments = [&](float step_m) -> Status {
        for (const std::vector<uint32_t>& set : attached_sets) {
            Vec3 mean{};
            for (uint32_t p : set) mean = {mean.x + x[p].x, mean.y + x[p].y, mean.z + x[p].z};
            const float inv = 1.0f / float(set.size());
            mean = {mean.x * inv, mean.y * inv, mean.z * inv};
            BodyContact c;
            if (!query_body(probe.world, probe.body, mean, &c, kProbeReach_m).ok() || !c.found)
                return {"attached particle " + std::to_string(set[0]) + " is more than 0.5 m from the body"};
            const Vec3 d = sub(c.hull_point, mean);
            const float l = length(d), t = l > step_m ? step_m / l : 1.0f;
            for (uint32_t p : set) {
                x[p] = {mean.x + d.x * t, mean.y + d.y * t, mean.z + d.z * t};
                const uint32_t q = stage->garment.new_of_old[p];
                set_particle(sewing_world->world, sewing_world->cloth, q, x[p], 1.0f / stage->garment.masses[q]);
            }
        }
        return {};
    };
    // While the seams close, the attachments keep their height (GarmentCode's simulator holds its
    // attachment edges on a horizontal plane for the first frames): a waistband pulled around a
    // frictionless body by its closing side seams slid down over the hips otherwise (a skirt's top
    // from y = 1.09 to 0.77 m) and the garment was dressed where it does not belong.
    std::vector<float> held_y(n, NAN);
    std::vector<uint32_t> group_of_root(n, ~0u);
    for (size_t k = 0; k < groups.size(); ++k) group_of_root[root[groups[k][0]]] = uint32_t(k);
    for (uint32_t p : held) held_y[p] = group_of_root[root[p]] != ~0u ? target[group_of_root[root[p]]].y : x[p].y;
    const auto hold_attachments = [&] {  // those not on an open seam point (close_seams moves those), back to their height
        for (uint32_t p : held) {
            const uint32_t k = group_of_root[root[p]], q = stage->garment.new_of_old[p];
            if ((k != ~0u && !closed[k]) || stage->garment.masses[q] == 0.0f || x[p].y == held_y[p]) continue;
            x[p].y = held_y[p];
            set_particle(sewing_world->world, sewing_world->cloth, q, x[p], 1.0f / stage->garment.masses[q]);
        }
    };
    {
        if (Status s = merge_closed(); !s.ok()) return s;
        // The sources reach their targets, then the cloth settles around the closed seams.
        const auto watch = [&](bool last) {
            if (!o.on_frame || (!last && rep.sewing_frames % std::max(o.frame_every, 1u) != 0)) return;
            o.on_frame({"sewing", rep.sewing_frames, last, x.data(), n, unsewn.triangles, unsewn.triangle_count,
                        unsewn.uv, seam_gap()});
        };
        for (uint32_t settled = 0; settled < o.settle_frames;) {
            if (Status s = read_sewing(); !s.ok()) return s;
            watch(false);
            // Seam points closed since the last merge join the cloth (all of them once every seam
            // is closed, so the cloth settles sewn).
            const bool all_closed = std::all_of(closed.begin(), closed.end(), [](char c) { return c != 0; });
            if (closed != merged && (all_closed || rep.sewing_frames >= merged_at + o.merge_every_frames))
                if (Status s = merge_closed(); !s.ok()) return s;
            // Every open seam point's sources move toward its target.
            const float gap = close_seams(sewing_world->world, sewing_world->cloth, probe, groups, target, stage->garment.new_of_old, closed, x,
                                          o.sewing_speed_m_s * o.dt_s);
            if (!attaching) hold_attachments();
            attaching = attaching || (all_closed && closed == merged);
            if (attaching) {  // sewn: the attachments slide onto the body
                if (Status s = slide_attachments(o.sewing_speed_m_s * o.dt_s); !s.ok()) return s;
                ++settled;
            }
            if (rep.sewing_frames == o.max_sewing_frames)
                return {"a seam is still " + std::to_string(gap * 100.0) + " cm open after " +
                        std::to_string(o.max_sewing_frames) + " sewing frames"};
            if (Result r = step(sewing_world->world, o.dt_s); !r.ok()) return {r.message};
            ++rep.sewing_frames;
        }
        if (Status s = read_sewing(); !s.ok()) return s;
        // The last step moved the attachments a little off the hull: back on it.
        if (Status s = slide_attachments(HUGE_VALF); !s.ok()) return s;
        watch(true);
        rep.max_seam_gap_m = seam_gap();
        {  // sewn, attachments on the body: before the drape
            std::vector<uint32_t> on_body;
            for (uint32_t p : attached) on_body.push_back(stage->garment.new_of_old[p]);
            rep.top_at_closed_m = top_of_openings(stage->garment.triangles, now, on_body);
        }
        sewing_world.reset();  // before the garment its cloth reads
        stage.reset();
    }

    // Attachments: each attached particle goes to the closest point of the body's offset hull and
    // is bound there by barycentric weights (pinned from now on: it follows the body).
    std::vector<float> mass(unsewn.masses, unsewn.masses + n);
    struct Binding {
        uint32_t particle, triangle;
        float weight[3];
    };
    std::vector<Binding> bindings;
    if (!attached.empty()) {
        BodyView view;
        view_body(probe.world, probe.body, &view);
        for (uint32_t p : attached) {
            BodyContact c;
            if (!query_body(probe.world, probe.body, x[p], &c, kProbeReach_m).ok() || !c.found)
                return {"attached particle " + std::to_string(p) + " is more than 0.5 m from the body"};
            const uint32_t* t = view.triangles + 3 * c.triangle;
            const Vec3 a{view.hull[4 * t[0]], view.hull[4 * t[0] + 1], view.hull[4 * t[0] + 2]};
            const Vec3 b{view.hull[4 * t[1]], view.hull[4 * t[1] + 1], view.hull[4 * t[1] + 2]};
            const Vec3 cc{view.hull[4 * t[2]], view.hull[4 * t[2] + 1], view.hull[4 * t[2] + 2]};
            // Barycentric weights of the hull point (it lies on the triangle: plain area ratios).
            const Vec3 e1 = sub(b, a), e2 = sub(cc, a), d = sub(c.hull_point, a);
            const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), dd1 = dot(d, e1), dd2 = dot(d, e2);
            const float det = d11 * d22 - d12 * d12;
            float v = det > 0.0f ? (d22 * dd1 - d12 * dd2) / det : 0.0f, u = det > 0.0f ? (d11 * dd2 - d12 * dd1) / det : 0.0f;
            v = std::clamp(v, 0.0f, 1.0f), u = std::clamp(u, 0.0f, 1.0f - v);
            Binding bind{p, whole_triangle[c.triangle], {1.0f - v - u, v, u}};
            bindings.push_back(bind);
            x[p] = {a.x * bind.weight[0] + b.x * bind.weight[1] + cc.x * bind.weight[2],
                    a.y * bind.weight[0] + b.y * bind.weight[1] + cc.y * bind.weight[2],
                    a.z * bind.weight[0] + b.z * bind.weight[1] + cc.z * bind.weight[2]};
            mass[p] = 0.0f;
        }
    }
    // 2. Merging: one particle per seam group (the first source's index order), summed mass.
    SewnGarment g;
    merge_seams(unsewn, root, groups, std::vector<char>(groups.size(), 1), x, mass.data(), &g);
    for (const Binding& b : bindings) {  // one binding per sewn particle (the first source's)
        const uint32_t q = g.new_of_old[b.particle];
        if (std::find(g.attached_particle.begin(), g.attached_particle.end(), q) != g.attached_particle.end()) continue;
        g.attached_particle.push_back(q);
        g.attached_triangle.push_back(b.triangle);
        g.attached_weight.insert(g.attached_weight.end(), b.weight, b.weight + 3);
        g.positions[q] = x[b.particle];
    }
    const uint32_t m = g.desc.particle_count;
    rep.attached = uint32_t(g.attached_particle.size());
    rep.seam_points = uint32_t(groups.size());
    rep.particles_after = m;
    ClothMeshDesc& d = g.desc;
    if (!g.attached_particle.empty()) {
        d.attachment_count = uint32_t(g.attached_particle.size());
        d.attached_particle = g.attached_particle.data();
        d.attached_triangle = g.attached_triangle.data();
        d.attached_weight = g.attached_weight.data();
    }

    // 3. Draping under full gravity until at rest; a garment sewn without the arm tips then drapes
    // again on the whole body, so the dressed pose is outside the body the game steps it with.
    for (const SewBody* drape_body : {static_cast<const SewBody*>(&body), &whole_exterior}) {
        if (drape_body == &whole_exterior && !o.ignore_arm_tips) break;
        CookedCloth sewn;  // starting where the garment is (d.positions)
        if (Result r = o.cook_sewn ? o.cook_sewn(d, &sewn) : cook_cloth(d, sewn_cook_options(cook), &sewn); !r.ok())
            return {std::string("sewn garment: ") + r.message};
        BodyWorld w;
        if (Status s = open_body_world(sewn.asset(), *drape_body, o, o.gravity_m_s2, o.drape_damping_per_s, &w); !s.ok()) return s;
        std::vector<Vec3> now(m), before(g.positions);
        const auto watch = [&](const std::vector<Vec3>& pose, bool last) {
            if (o.on_frame && (last || rep.drape_frames % std::max(o.frame_every, 1u) == 0))
                o.on_frame({"drape", rep.drape_frames, last, pose.data(), m, g.triangles.data(),
                            uint32_t(g.triangles.size() / 3), g.uv.empty() ? nullptr : g.uv.data(), 0.0f});
        };
        watch(before, false);
        // Particles the sewing left deeper inside the body than the step's contacts reach stay
        // there (a band pulled through the waist's side as its seams closed): at rest they go to
        // the closest hull point clear of the body (OutsideHull) and the drape goes on. In a
        // crease (the armpit, between the legs) the step's closest triangle is another part's,
        // facing the particle, and a taut edge took it back in after each untangling: so from
        // then on it is kept clear after every step, as a collision that knew the body part
        // would. Clear means outside the hull of every part, not only the skin: a particle left
        // in the crease between the skin and the hull is one the game's step, which collides
        // with the buried triangles too, sees outside and lets the edge draw into the skin.
        const SewBody& skin = drape_body == &body ? closed_body : whole_body;
        const BodyInsideTest inside(skin);
        const BodyClearance clear(skin, inside, o);
        if (!clear.status().ok()) return clear.status();
        const OutsideHull outside(*drape_body, o.body_thickness_m, clear);
        std::vector<uint32_t> held;                 // particles found inside at rest
        std::vector<std::vector<uint32_t>> near;    // their hull triangles (OutsideHull::find)
        const auto hold_out = [&](uint32_t q, std::vector<uint32_t>* triangles, Vec3* at) {
            Vec3 to;
            if (!outside.find(*at, triangles, &to)) return false;
            *at = to;
            set_particle(w.world, w.cloth, q, to, 1.0f / g.masses[q]);
            return true;
        };
        uint32_t calm = 0, frames = 0;
        for (uint32_t round = 0;; ++round) {
            while (frames++ < o.max_drape_frames && calm < o.rest_frames) {
                if (Result r = step(w.world, o.dt_s); !r.ok()) return {r.message};
                ++rep.drape_frames;
                read_positions(w.world, w.cloth, now.data(), m);
                for (size_t k = 0; k < held.size(); ++k)
                    if (clear.violated(now[held[k]])) hold_out(held[k], &near[k], &now[held[k]]);
                double sum = 0.0;
                for (uint32_t q = 0; q < m; ++q) sum += length(sub(now[q], before[q]));
                rep.mean_speed_m_s = sum / m / o.dt_s;
                calm = rep.mean_speed_m_s < o.rest_speed_m_s ? calm + 1 : 0;
                if (frames < o.max_drape_frames && calm < o.rest_frames) watch(now, false);  // (the last below)
                std::swap(now, before);
            }
            if (round == o.untangle_rounds || frames >= o.max_drape_frames) break;
            uint32_t moved = 0;
            for (uint32_t q = 0; q < m; ++q) {
                if (g.masses[q] == 0.0f || !clear.violated(before[q])) continue;
                const auto it = std::find(held.begin(), held.end(), q);
                std::vector<uint32_t> triangles;  // searched among all: it went past its near ones
                if (!hold_out(q, &triangles, &before[q])) continue;
                if (it == held.end()) held.push_back(q), near.push_back(std::move(triangles));
                else near[it - held.begin()] = std::move(triangles);
                ++moved;
            }
            if (moved == 0) break;
            rep.untangled_particles += moved;
            calm = 0;
        }
        g.positions = before;
        d.positions = g.positions.data();
        const bool final_drape = !o.ignore_arm_tips || drape_body == &whole_exterior;
        watch(g.positions, final_drape);
        if (!final_drape) continue;  // the report is of the last drape
        rep.top_at_rest_m = top_of_openings(g.triangles, g.positions, g.attached_particle);
        rep.lowest_at_rest_m = HUGE_VAL, rep.body_lowest_m = HUGE_VAL;
        for (const Vec3& p : g.positions) rep.lowest_at_rest_m = std::min(rep.lowest_at_rest_m, double(p.y));
        for (const Vec3& p : body.positions) rep.body_lowest_m = std::min(rep.body_lowest_m, double(p.y));
        const BodyInsideTest inside_whole(whole_body);
        for (uint32_t q = 0; q < m; ++q) {
            BodyContact c;
            if (query_body(w.world, w.body, g.positions[q], &c).ok() && c.found)
                rep.max_penetration_m = std::max(rep.max_penetration_m, double(c.penetration_m));
            if (inside_whole.contains(g.positions[q])) {
                ++rep.particles_inside_body;
                if (c.found) rep.max_skin_penetration_m = std::max(rep.max_skin_penetration_m, double(c.penetration_m - o.body_thickness_m));
            }
        }
    }

    // 4. Skin constraints: the dressed pose bound to the whole body (the one the game steps, its
    // triangles as the attachments name them) at rest, with the hull the sewing used; each panel's
    // max distance as its pattern says, else the default (default_max_distance_scales: none for a
    // garment hung from attachments, beyond the hips under its waistband).
    const auto binding_start = std::chrono::steady_clock::now();
    {
        BodyWorld w;
        if (Status s = open_world(nullptr, whole_body, o, 0.0f, 1.0f, &w, 0.002f); !s.ok()) return s;
        BodyView view;
        if (Result r = view_body(w.world, w.body, &view); !r.ok()) return {r.message};
        std::vector<float> inverse_mass(m), scale(m);
        for (uint32_t q = 0; q < m; ++q) inverse_mass[q] = g.masses[q] > 0.0f ? 1.0f / g.masses[q] : 0.0f;
        SkinBindingDesc skin;
        skin.particle_count = m;
        skin.positions = g.positions.data();
        skin.inverse_masses = inverse_mass.data();
        skin.triangles = g.triangles.data();
        skin.triangle_count = uint32_t(g.triangles.size() / 3);
        skin.options = o.skin;
        const std::vector<float> default_scale = default_max_distance_scales(skin);
        for (uint32_t q = 0; q < m; ++q) {
            const std::optional<float> given =
                g.panel.empty() || o.skin_max_distance_scale.empty() ? std::nullopt : o.skin_max_distance_scale.at(g.panel[q]);
            scale[q] = given.value_or(default_scale[q]);
        }
        skin.max_distance_scale = scale.data();
        if (Result r = cook_skin_binding(view, skin, &g.skin); !r.ok()) return {std::string("skin constraints: ") + r.message};
        d.skin = g.skin.constraints();
    }
    rep.skin_constraints = uint32_t(g.skin.particle.size());
    rep.skin_binding_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - binding_start).count();
    rep.sewing_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    *out = std::move(g);
    // The vectors moved with their buffers: desc's pointers stay valid.
    if (report != nullptr) *report = rep;
    return {};
}

}  // namespace weft::bake
