// One step of the world: the seed's algorithm (section 2.3), per cloth, per substep.
//
//   0. at begin_step, with a frame budget: each cloth's split for this step (budget.cpp)
//   1. external forces: gravity and damping (folded into Verlet), wind drag and lift (eq. 2-4)
//   2. Verlet integration
//   3. spring correction: a) `coarse_iterations` sweeps of the coarse level (if any; with contact
//      tethers, which the end of each step re-anchors), b) `iterations` sweeps over
//      every constraint batch, c) the tethers once (measured: tethers after every sweep cost 2x the
//      pass for a smaller max strain, docs/solver.md), d) a cloth's skin constraints (max distance,
//      backstop; weft/attachments.h)
//   4. collision test and response: the cloth against itself (with ClothDesc::self_collision), against
//      the cloths it is worn over (ClothDesc::worn_over), the inflated colliders, then the bodies' offset hulls
//      (section 4.2; a body the game moved is refitted once at the start of the step; a
//      skin_constraints body skips both for the cloths its skin constraints bind)
//   5. after the last substep, the render output (the normals feature): vertex normals (and
//      tangents), then the render mesh driven by them
//   6. its health (non-finite, overstretched, an energy spike: cloth_health), and with a
//      ClothDesc::recovery policy, the recovery of an unhealthy cloth
//   7. with ClothDesc::sleep_speed_m_s, whether the cloth was calm: after kCalmStepsBeforeSleep
//      calm steps it sleeps, and its steps run nothing until something wakes it (world.cpp: wake)
// 3a runs before 2 on the coarse nodes' own Verlet prediction, so that its correction rides along
// in the integration pass (one trip through the particle arrays instead of two).
//
// Which of these passes exist is decided by what the world and the cloth have (no wind feature,
// no wind pass; no colliders, no collision pass; no tethers, no tether pass), not per particle.
// Nothing here allocates, throws, locks or reads global state.
//
// The step runs in stages of independent work items (weft/world.h, StepStage): the bodies (each
// moved body's refit), then the cloths (all of the above for one cloth, which writes only its own
// particles and counters and reads the bodies and colliders), then the cloths worn over those, layer
// by layer (they also read the stepped cloths they are worn over); end_step then adds the counters
// up in a fixed order. So any split of the items over threads gives the same bits.
#include <algorithm>
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

// Times one pass of one cloth (or body) into its own counter when the world was created with
// `profile`; end_step adds the counters into WorldStats.
class PassTimer {
public:
    PassTimer(const World& world, uint64_t& ns) : ns_(world.profiling ? &ns : nullptr) {
        if (ns_ != nullptr) start_ = std::chrono::steady_clock::now();
    }
    PassTimer(const World& world, ClothInstance& cloth, Pass pass)
        : PassTimer(world, cloth.counts.pass_ns[static_cast<int>(pass)]) {}
    ~PassTimer() {
        if (ns_ == nullptr) return;
        const auto elapsed = std::chrono::steady_clock::now() - start_;
        *ns_ += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count());
    }

private:
    uint64_t* ns_;
    std::chrono::steady_clock::time_point start_{};
};

void apply_external_forces(World& world, ClothInstance& cloth, float h) {
    if (!world.desc.wind) return;  // gravity and damping are applied inside Verlet
    PassTimer timer(world, cloth, Pass::wind);
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
    PassTimer timer(world, cloth, Pass::coarse);
    CoarseState state = cloth.coarse;
    if (!has_contact_tethers(cloth)) state.anchor = nullptr;  // the solve then skips them
    world.kernels->solve_coarse_level(cloth.particles, integrate_args(world, cloth, h), *cloth.asset, state,
                                      cloth.split.relaxation, cloth.split.coarse_iterations);
}

