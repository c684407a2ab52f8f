// World creation, the things added to it, and particle access. The step itself is in step.cpp.
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <new>
#include <type_traits>

#include "collide/colliders.h"
#include "world_internal.h"

namespace weft {

Result make_error(ErrorCode code, const char* format, ...) {
    Result result;
    result.code = code;
    va_list args;
    va_start(args, format);
    std::vsnprintf(result.message, sizeof(result.message), format, args);
    va_end(args);
    return result;
}

const char* simd_path_name(SimdPath path) {
    switch (path) {
        case SimdPath::automatic: return "automatic";
        case SimdPath::scalar: return "scalar";
        case SimdPath::avx2: return "avx2";
    }
    return "unknown";
}

bool simd_path_available(SimdPath path) {
    switch (path) {
        case SimdPath::scalar: return true;
        case SimdPath::avx2: return avx2_kernels() != nullptr;
        case SimdPath::automatic: return true;
    }
    return false;
}

const char* pass_name(Pass pass) {
    switch (pass) {
        case Pass::wind: return "wind";
        case Pass::integrate: return "integrate";
        case Pass::coarse: return "coarse";
        case Pass::constraints: return "constraints";
        case Pass::tethers: return "tethers";
        case Pass::collide: return "collide";
        case Pass::body: return "body";
        case Pass::normals: return "normals";
        case Pass::render_mesh: return "render_mesh";
        case Pass::health: return "health";
        case Pass::self_collision: return "self_collision";
        case Pass::layers: return "layers";
        case Pass::count: break;
    }
    return "unknown";
}

bool is_finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

namespace {

// A cloth's arrays in the world's block, each starting on a cache line. One description serves
// both uses: add_cloth carves one cloth's (cloth_array_counts), size_world sizes the block for the
// capacities (capacity_array_counts: the counts summed over max_cloths cloths, bounded).
struct ClothArrayCounts {
    size_t slots = 0;          // per particle slot (positions, previous, inverse mass, wind, normals)
    size_t node_lanes = 0;     // the coarse solve's per-node arrays, padded (kCoarseNodePadding)
    size_t nodes = 0;          // per coarse node slot: its particle slot, anchor, anchor's rest, holds
    size_t column_floats = 0;  // the coarse level's interpolated rows (CoarseState::column_rows)
    size_t body_order = 0;     // the body pass's slot order (a world with bodies)
    size_t plane_floats = 0;   // contact planes, per cached_planes body (a world with them)
    size_t triangle_lanes = 0; // the tangents' uv gradients (a world with tangents)
    size_t render_vertices = 0; // the render mesh's vertices (a world with render meshes)
    size_t last_good = 0;       // the last good copy's slots (RecoveryPolicy::last_good_state)
    size_t self_slots = 0;      // self-collision's per-slot arrays (ClothDesc::self_collision)
    size_t self_buckets = 0;    // its hash's bucket starts (table size + 1)
    size_t self_entries = 0;    // its hash's entries (slots + kHashEntryBlock)
    size_t self_edge_first = 0; // its edges by particle: the offsets (slots + 1)
    size_t self_edge_other = 0; // and the neighbours (6 per triangle)
    size_t layer_own_slots = 0;       // a layered cloth's hash of its own particles (ClothDesc::worn_over)
    size_t layer_own_buckets = 0;
    size_t layer_own_entries = 0;
    size_t layer_inner_slots = 0;     // its hash of the largest inner cloth's particles, and their positions
    size_t layer_inner_buckets = 0;
    size_t layer_inner_entries = 0;
    size_t layer_edge_first = 0;      // its mesh edges by particle (slots + 1)
    size_t layer_edge_other = 0;      // and the neighbours (6 per triangle)
};

// The entries of a cloth's per-triangle arrays in the normals pass's walk: the runs' lanes, then
// one per triangle done one at a time (as ClothAsset::wind_rest_area).
uint32_t triangle_lanes(const ClothAsset& a) { return a.wind_lane_count + a.triangle_count - a.wind_run_triangles; }

// `inner_slots`: the slots of the largest cloth it is worn over (0: none).
ClothArrayCounts cloth_array_counts(const WorldDesc& desc, const ClothAsset& asset, const ClothDesc& cloth,
                                    uint32_t inner_slots) {
    ClothArrayCounts n;
    if (inner_slots > 0) {
        n.layer_own_slots = asset.slot_count;
        n.layer_own_buckets = size_t(particle_hash_table_size(asset.slot_count)) + 1;
        n.layer_own_entries = size_t(asset.slot_count) + kHashEntryBlock;
        n.layer_inner_slots = inner_slots;
        n.layer_inner_buckets = size_t(particle_hash_table_size(inner_slots)) + 1;
        n.layer_inner_entries = size_t(inner_slots) + kHashEntryBlock;
        n.layer_edge_first = size_t(asset.slot_count) + 1;
        n.layer_edge_other = 6 * size_t(asset.triangle_count);
    }
    n.last_good = cloth.recovery == RecoveryPolicy::last_good_state ? asset.slot_count : 0;
    n.self_slots = cloth.self_collision ? asset.slot_count : 0;
    n.self_buckets = cloth.self_collision ? size_t(particle_hash_table_size(asset.slot_count)) + 1 : 0;
    n.self_entries = cloth.self_collision ? size_t(asset.slot_count) + kHashEntryBlock : 0;
    n.self_edge_first = cloth.self_collision ? size_t(asset.slot_count) + 1 : 0;
    n.self_edge_other = cloth.self_collision ? 6 * size_t(asset.triangle_count) : 0;
    n.slots = asset.slot_count;
    n.node_lanes = size_t(asset.coarse_slot_count) + kCoarseNodePadding;
    n.nodes = asset.coarse_slot_count;
    n.column_floats = size_t(kCoarseColumnRows) * coarse_column_stride(asset.lattice_plane_cols);
    n.body_order = desc.max_bodies > 0 ? asset.slot_count : 0;
    n.plane_floats = size_t(kContactPlaneArrays) * desc.max_cached_plane_bodies * asset.slot_count;
    n.triangle_lanes = desc.tangents ? triangle_lanes(asset) : 0;
    n.render_vertices = desc.render_meshes ? asset.render.vertex_count : 0;
    return n;
}

// A lattice's plane holds at most a quarter of the slots, so a cloth's column stride is at most
// slot_count / 4 + 2 * kSimdWidth (coarse_column_stride).
ClothArrayCounts capacity_array_counts(const WorldDesc& desc) {
    ClothArrayCounts n;
    const size_t cloths = desc.max_cloths;
    n.slots = desc.max_particles;
    n.node_lanes = size_t(desc.max_coarse_nodes) + kCoarseNodePadding * cloths;
    n.nodes = desc.max_coarse_nodes;
    n.column_floats = kCoarseColumnRows * (size_t(desc.max_particles) / 4 + 2 * kSimdWidth * cloths);
    n.body_order = desc.max_bodies > 0 ? desc.max_particles : 0;
    n.plane_floats = size_t(kContactPlaneArrays) * desc.max_cached_plane_bodies * desc.max_particles;
    n.triangle_lanes = desc.tangents ? desc.max_triangle_lanes : 0;
    n.render_vertices = desc.render_meshes ? desc.max_render_vertices : 0;
    n.last_good = desc.max_last_good_particles;
    // A cloth's table is at most twice its slots, or 16 buckets (self_collision_table_size).
    n.self_slots = desc.max_self_collision_particles;
    n.self_buckets = desc.max_self_collision_particles > 0
                         ? 2 * size_t(desc.max_self_collision_particles) + 17 * size_t(desc.max_cloths)
                         : 0;
    n.self_entries = desc.max_self_collision_particles > 0
                         ? size_t(desc.max_self_collision_particles) + kHashEntryBlock * size_t(desc.max_cloths)
                         : 0;
    n.self_edge_first = desc.max_self_collision_particles > 0 ? size_t(desc.max_self_collision_particles) + desc.max_cloths : 0;
    n.self_edge_other = 6 * size_t(desc.max_self_collision_triangles);
    // Each layered cloth's own and inner slots are both within its share of max_layer_particles.
    const size_t layered = desc.max_layer_particles;
    n.layer_own_slots = n.layer_inner_slots = layered;
    n.layer_own_buckets = n.layer_inner_buckets = layered > 0 ? 2 * layered + 17 * size_t(desc.max_cloths) : 0;
    n.layer_own_entries = n.layer_inner_entries = layered > 0 ? layered + kHashEntryBlock * size_t(desc.max_cloths) : 0;
    n.layer_edge_first = layered > 0 ? layered + desc.max_cloths : 0;
    n.layer_edge_other = 6 * size_t(desc.max_layer_triangles);
    return n;
}

// Calls visit(array, count) for every array of `cloth` in carving order (`array` a reference to the
// cloth's pointer). Arrays of count 0 are visited too (they cost the sizer a cache line).
template <class Visit>
void visit_cloth_arrays(const WorldDesc& desc, const ClothArrayCounts& n, ClothInstance& cloth, Visit&& visit) {
    Particles& p = cloth.particles;
    for (float** a : {&p.x, &p.y, &p.z, &p.previous_x, &p.previous_y, &p.previous_z, &p.inverse_mass}) visit(*a, n.slots);
    if (desc.wind)
        for (float** a : {&p.wind_x, &p.wind_y, &p.wind_z}) visit(*a, n.slots);
    if (has_normals(desc))
        for (float** a : {&p.normal_x, &p.normal_y, &p.normal_z}) visit(*a, n.slots);
    if (desc.tangents) {
        for (float** a : {&p.tangent_x, &p.tangent_y, &p.tangent_z, &p.tangent_w, &p.bitangent_x, &p.bitangent_y, &p.bitangent_z})
            visit(*a, n.slots);
        for (float*& a : p.uv_gradient) visit(a, n.triangle_lanes);
    }
    if (n.render_vertices > 0) {
        RenderOutput& r = cloth.render;
        for (float** a : {&r.x, &r.y, &r.z, &r.normal_x, &r.normal_y, &r.normal_z}) visit(*a, n.render_vertices);
        visit(r.corners, kRenderCornerFloats * n.slots);
    }
    CoarseState& c = cloth.coarse;
    for (float** a : {&c.x, &c.y, &c.z, &c.dx, &c.dy, &c.dz}) visit(*a, n.node_lanes);
    visit(c.column_rows, n.column_floats);
    visit(c.particle_slot, n.nodes);
    visit(c.anchor, n.nodes);
    visit(c.anchor_rest, n.nodes);
    visit(c.holds, n.nodes);
    if (n.body_order > 0) visit(cloth.body_order, n.body_order);
    if (n.plane_floats > 0) visit(cloth.contact_planes, n.plane_floats);
    if (n.last_good > 0) {
        LastGoodState& g = cloth.last_good;
        for (float** a : {&g.x, &g.y, &g.z, &g.previous_x, &g.previous_y, &g.previous_z}) visit(*a, n.last_good);
    }
    if (n.self_slots > 0) {
        SelfCollisionState& s = cloth.self_collision;
        visit(s.hash.cell_start, n.self_buckets);
        visit(s.hash.slot_bucket, n.self_slots);
        visit(s.shortest_edge_m, n.self_slots);
        visit(s.edge_first, n.self_edge_first);
        visit(s.edge_other, n.self_edge_other);
        visit(s.hash.entry_slot, n.self_entries);
        for (float** a : {&s.hash.entry_x, &s.hash.entry_y, &s.hash.entry_z}) visit(*a, n.self_entries);
    }
    if (n.layer_own_slots > 0) {
        LayerState& l = cloth.layers;
        for (ParticleHash* h : {&l.own, &l.inner}) {
            const bool own = h == &l.own;
            visit(h->cell_start, own ? n.layer_own_buckets : n.layer_inner_buckets);
            visit(h->slot_bucket, own ? n.layer_own_slots : n.layer_inner_slots);
            visit(h->entry_slot, own ? n.layer_own_entries : n.layer_inner_entries);
            for (float** a : {&h->entry_x, &h->entry_y, &h->entry_z}) visit(*a, own ? n.layer_own_entries : n.layer_inner_entries);
        }
        for (float** a : {&l.inner_x, &l.inner_y, &l.inner_z}) visit(*a, n.layer_inner_slots);
        visit(l.edge_first, n.layer_edge_first);
        visit(l.edge_other, n.layer_edge_other);
    }
}

// Asset validation stamps every particle slot and every coarse node slot.
uint32_t validation_scratch_count(const WorldDesc& desc) {
    return desc.max_particles > desc.max_coarse_nodes ? desc.max_particles : desc.max_coarse_nodes;
}

// The skin constraint pool: kSkinArrays arrays of 4 bytes a lane; each cloth's block pads to a
// whole number of SIMD groups and starts on a cache line.
size_t skin_pool_bytes(const WorldDesc& desc) {
    if (desc.max_skin_constraints == 0) return 0;
    return kSkinArrays * sizeof(float) * (size_t(desc.max_skin_constraints) + (kSimdWidth - 1) * size_t(desc.max_cloths)) +
           kCacheLine * size_t(desc.max_cloths);
}

ArenaSizer size_world(const WorldDesc& desc) {
    ArenaSizer sizer;
    sizer.add(sizeof(World));
    sizer.add(sizeof(ClothInstance) * desc.max_cloths);
    sizer.add(sizeof(ColliderState) * desc.max_colliders);
    sizer.add(sizeof(uint32_t) * validation_scratch_count(desc));
    sizer.add(sizeof(Region) * (size_t(desc.max_cloths) + desc.max_bodies));
    sizer.add(sizeof(uint32_t) * desc.max_cloths);  // budget_order
    // The cloths' arrays: each cloth's start on a cache line, so each may waste up to one per array.
    ClothInstance shape;
    visit_cloth_arrays(desc, capacity_array_counts(desc), shape, [&](auto*& array, size_t count) {
        sizer.add(sizeof(*array) * count + kCacheLine * desc.max_cloths);
    });
    // Bodies: hull and previous hull (4 floats a vertex), normals (3), triangles (3 indices); each
    // array may waste a cache line per body, and Embree reads its buffers 16 bytes past the end.
    sizer.add(sizeof(BodyState) * desc.max_bodies);
    sizer.add(sizeof(float) * 11 * size_t(desc.max_body_vertices) + sizeof(uint32_t) * 3 * size_t(desc.max_body_triangles) +
              4 * (kCacheLine + 16) * size_t(desc.max_bodies));
    sizer.add(body_hierarchy_bytes(desc.max_body_triangles, desc.max_bodies));
    sizer.add(skin_pool_bytes(desc));
    sizer.bytes += kCacheLine;  // the caller's block may start anywhere on a cache line
    return sizer;
}

Result check_world_desc(const WorldDesc& desc) {
    if (desc.max_cloths == 0) return make_error(ErrorCode::invalid_argument, "max_cloths is 0");
    if (desc.max_cloths > (1u << 16) || desc.max_colliders > (1u << 16) ||
        desc.max_particles > (1u << 28) || desc.max_constraints > (1u << 30) ||
        desc.max_coarse_nodes > (1u << 28) || desc.max_bodies > (1u << 10) ||
        desc.max_body_vertices > (1u << 26) || desc.max_body_triangles > (1u << 26) ||
        desc.max_skin_constraints > (1u << 28) || desc.max_triangle_lanes > (1u << 28) ||
        desc.max_render_vertices > (1u << 28) || desc.max_last_good_particles > (1u << 28) ||
        desc.max_self_collision_particles > (1u << 28) || desc.max_self_collision_triangles > (1u << 28) ||
        desc.max_layer_particles > (1u << 28) || desc.max_layer_triangles > (1u << 28))
        return make_error(ErrorCode::out_of_range, "a capacity is absurdly large");
    if (!is_finite(desc.gravity_m_s2) || !std::isfinite(desc.air_density_kg_m3))
        return make_error(ErrorCode::non_finite, "gravity or air density is not finite");
    if (desc.air_density_kg_m3 < 0.0f)
        return make_error(ErrorCode::out_of_range, "air density is negative");
    if (desc.max_cached_plane_bodies > desc.max_bodies)
        return make_error(ErrorCode::invalid_argument, "max_cached_plane_bodies %u is more than max_bodies %u",
                          desc.max_cached_plane_bodies, desc.max_bodies);
    if (desc.max_bodies > 0 && (desc.max_body_vertices < 3 || desc.max_body_triangles < 1))
        return make_error(ErrorCode::invalid_argument, "bodies need max_body_vertices >= 3 and max_body_triangles >= 1");
    if (!std::isfinite(desc.budget_ns_per_lane) || !std::isfinite(desc.budget_ns_per_particle))
        return make_error(ErrorCode::non_finite, "the frame budget's cost model is not finite");
    if (desc.budget_ns_per_lane < 0.0f || desc.budget_ns_per_particle < 0.0f)
        return make_error(ErrorCode::out_of_range, "the frame budget's cost model is negative");
    if (desc.simd != SimdPath::automatic && !simd_path_available(desc.simd))
        return make_error(ErrorCode::unsupported, "SIMD path '%s' is not available in this build or CPU",
                          simd_path_name(desc.simd));
    return {};
}

Result check_cloth_settings(const ClothDesc& desc) {
    if (desc.asset == nullptr) return make_error(ErrorCode::invalid_argument, "cloth has no asset");
    if (desc.policy != BudgetPolicy::automatic && desc.policy != BudgetPolicy::explicit_split)
        return make_error(ErrorCode::invalid_argument, "unknown budget policy");
    if (desc.policy == BudgetPolicy::automatic && (desc.sweeps < 1 || desc.sweeps > 1000))
        return make_error(ErrorCode::out_of_range, "sweeps %u outside 1..1000", desc.sweeps);
    if (desc.substeps < 1 || desc.substeps > 64)
        return make_error(ErrorCode::out_of_range, "substeps %u outside 1..64", desc.substeps);
    if (desc.projection != SpringProjection::exact && desc.projection != SpringProjection::sqrt_free)
        return make_error(ErrorCode::invalid_argument, "unknown spring projection");
    if (desc.coarse_iterations < 1 || desc.coarse_iterations > 16)
        return make_error(ErrorCode::out_of_range, "coarse_iterations %u outside 1..16", desc.coarse_iterations);
    if (desc.iterations > 1000)
        return make_error(ErrorCode::out_of_range, "iterations %u outside 0..1000", desc.iterations);
    if (!std::isfinite(desc.relaxation) || !is_finite(desc.translation_m) ||
        !std::isfinite(desc.damping_per_s) || !std::isfinite(desc.tether_slack) ||
        !std::isfinite(desc.drag_coefficient) || !std::isfinite(desc.lift_coefficient))
        return make_error(ErrorCode::non_finite, "a cloth setting is not finite");
    if (!(desc.linear_inertia >= 0.0f && desc.linear_inertia <= 1.0f) ||
        !(desc.angular_inertia >= 0.0f && desc.angular_inertia <= 1.0f))
        return make_error(ErrorCode::out_of_range, "inertia (linear %g, angular %g) outside 0..1",
                          double(desc.linear_inertia), double(desc.angular_inertia));
    if (!(desc.max_inertial_speed_m_s >= 0.0f && desc.max_inertial_speed_m_s <= 1e6f))
        return make_error(ErrorCode::out_of_range, "max_inertial_speed_m_s %g outside 0..1e6",
                          double(desc.max_inertial_speed_m_s));
    if (!(desc.max_step_s >= 0.0f && desc.max_step_s <= 1.0f) || !(desc.max_step_growth == 0.0f || (desc.max_step_growth >= 1.0f && desc.max_step_growth <= 1e6f)))
        return make_error(ErrorCode::out_of_range, "max_step_s %g outside 0..1, or max_step_growth %g neither 0 nor 1..1e6",
                          double(desc.max_step_s), double(desc.max_step_growth));
    if (!(desc.jump_speed_m_s >= 0.0f && desc.jump_speed_m_s <= 1e6f) ||
        !(desc.jump_turn_rad_s >= 0.0f && desc.jump_turn_rad_s <= 1e6f))
        return make_error(ErrorCode::out_of_range, "jump_speed_m_s %g or jump_turn_rad_s %g outside 0..1e6",
                          double(desc.jump_speed_m_s), double(desc.jump_turn_rad_s));
    // Only what measured stable (docs/solver.md, "Splits the API refuses"; tests/test_stress.cpp):
    // over-relaxation jitters inside Verlet (1.3: 5-7 cm/s back and forth on the n = 16 drape and
    // sphere; 1.5: up to 16 m/s; 1.95 blew up with the coarse level), and below 0.5 the coarse level
    // kept the n = 10 grid on the sphere moving at 6-11 cm/s.
    if (!(desc.relaxation >= kMinRelaxation && desc.relaxation <= kMaxRelaxation))
        return make_error(ErrorCode::out_of_range, "relaxation %g outside %g..%g", double(desc.relaxation),
                          double(kMinRelaxation), double(kMaxRelaxation));
    // The coarse correction, applied every substep, adds a little velocity each time: with 64
    // substeps it kept the n = 16 drape moving back and forth at 6-13 cm/s (8: at rest).
    if (desc.policy == BudgetPolicy::explicit_split && resolve_split(desc, *desc.asset).coarse_level &&
        desc.substeps > kMaxCoarseSubsteps)
        return make_error(ErrorCode::out_of_range, "coarse_level with %u substeps: at most %u (or coarse_level off)",
                          desc.substeps, kMaxCoarseSubsteps);
    for (float c : desc.compliance_m_per_n) {
        if (!std::isfinite(c)) return make_error(ErrorCode::non_finite, "compliance is not finite");
        if (c < 0.0f) return make_error(ErrorCode::out_of_range, "compliance is negative");
    }
    if (desc.damping_per_s < 0.0f || desc.damping_per_s > 1000.0f)
        return make_error(ErrorCode::out_of_range, "damping %g 1/s outside 0..1000", double(desc.damping_per_s));
    if (desc.tether_slack < 0.0f)
        return make_error(ErrorCode::out_of_range, "tether slack is negative");
    if (desc.drag_coefficient < 0.0f || desc.lift_coefficient < 0.0f)
        return make_error(ErrorCode::out_of_range, "drag and lift coefficients must be >= 0");
    if (desc.recovery != RecoveryPolicy::none && desc.recovery != RecoveryPolicy::last_good_state &&
        desc.recovery != RecoveryPolicy::rest_pose && desc.recovery != RecoveryPolicy::dressed_pose)
        return make_error(ErrorCode::invalid_argument, "unknown recovery policy");
    if (!std::isfinite(desc.sleep_speed_m_s))
        return make_error(ErrorCode::non_finite, "sleep_speed_m_s is not finite");
    if (desc.sleep_speed_m_s < 0.0f || desc.sleep_speed_m_s > 1000.0f)
        return make_error(ErrorCode::out_of_range, "sleep_speed_m_s %g outside 0..1000 m/s",
                          double(desc.sleep_speed_m_s));
    if (!std::isfinite(desc.self_thickness_m) || !std::isfinite(desc.self_friction))
        return make_error(ErrorCode::non_finite, "self_thickness_m or self_friction is not finite");
    if (desc.self_thickness_m < kMinSelfThickness_m || desc.self_thickness_m > kMaxSelfThickness_m)
        return make_error(ErrorCode::out_of_range, "self_thickness_m %g outside %g..%g m", double(desc.self_thickness_m),
                          double(kMinSelfThickness_m), double(kMaxSelfThickness_m));
    if (desc.self_friction < 0.0f || desc.self_friction > 10.0f)
        return make_error(ErrorCode::out_of_range, "self_friction %g outside 0..10", double(desc.self_friction));
    if (!std::isfinite(desc.layer_thickness_m) || !std::isfinite(desc.layer_friction))
        return make_error(ErrorCode::non_finite, "layer_thickness_m or layer_friction is not finite");
    if (desc.layer_thickness_m < kMinSelfThickness_m || desc.layer_thickness_m > kMaxSelfThickness_m)
        return make_error(ErrorCode::out_of_range, "layer_thickness_m %g outside %g..%g m", double(desc.layer_thickness_m),
                          double(kMinSelfThickness_m), double(kMaxSelfThickness_m));
    if (desc.layer_friction < 0.0f || desc.layer_friction > 10.0f)
        return make_error(ErrorCode::out_of_range, "layer_friction %g outside 0..10", double(desc.layer_friction));
    if (desc.worn_over_count > kMaxWornOver)
        return make_error(ErrorCode::out_of_range, "worn over %u cloths, at most %u", desc.worn_over_count, kMaxWornOver);
    return {};
}

Result check_collider(const ColliderDesc& desc) {
    if (!is_finite(desc.p0) || !is_finite(desc.p1) || !std::isfinite(desc.radius_m) ||
        !std::isfinite(desc.inflation_m) || !std::isfinite(desc.friction))
        return make_error(ErrorCode::non_finite, "collider has a non-finite value");
    const float bound = 1e6f;  // metres: beyond this float precision no longer resolves a cloth
    const float extent = std::fmax(std::fmax(std::fabs(desc.p0.x), std::fabs(desc.p0.y)),
                                   std::fmax(std::fabs(desc.p0.z), std::fabs(desc.radius_m)));
    if (extent > bound) return make_error(ErrorCode::out_of_range, "collider beyond 1e6 m");
    if (desc.radius_m < 0.0f || desc.inflation_m < 0.0f || desc.friction < 0.0f)
        return make_error(ErrorCode::out_of_range, "collider radius, inflation and friction must be >= 0");
    switch (desc.shape) {
        case ColliderShape::sphere:
        case ColliderShape::capsule:
        case ColliderShape::cylinder: break;
        case ColliderShape::plane: {
            const Vec3 n = desc.p1;
            const float len2 = n.x * n.x + n.y * n.y + n.z * n.z;
            if (!(std::fabs(len2 - 1.0f) < 1e-3f))
                return make_error(ErrorCode::invalid_argument, "plane normal (p1) is not unit length");
            break;
        }
        default: return make_error(ErrorCode::invalid_argument, "unknown collider shape");
    }
    return {};
}

// Slots [0, this) are the lattice's four parity planes (none without a lattice).
uint32_t lattice_plane_slots(const ClothAsset& a) { return 4 * a.lattice_plane_rows * a.lattice_plane_cols; }
// No contact anchors (ClothDesc::contact_tethers): the first step's end finds them.
void clear_contact_anchors(ClothInstance& cloth) {
    for (uint32_t k = 0; k < cloth.asset->coarse_slot_count; ++k) {
        cloth.coarse.anchor[k] = k;
        cloth.coarse.anchor_rest[k] = std::numeric_limits<float>::infinity();
        cloth.coarse.holds[k] = 0;
    }
}

}  // namespace

// Particles::uv_gradient for every triangle lane of the walk (render/normals.h). With e1, e2 the
// edges P1 - P0, P2 - P0 and (s1, t1), (s2, t2) their uv deltas, Lengyel's solve gives
// dP/du = (t2 e1 - t1 e2) / r and dP/dv = (s1 e2 - s2 e1) / r, r = s1 t2 - s2 t1; weighted by the uv
// area |r| / 2 the division goes away (the constant 1/2 changes no direction). A corner on a sewn
// seam has one uv per panel (ClothAsset::sewn_uv): the triangle takes the combination whose uv
// edge lengths best match its start pose's (its own panel's; another panel's lies elsewhere in the
// pattern). Padding lanes and triangles of no uv area get 0. Runs once, at add_cloth.
static void tangent_uv_gradients(const ClothAsset& a, const Particles& p) {
    // Scratch until the first pass: bitangent_x[slot] = 1 + the slot's sewn point, or 0 (exact in
    // a float: fewer than 2^24 points).
    for (uint32_t i = 0; i < a.slot_count; ++i) p.bitangent_x[i] = 0.0f;
    for (uint32_t k = 0; k < a.sewn_point_count; ++k) p.bitangent_x[a.slot_of_particle[a.sewn_particle[k]]] = float(k + 1);
    auto gradient = [&](const uint32_t (&slot)[3], uint32_t g) {
        const float* option[3];  // each corner's uv choices, `count` pairs
        uint32_t count[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t s = slot[k], sewn = uint32_t(p.bitangent_x[s]);
            if (sewn == 0) {
                option[k] = a.uv + 2 * size_t(a.particle_of_slot[s]), count[k] = 1;
            } else {
                option[k] = a.sewn_uv + 2 * size_t(a.sewn_uv_first[sewn - 1]);
                count[k] = a.sewn_uv_first[sewn] - a.sewn_uv_first[sewn - 1];
            }
        }
        double length[3];  // start pose edge lengths: 01, 12, 20
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = slot[k], j = slot[(k + 1) % 3];
            length[k] = std::hypot(double(a.start_x[j]) - a.start_x[i], double(a.start_y[j]) - a.start_y[i],
                                   double(a.start_z[j]) - a.start_z[i]);
        }
        const float* uv[3] = {option[0], option[1], option[2]};
        double best = std::numeric_limits<double>::infinity();
        for (uint32_t i0 = 0; i0 < count[0]; ++i0)
            for (uint32_t i1 = 0; i1 < count[1]; ++i1)
                for (uint32_t i2 = 0; i2 < count[2]; ++i2) {
                    const float* c[3] = {option[0] + 2 * i0, option[1] + 2 * i1, option[2] + 2 * i2};
                    double misfit = 0.0;
                    for (int k = 0; k < 3; ++k) {
                        const float* u = c[k];
                        const float* v = c[(k + 1) % 3];
                        const double d = std::hypot(double(v[0]) - u[0], double(v[1]) - u[1]) - length[k];
                        misfit += d * d;
                    }
                    if (misfit < best) best = misfit, uv[0] = c[0], uv[1] = c[1], uv[2] = c[2];
                }
        const float s1 = uv[1][0] - uv[0][0], t1 = uv[1][1] - uv[0][1];
        const float s2 = uv[2][0] - uv[0][0], t2 = uv[2][1] - uv[0][1];
        const float r = s1 * t2 - s2 * t1;
        const float sign = r > 0.0f ? 1.0f : r < 0.0f ? -1.0f : 0.0f;  // |r| / r
        p.uv_gradient[0][g] = sign * t2, p.uv_gradient[1][g] = -sign * t1;
        p.uv_gradient[2][g] = -sign * s2, p.uv_gradient[3][g] = sign * s1;
    };
    for (uint32_t r = 0; r < a.wind_run_count; ++r) {
        const TriangleRun& run = a.wind_runs[r];
        for (uint32_t k = 0; k < run.lane_count; ++k) {
            const uint32_t g = run.first_lane + k;
            if (a.wind_lane_weight[g] == 0.0f) {
                for (float* array : p.uv_gradient) array[g] = 0.0f;
                continue;
            }
            const uint32_t slot[3] = {run.a0 + k, run.b0 + k, run.c0 + k};
            gradient(slot, g);
        }
    }
    for (uint32_t t = a.wind_run_triangles; t < a.triangle_count; ++t) {
        const uint32_t slot[3] = {a.triangles[3 * t], a.triangles[3 * t + 1], a.triangles[3 * t + 2]};
        gradient(slot, a.wind_lane_count + t - a.wind_run_triangles);
    }
}

