// The peer in the same run (acceptance point 4): Bullet's position-based soft body (btSoftBody) on the
// same scene, its points measured with the same metrics against the same reference as Weft's.
// Built only where Bullet is found (WEFT_HAVE_BULLET); elsewhere `bullet_available()` is false and
// the sweep leaves the peer out.
#pragma once

#include <string>

#include "bench/accuracy.h"
#include "bench/garment_sweep.h"

namespace weft::bench {

bool bullet_available();

// Runs the seed scene `scene` (the n, friction, inflation and damping of `options`) as a btSoftBody:
// the same particles, masses and pins (mass 0), one link per Weft spring (stretch, shear and bend,
// rest length from the start pose, full stiffness), the sphere as a static btSphereShape rigid body
// with the same friction, gravity, and one internal Bullet step per dt of 0.033 s. Its budget is
// Config::piterations = `iterations`. Fills positions per sampled frame and per-step times like
// run_trajectory; returns the failure message (empty on success).
std::string run_bullet(scenes::SeedScene scene, const scenes::SceneOptions& options, uint32_t iterations,
                       const Sampling& sampling, Trajectory* out, float voxel_m = 0.25f);

// The dressed garment (garment_sweep.h) as a btSoftBody: the same particles, masses and springs (at
// Weft's rest lengths, hard), the attached waistband as mass-0 nodes moved every step to where
// Weft's attachments put them, the fabric's damping, and with `collide_body` the body's offset hull
// as a btBvhTriangleMeshShape on a kinematic body, refitted to the walk's pose every step (timed
// with the step). Penetration is measured against the same hull as Weft's.
// `voxel_m`: the cell of Bullet's sparse signed distance field (btSparseSdf, default 0.25 m).
std::string run_bullet_garment(const GarmentSweepScene& garment, uint32_t iterations, bool collide_body,
                               const Sampling& sampling, Trajectory* out, float voxel_m = 0.25f);

}  // namespace weft::bench
