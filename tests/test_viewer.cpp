// The interactive viewer (samples/viewer), seen as a person sees it: CTest's fixture
// viewer.screenshot_under_xvfb runs weft-viewer under Xvfb on the sphere scene for 30 frames and
// writes the whole window (panel included) to a PNG. This test reads that picture and checks it
// as test_render.cpp checks weft-sim's: not blank, and the cloth's front (the renderer's brick red,
// the only red on the screen) exactly where the cloth's projected bounding box says, for the
// viewer's first camera (viewer::frame_orbit of frame 0) and the cloth after 30 steps.
#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include <stb_image.h>  // the implementation is in Debian's libstb

#include "viewer/orbit.h"
#include "viewer/session.h"

using namespace weft;

namespace {

// The lit, checkered front side: red well above green and blue (the sky is blue, the ground and the
// sphere grey, the panel dark grey and blue; the panel's translucent background over the cloth
// falls below the ratio).
bool is_cloth_front(const unsigned char* p) {
    return p[0] > 60 && p[0] > 1.4f * p[1] && p[0] > 1.4f * p[2];
}

}  // namespace

TEST_CASE("the viewer's screenshot after 30 frames of the sphere: not blank, the cloth inside its projected box") {
    int width = 0, height = 0, channels = 0;
    unsigned char* pixels = stbi_load(WEFT_VIEWER_SCREENSHOT, &width, &height, &channels, 3);
    REQUIRE_MESSAGE(pixels, "no screenshot at " WEFT_VIEWER_SCREENSHOT " (the fixture viewer.screenshot_under_xvfb writes it)");
    const auto pixel = [&](int x, int y) { return pixels + 3 * (size_t(y) * size_t(width) + size_t(x)); };
    CHECK(width == 1280);
    CHECK(height == 720);

    // The same simulation as the viewer's (the viewer's own Session: deterministic, same SIMD path).
    viewer::Session session;
    REQUIRE(session.open(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/sphere.json", {}).empty());
    // The viewer's first camera: the scene at frame 0 framed into the part of the window right of the panel.
    const float aspect = float(width) / float(height), panel = viewer::kPanelWidth / float(width);
    const render::Camera camera = viewer::orbit_camera(
        viewer::frame_orbit(render::bounds(session.snapshot()), (1.0f - panel) * aspect), aspect, panel);
    std::string error;
    for (int frame = 0; frame < 30; ++frame) REQUIRE_MESSAGE(session.step(&error), error);
    CHECK(session.last().max_penetration_m < 0.005);

    const render::PixelBox box = render::projected_box(camera, session.snapshot().cloths[0].positions, width, height);
    const float box_x0 = box.min.x, box_x1 = box.max.x, box_y0 = box.min.y, box_y1 = box.max.y;
    INFO("projected cloth box x " << box_x0 << ".." << box_x1 << ", y " << box_y0 << ".." << box_y1);
    REQUIRE(box_x1 - box_x0 > 100.0f);
    REQUIRE(box_y1 - box_y0 > 50.0f);

    std::set<uint32_t> colours;
    int cloth = 0, outside = 0;
    float seen_x0 = 1e9f, seen_x1 = -1e9f, seen_y0 = 1e9f, seen_y1 = -1e9f;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const unsigned char* p = pixel(x, y);
            colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
            if (!is_cloth_front(p)) continue;
            ++cloth;
            const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
            outside += cx < box_x0 - 2.0f || cx > box_x1 + 2.0f || cy < box_y0 - 2.0f || cy > box_y1 + 2.0f;
            seen_x0 = std::min(seen_x0, cx), seen_x1 = std::max(seen_x1, cx);
            seen_y0 = std::min(seen_y0, cy), seen_y1 = std::max(seen_y1, cy);
        }
    }
    INFO("cloth pixels " << cloth << ", seen x " << seen_x0 << ".." << seen_x1 << ", y " << seen_y0 << ".." << seen_y1);
    CHECK(colours.size() > 200);  // sky, ground grid, sphere, checkered cloth, the panel's text
    CHECK(outside == 0);
    // The cloth lies over the sphere, its front up: seen from 20 degrees above it fills much of its
    // box, reaches the box's top and bottom, and spans most of its width (the folds at the far left
    // and right show the blue back).
    CHECK(cloth > 0.3f * (box_x1 - box_x0) * (box_y1 - box_y0));
    CHECK(seen_y0 < box_y0 + 3.0f);
    CHECK(seen_y1 > box_y1 - 3.0f);
    CHECK(seen_x1 - seen_x0 > 0.8f * (box_x1 - box_x0));
    // ... and right of the panel: the camera centres the scene in the part of the window it leaves free.
    CHECK(seen_x0 > viewer::kPanelWidth);
    stbi_image_free(pixels);
}