void place_at_start(const Kernels& kernels, ClothInstance& cloth) {
    const ClothAsset& a = *cloth.asset;
    const Particles& p = cloth.particles;
    const Vec3 t = cloth.settings.translation_m;
    for (uint32_t i = 0; i < a.slot_count; ++i) {
        p.x[i] = p.previous_x[i] = a.start_x[i] + t.x;
        p.y[i] = p.previous_y[i] = a.start_y[i] + t.y;
        p.z[i] = p.previous_z[i] = a.start_z[i] + t.z;
        p.inverse_mass[i] = a.inverse_mass[i];
    }
    cloth.held_plane_slots = 0;
    for (uint32_t i = 0; i < lattice_plane_slots(a); ++i) cloth.held_plane_slots += !(p.inverse_mass[i] > 0.0f);
    start_from_new_positions(kernels, cloth);
    cloth.previous_substep_s = 0.0f;
}

// What follows from the positions after a jump (place_at_start, restore_last_good): no contact
// anchors or wind from before it, the render output found again.
void start_from_new_positions(const Kernels& kernels, ClothInstance& cloth) {
    const ClothAsset& a = *cloth.asset;
    const Particles& p = cloth.particles;
    clear_contact_anchors(cloth);
    if (p.wind_x != nullptr) {
        std::memset(p.wind_x, 0, sizeof(float) * a.slot_count);
        std::memset(p.wind_y, 0, sizeof(float) * a.slot_count);
        std::memset(p.wind_z, 0, sizeof(float) * a.slot_count);
    }
    if (p.tangent_x != nullptr)
        kernels.vertex_normals_tangents(p, a);
    else if (p.normal_x != nullptr)
        kernels.vertex_normals(p, a);
    if (cloth.render.x != nullptr) kernels.render_mesh(p, a, cloth.render);
}

