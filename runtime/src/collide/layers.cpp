// Layered garments: a cloth against the cloths it is worn over (layers.h).
#include "collide/layers.h"

#include <cmath>

namespace weft {
namespace {

// The box of the finite points among slots [0, count) (with inverse_mass > 0 when given), widened
// by `reach`; an empty box (lo > hi) when there are none.
Box bounds(const float* x, const float* y, const float* z, const float* inverse_mass, uint32_t count, float reach) {
    const float inf = INFINITY;
    Box box{{inf, inf, inf}, {-inf, -inf, -inf}};
    for (uint32_t s = 0; s < count; ++s) {
        if (inverse_mass != nullptr && !(inverse_mass[s] > 0.0f)) continue;
        if (!(std::isfinite(x[s]) && std::isfinite(y[s]) && std::isfinite(z[s]))) continue;
        box.lo = {box.lo.x < x[s] ? box.lo.x : x[s], box.lo.y < y[s] ? box.lo.y : y[s], box.lo.z < z[s] ? box.lo.z : z[s]};
        box.hi = {box.hi.x > x[s] ? box.hi.x : x[s], box.hi.y > y[s] ? box.hi.y : y[s], box.hi.z > z[s] ? box.hi.z : z[s]};
    }
    box.lo = box.lo - P3{reach, reach, reach};
    box.hi = box.hi + P3{reach, reach, reach};
    return box;
}

bool overlap(const Box& a, const Box& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y && a.lo.z <= b.hi.z &&
           b.lo.z <= a.hi.z;
}

// The inner cloth where this substep reads it, and its motion over this substep.
struct InnerView {
    const LayerState& st;
    const Particles& p;
    float motion_share;  // this substep over the inner cloth's last substep