void integrate(World& world, ClothInstance& cloth, float h) {
    PassTimer timer(world, cloth, Pass::integrate);
    Particles& p = cloth.particles;
    world.kernels->integrate(p, integrate_args(world, cloth, h), *cloth.asset,
                             has_coarse_level(cloth) ? &cloth.coarse : nullptr);
    // The pass wrote x(t+h) over x(t-h): x(t) is now the previous position.
    std::swap(p.x, p.previous_x);
    std::swap(p.y, p.previous_y);
    std::swap(p.z, p.previous_z);
}

void correct_springs(World& world, ClothInstance& cloth, float h) {
    PassTimer timer(world, cloth, Pass::constraints);
    const ClothAsset& asset = *cloth.asset;
    DistanceArgs args[kConstraintKindCount];
    for (uint32_t kind = 0; kind < kConstraintKindCount; ++kind)
        args[kind] = {cloth.settings.compliance_m_per_n[kind] / (h * h), cloth.split.relaxation};
    const uint32_t mode = static_cast<uint32_t>(cloth.settings.projection);
    world.kernels->project_springs[mode](points_of(cloth.particles), spring_lanes(asset), asset.batches, asset.batch_count,
                                         args);
}

void apply_tethers(World& world, ClothInstance& cloth) {
    if (!cloth.split.tethers) return;
    PassTimer timer(world, cloth, Pass::tethers);
    const ClothAsset& asset = *cloth.asset;
    for (uint32_t b = 0; b < asset.tether_batch_count; ++b)
        world.kernels->project_tethers(cloth.particles, asset, asset.tether_batches[b],
                                       cloth.settings.tether_slack);
}

void collide(World& world, ClothInstance& cloth, uint32_t substep, uint32_t substeps) {
    if (world.colliders_live == 0) return;
    PassTimer timer(world, cloth, Pass::collide);
    const float share = 1.0f / float(substeps);
    // A moved collider stands where it was this far into the step, as the body's hull and the
    // carry do: the share of its motion still to come is taken off (none in the last substep).
    // A cloth whose root jumped was carried whole: its colliders stand at their end pose, still.
    const float to_come = cloth.root_jumped ? 0.0f : 1.0f - float(substep + 1) / float(substeps);
    // A collider whose box misses the cloth's is skipped (a skirt's thigh capsules cost its
    // character's tee nothing).
    ParticleBounds& box = cloth.bounds;  // kept: a moved collider wakes the sleeping cloths it meets
    world.kernels->particle_bounds(cloth.particles, &box);
    cloth.bounds_known = true;
    for (uint32_t i = 0; i < world.collider_slots; ++i) {
        const ColliderState& c = world.colliders[i];
        if (!c.slot.live) continue;
        ColliderKernelArgs args = collider_shape_args(c.desc);
        const bool axis = c.desc.shape == ColliderShape::capsule || c.desc.shape == ColliderShape::cylinder;
        if (to_come > 0.0f) {
            args.p0 = {args.p0.x - c.motion_m.x * to_come, args.p0.y - c.motion_m.y * to_come,
                       args.p0.z - c.motion_m.z * to_come};
            if (c.desc.shape == ColliderShape::sphere) args.p1 = args.p0;
            if (axis)
                args.p1 = {args.p1.x - c.motion_p1_m.x * to_come, args.p1.y - c.motion_p1_m.y * to_come,
                           args.p1.z - c.motion_p1_m.z * to_come};
        }
        // The collider's motion relative to the cloth's carry (character motion): the carry moved
        // the particles already, so friction drags them only by the rest.
        const Vec3 centre = axis ? Vec3{0.5f * (args.p0.x + args.p1.x), 0.5f * (args.p0.y + args.p1.y),
                                        0.5f * (args.p0.z + args.p1.z)}
                                 : args.p0;
        const Vec3 carried = carried_motion(cloth, centre);
        args.motion = {c.motion_m.x * share - carried.x, c.motion_m.y * share - carried.y,
                       c.motion_m.z * share - carried.z};
        if (cloth.root_jumped) args.motion = {};
        if (!collider_may_touch(box, args)) {
            cloth.counts.colliders_skipped += 1;
            continue;
        }
        world.kernels->collide(cloth.particles, args);
    }
}