void save_last_good(ClothInstance& cloth) {
    const Particles& p = cloth.particles;
    LastGoodState& g = cloth.last_good;
    const size_t bytes = sizeof(float) * size_t(p.slot_count);
    std::memcpy(g.x, p.x, bytes), std::memcpy(g.y, p.y, bytes), std::memcpy(g.z, p.z, bytes);
    std::memcpy(g.previous_x, p.previous_x, bytes), std::memcpy(g.previous_y, p.previous_y, bytes);
    std::memcpy(g.previous_z, p.previous_z, bytes);
    g.previous_substep_s = cloth.previous_substep_s;
    g.saved = true;
}

void restore_last_good(const Kernels& kernels, ClothInstance& cloth) {
    const Particles& p = cloth.particles;
    const LastGoodState& g = cloth.last_good;
    const size_t bytes = sizeof(float) * size_t(p.slot_count);
    std::memcpy(p.x, g.x, bytes), std::memcpy(p.y, g.y, bytes), std::memcpy(p.z, g.z, bytes);
    std::memcpy(p.previous_x, g.previous_x, bytes), std::memcpy(p.previous_y, g.previous_y, bytes);
    std::memcpy(p.previous_z, g.previous_z, bytes);
    cloth.previous_substep_s = g.previous_substep_s;
    start_from_new_positions(kernels, cloth);
}


