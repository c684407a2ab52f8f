// The viewer's simulation side (samples/viewer/session.h), without a window: every control of the
// panel changes the world it claims to change, a baked asset opens above a floor, and the camera
// frames, pans, zooms and orbits as the mouse says.
#include <doctest/doctest.h>

#include <cmath>

#include "viewer/orbit.h"
#include "viewer/session.h"

using namespace weft;

namespace {

const std::string kScenes = std::string(WEFT_SOURCE_DIR) + "/samples/scenes/";

std::vector<Vec3> positions(viewer::Session& s) { return s.snapshot().cloths[0].positions; }

}  // namespace

TEST_CASE("viewer controls: no gravity keeps the cloth still, turning the wind on resets and runs the wind pass") {
    viewer::Session s;
    REQUIRE(s.open(kScenes + "sphere.json", {}).empty());
    CHECK_FALSE(s.controls().wind_on);
    CHECK(s.controls().gravity_m_s2 == doctest::Approx(9.81f));
    CHECK(s.controls().inflation_m == doctest::Approx(0.01f));
    viewer::Controls c = s.controls();
    c.gravity_m_s2 = 0.0f;
    REQUIRE(s.apply(c).empty());
    const std::vector<Vec3> start = positions(s);
    std::string error;
    for (int i = 0; i < 10; ++i) REQUIRE(s.step(&error));
    const std::vector<Vec3> after = positions(s);
    for (size_t i = 0; i < start.size(); ++i) REQUIRE(after[i].y == start[i].y);
    CHECK(s.last().pass_ms[int(viewer::PassGroup::wind)] == 0.0);
    CHECK(s.last().pass_ms[int(viewer::PassGroup::constraints)] > 0.0);

    c.wind_on = true;
    c.wind_speed_m_s = 20.0f;
    c.wind_direction_deg = 90.0f;  // towards +z
    REQUIRE(s.apply(c).empty());
    CHECK(s.frame() == 0);  // a new world, with the wind pass
    for (int i = 0; i < 10; ++i) REQUIRE(s.step(&error));
    CHECK(s.last().pass_ms[int(viewer::PassGroup::wind)] > 0.0);
}

TEST_CASE("viewer controls: the wind's direction turns the flag") {
    // The flag hangs in the x-y plane; wind along +z or -z meets it face on and blows it that way.
    for (float direction_deg : {90.0f, -90.0f}) {
        viewer::Session s;
        REQUIRE(s.open(kScenes + "flag.json", {}).empty());
        CHECK(s.controls().wind_on);
        CHECK(s.controls().wind_speed_m_s == doctest::Approx(20.0f));
        viewer::Controls c = s.controls();
        c.wind_direction_deg = direction_deg;
        REQUIRE(s.apply(c).empty());
        std::string error;
        for (int i = 0; i < 10; ++i) REQUIRE(s.step(&error));
        double mean_z = 0.0;
        const std::vector<Vec3> p = positions(s);
        for (const Vec3& q : p) mean_z += q.z / double(p.size());
        INFO("direction " << direction_deg << " deg: mean z " << mean_z << " m");
        CHECK(mean_z * (direction_deg > 0.0f ? 1.0 : -1.0) > 0.1);
    }
}

TEST_CASE("viewer controls: an explicit split and the tethers reach the runtime") {
    viewer::Session s;
    REQUIRE(s.open(kScenes + "drape.json", {}).empty());
    CHECK(s.split().tethers);
    viewer::Controls c = s.controls();
    c.explicit_split = true;
    c.substeps = 2;
    c.iterations = 5;
    c.tethers = false;
    REQUIRE(s.apply(c).empty());
    CHECK(s.split().substeps == 2);
    CHECK(s.split().iterations == 5);
    CHECK_FALSE(s.split().tethers);
}

TEST_CASE("viewer controls: a thicker collider skin holds the cloth further off the sphere") {
    for (float inflation_m : {0.0f, 0.05f}) {
        viewer::Session s;
        REQUIRE(s.open(kScenes + "sphere.json", {}).empty());
        viewer::Controls c = s.controls();
        c.inflation_m = inflation_m;
        REQUIRE(s.apply(c).empty());
        CHECK(s.snapshot().colliders[0].inflation_m == inflation_m);
        std::string error;
        for (int i = 0; i < 40; ++i) REQUIRE(s.step(&error));
        double nearest_m = 1e9;  // the sphere: centre at the origin, radius 0.5 m
        for (const Vec3& p : positions(s)) nearest_m = std::min(nearest_m, double(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z)));
        INFO("inflation " << inflation_m << " m: nearest particle " << nearest_m << " m from the centre");
        CHECK(nearest_m > 0.5 + inflation_m - 0.005);
        CHECK(nearest_m < 0.5 + inflation_m + 0.02);  // it does lie on the sphere
    }
}

TEST_CASE("the viewer opens a baked asset above a floor it lands on") {
    viewer::Session s;
    REQUIRE(s.open(WEFT_SAMPLE_ASSETS "/sheet.weft", {}).empty());
    REQUIRE(s.scene().colliders.size() == 1);
    const ColliderDesc floor = s.scene().colliders[0];
    CHECK(floor.shape == ColliderShape::plane);
    std::string error;
    for (int i = 0; i < 60; ++i) REQUIRE(s.step(&error));
    for (const Vec3& p : positions(s)) REQUIRE(p.y > floor.p0.y - 0.01f);
    CHECK(s.open("no-such-asset.weft", {}) != "");
    CHECK(s.open(kScenes + "no-such-scene.json", {}) != "");
}

TEST_CASE("viewer camera: framing right of the panel, pan follows the mouse, zoom and orbit") {
    render::Box box;
    box.add({-1.0f, 0.0f, -1.0f});
    box.add({1.0f, 0.5f, 1.0f});
    constexpr int kWidth = 1600, kHeight = 900;
    constexpr float kAspect = float(kWidth) / kHeight, kPanel = 0.3f;
    viewer::Orbit orbit = viewer::frame_orbit(box, (1.0f - kPanel) * kAspect);
    const render::Camera camera = viewer::orbit_camera(orbit, kAspect, kPanel);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p{corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                          corner & 4 ? box.max.z : box.min.z};
        const glm::vec2 q = render::project_to_pixels(camera, p, kWidth, kHeight);
        CHECK(q.x >= kPanel * kWidth);  // never under the panel
        CHECK(q.x <= kWidth);
        CHECK(q.y >= 0.0f);
        CHECK(q.y <= kHeight);
    }
    // Dragging 100 pixels right and 50 down moves the scene with the mouse.
    const glm::vec2 before = render::project_to_pixels(camera, orbit.target, kWidth, kHeight);
    viewer::Orbit panned = orbit;
    viewer::pan(&panned, camera, 100.0f, 50.0f, float(kHeight));
    const glm::vec2 after = render::project_to_pixels(viewer::orbit_camera(panned, kAspect, kPanel), orbit.target, kWidth, kHeight);
    CHECK(after.x - before.x == doctest::Approx(100.0f).epsilon(0.02));
    CHECK(after.y - before.y == doctest::Approx(50.0f).epsilon(0.02));
    viewer::Orbit zoomed = orbit;
    viewer::zoom(&zoomed, 2.0f);  // two wheel steps in
    CHECK(zoomed.distance_m == doctest::Approx(orbit.distance_m * 0.88f * 0.88f));
    viewer::rotate(&zoomed, 0.0f, 1000.0f);  // dragging far down stops looking straight down
    CHECK(zoomed.elevation_deg == 89.0f);
}