// 4. The cloth against its own triangles (ClothDesc::self_collision; collide/self_collision.h),
// before the colliders and bodies, so that those have the last word.
void collide_with_itself(World& world, ClothInstance& cloth) {
    if (!cloth.settings.self_collision) return;
    PassTimer timer(world, cloth, Pass::self_collision);
    collide_self(cloth.particles, *cloth.asset, cloth.self_collision,
                 {cloth.settings.self_thickness_m, cloth.settings.self_friction}, cloth.counts.self);
}

// 4. The cloth against the cloths it is worn over (ClothDesc::worn_over; collide/layers.h). They
// stepped in an earlier stage: each is read where it was at this substep's end.
void collide_with_layers(World& world, ClothInstance& cloth, uint32_t substep, uint32_t substeps, float h) {
    if (cloth.worn_over_count == 0) return;
    PassTimer timer(world, cloth, Pass::layers);
    const LayerArgs args{cloth.settings.layer_thickness_m, cloth.settings.layer_friction, h};
    for (uint32_t k = 0; k < cloth.worn_over_count; ++k) {
        const ClothInstance& inner = world.cloths[cloth.worn_over[k]];
        // An inner cloth asleep did not move this step.
        const InnerLayer layer{&inner.particles, inner.asset, float(substeps - 1 - substep) * h,
                               inner.counts.skipped ? 0.0f : inner.previous_substep_s};
        collide_layer(cloth.particles, *cloth.asset, cloth.layers, layer, args, cloth.counts.layers);
    }
}

// After the step's last collision pass: which coarse nodes hold the cloth (in contact with a
// collider that has friction, or pinned), and each other node's anchor among them, for the next
// step's coarse solves (constraints/contact_tethers.h). Timed with the coarse level.
void find_contact_anchors(World& world, ClothInstance& cloth) {
    if (!has_contact_tethers(cloth)) return;
    PassTimer timer(world, cloth, Pass::coarse);
    const ClothAsset& asset = *cloth.asset;
    begin_holding_nodes(cloth.particles, asset, cloth.coarse);
    for (uint32_t i = 0; i < world.collider_slots; ++i)
        if (world.colliders[i].slot.live && world.colliders[i].desc.friction > 0.0f)
            mark_contact_nodes(cloth.particles, asset, cloth.coarse, world.colliders[i].desc);
    update_contact_anchors(asset, cloth.coarse, (world.stats.steps & 1u) == 0);
}

// Does `cloth` search `body`'s hull: every body, or its own (set_cloth_body), except the one its
// skin constraints bind under skin_constraints (their backstop is its collision with that body).
// A sleeping cloth searches none (a lazy body's hierarchy waits for a cloth that is awake).
bool searches(const ClothInstance& cloth, const BodyState& body, uint32_t index) {
    if (!body.slot.live || cloth.sleeping) return false;
    if (cloth.own_body != ~0u && cloth.own_body != index) return false;
    return !(body.desc.collision == BodyCollision::skin_constraints && cloth.skin_body == index);
}

bool searched_by_a_cloth(const World& world, uint32_t body) {
    for (uint32_t i = 0; i < world.cloth_slots; ++i)
        if (world.cloths[i].slot.live && searches(world.cloths[i], world.bodies[body], body)) return true;
    return false;
}