SolverSplit resolve_split(const ClothDesc& desc, const ClothAsset& asset) {
    SolverSplit split;
    split.tethers = desc.tethers && asset.tether_batch_count > 0;
    if (desc.policy == BudgetPolicy::explicit_split) {
        split.substeps = desc.substeps;
        split.iterations = desc.iterations;
        split.relaxation = desc.relaxation;
        const bool coarse = desc.coarse_level == CoarseLevel::on ||
                            (desc.coarse_level == CoarseLevel::automatic && !split.tethers);
        split.coarse_level = coarse && asset.coarse_node_count > 0;
        split.coarse_iterations = desc.coarse_iterations;
    } else if (split.tethers) {  // held by pins: iterations, tethers (docs/solver.md)
        split.substeps = 1;
        split.iterations = desc.sweeps;
        split.relaxation = 1.0f;
        split.coarse_level = false;
        split.coarse_iterations = 1;
    } else {  // held by colliders only: substeps for friction, the coarse level for tension
        // 2 substeps with 3 coarse sweeps each up to 5 sweeps: the sphere's grid stays on at every
        // size and offset at about plain's cost at 3 sweeps (3 substeps with one coarse sweep cost
        // 1.25-1.5x). From 6 sweeps 3 substeps (better contact on moving bodies), never more: the
        // coarse correction, applied every substep, keeps a draped cloth moving at 1-6 cm/s with 4
        // to 100 substeps (docs/solver.md).
        split.substeps = desc.sweeps < 2 ? desc.sweeps : desc.sweeps < 6 ? 2 : 3;
        split.iterations = desc.sweeps / split.substeps;  // never more than the budget
        split.relaxation = 0.8f;
        split.coarse_level = asset.coarse_node_count > 0;
        split.coarse_iterations = 3;
    }
    return split;
}

namespace {

bool count_embree_memory(void* user, ssize_t bytes, bool /*post*/) {
    // Embree may call this from any thread that commits (bodies refit on the game's workers).
    WorldStats& stats = static_cast<World*>(user)->stats;
    std::atomic_ref<int64_t>(stats.embree_bytes).fetch_add(int64_t(bytes), std::memory_order_relaxed);
    if (bytes > 0) std::atomic_ref<uint64_t>(stats.embree_allocations).fetch_add(1, std::memory_order_relaxed);
    return true;  // never refuse: the budget was fixed at creation
}


}  // namespace

