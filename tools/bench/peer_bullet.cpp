#include "peer_bullet.h"

#ifdef WEFT_HAVE_BULLET

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>

namespace weft::bench {

bool bullet_available() { return true; }

std::string run_bullet(scenes::SeedScene scene, const scenes::SceneOptions& options, uint32_t iterations,
                       const Sampling& sampling, Trajectory* out) {
    *out = Trajectory{};
    if (iterations == 0) return "bullet needs at least one position iteration";
    // The Weft world of the same scene gives the particles (caller order), masses, pins and springs.
    scenes::SeedWorld sw;
    if (std::string err = scenes::make_seed_world(scene, options, &sw); !err.empty()) return err;
    const scenes::Scene description = scenes::seed_scene(scene, options);
    const ClothAsset& asset = sw.asset();
    const uint32_t count = asset.particle_count;
    out->start.resize(count);
    if (Result r = read_positions(sw.world, sw.cloth, out->start.data(), count); !r.ok()) return r.message;

    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver constraint_solver;
    btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &constraint_solver, &configuration);
    const Vec3 g = description.gravity_m_s2;
    world.setGravity(btVector3(g.x, g.y, g.z));
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = btVector3(g.x, g.y, g.z);  // the soft body reads gravity here, not from the world
    info.air_density = description.air_density_kg_m3;
    info.m_sparsesdf.Initialize();

    std::vector<btVector3> x(count);
    std::vector<btScalar> m(count);
    for (uint32_t p = 0; p < count; ++p) {
        x[p] = btVector3(out->start[p].x, out->start[p].y, out->start[p].z);
        m[p] = sw.mesh.masses[p];  // 0 pins the particle, as in Weft
    }
    auto body = std::make_unique<btSoftBody>(&info, int(count), x.data(), m.data());
    // One link per Weft spring (every kind), in Weft's batch order; padding lanes are skipped.
    for (uint32_t b = 0; b < asset.batch_count; ++b) {
        const ConstraintBatch& batch = asset.batches[b];
        for (uint32_t l = batch.first_lane; l < batch.first_lane + batch.lane_count; ++l) {
            if (asset.lane_weight[l] == 0.0f) continue;
            body->appendLink(int(asset.particle_of_slot[asset.index_a[l]]), int(asset.particle_of_slot[asset.index_b[l]]));
        }
    }
    body->m_materials[0]->m_kLST = 1.0f;  // hard springs, like Weft's compliance 0
    btSoftBody::Config& cfg = body->m_cfg;
    cfg.piterations = int(iterations);
    // Weft damps velocity as dv/dt = -d v; Bullet multiplies it by (1 - kDP) once per step.
    cfg.kDP = btScalar(1.0 - std::exp(-double(options.damping_per_s) * sw.dt_s));
    cfg.collisions = btSoftBody::fCollision::SDF_RS;
    btSphereShape* sphere_shape = nullptr;
    std::unique_ptr<btSphereShape> sphere_storage;
    std::unique_ptr<btRigidBody> sphere;
    for (const ColliderDesc& c : description.colliders) {
        if (c.shape != ColliderShape::sphere || sphere) return "the bullet peer models one sphere collider only";
        cfg.kDF = c.friction;
        body->getCollisionShape()->setMargin(c.inflation_m);  // Weft's collision skin
        sphere_storage = std::make_unique<btSphereShape>(c.radius_m);
        sphere_shape = sphere_storage.get();
        btTransform pose;
        pose.setIdentity();
        pose.setOrigin(btVector3(c.p0.x, c.p0.y, c.p0.z));
        btRigidBody::btRigidBodyConstructionInfo rigid(0.0f, nullptr, sphere_shape);
        rigid.m_startWorldTransform = pose;
        rigid.m_friction = c.friction;
        sphere = std::make_unique<btRigidBody>(rigid);
        world.addRigidBody(sphere.get());
    }
    world.addSoftBody(body.get());

    out->step_us.reserve(sampling.frames);
    out->step_wall_us.reserve(sampling.frames);
    StepClock clock;
    for (uint32_t frame = 1; frame <= sampling.frames; ++frame) {
        clock.start();
        world.stepSimulation(sw.dt_s, 0);  // maxSubSteps 0: exactly one internal step of dt
        clock.stop(&out->step_us, &out->step_wall_us);
        info.m_sparsesdf.GarbageCollect();
        if (!sampling.sampled(frame)) continue;
        std::vector<Vec3> positions(count);
        for (uint32_t p = 0; p < count; ++p) {
            const btVector3& q = body->m_nodes[int(p)].m_x;
            positions[p] = {q.x(), q.y(), q.z()};
            out->finite = out->finite && std::isfinite(q.x() + q.y() + q.z());
        }
        out->max_penetration_m =
            std::max(out->max_penetration_m, metrics::max_penetration_m(asset, positions, description.colliders.data(),
                                                                       uint32_t(description.colliders.size())));
        out->frames.push_back(std::move(positions));
    }
    world.removeSoftBody(body.get());
    if (sphere) world.removeRigidBody(sphere.get());
    return {};
}

}  // namespace weft::bench

#else  // no Bullet in this build

namespace weft::bench {

bool bullet_available() { return false; }

std::string run_bullet(scenes::SeedScene, const scenes::SceneOptions&, uint32_t, const Sampling&, Trajectory* out) {
    *out = Trajectory{};
    return "this build has no Bullet (install libbullet-dev and reconfigure)";
}

}  // namespace weft::bench

#endif