// The bodies stage, one body: if the game moved it since the last step, refit Weft's hierarchy
// over the new offset hull (computed by set_body_vertices; the plain reference pass's Embree BVH
// was refitted by begin_step). A body that stopped gets its previous hull equal to its hull again,
// so the surface velocity friction sees is zero; a body that stays still costs nothing. A
// skin_constraints body is refitted only when a cloth will search it (query_body refits on demand).
void move_body(World& world, uint32_t index) {
    BodyState& body = world.bodies[index];
    PassTimer timer(world, body.pass_ns);
    const auto start = world.profiling ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    const bool lazy = body.desc.collision == BodyCollision::skin_constraints && !body.reference_queries;
    if (body.refit_pending) {
        if (lazy) {
            body.hierarchy_stale = true;
        } else if (!body.reference_queries) {
            refit_body_hierarchy(body, world.kernels->path);
        }
        body.refit_pending = false;
        body.moving = true;
        body.refits += 1;
    } else if (body.moving) {
        for (uint32_t v = 0; v < body.vertex_count; ++v) body.hull[4 * v + 3] = 0.0f;  // no motion
        std::memcpy(body.previous_hull, body.hull, sizeof(float) * 4 * size_t(body.vertex_count));
        if (lazy)
            body.hierarchy_stale = true;
        else if (!body.reference_queries)
            refit_body_hierarchy(body, world.kernels->path);  // boxes no longer widened by the motion
        body.moving = false;
    }
    if (body.hierarchy_stale && searched_by_a_cloth(world, index)) refresh_body_hierarchy(body, world.kernels->path);
    if (world.profiling)
        body.refit_ns += uint64_t(
            std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
}

// Skin constraints of a cloth bound to a body (bind_skin_constraints); timed as body collision,
// which they replace under BodyCollision::skin_constraints. Once a step, each constraint's point
// on the body's previous and current hull and its normal; every substep, the projection.
void find_skin_frames(World& world, ClothInstance& cloth) {
    if (cloth.skin_body == ~0u) return;
    PassTimer timer(world, cloth, Pass::body);
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
    PassTimer timer(world, cloth, Pass::body);
    SkinProjectArgs args;
    args.t_start = float(substep) / float(substeps);
    args.t_end = float(substep + 1) / float(substeps);
    args.friction = world.bodies[cloth.skin_body].desc.friction;
    args.carried = cloth.carried;
    if (cloth.carried) {
        std::copy(cloth.carry_rotation, cloth.carry_rotation + 9, args.carry_rotation);
        args.carry_pivot = cloth.carry_pivot;
        args.carry_shift = cloth.carry_shift;
    }
    world.kernels->project_skin(cloth.particles, cloth.skin_state, args);
}

void collide_bodies(World& world, ClothInstance& cloth, uint32_t substep, uint32_t substeps) {
    if (world.bodies_live == 0) return;
    PassTimer timer(world, cloth, Pass::body);
    BodyPassCounts& counts = cloth.counts.body;
    const uint32_t slots = cloth.particles.slot_count;
    for (uint32_t i = 0; i < world.body_slots; ++i) {
        const BodyState& body = world.bodies[i];
        if (!searches(cloth, body, i)) continue;
        ContactPlanes planes{};
        if (body.plane_index != ~0u)  // a cached_planes body (add_body gave it its place)
            planes = contact_planes_in(cloth.contact_planes + size_t(body.plane_index) * kContactPlaneArrays * slots,
                                       slots);
        collide_body(cloth.particles, cloth.body_order, body, substep, substeps,
                     body.plane_index != ~0u ? &planes : nullptr, world.kernels->path, counts);
    }
}

void find_vertex_normals(World& world, ClothInstance& cloth) {
    if (!has_normals(world.desc)) return;
    {
        PassTimer timer(world, cloth, Pass::normals);
        if (world.desc.tangents)
            world.kernels->vertex_normals_tangents(cloth.particles, *cloth.asset);
        else
            world.kernels->vertex_normals(cloth.particles, *cloth.asset);
    }
    if (cloth.render.x != nullptr) {
        PassTimer timer(world, cloth, Pass::render_mesh);
        world.kernels->render_mesh(cloth.particles, *cloth.asset, cloth.render);
    }
}

// Whether every particle moved slower than `speed_m_s` over the last substep: |x - x_prev| / h,
// x_prev the position before it (a carry by the root moved both, so it is not counted).
bool calm(const Particles& p, float h, float speed_m_s) {
    const float reach = speed_m_s * h, limit = reach * reach;
    uint32_t fast = 0;  // counted, not branched on: the loop vectorises; NaN counts as fast
    for (uint32_t i = 0; i < p.slot_count; ++i) {
        const float dx = p.x[i] - p.previous_x[i], dy = p.y[i] - p.previous_y[i], dz = p.z[i] - p.previous_z[i];
        fast += uint32_t(!(dx * dx + dy * dy + dz * dz <= limit));
    }
    return fast == 0;
}

// Each step's share of a cloth's running energy baseline (an exponential mean over about 10 steps).
constexpr float kEnergyBaselineShare = 0.1f;

// The health pass at the end of a step, over the movable particles (pinned and padding slots are
// moved by the game or a body): one SIMD walk (health.h) for their box and the kinetic energy per
// kg over the last substep (h) as the mean of |v|^2 / 2: a particle's mass is not weighed in (a
// cooked cloth's particles nearly weigh the same), which saves a division a particle. A
// non-finite position makes the sum non-finite. Returns HealthProblem bits.
uint32_t find_health(const World& world, ClothInstance& cloth, float h) {
    HealthState& health = cloth.health;
    HealthSums sums;
    world.kernels->health_sums(cloth.particles, &sums);
    if (!(sums.movable > 0.0f)) return 0;  // nothing movable
    uint32_t problems = 0;
    const float energy = 0.5f * sums.squared_m2 / (h * h * sums.movable);
    health.energy_J_per_kg = energy;
    if (!std::isfinite(energy)) problems |= kNonFinite;
    const float ex = sums.hi.x - sums.lo.x, ey = sums.hi.y - sums.lo.y, ez = sums.hi.z - sums.lo.z;
    const float extent = std::sqrt(ex * ex + ey * ey + ez * ez);
    if (health.start_extent_m > 0.0f && !(extent <= kOverstretchRatio * health.start_extent_m))
        problems |= kOverstretched;
    if (energy > kEnergySpikeRatio * std::max(health.baseline_J_per_kg, kEnergyFloor_J_per_kg)) problems |= kEnergySpike;
    return problems;
}

// An unhealthy cloth's recovery (ClothDesc::recovery). The last good state falls back to the
// dressed pose while no copy is saved, and the dressed pose to the rest pose without a body binding.
void recover(World& world, ClothInstance& cloth) {
    const RecoveryPolicy policy = cloth.settings.recovery;
    const bool on_body = cloth.skin_body != ~0u || cloth.attached_body != ~0u;
    if (policy == RecoveryPolicy::last_good_state && cloth.last_good.saved) {
        restore_last_good(*world.kernels, cloth);
    } else if (policy != RecoveryPolicy::rest_pose && on_body) {
        place_on_body(world, cloth);
    } else {
        place_at_start(*world.kernels, cloth);
        cloth.has_root = false;  // as reset_cloth: the next set_cloth_root starts afresh
    }
    wake(cloth);  // its calm steps count afresh
}

// 6. After a step: the cloth's health, its recovery when its policy asks, and the running
// baseline and last good copy that healthy steps keep.
void check_health(World& world, ClothInstance& cloth, float h) {
    PassTimer timer(world, cloth, Pass::health);
    HealthState& health = cloth.health;
    health.problems = find_health(world, cloth, h);
    health.recovered = health.problems != 0 && cloth.settings.recovery != RecoveryPolicy::none;
    if (health.recovered) {
        recover(world, cloth);
        health.recoveries += 1;
        health.healthy_steps = 0;
        return;  // the baseline keeps its healthy value
    }
    if (std::isfinite(health.energy_J_per_kg))  // a lasting rise becomes the baseline: a spike is brief
        health.baseline_J_per_kg += kEnergyBaselineShare * (health.energy_J_per_kg - health.baseline_J_per_kg);
    if (health.problems != 0) {
        health.healthy_steps = 0;
        return;
    }
    health.healthy_steps += 1;
    if (cloth.last_good.x != nullptr && (!cloth.last_good.saved || health.healthy_steps % kLastGoodRefreshSteps == 0))
        save_last_good(cloth);
}

// After a step: counts the cloth's calm steps and puts it to sleep after kCalmStepsBeforeSleep of
// them, with its box found for the colliders that may wake it.
void count_calm_steps(World& world, ClothInstance& cloth, float h) {
    if (!(cloth.settings.sleep_speed_m_s > 0.0f)) return;
    cloth.calm_steps = calm(cloth.particles, h, cloth.settings.sleep_speed_m_s) ? cloth.calm_steps + 1 : 0;
    if (cloth.calm_steps < kCalmStepsBeforeSleep) return;
    cloth.sleeping = true;
    world.kernels->particle_bounds(cloth.particles, &cloth.bounds);
    cloth.bounds_known = true;
}

void step_cloth(World& world, ClothInstance& cloth, float dt) {
    cloth.counts.skipped = cloth.sleeping;
    cloth.health.recovered = false;
    if (cloth.sleeping) return;  // until something wakes it (world.cpp: wake)
    const float h = dt / float(cloth.split.substeps);
    find_skin_frames(world, cloth);                            // the skinned frames of 3d
    for (uint32_t substep = 0; substep < cloth.split.substeps; ++substep) {
        follow_root(cloth, dt, substep, cloth.split.substeps);  //    carried by its character's root
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
        collide_with_itself(world, cloth);                     // 4. collision response: itself,
        collide_with_layers(world, cloth, substep,
                            cloth.split.substeps, h);          //    the cloths it is worn over,
        collide(world, cloth, substep,
                cloth.split.substeps);                         //    colliders,
        collide_bodies(world, cloth, substep, cloth.split.substeps);  // then bodies
        cloth.previous_substep_s = h;
    }
    find_contact_anchors(world, cloth);
    find_vertex_normals(world, cloth);                         // 5. render output: vertex normals
    check_health(world, cloth, h);                             // 6. health, and recovery
    count_calm_steps(world, cloth, h);                         // 7. asleep when calm long enough
}

uint64_t count_projections(const World& world, BatchLayout layout) {
    uint64_t lanes = 0;
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        const ClothInstance& c = world.cloths[i];
        if (!c.slot.live || c.counts.skipped) continue;
        const uint64_t sweeps = uint64_t(c.split.substeps) * c.split.iterations;
        const uint64_t on_runs = c.asset->constraints_on_runs;
        lanes += sweeps * (layout == BatchLayout::run ? on_runs : c.asset->total_constraints() - on_runs);
    }
    return lanes;
}