Result find_cloth(const World* world, ClothId id) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    return check_id(world->cloths, world->desc.max_cloths, id.index, id.generation, "cloth");
}

namespace {

Result find_collider(const World* world, ColliderId id) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    return check_id(world->colliders, world->desc.max_colliders, id.index, id.generation, "collider");
}

// A cloth's arrays moved by `delta` bytes (compaction): its pointers follow.
void rebase_cloth(const WorldDesc& desc, ClothInstance& cloth, ptrdiff_t delta) {
    visit_cloth_arrays(desc, cloth_array_counts(desc, *cloth.asset, cloth.settings, cloth.layers.inner_capacity), cloth,
                       [&](auto*& array, size_t) { rebase(array, delta); });
}

size_t cloth_region_bytes(const WorldDesc& desc, const ClothAsset& asset, const ClothDesc& cloth, uint32_t inner_slots) {
    ArenaSizer sizer;
    ClothInstance shape;
    visit_cloth_arrays(desc, cloth_array_counts(desc, asset, cloth, inner_slots), shape,
                       [&](auto*& array, size_t count) { sizer.add(sizeof(*array) * count); });
    return sizer.bytes;
}

constexpr uint32_t kBodyRegion = 1u << 31;  // Region::owner: a body's index with this bit, else a cloth's

// The live cloths' and bodies' regions, sorted by where they start.
uint32_t live_regions(const World& world, Region* out) {
    uint32_t n = 0;
    for (uint32_t i = 0; i < world.cloth_slots; ++i)
        if (world.cloths[i].slot.live) out[n++] = {world.cloths[i].slot.memory.begin, world.cloths[i].slot.memory.end, i};
    for (uint32_t i = 0; i < world.body_slots; ++i)
        if (world.bodies[i].slot.live)
            out[n++] = {world.bodies[i].slot.memory.begin, world.bodies[i].slot.memory.end, i | kBodyRegion};
    sort_regions(out, n);
    return n;
}

}  // namespace

Result reserve_instance_memory(World& world, size_t bytes, Arena* out_arena, Region* out_region) {
    uint8_t* const base = world.arena.base;
    const size_t low = world.instance_memory_begin, high = world.arena.capacity;
    uint32_t n = live_regions(world, world.regions);
    size_t at = first_fit(base, world.regions, n, low, high, bytes);
    if (at == SIZE_MAX) {  // no gap fits: close them all, then the room is at the end
        if (first_fit(base, nullptr, 0, compacted_end(base, world.regions, n, low), high, bytes) == SIZE_MAX)
            return make_error(ErrorCode::capacity_exceeded, "world memory exhausted");
        world.stats.memory_compactions += 1;
        compact_regions(base, world.regions, n, low, [&](const Region& r, ptrdiff_t delta) {
            if (r.owner & kBodyRegion) {
                BodyState& body = world.bodies[r.owner & ~kBodyRegion];
                body.slot.memory = {r.begin, r.end};
                rebase_body(world, body, delta);
            } else {
                ClothInstance& cloth = world.cloths[r.owner];
                cloth.slot.memory = {r.begin, r.end};
                rebase_cloth(world.desc, cloth, delta);
            }
        });
        n = live_regions(world, world.regions);
        at = first_fit(base, world.regions, n, low, high, bytes);
        if (at == SIZE_MAX) return make_error(ErrorCode::capacity_exceeded, "world memory exhausted");
    }
    *out_arena = Arena{base, at + bytes, at};
    *out_region = {at, at + bytes};
    return {};
}

void reserve_cloth(WorldDesc& desc, const ClothAsset& asset, RecoveryPolicy recovery) {
    desc.max_cloths += 1;
    if (recovery == RecoveryPolicy::last_good_state) desc.max_last_good_particles += asset.slot_count;
    desc.max_particles += asset.slot_count;
    desc.max_constraints += asset.lane_count;
    desc.max_coarse_nodes += asset.coarse_slot_count;
    desc.max_skin_constraints += asset.skin.count;
    desc.max_triangle_lanes += triangle_lanes(asset);
    desc.max_render_vertices += asset.render.vertex_count;
}

void reserve_cloth(WorldDesc& desc, const ClothDesc& cloth) {
    if (cloth.asset == nullptr) return;
    reserve_cloth(desc, *cloth.asset, cloth.recovery);
    if (cloth.self_collision) {
        desc.max_self_collision_particles += cloth.asset->slot_count;
        desc.max_self_collision_triangles += cloth.asset->triangle_count;
    }
}

void reserve_layer(WorldDesc& desc, const ClothAsset& outer, const ClothAsset& largest_inner) {
    desc.max_layer_particles += outer.slot_count + largest_inner.slot_count;
    desc.max_layer_triangles += outer.triangle_count;
}

MemoryRequirements world_memory_requirements(const WorldDesc& desc) {
    MemoryRequirements req;
    if (!check_world_desc(desc).ok()) return req;
    req.bytes = size_world(desc).bytes;
    req.alignment = kCacheLine;
    return req;
}

Result create_world(const WorldDesc& desc, void* memory, size_t bytes, World** out_world) {
    if (out_world == nullptr) return make_error(ErrorCode::invalid_argument, "out_world is null");
    *out_world = nullptr;
    if (Result r = check_world_desc(desc); !r.ok()) return r;
    if (memory == nullptr) return make_error(ErrorCode::invalid_argument, "memory is null");
    const size_t needed = size_world(desc).bytes;
    if (bytes < needed)
        return make_error(ErrorCode::memory_too_small, "block of %zu bytes, world needs %zu", bytes, needed);

    Arena arena{static_cast<uint8_t*>(memory), bytes, 0};
    World* world = new (arena.allocate(sizeof(World), alignof(World))) World();
    world->desc = desc;
    world->cloths = arena.allocate_array<ClothInstance>(desc.max_cloths);
    for (uint32_t i = 0; i < desc.max_cloths; ++i) new (&world->cloths[i]) ClothInstance();
    world->colliders = arena.allocate_array<ColliderState>(desc.max_colliders);
    for (uint32_t i = 0; i < desc.max_colliders; ++i) new (&world->colliders[i]) ColliderState();
    world->validation_scratch = arena.allocate_array<uint32_t>(validation_scratch_count(desc));
    world->regions = arena.allocate_array<Region>(size_t(desc.max_cloths) + desc.max_bodies);
    world->budget_order = arena.allocate_array<uint32_t>(desc.max_cloths);
    world->bodies = arena.allocate_array<BodyState>(desc.max_bodies);
    for (uint32_t i = 0; i < desc.max_bodies; ++i) new (&world->bodies[i]) BodyState();
    if (desc.max_bodies > 0) {
        // One thread: the step is single-threaded and deterministic; Embree's refit then runs on the
        // caller's thread. Its memory monitor feeds WorldStats (rtcSetDeviceMemoryMonitorFunction).
        world->embree_device = rtcNewDevice("threads=1,set_affinity=0");
        if (world->embree_device == nullptr)
            return make_error(ErrorCode::unsupported, "Embree device creation failed (error %d)",
                              int(rtcGetDeviceError(nullptr)));
        rtcSetDeviceMemoryMonitorFunction(world->embree_device, count_embree_memory, world);
    }
    if (const size_t skin_bytes = skin_pool_bytes(desc); skin_bytes > 0)
        world->skin_pool = Arena{static_cast<uint8_t*>(arena.allocate(skin_bytes)), skin_bytes, 0};
    world->arena = arena;
    world->instance_memory_begin = arena.used;
    world->gravity_m_s2 = desc.gravity_m_s2;

    const Kernels* avx2 = avx2_kernels();
    switch (desc.simd) {
        case SimdPath::scalar: world->kernels = &scalar_kernels(); break;
        case SimdPath::avx2: world->kernels = avx2; break;
        case SimdPath::automatic: world->kernels = avx2 != nullptr ? avx2 : &scalar_kernels(); break;
    }
    *out_world = world;
    return {};
}

