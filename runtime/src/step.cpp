// One step of the world: the seed's algorithm (section 2.3), per cloth, per substep.
//
//   1. external forces: gravity and damping (folded into Verlet), wind drag and lift (eq. 2-4)
//   2. Verlet integration
//   3. spring correction: a) `coarse_iterations` sweeps of the coarse level (if any; with contact
//      tethers, which the end of each step re-anchors), b) `iterations` sweeps over
//      every constraint batch, c) the tethers once (measured: tethers after every sweep cost 2x the
//      pass for a smaller max strain, docs/solver.md), d) a cloth's skin constraints (max distance,
//      backstop; weft/attachments.h)
//   4. collision test and response against the inflated colliders, then the bodies' offset hulls
//      (section 4.2; a body the game moved is refitted once at the start of the step; a
//      skin_constraints body skips both for the cloths its skin constraints bind)
//   5. after the last substep, the render output (the normals feature): vertex normals
// 3a runs before 2 on the coarse nodes' own Verlet prediction, so that its correction rides along
// in the integration pass (one trip through the particle arrays instead of two).
//
// Which of these passes exist is decided by what the world and the cloth have (no wind feature,
// no wind pass; no colliders, no collision pass; no tethers, no tether pass), not per particle.
// Nothing here allocates, throws, locks or reads global state.
#include <chrono>
#include <cmath>
#include <cstring>
#include <utility>

#include "aerodynamics/wind.h"
#include "collide/colliders.h"
#include "constraints/attachments.h"
#include "constraints/contact_tethers.h"
#include "constraints/skin.h"
#include "world_internal.h"