// The time a cloth is stepped by: the game's dt; a hitch (more than ClothDesc::max_step_growth
// times the last step's dt) as long as the last step; at most ClothDesc::max_step_s.
float cloth_step_s(const ClothInstance& cloth, float dt_s, float last_dt_s) {
    const ClothDesc& s = cloth.settings;
    if (s.max_step_growth > 0.0f && last_dt_s > 0.0f && dt_s > s.max_step_growth * last_dt_s) dt_s = last_dt_s;
    return s.max_step_s > 0.0f && dt_s > s.max_step_s ? s.max_step_s : dt_s;
}

// The layer a cloth stage steps (StepStage: cloths, second_layer, third_layer).
uint32_t cloth_layer(StepStage stage) { return uint32_t(stage) - uint32_t(StepStage::cloths); }

// The stages' work items: run_step_items and the scheduler's tasks.
void run_items(World& world, StepStage stage, uint32_t begin, uint32_t end) {
    for (uint32_t i = begin; i < end; ++i) {
        if (stage == StepStage::bodies) {
            if (world.bodies[i].slot.live) move_body(world, i);
        } else if (world.cloths[i].slot.live && world.cloths[i].layer == cloth_layer(stage)) {
            step_cloth(world, world.cloths[i], cloth_step_s(world.cloths[i], world.step_dt_s, world.last_dt_s));
        }
    }
}

