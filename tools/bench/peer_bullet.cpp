#include "bench/peer_bullet.h"

#ifdef WEFT_HAVE_BULLET

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>
#include "weft/debug.h"

namespace weft::bench {

bool bullet_available() { return true; }

namespace {

// One link per Weft spring (every kind), in Weft's batch order (padding lanes skipped), at Weft's
// rest length (Bullet would take the start pose's; the two differ on a dressed garment), hard.
void append_links(const ClothAsset& asset, btSoftBody* body) {
    std::vector<float> rest;
    for (uint32_t b = 0; b < asset.batch_count; ++b) {
        const ConstraintBatch& batch = asset.batches[b];
        for (uint32_t l = batch.first_lane; l < batch.first_lane + batch.lane_count; ++l) {
            if (asset.lane_weight[l] == 0.0f) continue;
            body->appendLink(int(asset.particle_of_slot[asset.index_a[l]]), int(asset.particle_of_slot[asset.index_b[l]]));
            rest.push_back(asset.rest_length[l]);
        }
    }
    body->m_materials[0]->m_kLST = 1.0f;  // hard springs, like Weft's compliance 0
    body->updateConstants();  // what the first step would do (rest lengths from the start pose) ...
    for (int k = 0; k < body->m_links.size(); ++k) {  // ... then Weft's
        body->m_links[k].m_rl = rest[size_t(k)];
        body->m_links[k].m_c1 = rest[size_t(k)] * rest[size_t(k)];
    }
    body->m_bUpdateRtCst = false;
}

// The nodes' positions (caller order); clears *finite on a non-finite one.
std::vector<Vec3> node_positions(const btSoftBody& body, bool* finite) {
    std::vector<Vec3> positions(size_t(body.m_nodes.size()));
    for (int p = 0; p < body.m_nodes.size(); ++p) {
        const btVector3& q = body.m_nodes[p].m_x;
        positions[size_t(p)] = {q.x(), q.y(), q.z()};
        *finite = *finite && std::isfinite(q.x() + q.y() + q.z());
    }
    return positions;
}

// Bullet's soft-rigid world, gravity set where the soft body reads it.
struct BulletWorld {
    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver constraint_solver;
    btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &constraint_solver, &configuration};
    BulletWorld(const scenes::Scene& scene, float voxel_m) {
        const Vec3 g = scene.gravity_m_s2;
        world.setGravity(btVector3(g.x, g.y, g.z));
        btSoftBodyWorldInfo& info = world.getWorldInfo();
        info.m_gravity = btVector3(g.x, g.y, g.z);  // the soft body reads gravity here, not from the world
        info.air_density = scene.air_density_kg_m3;
        info.m_sparsesdf.Initialize();  // sets the voxel to 0.25 m ...
        info.m_sparsesdf.setDefaultVoxelsz(voxel_m);
        info.m_sparsesdf.Reset();  // ... which Reset replaces
    }
};

}  // namespace

std::string run_bullet(scenes::SeedScene scene, const scenes::SceneOptions& options, uint32_t iterations,
                       const Sampling& sampling, Trajectory* out, float voxel_m) {
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

    BulletWorld bw(description, voxel_m);
    btSoftRigidDynamicsWorld& world = bw.world;
    btSoftBodyWorldInfo& info = world.getWorldInfo();

    std::vector<btVector3> x(count);
    std::vector<btScalar> m(count);
    for (uint32_t p = 0; p < count; ++p) {
        x[p] = btVector3(out->start[p].x, out->start[p].y, out->start[p].z);
        m[p] = sw.mesh.masses[p];  // 0 pins the particle, as in Weft
    }
    auto body = std::make_unique<btSoftBody>(&info, int(count), x.data(), m.data());
    append_links(asset, body.get());
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
        std::vector<Vec3> positions = node_positions(*body, &out->finite);
        out->max_penetration_m =
            std::max(out->max_penetration_m, metrics::max_penetration_m(asset, positions, description.colliders.data(),
                                                                       uint32_t(description.colliders.size())));
        out->frames.push_back(std::move(positions));
    }
    world.removeSoftBody(body.get());
    if (sphere) world.removeRigidBody(sphere.get());
    return {};
}

