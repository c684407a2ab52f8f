// The project's own mannequin (lib/body): a closed, consistently oriented manifold whose girths
// are the measurements it was made from, and a walk that moves its limbs and nothing else wildly.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "body/mannequin.h"

namespace weft {
namespace {

const body::Mannequin& mannequin() {
    static const body::Mannequin m = [] {
        body::Mannequin made;
        const std::string error = body::make_mannequin({}, {}, &made);
        INFO(error);
        REQUIRE(error.empty());
        return made;
    }();
    return m;
}

// Perimeter of the body's cross-section at height y, torso only (segments within 0.24 m of the axis).
double girth_at(const body::Mannequin& m, float y) {
    double perimeter = 0.0;
    for (size_t t = 0; t < m.triangles.size(); t += 3) {
        Vec3 cut[2];
        int n = 0;
        for (int e = 0; e < 3; ++e) {
            const Vec3 a = m.positions[m.triangles[t + e]], b = m.positions[m.triangles[t + (e + 1) % 3]];
            if ((a.y < y) == (b.y < y)) continue;
            const float s = (y - a.y) / (b.y - a.y);
            if (n < 2) cut[n++] = {a.x + s * (b.x - a.x), y, a.z + s * (b.z - a.z)};
        }
        if (n != 2) continue;
        const float mx = 0.5f * (cut[0].x + cut[1].x), mz = 0.5f * (cut[0].z + cut[1].z);
        if (std::sqrt(mx * mx + mz * mz) > 0.24f) continue;  // an arm or a hand
        perimeter += std::hypot(double(cut[1].x) - cut[0].x, double(cut[1].z) - cut[0].z);
    }
    return perimeter;
}

TEST_CASE("mannequin: closed, manifold, oriented outwards") {
    const body::Mannequin& m = mannequin();
    REQUIRE(m.triangles.size() >= 3 * 2000);
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t t = 0; t < m.triangles.size(); t += 3)
        for (int e = 0; e < 3; ++e) directed[{m.triangles[t + e], m.triangles[t + (e + 1) % 3]}] += 1;
    bool manifold = true;
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        manifold = manifold && count == 1 && reverse != directed.end() && reverse->second == 1;
    }
    CHECK(manifold);  // every edge has exactly two triangles, which traverse it in opposite directions
    double volume = 0.0;  // divergence theorem: positive when the triangles face outwards
    for (size_t t = 0; t < m.triangles.size(); t += 3) {
        const Vec3 a = m.positions[m.triangles[t]], b = m.positions[m.triangles[t + 1]], c = m.positions[m.triangles[t + 2]];
        volume += (double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) - double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
                   double(a.z) * (double(b.x) * c.y - double(b.y) * c.x)) / 6.0;
    }
    CHECK(volume > 0.04);  // the real 172 cm body of ../shared is about 0.073 m^3
    CHECK(volume < 0.10);
}

TEST_CASE("mannequin: its girths are the measurements") {
    const body::Mannequin& m = mannequin();
    const body::Measurements size;
    CHECK(girth_at(m, body::kWaistHeight * size.height_m) == doctest::Approx(size.waist_m).epsilon(0.05));
    CHECK(girth_at(m, body::kHipHeight * size.height_m) == doctest::Approx(size.hips_m).epsilon(0.05));
    CHECK(girth_at(m, body::kBustHeight * size.height_m) == doctest::Approx(size.bust_m).epsilon(0.05));
    float top = -1e9f, bottom = 1e9f;
    for (const Vec3& p : m.positions) top = std::max(top, p.y), bottom = std::min(bottom, p.y);
    CHECK(top - bottom == doctest::Approx(size.height_m).epsilon(0.03));
    CHECK(bottom == doctest::Approx(0.0).epsilon(0.02));
}

TEST_CASE("mannequin: bad measurements are refused") {
    body::Mannequin m;
    body::Measurements tall;
    tall.height_m = 30.0f;
    CHECK_FALSE(body::make_mannequin(tall, {}, &m).empty());
    body::Measurements thin;
    thin.waist_m = 0.0f;
    CHECK_FALSE(body::make_mannequin(thin, {}, &m).empty());
    CHECK(m.positions.empty());
}

TEST_CASE("mannequin: the walk swings the limbs, keeps the body together and repeats") {
    const body::Mannequin& m = mannequin();
    std::vector<Vec3> a, b, again;
    body::walk_pose(m, 0.0f, &a);
    body::walk_pose(m, 0.275f, &b);  // a quarter stride later: the legs are at their widest
    body::walk_pose(m, 1.1f, &again);  // one stride later
    REQUIRE(a.size() == m.positions.size());
    double moved = 0.0, furthest = 0.0, repeat = 0.0;
    for (size_t v = 0; v < a.size(); ++v) {
        const double d = std::hypot(double(b[v].x) - a[v].x, double(b[v].y) - a[v].y, double(b[v].z) - a[v].z);
        moved = std::max(moved, d);
        furthest = std::max(furthest, double(std::abs(b[v].y - m.positions[v].y)));
        repeat = std::max(repeat, std::hypot(double(again[v].x) - a[v].x, double(again[v].y) - a[v].y,
                                             double(again[v].z) - a[v].z));
    }
    CHECK(moved > 0.1);      // a foot or a hand travels
    CHECK(furthest < 0.5);   // nothing flies off
    CHECK(repeat < 1e-4);    // periodic
}