Result add_cloth(World* world, const ClothDesc& desc, ClothId* out_cloth) {
    if (world == nullptr || out_cloth == nullptr)
        return make_error(ErrorCode::invalid_argument, "world or out_cloth is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (Result r = check_cloth_settings(desc); !r.ok()) return r;
    const ClothAsset& asset = *desc.asset;
    const uint32_t index = free_slot(world->cloths, world->cloth_slots, world->desc.max_cloths);
    if (index == world->desc.max_cloths)
        return make_error(ErrorCode::capacity_exceeded, "world holds at most %u cloths", world->desc.max_cloths);
    if (asset.slot_count > world->desc.max_particles - world->particles_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u particle slots, %u left",
                          asset.slot_count, world->desc.max_particles - world->particles_used);
    if (asset.lane_count > world->desc.max_constraints - world->constraints_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u constraint lanes, %u left",
                          asset.lane_count, world->desc.max_constraints - world->constraints_used);
    if (asset.coarse_slot_count > world->desc.max_coarse_nodes - world->coarse_nodes_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u coarse node slots, %u left",
                          asset.coarse_slot_count, world->desc.max_coarse_nodes - world->coarse_nodes_used);
    const uint32_t tangent_lanes = world->desc.tangents ? triangle_lanes(asset) : 0;
    if (tangent_lanes > world->desc.max_triangle_lanes - world->triangle_lanes_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u triangle lanes (tangents), %u left",
                          tangent_lanes, world->desc.max_triangle_lanes - world->triangle_lanes_used);
    const uint32_t render_vertices = world->desc.render_meshes ? asset.render.vertex_count : 0;
    if (render_vertices > world->desc.max_render_vertices - world->render_vertices_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u render mesh vertices, %u left", render_vertices,
                          world->desc.max_render_vertices - world->render_vertices_used);
    const uint32_t last_good = desc.recovery == RecoveryPolicy::last_good_state ? asset.slot_count : 0;
    if (last_good > world->desc.max_last_good_particles - world->last_good_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u last good slots (max_last_good_particles), %u left",
                          last_good, world->desc.max_last_good_particles - world->last_good_used);
    const uint32_t self_slots = desc.self_collision ? asset.slot_count : 0;
    if (self_slots > world->desc.max_self_collision_particles - world->self_collision_used)
        return make_error(ErrorCode::capacity_exceeded,
                          "cloth needs %u self-collision slots (max_self_collision_particles), %u left", self_slots,
                          world->desc.max_self_collision_particles - world->self_collision_used);
    const uint32_t self_triangles = desc.self_collision ? asset.triangle_count : 0;
    if (self_triangles > world->desc.max_self_collision_triangles - world->self_collision_triangles_used)
        return make_error(ErrorCode::capacity_exceeded,
                          "cloth needs %u self-collision triangles (max_self_collision_triangles), %u left", self_triangles,
                          world->desc.max_self_collision_triangles - world->self_collision_triangles_used);
    // Layered garments: the cloths it is worn over must be live (they step in an earlier stage).
    uint32_t inner_slots = 0, layer = 0;
    for (uint32_t k = 0; k < desc.worn_over_count; ++k) {
        if (Result r = find_cloth(world, desc.worn_over[k]); !r.ok()) return r;
        const ClothInstance& inner = world->cloths[desc.worn_over[k].index];
        if (inner.layer + 1 >= kMaxClothLayers)
            return make_error(ErrorCode::out_of_range, "worn over cloth %u, itself in layer %u of at most %u",
                              desc.worn_over[k].index, inner.layer + 1, kMaxClothLayers);
        inner_slots = std::max(inner_slots, inner.asset->slot_count);
        layer = std::max(layer, inner.layer + 1);
    }
    const uint32_t layer_slots = inner_slots > 0 ? asset.slot_count + inner_slots : 0;
    if (layer_slots > world->desc.max_layer_particles - world->layer_particles_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u layer slots (max_layer_particles), %u left",
                          layer_slots, world->desc.max_layer_particles - world->layer_particles_used);
    const uint32_t layer_triangles = inner_slots > 0 ? asset.triangle_count : 0;
    if (layer_triangles > world->desc.max_layer_triangles - world->layer_triangles_used)
        return make_error(ErrorCode::capacity_exceeded, "cloth needs %u layer triangles (max_layer_triangles), %u left",
                          layer_triangles, world->desc.max_layer_triangles - world->layer_triangles_used);
    if (world->desc.tangents && asset.uv == nullptr)
        return make_error(ErrorCode::invalid_argument, "the world has tangents but the asset has no texture coordinates");
    if (Result r = validate_asset_with_scratch(asset, world->validation_scratch, validation_scratch_count(world->desc));
        !r.ok())
        return r;

    // Carve the cloth's arrays in a region of their own (the sizing above says they fit).
    Arena room;
    Region region;
    if (Result r = reserve_instance_memory(*world, cloth_region_bytes(world->desc, asset, desc, inner_slots), &room, &region); !r.ok())
        return r;
    ClothInstance& cloth = world->cloths[index];
    const uint32_t generation = cloth.slot.generation;
    cloth = ClothInstance();
    cloth.slot = {true, generation, region};
    const ClothArrayCounts counts = cloth_array_counts(world->desc, asset, desc, inner_slots);
    visit_cloth_arrays(world->desc, counts, cloth, [&](auto*& array, size_t count) {
        array = room.allocate_array<std::remove_reference_t<decltype(*array)>>(count);
    });
    cloth.asset = &asset;
    cloth.settings = desc;
    cloth.split = resolve_split(desc, asset);
    cloth.particles.slot_count = asset.slot_count;
    if (cloth.body_order != nullptr) order_for_body_pass(asset, world->validation_scratch, cloth.body_order);
    for (size_t f = 0; f < counts.plane_floats; ++f) cloth.contact_planes[f] = 0.0f;  // found at each step's first substep
    CoarseState& c = cloth.coarse;
    for (uint32_t k = 0; k < asset.coarse_slot_count; ++k)
        c.particle_slot[k] = asset.coarse_node_slot[asset.coarse_node_of_slot[k]];
    c.column_stride = coarse_column_stride(asset.lattice_plane_cols);
    for (float* node_array : {c.x, c.y, c.z, c.dx, c.dy, c.dz})  // the padding is read, never used
        for (uint32_t i = 0; i < asset.coarse_slot_count + kCoarseNodePadding; ++i) node_array[i] = 0.0f;
    if (cloth.particles.tangent_x != nullptr) tangent_uv_gradients(asset, cloth.particles);
    if (desc.self_collision) {
        cloth.self_collision.hash.table_size = particle_hash_table_size(asset.slot_count);
        cloth.self_collision.hash.cell_m = self_collision_cell_m(asset, desc.self_thickness_m);
        build_self_collision_edges(asset, cloth.self_collision);
    }
    if (inner_slots > 0) {
        LayerState& l = cloth.layers;
        l.inner_capacity = inner_slots;
        l.own.table_size = particle_hash_table_size(asset.slot_count);
        l.inner.table_size = particle_hash_table_size(inner_slots);
        // Its particles are walked by the inner cloths' triangles, theirs by its own.
        l.inner.cell_m = layer_cell_m(asset, desc.layer_thickness_m);
        for (uint32_t k = 0; k < desc.worn_over_count; ++k) {
            cloth.worn_over[k] = desc.worn_over[k].index;
            l.own.cell_m = std::max(l.own.cell_m, layer_cell_m(*world->cloths[desc.worn_over[k].index].asset,
                                                               desc.layer_thickness_m));
        }
        cloth.worn_over_count = desc.worn_over_count;
        cloth.layer = layer;
        build_mesh_edges(asset, l.edge_first, l.edge_other, l.own.slot_bucket);
    }
    place_at_start(*world->kernels, cloth);
    cloth.health.start_extent_m = start_extent_m(asset);
    world->particles_used += asset.slot_count;
    world->last_good_used += last_good;
    world->self_collision_used += self_slots;
    world->self_collision_triangles_used += self_triangles;
    world->layer_particles_used += layer_slots;
    world->layer_triangles_used += layer_triangles;
    world->triangle_lanes_used += tangent_lanes;
    world->render_vertices_used += render_vertices;
    world->constraints_used += asset.lane_count;
    world->coarse_nodes_used += asset.coarse_slot_count;
    world->cloth_slots = std::max(world->cloth_slots, index + 1);
    world->cloths_live += 1;
    *out_cloth = {index, generation};
    return {};
}

Result remove_cloth(World* world, ClothId id) {
    if (Result r = find_cloth(world, id); !r.ok()) return r;
    for (uint32_t i = 0; i < world->cloth_slots; ++i) {
        const ClothInstance& c = world->cloths[i];
        for (uint32_t k = 0; c.slot.live && k < c.worn_over_count; ++k)
            if (c.worn_over[k] == id.index)
                return make_error(ErrorCode::invalid_argument, "cloth %u is worn over cloth %u: remove that one first",
                                  id.index, i);
    }
    ClothInstance& cloth = world->cloths[id.index];
    const ClothAsset& asset = *cloth.asset;
    world->particles_used -= asset.slot_count;
    if (cloth.worn_over_count > 0) {
        world->layer_particles_used -= asset.slot_count + cloth.layers.inner_capacity;
        world->layer_triangles_used -= asset.triangle_count;
    }
    world->constraints_used -= asset.lane_count;
    world->coarse_nodes_used -= asset.coarse_slot_count;
    if (world->desc.tangents) world->triangle_lanes_used -= triangle_lanes(asset);
    if (world->desc.render_meshes) world->render_vertices_used -= asset.render.vertex_count;
    if (cloth.last_good.x != nullptr) world->last_good_used -= asset.slot_count;
    if (cloth.self_collision.hash.cell_start != nullptr) {
        world->self_collision_used -= asset.slot_count;
        world->self_collision_triangles_used -= asset.triangle_count;
    }
    world->cloths_live -= 1;
    const InstanceSlot slot = cloth.slot;
    cloth = ClothInstance();  // its regions (arrays, skin constraints) are free with it
    cloth.slot = slot;
    release_slot(world->cloths, id.index, &world->cloth_slots);
    return {};
}

Result add_collider(World* world, const ColliderDesc& desc, ColliderId* out_collider) {
    if (world == nullptr || out_collider == nullptr)
        return make_error(ErrorCode::invalid_argument, "world or out_collider is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (Result r = check_collider(desc); !r.ok()) return r;
    const uint32_t index = free_slot(world->colliders, world->collider_slots, world->desc.max_colliders);
    if (index == world->desc.max_colliders)
        return make_error(ErrorCode::capacity_exceeded, "world holds at most %u colliders",
                          world->desc.max_colliders);
    ColliderState& c = world->colliders[index];
    c.slot.live = true;
    c.desc = desc;
    c.motion_m = {};
    c.motion_p1_m = {};
    wake_cloths_near(*world, desc);
    world->collider_slots = std::max(world->collider_slots, index + 1);
    world->colliders_live += 1;
    *out_collider = {index, c.slot.generation};
    return {};
}

Result remove_collider(World* world, ColliderId id) {
    if (Result r = find_collider(world, id); !r.ok()) return r;
    wake_cloths_near(*world, world->colliders[id.index].desc);
    world->colliders[id.index].desc = {};
    world->colliders[id.index].motion_m = {};
    world->colliders[id.index].motion_p1_m = {};
    world->colliders_live -= 1;
    release_slot(world->colliders, id.index, &world->collider_slots);
    return {};
}

Result set_collider(World* world, ColliderId collider, const ColliderDesc& desc) {
    if (Result r = find_collider(world, collider); !r.ok()) return r;
    if (Result r = check_collider(desc); !r.ok()) return r;
    ColliderState& c = world->colliders[collider.index];
    if (!same_collider(c.desc, desc)) {  // where it was and where it goes
        wake_cloths_near(*world, c.desc);
        wake_cloths_near(*world, desc);
    }
    c.motion_m.x += desc.p0.x - c.desc.p0.x;
    c.motion_m.y += desc.p0.y - c.desc.p0.y;
    c.motion_m.z += desc.p0.z - c.desc.p0.z;
    // p1 is a capsule's or cylinder's other end; on other shapes (or a changed shape) it is no point that moved.
    if (desc.shape == c.desc.shape && (desc.shape == ColliderShape::capsule || desc.shape == ColliderShape::cylinder)) {
        c.motion_p1_m.x += desc.p1.x - c.desc.p1.x;
        c.motion_p1_m.y += desc.p1.y - c.desc.p1.y;
        c.motion_p1_m.z += desc.p1.z - c.desc.p1.z;
    }
    c.desc = desc;
    return {};
}

Result teleport_collider(World* world, ColliderId collider, const ColliderDesc& desc) {
    if (Result r = set_collider(world, collider, desc); !r.ok()) return r;
    wake_cloths_near(*world, desc);  // even in place: its motion is dropped
    world->colliders[collider.index].motion_m = {};
    world->colliders[collider.index].motion_p1_m = {};
    return {};
}

Result set_wind(World* world, Vec3 velocity_m_s) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (!world->desc.wind)
        return make_error(ErrorCode::invalid_argument, "world was created without the wind feature");
    if (!is_finite(velocity_m_s)) return make_error(ErrorCode::non_finite, "wind velocity is not finite");
    const float speed2 = velocity_m_s.x * velocity_m_s.x + velocity_m_s.y * velocity_m_s.y +
                         velocity_m_s.z * velocity_m_s.z;
    if (speed2 > 1000.0f * 1000.0f)
        return make_error(ErrorCode::out_of_range, "wind faster than 1000 m/s");
    if (!same_vec3(world->wind_m_s, velocity_m_s)) wake_every_cloth(*world);
    world->wind_m_s = velocity_m_s;
    return {};
}

Result set_gravity(World* world, Vec3 gravity_m_s2) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (!is_finite(gravity_m_s2)) return make_error(ErrorCode::non_finite, "gravity is not finite");
    const float g2 = gravity_m_s2.x * gravity_m_s2.x + gravity_m_s2.y * gravity_m_s2.y +
                     gravity_m_s2.z * gravity_m_s2.z;
    if (g2 > 1e6f) return make_error(ErrorCode::out_of_range, "gravity above 1000 m/s^2");
    if (!same_vec3(world->gravity_m_s2, gravity_m_s2)) wake_every_cloth(*world);
    world->gravity_m_s2 = gravity_m_s2;
    return {};
}