struct StageTask {
    World* world;
    StepStage stage;
};

void run_stage_task(uint32_t begin, uint32_t end, void* context) {
    const StageTask& task = *static_cast<const StageTask*>(context);
    run_items(*task.world, task.stage, begin, end);
}

// One stage through the game's scheduler, or on this thread without one.
void run_stage(World& world, StepStage stage) {
    const uint32_t items = step_stage_items(&world, stage);
    if (items == 0) return;
    const StepScheduler& scheduler = world.desc.scheduler;
    StageTask task{&world, stage};
    if (scheduler.enqueue_task == nullptr) {
        run_items(world, stage, 0, items);
        return;
    }
    if (void* handle = scheduler.enqueue_task(run_stage_task, items, 1, &task, scheduler.user_context))
        scheduler.finish_task(handle, scheduler.user_context);
}

Result check_step_range(const World* world, StepStage stage, uint32_t begin, uint32_t end) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (!world->step_open) return make_error(ErrorCode::invalid_argument, "no step is open: call begin_step first");
    if (stage != StepStage::bodies && stage != StepStage::cloths && stage != StepStage::second_layer &&
        stage != StepStage::third_layer)
        return make_error(ErrorCode::invalid_argument, "unknown step stage %u", unsigned(stage));
    const uint32_t items = step_stage_items(world, stage);
    if (begin > end || end > items)
        return make_error(ErrorCode::out_of_range, "items [%u, %u) outside the stage's %u", begin, end, items);
    return {};
}

}  // namespace

