// The garment data's invariants (asset/garment_checks.h).
#include "asset/garment_checks.h"

#include <cmath>
#include <cstring>

#include "error.h"

namespace weft {

Result check_uv(const float* uv, uint32_t particle_count) {
    if (uv == nullptr) return {};
    for (uint32_t i = 0; i < 2 * uint64_t(particle_count); ++i)
        if (!std::isfinite(uv[i]))
            return make_error(ErrorCode::non_finite, "particle %u has a non-finite texture coordinate", i / 2);
    return {};
}

Result check_seam_offsets(uint32_t point_count, const uint32_t* seam_first) {
    if (point_count == 0) return {};
    if (seam_first == nullptr) return make_error(ErrorCode::invalid_argument, "seam points without seam_first");
    if (seam_first[0] != 0) return make_error(ErrorCode::invalid_argument, "seam_first[0] is %u, not 0", seam_first[0]);
    for (uint32_t s = 0; s < point_count; ++s) {
        // Compared before subtracting: a decreasing pair must not wrap into a valid count.
        if (seam_first[s + 1] < uint64_t(seam_first[s]) + 2 || seam_first[s + 1] - seam_first[s] > kMaxSeamSources)
            return make_error(ErrorCode::invalid_argument, "seam point %u does not have 2 to %u sources", s,
                              kMaxSeamSources);
    }
    return {};
}

Result check_seam_sources(uint32_t point_count, const uint32_t* seam_first, const uint32_t* seam_source,
                          uint32_t particle_count) {
    if (point_count == 0) return {};
    if (seam_source == nullptr) return make_error(ErrorCode::invalid_argument, "seam points without seam_source");
    for (uint32_t s = 0; s < point_count; ++s) {
        const uint32_t first = seam_first[s], end = seam_first[s + 1];
        for (uint32_t i = first; i < end; ++i) {
            if (seam_source[i] >= particle_count)
                return make_error(ErrorCode::out_of_range, "seam point %u names particle %u of %u", s,
                                  seam_source[i], particle_count);
            for (uint32_t j = first; j < i; ++j)
                if (seam_source[j] == seam_source[i])
                    return make_error(ErrorCode::invalid_argument, "seam point %u names particle %u twice", s,
                                      seam_source[i]);
        }
    }
    return {};
}

Result check_sewn(uint32_t point_count, const uint32_t* particle, const uint32_t* uv_first, const float* uv,
                  uint32_t particle_count) {
    if (point_count == 0) return {};
    if (particle == nullptr || uv == nullptr)
        return make_error(ErrorCode::invalid_argument, "sewn points without particles or uvs");
    if (Result r = check_seam_offsets(point_count, uv_first); !r.ok()) return r;
    for (uint32_t s = 0; s < point_count; ++s)
        if (particle[s] >= particle_count)
            return make_error(ErrorCode::out_of_range, "sewn point %u is particle %u of %u", s, particle[s],
                              particle_count);
    for (uint64_t i = 0; i < 2 * uint64_t(uv_first[point_count]); ++i)
        if (!std::isfinite(uv[i]))
            return make_error(ErrorCode::non_finite, "sewn uv %llu is not finite", (unsigned long long)(i / 2));
    return {};
}

Result check_attachments(uint32_t count, const uint32_t* particle, const uint32_t* triangle, const float* weight,
                         uint32_t particle_count) {
    if (count == 0) return {};
    if (particle == nullptr || triangle == nullptr || weight == nullptr)
        return make_error(ErrorCode::invalid_argument, "attachments without particles, triangles or weights");
    for (uint32_t k = 0; k < count; ++k) {
        if (particle[k] >= particle_count)
            return make_error(ErrorCode::out_of_range, "attachment %u names particle %u of %u", k, particle[k],
                              particle_count);
        const float* w = weight + 3 * size_t(k);
        const float sum = w[0] + w[1] + w[2];
        for (int i = 0; i < 3; ++i)
            if (!(w[i] >= -1e-4f && w[i] <= 1.0001f))
                return make_error(ErrorCode::out_of_range, "attachment %u has weight %g outside [0, 1]", k, double(w[i]));
        if (!(std::fabs(sum - 1.0f) <= 1e-3f))
            return make_error(ErrorCode::invalid_argument, "attachment %u's weights sum to %g, not 1", k, double(sum));
    }
    return {};
}

Result check_skin_constraints(const SkinConstraints& skin, uint32_t particle_count, const uint32_t* slot_of_particle,
                              const float* pin_weight, uint32_t* seen) {
    if (skin.count == 0) return {};
    if (skin.particle == nullptr || skin.triangle == nullptr || skin.weight == nullptr || skin.rest_offset_m == nullptr ||
        skin.max_distance_m == nullptr || skin.backstop_m == nullptr)
        return make_error(ErrorCode::invalid_argument, "a skin constraint array is null");
    if (skin.count > particle_count)
        return make_error(ErrorCode::out_of_range, "%u skin constraints for %u particles", skin.count, particle_count);
    // Each particle at most once: two lanes of one SIMD group writing one particle would make the
    // scalar and AVX2 paths differ.
    std::memset(seen, 0, sizeof(uint32_t) * particle_count);
    for (uint32_t k = 0; k < skin.count; ++k) {
        const uint32_t particle = skin.particle[k];
        if (particle >= particle_count)
            return make_error(ErrorCode::out_of_range, "skin constraint %u names particle %u of %u", k, particle,
                              particle_count);
        if (seen[particle]++ != 0)
            return make_error(ErrorCode::invalid_argument, "particle %u has two skin constraints", particle);
        if (pin_weight[slot_of_particle != nullptr ? slot_of_particle[particle] : particle] == 0.0f)
            return make_error(ErrorCode::invalid_argument, "skin constraint %u: particle %u is pinned", k, particle);
        const float* w = skin.weight + 3 * size_t(k);
        if (!std::isfinite(w[0]) || !std::isfinite(w[1]) || !std::isfinite(w[2]) ||
            !(std::fabs(w[0] + w[1] + w[2] - 1.0f) <= 1e-3f))
            return make_error(ErrorCode::invalid_argument, "skin constraint %u: weights not finite or not summing to 1", k);
        if (!std::isfinite(skin.rest_offset_m[k]) || !std::isfinite(skin.max_distance_m[k]) ||
            !std::isfinite(skin.backstop_m[k]))
            return make_error(ErrorCode::non_finite, "skin constraint %u: a distance is not finite", k);
        if (skin.max_distance_m[k] < 0.0f)
            return make_error(ErrorCode::out_of_range, "skin constraint %u: max distance %g m < 0", k,
                              double(skin.max_distance_m[k]));
    }
    return {};
}

Result check_panels(const uint16_t* panel, uint32_t panel_count, uint32_t particle_count) {
    if (panel == nullptr) {
        if (panel_count != 0)
            return make_error(ErrorCode::invalid_argument, "panel_count %u without panels", panel_count);
        return {};
    }
    if (panel_count == 0 || panel_count > (1u << 16))
        return make_error(ErrorCode::out_of_range, "panel_count is %u (1 to 65536)", panel_count);
    for (uint32_t p = 0; p < particle_count; ++p)
        if (panel[p] >= panel_count)
            return make_error(ErrorCode::out_of_range, "particle %u is on panel %u of %u", p, panel[p], panel_count);
    return {};
}

Result check_fabric(const Fabric& f) {
    const float values[] = {f.areal_density_kg_m2, f.compliance_m_per_n[0], f.compliance_m_per_n[1],
                            f.compliance_m_per_n[2], f.damping_per_s, f.thickness_m, f.friction};
    for (float v : values) {
        if (!std::isfinite(v)) return make_error(ErrorCode::non_finite, "a fabric value is not finite");
        if (v < 0.0f) return make_error(ErrorCode::out_of_range, "a fabric value is negative");
    }
    return {};
}

Result check_render_mesh(const RenderMesh& m, uint32_t cloth_triangle_count) {
    if (m.vertex_count == 0) {
        if (m.triangle_count != 0) return make_error(ErrorCode::invalid_argument, "render triangles without render vertices");
        return {};
    }
    if (m.vertex_count > (1u << 26) || m.triangle_count > (1u << 26))
        return make_error(ErrorCode::out_of_range, "render mesh of %u vertices, %u triangles is absurd", m.vertex_count,
                          m.triangle_count);
    if (m.cloth_triangle == nullptr || m.weight_1 == nullptr || m.weight_2 == nullptr || m.offset_m == nullptr ||
        m.uv == nullptr || (m.triangle_count > 0 && m.triangles == nullptr))
        return make_error(ErrorCode::invalid_argument, "render mesh is missing an array");
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        if (m.cloth_triangle[v] >= cloth_triangle_count)
            return make_error(ErrorCode::out_of_range, "render vertex %u is bound to triangle %u of %u", v,
                              m.cloth_triangle[v], cloth_triangle_count);
        const float w1 = m.weight_1[v], w2 = m.weight_2[v], offset = m.offset_m[v];
        if (!std::isfinite(w1) || !std::isfinite(w2) || !std::isfinite(offset) || !std::isfinite(m.uv[2 * v]) ||
            !std::isfinite(m.uv[2 * v + 1]))
            return make_error(ErrorCode::non_finite, "render vertex %u has a weight, offset or uv that is not finite", v);
        if (w1 < -0.5f || w1 > 1.5f || w2 < -0.5f || w2 > 1.5f || std::fabs(offset) > 1.0f)
            return make_error(ErrorCode::out_of_range, "render vertex %u: weights (%g, %g) or offset %g m out of range", v,
                              w1, w2, offset);
    }
    for (uint64_t k = 0; k < 3 * uint64_t(m.triangle_count); ++k)
        if (m.triangles[k] >= m.vertex_count)
            return make_error(ErrorCode::out_of_range, "render triangle %llu names vertex %u of %u",
                              (unsigned long long)(k / 3), m.triangles[k], m.vertex_count);
    return {};
}

}  // namespace weft
