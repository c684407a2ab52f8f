// Character motion: a cloth carried by its character's root (set_cloth_root, teleport_cloth).
//
// The cloth is simulated in world space. When the root moves rigidly by D (rotation R_d about the
// old root's origin, then the root's translation), each particle is carried by the share of D its
// inertia leaves out: x' = R_p (x - t_old) + t_old + (delta - felt), where R_p is R_d's rotation
// scaled by (1 - angular_inertia) and `felt` is linear_inertia * delta, clamped to
// max_inertial_speed * dt. Previous positions move the same way, so the velocity turns with the
// root and the carried share adds none: inertia 0 is a cloth simulated in the root's frame, 1 one
// in world space (NvCloth's and Chaos's inertia scales).
#include <cmath>

#include "world_internal.h"

namespace weft {
namespace {

Quat multiply(Quat a, Quat b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

Quat conjugate(Quat q) { return {-q.x, -q.y, -q.z, q.w}; }

// The rotation q scaled to `share` of its angle (about the same axis), the shorter way round.
Quat scale_rotation(Quat q, float share) {
    if (q.w < 0.0f) q = {-q.x, -q.y, -q.z, -q.w};
    const float s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(s > 1e-9f)) return {};
    const float half = std::atan2(s, q.w) * share;
    const float k = std::sin(half) / s;
    return {q.x * k, q.y * k, q.z * k, std::cos(half)};
}

// The 3 x 3 matrix of a unit quaternion, row-major.
void to_matrix(Quat q, float m[9]) {
    const float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z, wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    m[0] = 1 - 2 * (yy + zz), m[1] = 2 * (xy - wz), m[2] = 2 * (xz + wy);
    m[3] = 2 * (xy + wz), m[4] = 1 - 2 * (xx + zz), m[5] = 2 * (yz - wx);
    m[6] = 2 * (xz - wy), m[7] = 2 * (yz + wx), m[8] = 1 - 2 * (xx + yy);
}

// x <- R (x - pivot) + pivot + shift, over one set of position arrays.
void move_rigidly(float* x, float* y, float* z, uint32_t count, const float r[9], Vec3 pivot, Vec3 shift) {
    for (uint32_t i = 0; i < count; ++i) {
        const float dx = x[i] - pivot.x, dy = y[i] - pivot.y, dz = z[i] - pivot.z;
        x[i] = r[0] * dx + r[1] * dy + r[2] * dz + pivot.x + shift.x;
        y[i] = r[3] * dx + r[4] * dy + r[5] * dz + pivot.y + shift.y;
        z[i] = r[6] * dx + r[7] * dy + r[8] * dz + pivot.z + shift.z;
    }
}

void carry(ClothInstance& cloth, const Transform& from, const Transform& to, float angular_share, Vec3 shift) {
    float* r = cloth.carry_rotation;
    to_matrix(scale_rotation(multiply(to.rotation, conjugate(from.rotation)), angular_share), r);
    cloth.carry_pivot = from.translation_m;
    cloth.carry_shift = shift;
    cloth.carried = true;
    Particles& p = cloth.particles;
    move_rigidly(p.x, p.y, p.z, p.slot_count, r, from.translation_m, shift);
    move_rigidly(p.previous_x, p.previous_y, p.previous_z, p.slot_count, r, from.translation_m, shift);
}

// The root `share` of the way from a to b (the rotation about the same axis).
Transform along(const Transform& a, const Transform& b, float share) {
    const Vec3 t{a.translation_m.x + (b.translation_m.x - a.translation_m.x) * share,
                 a.translation_m.y + (b.translation_m.y - a.translation_m.y) * share,
                 a.translation_m.z + (b.translation_m.z - a.translation_m.z) * share};
    return {t, multiply(scale_rotation(multiply(b.rotation, conjugate(a.rotation)), share), a.rotation)};
}

}  // namespace

Vec3 carried_motion(const ClothInstance& cloth, Vec3 at) {
    if (!cloth.carried) return {};
    const float* r = cloth.carry_rotation;
    const Vec3 d{at.x - cloth.carry_pivot.x, at.y - cloth.carry_pivot.y, at.z - cloth.carry_pivot.z};
    return {r[0] * d.x + r[1] * d.y + r[2] * d.z - d.x + cloth.carry_shift.x,
            r[3] * d.x + r[4] * d.y + r[5] * d.z - d.y + cloth.carry_shift.y,
            r[6] * d.x + r[7] * d.y + r[8] * d.z - d.z + cloth.carry_shift.z};
}

void follow_root(ClothInstance& cloth, float dt_s, uint32_t substep, uint32_t substeps) {
    cloth.carried = false;
    if (!cloth.has_root) return;
    const Transform from = cloth.previous_root, to = cloth.root;
    if (substep + 1 == substeps) cloth.previous_root = to;
    const Vec3 delta{to.translation_m.x - from.translation_m.x, to.translation_m.y - from.translation_m.y,
                     to.translation_m.z - from.translation_m.z};
    const bool turned = to.rotation.x != from.rotation.x || to.rotation.y != from.rotation.y ||
                        to.rotation.z != from.rotation.z || to.rotation.w != from.rotation.w;
    if (delta.x == 0.0f && delta.y == 0.0f && delta.z == 0.0f && !turned) return;  // a still root costs nothing
    const ClothDesc& s = cloth.settings;
    Vec3 felt{s.linear_inertia * delta.x, s.linear_inertia * delta.y, s.linear_inertia * delta.z};
    const float felt_length = std::sqrt(felt.x * felt.x + felt.y * felt.y + felt.z * felt.z);
    const float most = s.max_inertial_speed_m_s * dt_s;
    if (felt_length > most) {
        const float k = most / felt_length;
        felt = {felt.x * k, felt.y * k, felt.z * k};
    }
    // Each substep its share, as the body's hull and the skinned points are interpolated.
    const float n = float(substeps);
    carry(cloth, along(from, to, float(substep) / n), along(from, to, float(substep + 1) / n), 1.0f - s.angular_inertia,
          {(delta.x - felt.x) / n, (delta.y - felt.y) / n, (delta.z - felt.z) / n});
}

bool root_jumps(const ClothInstance& cloth, float dt_s) {
    if (!cloth.has_root) return false;
    const Transform &from = cloth.previous_root, &to = cloth.root;
    const ClothDesc& s = cloth.settings;
    const Vec3 d{to.translation_m.x - from.translation_m.x, to.translation_m.y - from.translation_m.y,
                 to.translation_m.z - from.translation_m.z};
    if (s.jump_speed_m_s > 0.0f && d.x * d.x + d.y * d.y + d.z * d.z > (s.jump_speed_m_s * dt_s) * (s.jump_speed_m_s * dt_s))
        return true;
    if (!(s.jump_turn_rad_s > 0.0f)) return false;
    Quat q = multiply(to.rotation, conjugate(from.rotation));
    if (q.w < 0.0f) q = {-q.x, -q.y, -q.z, -q.w};  // the shorter way round
    const float turn_rad = 2.0f * std::atan2(std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z), q.w);
    return turn_rad > s.jump_turn_rad_s * dt_s;
}

void jump_to_root(ClothInstance& cloth, const Transform& root, bool drop_velocity) {
    if (cloth.has_root) {
        const Transform& from = cloth.previous_root;
        carry(cloth, from, root, 1.0f,
              {root.translation_m.x - from.translation_m.x, root.translation_m.y - from.translation_m.y,
               root.translation_m.z - from.translation_m.z});
    }
    Particles& p = cloth.particles;
    if (drop_velocity)
        for (uint32_t i = 0; i < p.slot_count; ++i)
            p.previous_x[i] = p.x[i], p.previous_y[i] = p.y[i], p.previous_z[i] = p.z[i];
    cloth.root = cloth.previous_root = root;
    cloth.has_root = true;
}

}  // namespace weft