Result set_cloth_settings(World* world, ClothId cloth, const ClothDesc& desc) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (Result r = check_cloth_settings(desc); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (desc.asset != c.asset)
        return make_error(ErrorCode::invalid_argument, "a cloth's asset cannot change");
    // The last good copy's arrays are carved at add_cloth: a cloth has them, or cannot take the policy.
    if ((desc.recovery == RecoveryPolicy::last_good_state) != (c.settings.recovery == RecoveryPolicy::last_good_state))
        return make_error(ErrorCode::invalid_argument,
                          "RecoveryPolicy::last_good_state is chosen at add_cloth (its copy's memory), not changed after");
    if (desc.self_collision != c.settings.self_collision)
        return make_error(ErrorCode::invalid_argument,
                          "self_collision is chosen at add_cloth (its hash's memory), not changed after");
    bool same_layers = desc.worn_over_count == c.settings.worn_over_count;
    for (uint32_t k = 0; same_layers && k < desc.worn_over_count; ++k)
        same_layers = desc.worn_over[k].index == c.settings.worn_over[k].index &&
                      desc.worn_over[k].generation == c.settings.worn_over[k].generation;
    if (!same_layers)
        return make_error(ErrorCode::invalid_argument,
                          "worn_over is chosen at add_cloth (its stage and memory), not changed after");
    if (desc.contact_tethers && !c.settings.contact_tethers) clear_contact_anchors(c);  // none are current
    wake(c);
    c.settings = desc;
    c.split = resolve_split(desc, *c.asset);
    return {};
}

Result cloth_solver_split(const World* world, ClothId cloth, SolverSplit* out) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    *out = world->cloths[cloth.index].split;
    return {};
}

namespace {

// Copies three slot arrays of a cloth out in the caller's particle order.
Result read_by_particle(const ClothInstance& c, const float* x, const float* y, const float* z, Vec3* out, uint32_t count) {
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (count != c.asset->particle_count)
        return make_error(ErrorCode::out_of_range, "count %u, cloth has %u particles", count,
                          c.asset->particle_count);
    const uint32_t* slot = c.asset->slot_of_particle;
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t s = slot[i];
        out[i] = {x[s], y[s], z[s]};
    }
    return {};
}

}  // namespace

Result read_positions(const World* world, ClothId cloth, Vec3* out, uint32_t count) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    const Particles& p = world->cloths[cloth.index].particles;
    return read_by_particle(world->cloths[cloth.index], p.x, p.y, p.z, out, count);
}

Result read_normals(const World* world, ClothId cloth, Vec3* out, uint32_t count) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    const Particles& p = world->cloths[cloth.index].particles;
    if (p.normal_x == nullptr)
        return make_error(ErrorCode::invalid_argument, "world was created without the normals feature");
    return read_by_particle(world->cloths[cloth.index], p.normal_x, p.normal_y, p.normal_z, out, count);
}

Result read_render_mesh(const World* world, ClothId cloth, Vec3* positions, Vec3* normals, uint32_t count) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (!world->desc.render_meshes)
        return make_error(ErrorCode::invalid_argument, "world was created without the render_meshes feature");
    const ClothInstance& c = world->cloths[cloth.index];
    const RenderOutput& r = c.render;
    if (r.x == nullptr) return make_error(ErrorCode::invalid_argument, "the cloth's asset has no render mesh");
    if (positions == nullptr) return make_error(ErrorCode::invalid_argument, "positions is null");
    if (count != c.asset->render.vertex_count)
        return make_error(ErrorCode::out_of_range, "count %u, render mesh has %u vertices", count, c.asset->render.vertex_count);
    for (uint32_t v = 0; v < count; ++v) positions[v] = {r.x[v], r.y[v], r.z[v]};
    if (normals != nullptr)
        for (uint32_t v = 0; v < count; ++v) normals[v] = {r.normal_x[v], r.normal_y[v], r.normal_z[v]};
    return {};
}

Result read_tangents(const World* world, ClothId cloth, Vec4* out, uint32_t count) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    const ClothInstance& c = world->cloths[cloth.index];
    const Particles& p = c.particles;
    if (p.tangent_x == nullptr)
        return make_error(ErrorCode::invalid_argument, "world was created without the tangents feature");
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (count != c.asset->particle_count)
        return make_error(ErrorCode::out_of_range, "count %u, cloth has %u particles", count, c.asset->particle_count);
    const uint32_t* slot = c.asset->slot_of_particle;
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t s = slot[i];
        out[i] = {p.tangent_x[s], p.tangent_y[s], p.tangent_z[s], p.tangent_w[s]};
    }
    return {};
}