    P3 at(uint32_t s) const { return {st.inner_x[s], st.inner_y[s], st.inner_z[s]}; }
    P3 motion(uint32_t s) const { return motion_share * (position(p, s) - previous(p, s)); }
};

// 2. This cloth's particle s against the inner face (corners k): pushed out in front of it.
bool push_particle(Particles& p, uint32_t s, const InnerView& inner, const uint32_t k[3], const LayerArgs& args) {
    const P3 a = inner.at(k[0]), x = position(p, s);
    FacePoint f;
    if (!project_onto_face(a, inner.at(k[1]), inner.at(k[2]), x, &f)) return false;
    const float distance = dot(x - a, f.n), capture = kLayerCaptureThicknesses * args.thickness_m;
    if (!(distance < args.thickness_m) || distance < -capture) return false;
    move(p, s, (args.thickness_m - distance) * f.n);  // C = distance - thickness >= 0; only s moves
    const float w = p.inverse_mass[s];
    const P3 moved_face = f.u * inner.motion(k[0]) + f.v * inner.motion(k[1]) + f.w * inner.motion(k[2]);
    const P3 slip = friction_slip((position(p, s) - previous(p, s)) - moved_face, f.n,
                                  args.friction * (args.thickness_m - distance), w);
    move(p, s, w * slip);
    return true;
}

// 2b. This cloth's edge (s, r) against the inner edge (q0, q1) of a face with unit normal n: where the
// closest points lie inside both segments and the outer one is less than `thickness`
// in front of the inner one along n, and not beside it by the thickness or more, the edge is pushed
// out to the thickness (C = d - thickness >= 0 at the closest point, gradients 1 - a and a).
bool push_edge(Particles& p, uint32_t s, uint32_t r, const InnerView& inner, uint32_t q0, uint32_t q1, P3 n,
               const LayerArgs& args) {
    SegmentPoints c;
    if (!closest_points_inside(position(p, s), position(p, r), inner.at(q0), inner.at(q1), &c)) return false;
    const float a = c.a, b = c.b;
    const P3 gap = c.gap;
    const float distance = dot(gap, n), capture = kLayerCaptureThicknesses * args.thickness_m;
    if (!(distance < args.thickness_m) || distance < -capture) return false;
    const P3 beside = gap - distance * n;
    if (!(dot(beside, beside) < args.thickness_m * args.thickness_m)) return false;
    const float ws = p.inverse_mass[s] * (1.0f - a), wr = p.inverse_mass[r] * a;
    const float weight = bounded_weight(ws, wr, 0.0f, 0.0f, ws * (1.0f - a) + wr * a);
    if (!(weight > 0.0f)) return false;
    const P3 push = ((args.thickness_m - distance) / weight) * n;
    const P3 ps = previous(p, s), pr = previous(p, r);
    move(p, s, ws * push);
    move(p, r, wr * push);
    const P3 moved_edge = (1.0f - a) * (position(p, s) - ps) + a * (position(p, r) - pr);
    const P3 moved_inner = (1.0f - b) * inner.motion(q0) + b * inner.motion(q1);
    const P3 slip = friction_slip(moved_edge - moved_inner, n, args.friction * (args.thickness_m - distance), weight);
    move(p, s, ws * slip);
    move(p, r, wr * slip);
    return true;
}

// 3. The inner particle q against this cloth's face (corners k): the face pushed out in front of it.
bool push_face(Particles& p, const uint32_t k[3], const InnerView& inner, uint32_t q, const LayerArgs& args) {
    const P3 a = position(p, k[0]), xq = inner.at(q);
    FacePoint f;
    if (!project_onto_face(a, position(p, k[1]), position(p, k[2]), xq, &f)) return false;
    const float distance = dot(xq - a, f.n), capture = kLayerCaptureThicknesses * args.thickness_m;
    if (!(distance > -args.thickness_m) || distance > capture) return false;
    const float wa = p.inverse_mass[k[0]] * f.u, wb = p.inverse_mass[k[1]] * f.v, wc = p.inverse_mass[k[2]] * f.w;
    const float weight = bounded_weight(wa, wb, wc, 0.0f, wa * f.u + wb * f.v + wc * f.w);
    if (!(weight > 0.0f)) return false;  // every corner pinned
    // C = -thickness - distance >= 0 for the face; its gradient at corner i is -g_i n.
    const P3 push = ((distance + args.thickness_m) / weight) * f.n;
    move(p, k[0], wa * push);
    move(p, k[1], wb * push);
    move(p, k[2], wc * push);
    const P3 moved_face = f.u * (position(p, k[0]) - previous(p, k[0])) + f.v * (position(p, k[1]) - previous(p, k[1])) +
                          f.w * (position(p, k[2]) - previous(p, k[2]));
    const P3 slip = friction_slip(inner.motion(q) - moved_face, f.n, args.friction * (distance + args.thickness_m), weight);
    move(p, k[0], (-wa) * slip);
    move(p, k[1], (-wb) * slip);
    move(p, k[2], (-wc) * slip);
    return true;
}

}  // namespace

float layer_cell_m(const ClothAsset& a, float thickness_m) {
    const float reach = (1.0f + kLayerCaptureThicknesses) * thickness_m;
    const float edge = mean_longest_edge_m(a.start_x, a.start_y, a.start_z, a.triangles, a.triangle_count);
    return std::fmax(edge + 2.0f * reach, 1e-3f);
}

void collide_layer(Particles& p, const ClothAsset& asset, LayerState& st, const InnerLayer& layer,
                   const LayerArgs& args, LayerCounts& counts) {
    const Particles& ip = *layer.particles;
    const ClothAsset& inner_asset = *layer.asset;
    const uint32_t inner_slots = ip.slot_count;
    // 1. The inner cloth at this substep's end, taken back along its last substep's motion.
    const float back = layer.inner_substep_s > 0.0f ? layer.time_before_end_s / layer.inner_substep_s : 0.0f;
    for (uint32_t s = 0; s < inner_slots; ++s) {
        st.inner_x[s] = ip.x[s] - back * (ip.x[s] - ip.previous_x[s]);
        st.inner_y[s] = ip.y[s] - back * (ip.y[s] - ip.previous_y[s]);
        st.inner_z[s] = ip.z[s] - back * (ip.z[s] - ip.previous_z[s]);
    }
    const InnerView inner{st, ip, layer.inner_substep_s > 0.0f ? args.substep_s / layer.inner_substep_s : 0.0f};
    const float reach = (1.0f + kLayerCaptureThicknesses) * args.thickness_m;
    const Box own_box = bounds(p.x, p.y, p.z, p.inverse_mass, p.slot_count, reach);
    const Box inner_box = bounds(st.inner_x, st.inner_y, st.inner_z, nullptr, inner_slots, reach);
    if (!overlap(own_box, inner_box)) return;
    const uint32_t none[3] = {~0u, ~0u, ~0u};  // two cloths: no triangle's corner is excluded

    // 2. This cloth's particles against the inner faces.
    sort_into_buckets(p.x, p.y, p.z, p.inverse_mass, p.slot_count, st.own);
    for (uint32_t t = 0; t < inner_asset.triangle_count; ++t) {
        const uint32_t* k = inner_asset.triangles + 3 * t;
        const P3 a = inner.at(k[0]), b = inner.at(k[1]), c = inner.at(k[2]);
        const Box box = widened_box(a, b, c, reach);
        if (!overlap(box, own_box)) continue;
        const P3 n_raw = cross(b - a, c - a);
        const float n2 = dot(n_raw, n_raw);
        if (!(n2 > 0.0f)) continue;  // degenerate, or not finite
        const P3 n = (1.0f / std::sqrt(n2)) * n_raw;
        const float capture = kLayerCaptureThicknesses * args.thickness_m;
        // The face's sides as lines in its plane: side j (corner j to j + 1) and its unit normal in the
        // plane, found for the first particle visited (most faces have none).
        const P3 corner[3] = {a, b, c};
        P3 side_normal[3];
        bool sides_found = false;
        const auto visit = [&](uint32_t s) {
            counts.contacts += uint64_t(push_particle(p, s, inner, k, args));
            if (!sides_found) {
                for (uint32_t j = 0; j < 3; ++j) {
                    const P3 m = cross(n, corner[(j + 1) % 3] - corner[j]);
                    side_normal[j] = (1.0f / std::sqrt(dot(m, m))) * m;
                }
                sides_found = true;
            }
            // 2b. Its edges against the face's sides: an edge with an end within reach of the plane,
            // against a side whose line it comes within the thickness of, seen along n (with both ends
            // further on one side, its closest point to the side lies beside it by more: push_edge
            // would refuse it). Read as they are now: each contact moves s and r.
            const float hs = dot(position(p, s) - a, n);
            for (uint32_t e = st.edge_first[s]; e < st.edge_first[s + 1]; ++e) {
                const uint32_t r = st.edge_other[e];
                const P3 xr = position(p, r);
                if (r < s && p.inverse_mass[r] > 0.0f && inside(box, xr)) continue;  // visited from r
                const float hr = dot(xr - a, n);
                if ((hs >= args.thickness_m && hr >= args.thickness_m) || (hs < -capture && hr < -capture)) continue;
                for (uint32_t j = 0; j < 3; ++j) {
                    const float ds = dot(position(p, s) - corner[j], side_normal[j]),
                                dr = dot(position(p, r) - corner[j], side_normal[j]);
                    if ((ds < args.thickness_m || dr < args.thickness_m) && (ds > -args.thickness_m || dr > -args.thickness_m))
                        counts.contacts += uint64_t(push_edge(p, s, r, inner, k[j], k[(j + 1) % 3], n, args));
                }
            }
        };
        if (for_particles_in_box(st.own, box, none, visit) == BoxWalk::too_large) counts.skipped_triangles += 1;
    }

    // 3. The inner particles against this cloth's faces (where 2 left them).
    sort_into_buckets(st.inner_x, st.inner_y, st.inner_z, nullptr, inner_slots, st.inner);
    for (uint32_t t = 0; t < asset.triangle_count; ++t) {
        const uint32_t* k = asset.triangles + 3 * t;
        const Box box = widened_box(position(p, k[0]), position(p, k[1]), position(p, k[2]), reach);
        if (!overlap(box, inner_box)) continue;
        const auto visit = [&](uint32_t q) { counts.contacts += uint64_t(push_face(p, k, inner, q, args)); };
        if (for_particles_in_box(st.inner, box, none, visit) == BoxWalk::too_large) counts.skipped_triangles += 1;
    }
}

}  // namespace weft
