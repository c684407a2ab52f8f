// Checks of the optional garment data (texture coordinates, seam points, panels, fabric). One place
// for both callers: cook_cloth reports a failure with these codes (bad caller input), validate_asset
// reports it as corrupt_asset.
#pragma once

#include "weft/cloth_asset.h"

namespace weft {

// Every coordinate finite.
Result check_uv(const float* uv, uint32_t particle_count);

// seam_first[0] = 0 and 2..kMaxSeamSources sources per point (so the offsets increase). Read
// seam_first[point_count] (the source count) only after this passed.
Result check_seam_offsets(uint32_t point_count, const uint32_t* seam_first);

// Every source a particle, distinct within its point. The offsets must have passed the check above.
Result check_seam_sources(uint32_t point_count, const uint32_t* seam_first, const uint32_t* seam_source,
                          uint32_t particle_count);

// Every particle's panel below panel_count (at most 2^16 panels: they are stored as uint16).
Result check_panels(const uint16_t* panel, uint32_t panel_count, uint32_t particle_count);

// Sewn seams: the offsets as check_seam_offsets, every particle in range, every uv finite.
Result check_sewn(uint32_t point_count, const uint32_t* particle, const uint32_t* uv_first, const float* uv,
                  uint32_t particle_count);

// Body attachments: every particle in range and distinct, weights finite in [0, 1] summing to 1.
// (The triangles are checked against the body when the cloth is attached.)
Result check_attachments(uint32_t count, const uint32_t* particle, const uint32_t* triangle, const float* weight,
                         uint32_t particle_count);

// Skin constraints (one check for the cook, the loader and bind_skin_constraints): every particle
// in range, bound once (`seen`: particle_count uint32 of scratch), not pinned (pin_weight of its
// slot is 0: an inverse mass by slot, or a mass with slot_of_particle null, caller order), weights
// finite summing to 1, distances finite, max distance >= 0. The triangles are checked against the
// body when the constraints are bound.
Result check_skin_constraints(const SkinConstraints& skin, uint32_t particle_count, const uint32_t* slot_of_particle,
                              const float* pin_weight, uint32_t* seen);

// The render mesh: every cloth triangle below cloth_triangle_count, weights and offsets finite
// (weights within [-0.5, 1.5]: a point near its triangle; offsets within 1 m), every render
// triangle's vertex below vertex_count, every uv finite.
Result check_render_mesh(const RenderMesh& render, uint32_t cloth_triangle_count);

// Every value finite and >= 0.
Result check_fabric(const Fabric& fabric);

}  // namespace weft