Result refuse_while_stepping(const World* world) {
    if (world != nullptr && world->step_open)
        return make_error(ErrorCode::invalid_argument, "a step is open (begin_step without end_step)");
    return {};
}

// Roots that moved faster than their cloth's jump speeds (ClothDesc::jump_speed_m_s,
// jump_turn_rad_s: a spin, a respawn the game did not announce) are taken as teleport_cloth: the
// cloth is carried whole to the new root now, and the bodies it is bound to or collides with alone
// stand at this step's pose from its start. Carried along the turn's arc while the hull went
// between poses along the chord, the cloth would be swept by its own body.
void jump_fast_roots(World& world, float dt_s) {
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        ClothInstance& cloth = world.cloths[i];
        cloth.root_jumped = false;
        if (!cloth.slot.live || !root_jumps(cloth, dt_s)) continue;  // the root moved over the whole frame
        cloth.root_jumped = true;
        wake(cloth);
        forget_last_good(cloth);
        jump_to_root(cloth, cloth.root, false);
        for (uint32_t b : {cloth.skin_body, cloth.attached_body, cloth.own_body})
            if (b < world.body_slots && world.bodies[b].slot.live) hold_body_still(world, b);
    }
}

Result begin_step(World* world, float dt_s) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (std::isnan(dt_s) || std::isinf(dt_s)) return make_error(ErrorCode::non_finite, "dt is not finite");
    if (!(dt_s > 0.0f) || dt_s > 1.0f)
        return make_error(ErrorCode::out_of_range, "dt %g s outside (0, 1]", double(dt_s));
    for (uint32_t i = 0; i < world->cloth_slots; ++i) world->cloths[i].counts = {};
    for (uint32_t i = 0; i < world->body_slots; ++i) {
        BodyState& body = world->bodies[i];
        body.refits = body.embree_refits = 0;
        body.refit_ns = body.pass_ns = 0;
        // The plain reference pass (a diagnostic) commits Embree scenes: here, on this thread.
        if (body.reference_queries && body.refit_pending) refit_embree(*world, body);
    }
    jump_fast_roots(*world, dt_s);
    spend_frame_budget(*world);  // this step's splits: every cloth its own, or cut to fit the budget
    world->last_dt_s = world->step_dt_s;
    world->step_dt_s = dt_s;
    world->step_open = true;
    return {};
}