std::string run_bullet_garment(const GarmentSweepScene& garment, uint32_t iterations, bool collide_body,
                               const Sampling& sampling, Trajectory* out, float voxel_m) {
    *out = Trajectory{};
    if (iterations == 0) return "bullet needs at least one position iteration";
    // The shadow: the Weft garment at 1 x 1, stepped untimed beside Bullet. It poses the body (its
    // offset hull is what Bullet collides with), places the attached waistband on the hull (Bullet
    // moves those nodes, mass 0, to the same places), and measures Bullet's penetration.
    scenes::SceneOptions cheap;
    cheap.substeps = 1;
    cheap.iterations = 1;
    cheap.tethers = false;
    cheap.coarse_level = CoarseLevel::off;
    scenes::SceneWorld shadow;
    if (std::string e = build_garment_world(garment, cheap, &shadow); !e.empty()) return e;
    const ClothAsset& asset = *shadow.cloths[0].asset;
    const ClothId cloth = shadow.cloths[0].id;
    const uint32_t count = asset.particle_count;
    const float dt_s = garment.scene.dt_s;
    std::vector<Vec3> weft_x(count);
    if (Result r = read_positions(shadow.world, cloth, weft_x.data(), count); !r.ok()) return r.message;
    out->start = weft_x;

    BulletWorld bw(garment.scene, voxel_m);
    btSoftRigidDynamicsWorld& world = bw.world;
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    std::vector<btVector3> x(count);
    std::vector<btScalar> m(count);
    std::vector<uint32_t> attached;  // caller indices of the pinned (attached) particles
    for (uint32_t p = 0; p < count; ++p) {
        x[p] = btVector3(weft_x[p].x, weft_x[p].y, weft_x[p].z);
        const float w = asset.inverse_mass[asset.slot_of_particle[p]];
        m[p] = w > 0.0f ? 1.0f / w : 0.0f;
        if (w == 0.0f) attached.push_back(p);
    }
    auto soft = std::make_unique<btSoftBody>(&info, int(count), x.data(), m.data());
    append_links(asset, soft.get());
    btSoftBody::Config& cfg = soft->m_cfg;
    cfg.piterations = int(iterations);
    cfg.kDP = btScalar(1.0 - std::exp(-double(shadow.cloths[0].desc.damping_per_s) * dt_s));
    cfg.collisions = btSoftBody::fCollision::SDF_RS;
    cfg.kDF = garment.scene.body->friction;
    soft->getCollisionShape()->setMargin(garment.scene.body->margin_m);
    world.addSoftBody(soft.get());

    // The body: Bullet's triangle mesh over the offset hull (4 floats a vertex, as the runtime keeps
    // it), on a kinematic rigid body. Soft bodies meet a concave shape through
    // btSoftBodyConcaveCollisionAlgorithm, which turns every triangle it meets into a convex prism
    // (the triangle extruded 6 cm each way) and caches it by triangle index for as long as the pair
    // lives; so after each refit the mesh leaves the world and comes back (a fresh pair, fresh prisms).
    BodyView view;
    if (Result r = view_body(shadow.world, shadow.body->id, &view); !r.ok()) return r.message;
    std::vector<float> hull(view.hull, view.hull + 4 * size_t(view.vertex_count));
    std::vector<int> triangles(view.triangles, view.triangles + 3 * size_t(view.triangle_count));
    btIndexedMesh part;
    part.m_numTriangles = int(view.triangle_count);
    part.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(triangles.data());
    part.m_triangleIndexStride = 3 * sizeof(int);
    part.m_numVertices = int(view.vertex_count);
    part.m_vertexBase = reinterpret_cast<const unsigned char*>(hull.data());
    part.m_vertexStride = 4 * sizeof(float);
    btTriangleIndexVertexArray mesh;
    mesh.addIndexedMesh(part, PHY_INTEGER);
    auto hull_bounds = [&](btVector3* lo, btVector3* hi) {
        *lo = btVector3(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
        *hi = -*lo;
        for (uint32_t v = 0; v < view.vertex_count; ++v) {
            const btVector3 q(hull[4 * v], hull[4 * v + 1], hull[4 * v + 2]);
            lo->setMin(q);
            hi->setMax(q);
        }
        *lo -= btVector3(0.1f, 0.1f, 0.1f);  // room for the walk between refits' bounds
        *hi += btVector3(0.1f, 0.1f, 0.1f);
    };
    btVector3 lo, hi;
    hull_bounds(&lo, &hi);
    btBvhTriangleMeshShape shape(&mesh, true, lo, hi, true);
    shape.setMargin(0.0f);  // the hull is already the body grown by its thickness
    btRigidBody::btRigidBodyConstructionInfo rigid(0.0f, nullptr, &shape);
    btRigidBody body(rigid);
    body.setCollisionFlags(body.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body.setActivationState(DISABLE_DEACTIVATION);
    body.setFriction(garment.scene.body->friction);
    if (collide_body) world.addRigidBody(&body);

    out->step_us.reserve(sampling.frames);
    out->step_wall_us.reserve(sampling.frames);
    StepClock clock;
    for (uint32_t frame = 1; frame <= sampling.frames; ++frame) {
        // Untimed: the shadow's step poses the body and places the attached particles.
        if (std::string e = scenes::animate_body(shadow, float(frame) * dt_s); !e.empty()) return e;
        if (Result r = step(shadow.world, dt_s); !r.ok()) return r.message;
        if (Result r = read_positions(shadow.world, cloth, weft_x.data(), count); !r.ok()) return r.message;
        if (Result r = view_body(shadow.world, shadow.body->id, &view); !r.ok()) return r.message;
        std::copy(view.hull, view.hull + hull.size(), hull.begin());
        for (uint32_t p : attached) {  // mass-0 nodes: Bullet's integration moves them by v dt, to Weft's place
            btSoftBody::Node& n = soft->m_nodes[int(p)];
            n.m_v = (btVector3(weft_x[p].x, weft_x[p].y, weft_x[p].z) - n.m_x) / dt_s;
        }
        clock.start();
        if (collide_body) {  // refit the mesh to this pose; a fresh pair drops the cached prisms
            hull_bounds(&lo, &hi);
            shape.refitTree(lo, hi);
            world.removeRigidBody(&body);
            world.addRigidBody(&body);
        }
        world.stepSimulation(dt_s, 0);  // maxSubSteps 0: exactly one internal step of dt
        clock.stop(&out->step_us, &out->step_wall_us);
        info.m_sparsesdf.GarbageCollect();
        if (!sampling.sampled(frame)) continue;
        std::vector<Vec3> positions = node_positions(*soft, &out->finite);
        out->max_penetration_m = std::max(
            out->max_penetration_m, metrics::max_body_penetration_m(shadow.world, shadow.body->id, asset, positions));
        out->frames.push_back(std::move(positions));
    }
    world.removeSoftBody(soft.get());
    if (collide_body) world.removeRigidBody(&body);
    return {};
}

}  // namespace weft::bench

#else  // no Bullet in this build

namespace weft::bench {

bool bullet_available() { return false; }

std::string run_bullet(scenes::SeedScene, const scenes::SceneOptions&, uint32_t, const Sampling&, Trajectory* out, float) {
    *out = Trajectory{};
    return "this build has no Bullet (install libbullet-dev and reconfigure)";
}

std::string run_bullet_garment(const GarmentSweepScene&, uint32_t, bool, const Sampling&, Trajectory* out, float) {
    *out = Trajectory{};
    return "this build has no Bullet (install libbullet-dev and reconfigure)";
}

}  // namespace weft::bench

#endif