// The clip a skirt's self-collision is tested on (tests/test_sew.cpp): it starts and ends at rest,
// bends forward, then sits with the feet on the floor and the hips lowered, the knees in front.
TEST_CASE("mannequin: bend-and-sit starts at rest, bends forward, sits with the feet level, and repeats") {
    const body::Mannequin& m = mannequin();
    std::vector<Vec3> start, bent, seated, again;
    body::clip_pose(m, body::Clip::bend_and_sit, 0.0f, &start);
    body::clip_pose(m, body::Clip::bend_and_sit, 1.5f, &bent);    // bent over, held
    body::clip_pose(m, body::Clip::bend_and_sit, 5.2f, &seated);  // seated, held
    body::clip_pose(m, body::Clip::bend_and_sit, body::kBendAndSitPeriod_s, &again);
    REQUIRE(start.size() == m.positions.size());
    double at_rest = 0.0, repeat = 0.0;
    float top_y = -1e9f, bent_top_y = -1e9f, bent_top_z = 0.0f, lowest = 1e9f, seated_lowest = 1e9f, seated_front = -1e9f;
    for (size_t v = 0; v < start.size(); ++v) {
        const Vec3 r = m.positions[v];
        at_rest = std::max(at_rest, std::hypot(double(start[v].x) - r.x, double(start[v].y) - r.y, double(start[v].z) - r.z));
        repeat = std::max(repeat, std::hypot(double(again[v].x) - r.x, double(again[v].y) - r.y, double(again[v].z) - r.z));
        if (r.y > top_y) top_y = r.y;
        if (bent[v].y > bent_top_y) bent_top_y = bent[v].y, bent_top_z = bent[v].z;
        lowest = std::min(lowest, r.y);
        seated_lowest = std::min(seated_lowest, seated[v].y);
        seated_front = std::max(seated_front, seated[v].z);
    }
    CHECK(at_rest < 1e-5);   // dressed in the rest pose, the clip starts there
    CHECK(repeat < 1e-5);    // and ends there
    CHECK(bent_top_y < top_y - 0.3f);  // bent over: the head well below its standing height
    CHECK(bent_top_z > 0.2f);          // and forward of the feet
    CHECK(std::abs(seated_lowest - lowest) < 0.03f);  // seated, the soles stay on the floor
    CHECK(seated_front > 0.4f);                        // the knees in front
    // The hips lowered: the crotch's vertices (the lowest of the torso, near x = 0) drop by 20 cm or more.
    float crotch = 1e9f, seated_crotch = 1e9f;
    for (size_t v = 0; v < start.size(); ++v)
        if (std::abs(m.positions[v].x) < 0.01f && m.positions[v].y > 0.5f * top_y - 0.2f && m.positions[v].y < 0.5f * top_y + 0.2f)
            crotch = std::min(crotch, m.positions[v].y), seated_crotch = std::min(seated_crotch, seated[v].y);
    CHECK(seated_crotch < crotch - 0.2f);
}

// Distance from p to the line through a and b, and where p projects on it (0 at a, 1 at b).
std::pair<double, double> axis_distance(Vec3 p, Vec3 a, Vec3 b) {
    const double ab[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double ap[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
    const double t = (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / (ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
    return {std::hypot(ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]), t};
}

TEST_CASE("mannequin: limb capsules hug their bone's vertices and move with the bone") {
    const body::Mannequin& m = mannequin();
    std::vector<body::LimbCapsule> rest, posed;
    REQUIRE(body::fit_limb_capsules(m, {"thigh.L", "thigh.R", "upper_arm.L"}, 2, &rest).empty());
    REQUIRE(rest.size() == 6);
    std::vector<Vec3> pose;
    body::walk_pose(m, 0.275f, &pose);  // the legs at their widest
    body::walk_capsules(m, rest, 0.275f, &posed);
    REQUIRE(posed.size() == rest.size());
    uint32_t rigid = 0;
    for (size_t c = 0; c < rest.size(); ++c) {
        CAPTURE(c);
        CHECK(rest[c].radius_m > 0.03f);  // a thigh or an upper arm, not a point
        CHECK(rest[c].radius_m < 0.12f);
        // Of the vertices that follow this bone alone and project within the capsule's axis, about 3
        // in 4 lie within its radius (the first section, shortened, more); the nearly rigid ones keep
        // their distance from the moved axis.
        uint32_t near = 0, count = 0;
        double drift = 0.0;
        for (size_t v = 0; v < m.positions.size(); ++v) {
            const int k = m.weight[v][0] >= m.weight[v][1] ? 0 : 1;
            if (m.bone[v][k] != rest[c].bone || m.weight[v][k] < 0.9f) continue;
            const auto [d, t] = axis_distance(m.positions[v], rest[c].p0, rest[c].p1);
            if (t < 0.0 || t > 1.0) continue;
            ++count;
            near += d <= rest[c].radius_m ? 1 : 0;
            if (m.weight[v][k] < 0.99f) continue;
            ++rigid;
            drift = std::max(drift, std::abs(axis_distance(pose[v], posed[c].p0, posed[c].p1).first - d));
        }
        REQUIRE(count > 20);
        CHECK(double(near) / count > 0.5);
        CHECK(drift < 0.002);
    }
    CHECK(rigid > 20);
    std::vector<body::LimbCapsule> none;
    CHECK(body::fit_limb_capsules(m, {"tail"}, 2, &none).find("no bone named 'tail'") != std::string::npos);
    CHECK(!body::fit_limb_capsules(m, {"thigh.L"}, 0, &none).empty());
}

}  // namespace
}  // namespace weft