namespace weft {
namespace {

// Times one pass into WorldStats when the world was created with `profile`.
class PassTimer {
public:
    PassTimer(World& world, Pass pass) : world_(world), pass_(pass) {
        if (world_.desc.profile) start_ = std::chrono::steady_clock::now();
    }
    ~PassTimer() {
        if (!world_.desc.profile) return;
        const auto elapsed = std::chrono::steady_clock::now() - start_;
        world_.stats.pass_ns[static_cast<int>(pass_)] +=
            uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count());
    }

private:
    World& world_;
    Pass pass_;
    std::chrono::steady_clock::time_point start_{};
};

void apply_external_forces(World& world, ClothInstance& cloth, float h) {
    if (!world.desc.wind) return;  // gravity and damping are applied inside Verlet
    PassTimer timer(world, Pass::wind);
    const WindArgs args{world.wind_m_s, world.desc.air_density_kg_m3, cloth.settings.drag_coefficient,
                        cloth.settings.lift_coefficient, cloth.previous_substep_s, h};
    world.kernels->apply_wind(cloth.particles, *cloth.asset, args);
}

IntegrateArgs integrate_args(const World& world, const ClothInstance& cloth, float h) {
    // Time-corrected Verlet: the implied velocity (x - x_prev) / h_prev carried over h. The first
    // step starts from rest (x_prev = x): x1 = x0 + a h^2 / 2 is the exact start, after which
    // Verlet is exact for a constant acceleration (a free fall matches x0 + g t^2 / 2; test).
    const bool first = !(cloth.previous_substep_s > 0.0f);
    const float ratio = first ? 1.0f : h / cloth.previous_substep_s;
    return {(first ? 0.5f : 1.0f) * h * h, ratio * std::exp(-cloth.settings.damping_per_s * h), world.gravity_m_s2,
            world.desc.wind, cloth.held_plane_slots == 0};
}

bool has_coarse_level(const ClothInstance& cloth) {
    return cloth.split.coarse_level;
}

bool has_contact_tethers(const ClothInstance& cloth) {
    return cloth.settings.contact_tethers && has_coarse_level(cloth);
}

// The coarse level's sweeps on its nodes' Verlet prediction; the integration pass then adds the
// resulting displacement to every particle.
void correct_coarse_level(World& world, ClothInstance& cloth, float h) {
    if (!has_coarse_level(cloth)) return;
    PassTimer timer(world, Pass::coarse);
    CoarseState state = cloth.coarse;
    if (!has_contact_tethers(cloth)) state.anchor = nullptr;  // the solve then skips them
    world.kernels->solve_coarse_level(cloth.particles, integrate_args(world, cloth, h), *cloth.asset, state,
                                      cloth.split.relaxation, cloth.split.coarse_iterations);
}

void integrate(World& world, ClothInstance& cloth, float h) {
    PassTimer timer(world, Pass::integrate);
    Particles& p = cloth.particles;
    world.kernels->integrate(p, integrate_args(world, cloth, h), *cloth.asset,
                             has_coarse_level(cloth) ? &cloth.coarse : nullptr);
    // The pass wrote x(t+h) over x(t-h): x(t) is now the previous position.
    std::swap(p.x, p.previous_x);
    std::swap(p.y, p.previous_y);
    std::swap(p.z, p.previous_z);
}

void correct_springs(World& world, ClothInstance& cloth, float h) {
    PassTimer timer(world, Pass::constraints);
    const ClothAsset& asset = *cloth.asset;
    DistanceArgs args[kConstraintKindCount];
    for (uint32_t kind = 0; kind < kConstraintKindCount; ++kind)
        args[kind] = {cloth.settings.compliance_m_per_n[kind] / (h * h), cloth.split.relaxation};
    const uint32_t mode = static_cast<uint32_t>(cloth.settings.projection);
    const auto project_run = world.kernels->project_run[mode];
    const auto project_indexed = world.kernels->project_indexed[mode];
    const PointSet points = points_of(cloth.particles);
    const ConstraintLanes springs = spring_lanes(asset);
    for (uint32_t b = 0; b < asset.batch_count; ++b) {
        const ConstraintBatch& batch = asset.batches[b];
        const DistanceArgs& a = args[static_cast<uint32_t>(batch.kind)];
        if (batch.layout == BatchLayout::run) {
            project_run(points, springs, batch, a);
        } else {
            project_indexed(points, springs, batch, a);
        }
    }
}

void apply_tethers(World& world, ClothInstance& cloth) {
    if (!cloth.split.tethers) return;
    PassTimer timer(world, Pass::tethers);
    const ClothAsset& asset = *cloth.asset;
    for (uint32_t b = 0; b < asset.tether_batch_count; ++b)
        world.kernels->project_tethers(cloth.particles, asset, asset.tether_batches[b],
                                       cloth.settings.tether_slack);
}

void collide(World& world, ClothInstance& cloth, uint32_t substeps) {
    if (world.collider_count == 0) return;
    PassTimer timer(world, Pass::collide);
    const float share = 1.0f / float(substeps);
    // A collider whose box misses the cloth's is skipped (a skirt's thigh capsules cost its
    // character's tee nothing).
    ParticleBounds box;
    world.kernels->particle_bounds(cloth.particles, &box);
    for (uint32_t i = 0; i < world.collider_count; ++i) {
        const ColliderState& c = world.colliders[i];
        ColliderKernelArgs args{};
        args.shape = static_cast<uint8_t>(c.desc.shape);
        args.p0 = c.desc.p0;
        args.p1 = c.desc.shape == ColliderShape::sphere ? c.desc.p0 : c.desc.p1;
        args.normal = c.desc.p1;
        args.radius = c.desc.shape == ColliderShape::plane ? c.desc.inflation_m
                                                           : c.desc.radius_m + c.desc.inflation_m;
        args.friction = c.desc.friction;
        args.motion = {c.motion_m.x * share, c.motion_m.y * share, c.motion_m.z * share};
        if (!collider_may_touch(box, args)) {
            world.stats.colliders_skipped += 1;
            continue;
        }
        world.kernels->collide(cloth.particles, args);
    }
}

// After the step's last collision pass: which coarse nodes hold the cloth (in contact with a
// collider that has friction, or pinned), and each other node's anchor among them, for the next
// step's coarse solves (constraints/contact_tethers.h). Timed with the coarse level.
void find_contact_anchors(World& world, ClothInstance& cloth) {
    if (!has_contact_tethers(cloth)) return;
    PassTimer timer(world, Pass::coarse);
    const ClothAsset& asset = *cloth.asset;
    begin_holding_nodes(cloth.particles, asset, cloth.coarse);
    for (uint32_t i = 0; i < world.collider_count; ++i)
        if (world.colliders[i].desc.friction > 0.0f)
            mark_contact_nodes(cloth.particles, asset, cloth.coarse, world.colliders[i].desc);
    update_contact_anchors(asset, cloth.coarse, (world.stats.steps & 1u) == 0);
}

// Bodies the game moved since the last step: refit Weft's hierarchy (or, for the plain reference
// pass, BodyDesc::reference_queries, Embree's BVH) over the new offset hull (computed by
// set_body_vertices). A body that stopped gets its previous hull equal to its hull again, so the
// surface velocity friction sees is zero; a body that stays still costs nothing.
void move_bodies(World& world) {
    if (world.body_count == 0) return;
    PassTimer timer(world, Pass::body);
    const auto start = world.desc.profile ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    world.stats.body_refits = 0;
    world.stats.body_embree_refits = 0;
    for (uint32_t i = 0; i < world.body_count; ++i) {
        BodyState& body = world.bodies[i];
        // A skin_constraints body refits its hierarchy only when a search needs it (an unbound
        // cloth in collide_bodies, query_body): its bound cloths never search.
        const bool lazy = body.desc.collision == BodyCollision::skin_constraints && !body.desc.reference_queries;
        if (body.refit_pending) {
            if (body.desc.reference_queries) {
                refit_embree(world, body);
            } else if (lazy) {
                body.hierarchy_stale = true;
            } else {
                refit_body_hierarchy(body, world.kernels->path);
            }
            body.refit_pending = false;
            body.moving = true;
            world.stats.body_refits += 1;
        } else if (body.moving) {
            for (uint32_t v = 0; v < body.vertex_count; ++v) body.hull[4 * v + 3] = 0.0f;  // no motion
            std::memcpy(body.previous_hull, body.hull, sizeof(float) * 4 * size_t(body.vertex_count));
            if (lazy)
                body.hierarchy_stale = true;
            else if (!body.desc.reference_queries)
                refit_body_hierarchy(body, world.kernels->path);  // boxes no longer widened by the motion
            body.moving = false;
        }
    }
    if (world.desc.profile)
        world.stats.body_refit_ns += uint64_t(
            std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
}

// Skin constraints of a cloth bound to a body (bind_skin_constraints); timed as body collision,
// which they replace under BodyCollision::skin_constraints. Once a step, each constraint's point
// on the body's previous and current hull and its normal; every substep, the projection.
void find_skin_frames(World& world, ClothInstance& cloth) {
    if (cloth.skin_body == ~0u) return;
    PassTimer timer(world, Pass::body);
    const BodyState& body = world.bodies[cloth.skin_body];
    // The last step's P is P on this step's previous hull (a byte copy of the hull it used).
    SkinState& s = cloth.skin_state;
    if (cloth.skin_points_current)
        for (int i = 0; i < 3; ++i) std::swap(s.previous_point[i], s.point[i]);
    const SkinFrameArgs args{body.hull, cloth.skin_points_current ? nullptr : body.previous_hull, body.normals};
    world.kernels->skin_frames(s, args);
    cloth.skin_points_current = true;
}

void project_skin_constraints(World& world, ClothInstance& cloth, uint32_t substep, uint32_t substeps) {
    if (cloth.skin_body == ~0u) return;
    PassTimer timer(world, Pass::body);
    world.kernels->project_skin(cloth.particles, cloth.skin_state, float(substep + 1) / float(substeps));
}

void collide_bodies(World& world, ClothInstance& cloth, uint32_t substep, uint32_t substeps) {
    if (world.body_count == 0) return;
    PassTimer timer(world, Pass::body);
    BodyPassCounts counts;
    const uint32_t slots = cloth.particles.slot_count;
    for (uint32_t i = 0; i < world.body_count; ++i) {
        BodyState& body = world.bodies[i];
        if (body.desc.collision == BodyCollision::skin_constraints && cloth.skin_body == i)
            continue;  // the skin constraints' backstop is this cloth's collision with the body
        refresh_body_hierarchy(body, world.kernels->path);
        ContactPlanes planes{};
        if (body.plane_index != ~0u)  // a cached_planes body (add_body gave it its place)
            planes = contact_planes_in(cloth.contact_planes + size_t(body.plane_index) * kContactPlaneArrays * slots,
                                       slots);
        collide_body(cloth.particles, cloth.body_order, body, substep, substeps,
                     body.plane_index != ~0u ? &planes : nullptr, world.kernels->path, counts);
    }
    world.stats.body_contacts += counts.contacts;
    world.stats.body_rays += counts.rays;
    world.stats.body_queried += counts.queried;
}

void find_vertex_normals(World& world, ClothInstance& cloth) {
    if (!world.desc.normals) return;
    PassTimer timer(world, Pass::normals);
    world.kernels->vertex_normals(cloth.particles, *cloth.asset);
}

void step_cloth(World& world, ClothInstance& cloth, float dt) {
    const float h = dt / float(cloth.split.substeps);
    find_skin_frames(world, cloth);                            // the skinned frames of 3d
    for (uint32_t substep = 0; substep < cloth.split.substeps; ++substep) {
        if (cloth.attached_body != ~0u)                        // 0. attached particles ride the body
            follow_attachments(world.bodies[cloth.attached_body], *cloth.asset, cloth.particles,
                               float(substep + 1) / float(cloth.split.substeps));
        apply_external_forces(world, cloth, h);                // 1. F_ext: wind (gravity, damping in 2)
        correct_coarse_level(world, cloth, h);                 // 3a. coarse level (on predicted nodes)
        integrate(world, cloth, h);                            // 2. Verlet (+ the coarse correction)
        if (cloth.settings.tethers_before_sweeps)
            apply_tethers(world, cloth);                       //     (optional) tethers first
        for (uint32_t it = 0; it < cloth.split.iterations; ++it)
            correct_springs(world, cloth, h);                  // 3b. the springs, batch by batch
        apply_tethers(world, cloth);                           // 3c. the long-range attachments
        project_skin_constraints(world, cloth, substep,
                                 cloth.split.substeps);        // 3d. max distance and backstop
        collide(world, cloth, cloth.split.substeps);           // 4. collision response: colliders,
        collide_bodies(world, cloth, substep, cloth.split.substeps);  // then bodies
        cloth.previous_substep_s = h;
    }
    find_contact_anchors(world, cloth);
    find_vertex_normals(world, cloth);                         // 5. render output: vertex normals
}

uint64_t count_projections(const World& world, BatchLayout layout) {
    uint64_t lanes = 0;
    for (uint32_t i = 0; i < world.cloth_count; ++i) {
        const ClothInstance& c = world.cloths[i];
        const uint64_t sweeps = uint64_t(c.split.substeps) * c.split.iterations;
        const uint64_t on_runs = c.asset->constraints_on_runs;
        lanes += sweeps * (layout == BatchLayout::run ? on_runs : c.asset->total_constraints() - on_runs);
    }
    return lanes;
}

}  // namespace

Result step(World* world, float dt_s) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (std::isnan(dt_s) || std::isinf(dt_s)) return make_error(ErrorCode::non_finite, "dt is not finite");
    if (!(dt_s > 0.0f) || dt_s > 1.0f)
        return make_error(ErrorCode::out_of_range, "dt %g s outside (0, 1]", double(dt_s));
    world->stats.colliders_skipped = 0;
    world->stats.body_contacts = 0;
    world->stats.body_rays = 0;
    world->stats.body_queried = 0;
    move_bodies(*world);                                       // 0. the game's new body pose
    for (uint32_t i = 0; i < world->cloth_count; ++i) step_cloth(*world, world->cloths[i], dt_s);
    for (uint32_t i = 0; i < world->collider_count; ++i) world->colliders[i].motion_m = {};
    world->stats.steps += 1;
    world->stats.run_projections = count_projections(*world, BatchLayout::run);
    world->stats.indexed_projections = count_projections(*world, BatchLayout::indexed);
    return {};
}

}  // namespace weft
