// The mannequin: an implicit body (smooth union of a torso of elliptic cross-sections sized by the
// girths, tapered capsules for neck, limbs, hands and feet, an ellipsoid head), meshed by CGAL's
// surface mesher (make_surface_mesh with the manifold tag: closed, manifold, oriented), then
// skinned to a skeleton of bone segments. The only CGAL translation unit of lib/body.
#include "body/mannequin.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_default_criteria_3.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/Random.h>

namespace weft::body {
namespace {

struct P {
    double x = 0, y = 0, z = 0;
};
P operator+(P a, P b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P operator-(P a, P b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P operator*(P a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(P a, P b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double length(P a) { return std::sqrt(dot(a, a)); }

// Polynomial smooth minimum (blend width k, metres): joins parts without creases.
double smooth_min(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k * 0.25;
}

// A tapered capsule from a (radius ra) to b (radius rb); t is where p projects on the axis.
struct Segment {
    P a, b;
    double ra, rb;
    double distance(P p, double* t_out = nullptr) const {
        const P ab = b - a;
        const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
        if (t_out) *t_out = t;
        return length(p - (a + ab * t)) - (ra + (rb - ra) * t);
    }
};

// Half-width a and half-depth b = k a of an ellipse of circumference c (Ramanujan's formula).
std::pair<double, double> ellipse_of_girth(double c, double k) {
    const double a = c / (M_PI * (3.0 * (1.0 + k) - std::sqrt((3.0 + k) * (1.0 + 3.0 * k))));
    return {a, k * a};
}

struct Level {
    double y, a, b;
};

// The body's parts and its skeleton, from the measurements.
struct Figure {
    std::vector<Level> torso;  // elliptic cross-sections from the crotch to the shoulders
    std::vector<Segment> limbs;
    P head_centre, head_radii;
    std::vector<Bone> bones;

    explicit Figure(const Measurements& m) {
        const double H = m.height_m;
        const auto [hip_a, hip_b] = ellipse_of_girth(m.hips_m, 0.75);
        const auto [waist_a, waist_b] = ellipse_of_girth(m.waist_m, 0.75);
        const auto [bust_a, bust_b] = ellipse_of_girth(m.bust_m, 0.8);
        torso = {{0.46 * H, 0.92 * hip_a, 0.92 * hip_b},
                 {kHipHeight * H, hip_a, hip_b},
                 {kWaistHeight * H, waist_a, waist_b},
                 {kBustHeight * H, bust_a, bust_b},
                 {0.79 * H, 0.97 * bust_a, 0.8 * bust_b},
                 {0.825 * H, 0.07 * H, 0.045 * H}};
        const double shoulder_y = 0.805 * H, shoulder_x = 0.105 * H, hip_x = 0.052 * H, hip_y = 0.49 * H;
        const double s = std::sqrt(0.5);  // A-pose: the arms hang 45 degrees from the body
        const P neck_a{0, 0.8 * H, 0}, neck_b{0, 0.88 * H, 0.005 * H};
        head_centre = {0, 0.935 * H, 0.01 * H};
        head_radii = {0.045 * H, 0.065 * H, 0.055 * H};
        auto side = [&](double sign) {
            const P shoulder{sign * shoulder_x, shoulder_y, 0}, elbow = shoulder + P{sign * s, -s, 0} * (0.17 * H);
            const P wrist = elbow + P{sign * s, -s, 0} * (0.15 * H), fingers = wrist + P{sign * s, -s, 0} * (0.1 * H);
            const P hip{sign * hip_x, hip_y, 0}, knee{sign * 0.055 * H, 0.285 * H, 0.005 * H};
            const P ankle{sign * 0.058 * H, 0.045 * H, 0}, toe{sign * 0.06 * H, 0.02 * H, 0.13 * H};
            limbs.push_back({shoulder, elbow, 0.027 * H, 0.021 * H});
            limbs.push_back({elbow, wrist, 0.021 * H, 0.016 * H});
            limbs.push_back({wrist, fingers, 0.016 * H, 0.012 * H});
            limbs.push_back({hip, knee, 0.052 * H, 0.033 * H});
            limbs.push_back({knee, ankle, 0.033 * H, 0.022 * H});
            limbs.push_back({ankle, toe, 0.022 * H, 0.018 * H});
            return std::array<P, 7>{shoulder, elbow, fingers, hip, knee, ankle, toe};
        };
        limbs.push_back({neck_a, neck_b, 0.034 * H, 0.031 * H});
        const auto left = side(1.0), right = side(-1.0);
        auto v = [](P p) { return Vec3{float(p.x), float(p.y), float(p.z)}; };
        const P pelvis_a{0, 0.46 * H, 0}, pelvis_b{0, kWaistHeight * H, 0}, chest{0, 0.8 * H, 0}, crown{0, H, 0};
        bones = {{"pelvis", -1, v(pelvis_a), v(pelvis_b)},   {"spine", 0, v(pelvis_b), v(chest)},
                 {"head", 1, v(chest), v(crown)},            {"upper_arm.L", 1, v(left[0]), v(left[1])},
                 {"forearm.L", 3, v(left[1]), v(left[2])},   {"upper_arm.R", 1, v(right[0]), v(right[1])},
                 {"forearm.R", 5, v(right[1]), v(right[2])}, {"thigh.L", 0, v(left[3]), v(left[4])},
                 {"shin.L", 7, v(left[4]), v(left[5])},      {"thigh.R", 0, v(right[3]), v(right[4])},
                 {"shin.R", 9, v(right[4]), v(right[5])},    {"foot.L", 8, v(left[5]), v(left[6])},
                 {"foot.R", 10, v(right[5]), v(right[6])}};
    }

    double torso_distance(P p) const {
        const double y = std::clamp(p.y, torso.front().y, torso.back().y);
        size_t i = 0;
        while (i + 2 < torso.size() && torso[i + 1].y <= y) ++i;
        double t = (y - torso[i].y) / (torso[i + 1].y - torso[i].y);
        t = t * t * (3.0 - 2.0 * t);  // smoothstep: the girth changes without kinks
        const double a = torso[i].a + t * (torso[i + 1].a - torso[i].a);
        const double b = torso[i].b + t * (torso[i + 1].b - torso[i].b);
        const double radial = (std::sqrt((p.x / a) * (p.x / a) + (p.z / b) * (p.z / b)) - 1.0) * std::min(a, b);
        return std::max({radial, torso.front().y - p.y, p.y - torso.back().y});
    }

    // Signed distance (approximate away from the surface): negative inside.
    double operator()(P p) const {
        const double blend = 0.025;  // metres over which parts merge
        double d = torso_distance(p);
        for (const Segment& s : limbs) d = smooth_min(d, s.distance(p), blend);
        const P q = p - head_centre;
        const P e{q.x / head_radii.x, q.y / head_radii.y, q.z / head_radii.z};
        const double head = (length(e) - 1.0) * std::min({head_radii.x, head_radii.y, head_radii.z});
        return smooth_min(d, head, blend);
    }
};

using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Point_3 = GT::Point_3;
using Function = std::function<GT::FT(Point_3)>;
using Surface_3 = CGAL::Implicit_surface_3<GT, Function>;

double segment_distance(const Bone& b, P p) {
    const Segment s{{b.head.x, b.head.y, b.head.z}, {b.tail.x, b.tail.y, b.tail.z}, 0.0, 0.0};
    return s.distance(p);
}

// Each vertex follows its kBoneInfluences nearest bones, weighted by inverse distance^4.
void skin(Mannequin& m) {
    m.bone.resize(m.positions.size());
    m.weight.resize(m.positions.size());
    for (size_t v = 0; v < m.positions.size(); ++v) {
        const P p{m.positions[v].x, m.positions[v].y, m.positions[v].z};
        std::vector<std::pair<double, uint16_t>> near;
        for (size_t b = 0; b < m.bones.size(); ++b) near.push_back({segment_distance(m.bones[b], p), uint16_t(b)});
        std::partial_sort(near.begin(), near.begin() + kBoneInfluences, near.end());
        double sum = 0.0, w[kBoneInfluences];
        for (int k = 0; k < kBoneInfluences; ++k) sum += w[k] = 1.0 / std::pow(near[k].first + 0.01, 4.0);
        for (int k = 0; k < kBoneInfluences; ++k) {
            m.bone[v][k] = near[k].second;
            m.weight[v][k] = float(w[k] / sum);
        }
    }
}

// A rigid motion: x -> R x + t.
struct Motion {
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    P t;
    P apply(P p) const {
        return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + t.x, r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + t.y,
                r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + t.z};
    }
};

Motion compose(const Motion& a, const Motion& b) {  // a after b
    Motion m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.r[i][j] = a.r[i][0] * b.r[0][j] + a.r[i][1] * b.r[1][j] + a.r[i][2] * b.r[2][j];
    m.t = a.apply(b.t);
    return m;
}

// Rotation by `angle` about the axis (unit) through `pivot` (Rodrigues).
Motion rotation_about(P pivot, P axis, double angle) {
    Motion m;
    const double c = std::cos(angle), s = std::sin(angle), k = 1.0 - c;
    const double x = axis.x, y = axis.y, z = axis.z;
    const double r[3][3] = {{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                            {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                            {z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.r[i][j] = r[i][j];
    const P rp = {r[0][0] * pivot.x + r[0][1] * pivot.y + r[0][2] * pivot.z,
                  r[1][0] * pivot.x + r[1][1] * pivot.y + r[1][2] * pivot.z,
                  r[2][0] * pivot.x + r[2][1] * pivot.y + r[2][2] * pivot.z};
    m.t = pivot - rp;
    return m;
}

// The mesher's output order follows its triangulation's memory layout, which differs from run to
// run even when the surface does not: vertices sorted by position and triangles by their vertices
// (each rotated to start at its smallest index, winding kept) give one mesh for one surface, so
// assets can bind to its triangles (body attachments).
void canonical_order(Mannequin& m) {
    const size_t n = m.positions.size();
    std::vector<uint32_t> order(n), rank(n);
    for (uint32_t v = 0; v < n; ++v) order[v] = v;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const Vec3 &p = m.positions[a], &q = m.positions[b];
        return std::tie(p.y, p.x, p.z, a) < std::tie(q.y, q.x, q.z, b);
    });
    std::vector<Vec3> positions(n);
    for (uint32_t i = 0; i < n; ++i) rank[order[i]] = i, positions[i] = m.positions[order[i]];
    std::vector<std::array<uint32_t, 3>> faces(m.triangles.size() / 3);
    for (size_t t = 0; t < faces.size(); ++t) {
        std::array<uint32_t, 3> f = {rank[m.triangles[3 * t]], rank[m.triangles[3 * t + 1]], rank[m.triangles[3 * t + 2]]};
        while (f[0] > f[1] || f[0] > f[2]) f = {f[1], f[2], f[0]};
        faces[t] = f;
    }
    std::sort(faces.begin(), faces.end());
    m.positions = std::move(positions);
    m.triangles.clear();
    for (const auto& f : faces) m.triangles.insert(m.triangles.end(), f.begin(), f.end());
}

}  // namespace

std::string make_mannequin(const Measurements& m, const MannequinOptions& options, Mannequin* out) {
    if (!(m.height_m > 0.5f && m.height_m < 3.0f)) return "height must lie in (0.5, 3) m";
    for (float girth : {m.bust_m, m.waist_m, m.hips_m})
        if (!(girth > 0.2f * m.height_m && girth < 1.5f * m.height_m)) return "a girth is out of proportion";
    if (!(options.edge_m >= 0.005f && options.edge_m <= 0.2f)) return "edge_m must lie in [0.005, 0.2] m";
    const Figure figure(m);
    Tr tr;
    C2t3 c2t3(tr);
    // The bounding sphere is centred inside the body (the mesher requires it) and holds all of it.
    const Point_3 centre(0.0, 0.5 * m.height_m, 0.0);
    const Function f = [&figure](Point_3 p) { return figure({p.x(), p.y(), p.z()}); };
    const Surface_3 surface(f, GT::Sphere_3(centre, 0.36 * m.height_m * m.height_m), 1e-7);
    const CGAL::Surface_mesh_default_criteria_3<Tr> criteria(25.0, options.edge_m, 0.1 * options.edge_m);
    // The mesher's initial points come from CGAL's default random generator, seeded by the clock:
    // a fixed seed makes the mannequin the same mesh every run (assets bind to its triangles).
    CGAL::get_default_random() = CGAL::Random(0);
    CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag());
    CGAL::Surface_mesh<Point_3> mesh;
    CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, mesh);
    if (mesh.number_of_faces() == 0) return "the surface mesher produced no triangles";
    Mannequin result;
    for (auto v : mesh.vertices()) {
        const Point_3& p = mesh.point(v);
        result.positions.push_back({float(p.x()), float(p.y()), float(p.z())});
    }
    for (auto f : mesh.faces())
        for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) result.triangles.push_back(uint32_t(v.idx()));
    canonical_order(result);
    result.bones = figure.bones;
    skin(result);
    *out = std::move(result);
    return {};
}

namespace {

// Each bone's rigid motion in the walk at time t.
std::vector<Motion> walk_motions(const Mannequin& body, float t_s) {
    const double phase = 2.0 * M_PI * t_s / 1.1;  // one stride (two steps) every 1.1 s
    const double swing = 0.35 * std::sin(phase), sway = 0.06 * std::sin(phase);
    const P x_axis{1, 0, 0}, y_axis{0, 1, 0};
    std::vector<Motion> world(body.bones.size());
    for (size_t b = 0; b < body.bones.size(); ++b) {
        const Bone& bone = body.bones[b];
        const P head{bone.head.x, bone.head.y, bone.head.z};
        double angle = 0.0;
        P axis = x_axis;
        const std::string& n = bone.name;
        const double side = n.back() == 'L' ? 1.0 : -1.0;
        if (n == "spine") axis = y_axis, angle = sway;                      // the torso turns with the stride
        else if (n.rfind("thigh", 0) == 0) angle = side * swing;              // legs swing in opposition
        else if (n.rfind("shin", 0) == 0) angle = 0.4 * std::max(0.0, std::sin(phase + side * M_PI / 2.0));  // knee bends back
        else if (n.rfind("upper_arm", 0) == 0) angle = -side * 0.6 * swing;  // arms against the legs
        else if (n.rfind("forearm", 0) == 0) angle = -0.2 - 0.1 * side * swing;
        const Motion local = rotation_about(head, axis, angle);
        world[b] = bone.parent < 0 ? local : compose(world[size_t(bone.parent)], local);
    }
    return world;
}

// 0 before `from`, 1 after `to`, smooth (zero speed at both ends) in between.
double ease(double t, double from, double to) {
    const double u = std::clamp((t - from) / (to - from), 0.0, 1.0);
    return u * u * (3.0 - 2.0 * u);
}

// Each bone's rigid motion in the bend-and-sit clip at time t. Angles about +X: positive tips what
// lies above the joint forward (+Z) and what hangs below it backward.
std::vector<Motion> bend_and_sit_motions(const Mannequin& body, float t_s) {
    const double t = std::fmod(double(t_s), double(kBendAndSitPeriod_s));
    // Bend over 0-1.2 s, hold to 1.8, straighten by 3.0; sit over 3.4-4.8 s, hold to 5.6, stand by 7.
    const double bend = ease(t, 0.0, 1.2) - ease(t, 1.8, 3.0);
    const double sit = ease(t, 3.4, 4.8) - ease(t, 5.6, 7.0);
    const double hip_flexion = 1.35 * sit;                    // thighs forward, near horizontal
    const double pelvis_tilt = 0.45 * bend + 0.10 * sit;      // the hips' share of the bend forward
    const double spine_bend = 0.65 * bend + 0.15 * sit;       // the waist's share; seated, a slight lean
    const P x_axis{1, 0, 0};
    // The pelvis turns about the hip joints' axis; seated, it is lowered by what the bent legs lose
    // in height (thigh length * (1 - cos)) less what the shins keep vertical, so the feet stay level.
    size_t thigh = 0;
    while (thigh < body.bones.size() && body.bones[thigh].name.rfind("thigh", 0) != 0) ++thigh;
    const Bone& leg = body.bones[thigh];
    const P hip{0.0, leg.head.y, leg.head.z};
    const double thigh_length = length(P{leg.tail.x, leg.tail.y, leg.tail.z} - P{leg.head.x, leg.head.y, leg.head.z});
    const double drop = thigh_length * (1.0 - std::cos(hip_flexion));
    std::vector<Motion> world(body.bones.size());
    for (size_t b = 0; b < body.bones.size(); ++b) {
        const Bone& bone = body.bones[b];
        const P head{bone.head.x, bone.head.y, bone.head.z};
        const std::string& n = bone.name;
        Motion local;
        if (n == "pelvis") {
            local = rotation_about(hip, x_axis, pelvis_tilt);
            local.t = local.t + P{0.0, -drop, 0.0};
        } else if (n == "spine") {
            local = rotation_about(head, x_axis, spine_bend);
        } else if (n.rfind("thigh", 0) == 0) {
            local = rotation_about(head, x_axis, -hip_flexion - pelvis_tilt);  // against the pelvis' tilt
        } else if (n.rfind("shin", 0) == 0) {
            local = rotation_about(head, x_axis, hip_flexion);  // the shins back to vertical
        } else if (n.rfind("upper_arm", 0) == 0) {
            local = rotation_about(head, x_axis, -0.5 * bend - 0.3 * sit);  // the arms reach forward
        } else if (n.rfind("forearm", 0) == 0) {
            local = rotation_about(head, x_axis, -0.3 * sit);  // seated, the hands beside the thighs
        }
        world[b] = bone.parent < 0 ? local : compose(world[size_t(bone.parent)], local);
    }
    return world;
}

std::vector<Motion> clip_motions(const Mannequin& body, Clip clip, float t_s) {
    return clip == Clip::walk ? walk_motions(body, t_s) : bend_and_sit_motions(body, t_s);
}

P to_p(Vec3 v) { return {v.x, v.y, v.z}; }
Vec3 to_vec3(P p) { return {float(p.x), float(p.y), float(p.z)}; }

}  // namespace

void clip_pose(const Mannequin& body, Clip clip, float t_s, std::vector<Vec3>* out) {
    const std::vector<Motion> world = clip_motions(body, clip, t_s);
    out->resize(body.positions.size());
    for (size_t v = 0; v < body.positions.size(); ++v) {
        const P p = to_p(body.positions[v]);
        P q;
        for (int k = 0; k < kBoneInfluences; ++k) q = q + world[body.bone[v][k]].apply(p) * body.weight[v][k];
        (*out)[v] = to_vec3(q);
    }
}

std::string fit_limb_capsules(const Mannequin& body, const std::vector<std::string>& bones, int sections,
                              std::vector<LimbCapsule>* out) {
    if (sections < 1) return "a limb needs at least one capsule section";
    out->clear();
    for (const std::string& name : bones) {
        size_t b = 0;
        while (b < body.bones.size() && body.bones[b].name != name) ++b;
        if (b == body.bones.size()) return "no bone named '" + name + "'";
        const P head = to_p(body.bones[b].head), axis = to_p(body.bones[b].tail) - head;
        std::vector<std::vector<double>> radii{size_t(sections)};
        for (size_t v = 0; v < body.positions.size(); ++v) {
            const int k = body.weight[v][0] >= body.weight[v][1] ? 0 : 1;
            if (body.bone[v][k] != b || body.weight[v][k] < 0.9f) continue;
            const P d = to_p(body.positions[v]) - head;
            const double t = dot(d, axis) / dot(axis, axis);
            if (t < 0.0 || t > 1.0) continue;
            radii[size_t(std::min(sections - 1, int(t * sections)))].push_back(length(d - axis * t));
        }
        for (int s = 0; s < sections; ++s) {
            std::vector<double>& r = radii[size_t(s)];
            if (r.empty()) return "bone '" + name + "' has a section no vertex follows alone";
            const size_t q = r.size() * 3 / 4;
            std::nth_element(r.begin(), r.begin() + ptrdiff_t(q), r.end());
            // The first section starts a radius down the bone: its cap ends at the joint instead of
            // bulging out of the blend into the parent (a thigh's out of the hip).
            const double start = s == 0 ? std::min(r[q] / length(axis), 0.5 / sections) : double(s) / sections;
            out->push_back({int(b), to_vec3(head + axis * start), to_vec3(head + axis * (double(s + 1) / sections)),
                            float(r[q])});
        }
    }
    return {};
}

void clip_capsules(const Mannequin& body, Clip clip, const std::vector<LimbCapsule>& rest, float t_s,
                   std::vector<LimbCapsule>* out) {
    const std::vector<Motion> world = clip_motions(body, clip, t_s);
    out->resize(rest.size());
    for (size_t i = 0; i < rest.size(); ++i) {
        const Motion& m = world[size_t(rest[i].bone)];
        (*out)[i] = {rest[i].bone, to_vec3(m.apply(to_p(rest[i].p0))), to_vec3(m.apply(to_p(rest[i].p1))), rest[i].radius_m};
    }
}

}  // namespace weft::body