uint32_t step_stage_items(const World* world, StepStage stage) {
    if (world == nullptr) return 0;
    // A free slot's item does nothing: the items keep their places, so the split over threads and
    // the order of the sums stay the same whatever came and went.
    switch (stage) {
        case StepStage::bodies: return world->body_slots;
        case StepStage::cloths: return world->cloth_slots;
        case StepStage::second_layer:
        case StepStage::third_layer:  // only while a cloth is in that layer: a scene pays for what it uses
            for (uint32_t i = 0; i < world->cloth_slots; ++i)
                if (world->cloths[i].slot.live && world->cloths[i].layer == cloth_layer(stage)) return world->cloth_slots;
            return 0;
    }
    return 0;
}

Result run_step_items(World* world, StepStage stage, uint32_t begin, uint32_t end) {
    if (Result r = check_step_range(world, stage, begin, end); !r.ok()) return r;
    run_items(*world, stage, begin, end);
    return {};
}

Result end_step(World* world) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (!world->step_open) return make_error(ErrorCode::invalid_argument, "no step is open: call begin_step first");
    WorldStats& stats = world->stats;
    stats.colliders_skipped = stats.body_contacts = stats.body_rays = stats.body_queried = 0;
    stats.self_contacts = stats.self_skipped_triangles = 0;
    stats.layer_contacts = stats.layer_skipped_triangles = 0;
    stats.sleeping_cloths = stats.unhealthy_cloths = stats.recovered_cloths = 0;
    stats.body_refits = stats.body_embree_refits = 0;
    for (uint32_t i = 0; i < world->body_slots; ++i) {  // in body order, then cloth order
        const BodyState& body = world->bodies[i];
        stats.body_refits += body.refits;
        stats.body_embree_refits += body.embree_refits;
        stats.body_refit_ns += body.refit_ns;
        stats.pass_ns[static_cast<int>(Pass::body)] += body.pass_ns;
    }
    for (uint32_t i = 0; i < world->cloth_slots; ++i) {
        const ClothStepCounts& c = world->cloths[i].counts;
        for (int pass = 0; pass < static_cast<int>(Pass::count); ++pass) stats.pass_ns[pass] += c.pass_ns[pass];
        stats.colliders_skipped += c.colliders_skipped;
        stats.body_contacts += c.body.contacts;
        stats.body_rays += c.body.rays;
        stats.body_queried += c.body.queried;
        stats.self_contacts += c.self.contacts;
        stats.self_skipped_triangles += c.self.skipped_triangles;
        stats.layer_contacts += c.layers.contacts;
        stats.layer_skipped_triangles += c.layers.skipped_triangles;
        stats.sleeping_cloths += uint64_t(world->cloths[i].slot.live && world->cloths[i].sleeping);
        const HealthState& health = world->cloths[i].health;
        const bool stepped = world->cloths[i].slot.live && !c.skipped;
        stats.unhealthy_cloths += uint64_t(stepped && health.problems != 0);
        stats.recovered_cloths += uint64_t(stepped && health.recovered);
    }
    for (uint32_t i = 0; i < world->collider_slots; ++i) world->colliders[i].motion_m = world->colliders[i].motion_p1_m = {};
    stats.total_recoveries += stats.recovered_cloths;
    stats.steps += 1;
    stats.run_projections = count_projections(*world, BatchLayout::run);
    stats.indexed_projections = count_projections(*world, BatchLayout::indexed);
    world->step_open = false;
    return {};
}

Result step(World* world, float dt_s) {
    if (Result r = begin_step(world, dt_s); !r.ok()) return r;
    run_stage(*world, StepStage::bodies);  // 0. the game's new body poses
    run_stage(*world, StepStage::cloths);  // 1-7 for every cloth worn over nothing
    run_stage(*world, StepStage::second_layer);  // then for those worn over them,
    run_stage(*world, StepStage::third_layer);   // and over those
    return end_step(world);
}

}  // namespace weft