Result set_particle(World* world, ClothId cloth, uint32_t particle, Vec3 position_m, float inverse_mass_per_kg) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (particle >= c.asset->particle_count)
        return make_error(ErrorCode::out_of_range, "particle %u of %u", particle, c.asset->particle_count);
    if (!is_finite(position_m) || !std::isfinite(inverse_mass_per_kg))
        return make_error(ErrorCode::non_finite, "particle position or inverse mass is not finite");
    if (inverse_mass_per_kg < 0.0f)
        return make_error(ErrorCode::out_of_range, "inverse mass is negative");
    const uint32_t s = c.asset->slot_of_particle[particle];
    Particles& p = c.particles;
    wake(c);  // the last good copy stays: a particle put somewhere absurd is what it undoes
    p.x[s] = p.previous_x[s] = position_m.x;
    p.y[s] = p.previous_y[s] = position_m.y;
    p.z[s] = p.previous_z[s] = position_m.z;
    if (s < lattice_plane_slots(*c.asset))
        c.held_plane_slots += uint32_t(!(inverse_mass_per_kg > 0.0f)) - uint32_t(!(p.inverse_mass[s] > 0.0f));
    p.inverse_mass[s] = inverse_mass_per_kg;
    return {};
}

Result reset_cloth(World* world, ClothId cloth) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    wake(world->cloths[cloth.index]);
    forget_last_good(world->cloths[cloth.index]);
    place_at_start(*world->kernels, world->cloths[cloth.index]);
    world->cloths[cloth.index].has_root = false;  // the next set_cloth_root starts afresh
    return {};
}

namespace {

Result check_root(const Transform& root) {
    const Quat& q = root.rotation;
    if (!is_finite(root.translation_m) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z) ||
        !std::isfinite(q.w))
        return make_error(ErrorCode::non_finite, "root transform is not finite");
    const Vec3& t = root.translation_m;
    if (std::fabs(t.x) > 1e6f || std::fabs(t.y) > 1e6f || std::fabs(t.z) > 1e6f)
        return make_error(ErrorCode::out_of_range, "root lies beyond 1e6 m");
    const float norm2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    if (!(std::fabs(norm2 - 1.0f) < 1e-3f))
        return make_error(ErrorCode::out_of_range, "root rotation is not a unit quaternion (|q|^2 = %g)", double(norm2));
    return {};
}

}  // namespace

Result set_cloth_root(World* world, ClothId cloth, const Transform& root) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (Result r = check_root(root); !r.ok()) return r;
    ClothInstance& c = world->cloths[cloth.index];
    if (c.has_root && !same_transform(c.root, root)) wake(c);
    c.root = root;
    if (!c.has_root) c.previous_root = root;  // the first root only says where the root is
    c.has_root = true;
    return {};
}

Result teleport_cloth(World* world, ClothId cloth, const Transform& root, bool drop_velocity) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (Result r = check_root(root); !r.ok()) return r;
    wake(world->cloths[cloth.index]);
    forget_last_good(world->cloths[cloth.index]);
    jump_to_root(world->cloths[cloth.index], root, drop_velocity);
    return {};
}

Result cloth_is_sleeping(const World* world, ClothId cloth, bool* out_sleeping) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (out_sleeping == nullptr) return make_error(ErrorCode::invalid_argument, "out_sleeping is null");
    *out_sleeping = world->cloths[cloth.index].sleeping;
    return {};
}

Result wake_cloth(World* world, ClothId cloth) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    wake(world->cloths[cloth.index]);
    return {};
}

Result cloth_health(const World* world, ClothId cloth, ClothHealth* out) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    const HealthState& h = world->cloths[cloth.index].health;
    *out = {h.problems, h.recovered, h.energy_J_per_kg, h.recoveries};
    return {};
}

float start_extent_m(const ClothAsset& a) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < a.slot_count; ++i) {
        if (!(a.inverse_mass[i] > 0.0f)) continue;
        const float p[3] = {a.start_x[i], a.start_y[i], a.start_z[i]};
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    if (!(lo[0] <= hi[0])) return 0.0f;  // nothing movable
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

Result set_frame_budget_us(World* world, float budget_us) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (!std::isfinite(budget_us)) return make_error(ErrorCode::non_finite, "frame budget is not finite");
    if (budget_us < 0.0f) return make_error(ErrorCode::out_of_range, "frame budget %g us is negative", double(budget_us));
    world->frame_budget_us = budget_us;
    if (budget_us == 0.0f)  // off: every cloth runs its own split again from now on
        for (uint32_t i = 0; i < world->cloth_slots; ++i) {
            ClothInstance& c = world->cloths[i];
            if (c.slot.live) c.split = resolve_split(c.settings, *c.asset);
        }
    return {};
}

Result set_cloth_priority(World* world, ClothId cloth, float priority) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (!std::isfinite(priority)) return make_error(ErrorCode::non_finite, "cloth priority is not finite");
    world->cloths[cloth.index].priority = priority;
    return {};
}

// --- sleeping cloths ----------------------------------------------------------------------------

void wake(ClothInstance& cloth) {
    if (cloth.sleeping) {  // it wakes at rest: the previous positions are the positions
        Particles& p = cloth.particles;
        const size_t bytes = sizeof(float) * size_t(p.slot_count);
        std::memcpy(p.previous_x, p.x, bytes);
        std::memcpy(p.previous_y, p.y, bytes);
        std::memcpy(p.previous_z, p.z, bytes);
        cloth.sleeping = false;
        cloth.bounds_known = false;  // the next collision pass finds it again
    }
    cloth.calm_steps = 0;
}

void wake_every_cloth(World& world) {
    for (uint32_t i = 0; i < world.cloth_slots; ++i)
        if (world.cloths[i].slot.live) wake(world.cloths[i]);
}

ColliderKernelArgs collider_shape_args(const ColliderDesc& desc) {
    ColliderKernelArgs args{};
    args.shape = static_cast<uint8_t>(desc.shape);
    args.p0 = desc.p0;
    args.p1 = desc.shape == ColliderShape::sphere ? desc.p0 : desc.p1;
    args.normal = desc.p1;
    args.radius = desc.shape == ColliderShape::plane ? desc.inflation_m : desc.radius_m + desc.inflation_m;
    args.friction = desc.friction;
    return args;
}

void wake_cloths_near(World& world, const ColliderDesc& collider) {
    const ColliderKernelArgs args = collider_shape_args(collider);
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        ClothInstance& c = world.cloths[i];
        // A cloth whose box is not known yet (no collision pass ran) wakes: more often, never less.
        if (c.slot.live && (!c.bounds_known || collider_may_touch(c.bounds, args))) wake(c);
    }
}

void wake_cloths_of_body(World& world, uint32_t body) {
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        ClothInstance& c = world.cloths[i];
        if (!c.slot.live) continue;
        if (c.own_body == ~0u || c.own_body == body || c.skin_body == body || c.attached_body == body) wake(c);
    }
}

bool same_vec3(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

bool same_transform(const Transform& a, const Transform& b) {
    return same_vec3(a.translation_m, b.translation_m) && a.rotation.x == b.rotation.x &&
           a.rotation.y == b.rotation.y && a.rotation.z == b.rotation.z && a.rotation.w == b.rotation.w;
}

bool same_collider(const ColliderDesc& a, const ColliderDesc& b) {
    return a.shape == b.shape && same_vec3(a.p0, b.p0) && same_vec3(a.p1, b.p1) && a.radius_m == b.radius_m &&
           a.inflation_m == b.inflation_m && a.friction == b.friction;
}

Result view_cloth(const World* world, ClothId cloth, ClothView* out) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    const ClothInstance& c = world->cloths[cloth.index];
    out->asset = c.asset;
    out->x = c.particles.x;
    out->y = c.particles.y;
    out->z = c.particles.z;
    out->previous_x = c.particles.previous_x;
    out->previous_y = c.particles.previous_y;
    out->previous_z = c.particles.previous_z;
    out->inverse_mass = c.particles.inverse_mass;
    out->normal_x = c.particles.normal_x;
    out->normal_y = c.particles.normal_y;
    out->normal_z = c.particles.normal_z;
    out->last_substep_s = c.previous_substep_s;
    return {};
}

WorldStats world_stats(const World* world) { return world != nullptr ? world->stats : WorldStats{}; }

Result set_profiling(World* world, bool on) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    world->profiling = on;
    return {};
}

WorldUsage world_usage(const World* world) {
    WorldUsage u;
    if (world == nullptr) return u;
    u.cloths = world->cloths_live, u.bodies = world->bodies_live, u.colliders = world->colliders_live;
    u.particle_slots = world->particles_used, u.constraint_lanes = world->constraints_used;
    u.coarse_nodes = world->coarse_nodes_used;
    u.body_vertices = world->body_vertices_used, u.body_triangles = world->body_triangles_used;
    for (uint32_t i = 0; i < world->cloth_slots; ++i)
        if (world->cloths[i].slot.live) {
            u.instance_bytes += world->cloths[i].slot.memory.end - world->cloths[i].slot.memory.begin;
            u.skin_bytes += world->cloths[i].skin_memory.end - world->cloths[i].skin_memory.begin;
        }
    for (uint32_t i = 0; i < world->body_slots; ++i)
        if (world->bodies[i].slot.live) u.instance_bytes += world->bodies[i].slot.memory.end - world->bodies[i].slot.memory.begin;
    return u;
}

SimdPath world_simd_path(const World* world) {
    return world != nullptr && world->kernels != nullptr ? world->kernels->path : SimdPath::scalar;
}

}  // namespace weft
