// The renderer (tools/render) on the headless context: the sphere scene's picture is not blank,
// and the cloth's pixels are where the cloth's projected bounding box says they must be; the dressed
// skirt in wind (figure 14) shows the body around the garment. Runs on
// Mesa's llvmpipe through EGL's surfaceless platform: no display, no GPU.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>

#include "render/headless.h"
#include "render/renderer.h"
#include "common/scene_json.h"
#include "render/scene_snapshot.h"

using namespace weft;

namespace {

constexpr int kWidth = 320, kHeight = 180;

bool is_cloth_mask(const render::Image& image, int x, int y) {
    const uint8_t* p = image.pixel(x, y);
    return p[0] == render::kClothMaskRgb[0] && p[1] == render::kClothMaskRgb[1] && p[2] == render::kClothMaskRgb[2];
}

uint32_t packed(const uint8_t* p) { return uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]; }

// A sample scene stepped `frames` times, and the renderer on a kWidth x kHeight headless context.
struct Stage {
    scenes::Scene scene;
    scenes::SceneWorld world;
    std::unique_ptr<render::HeadlessContext> context;
    std::unique_ptr<render::Renderer> renderer;
};

void set_stage(const std::string& scene_file, int frames, Stage* s) {
    REQUIRE(scenes::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/samples/scenes/" + scene_file, &s->scene).empty());
    const std::string built = scenes::build_scene(s->scene, &s->world, {WEFT_SAMPLE_ASSETS_DIR});
    REQUIRE_MESSAGE(built.empty(), built);
    for (int frame = 0; frame < frames; ++frame) REQUIRE(step(s->world.world, s->scene.dt_s).ok());
    std::string error;
    s->context = render::HeadlessContext::create(kWidth, kHeight, &error);
    REQUIRE_MESSAGE(s->context, error);
    s->renderer = render::Renderer::create(&error);
    REQUIRE_MESSAGE(s->renderer, error);
}

}  // namespace

TEST_CASE("frame_box keeps the whole box in the picture, from any direction") {
    render::Box box;
    box.add({-1.0f, -0.5f, -2.0f});
    box.add({3.0f, 0.5f, 1.0f});
    for (float azimuth : {0.0f, 35.0f, 90.0f, 200.0f}) {
        for (float elevation : {-30.0f, 0.0f, 20.0f, 80.0f}) {
            const render::Camera camera = render::frame_box(box, {azimuth, elevation, 0.0f}, 16.0f / 9.0f);
            float min_x = 1e9f, max_x = -1e9f, min_y = 1e9f, max_y = -1e9f;
            for (int corner = 0; corner < 8; ++corner) {
                const glm::vec3 p{corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                                  corner & 4 ? box.max.z : box.min.z};
                const glm::vec2 q = render::project_to_pixels(camera, p, 1600, 900);
                min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
                min_y = std::min(min_y, q.y), max_y = std::max(max_y, q.y);
            }
            INFO("azimuth " << azimuth << ", elevation " << elevation);
            CHECK(min_x >= 0.0f);
            CHECK(max_x <= 1600.0f);
            CHECK(min_y >= 0.0f);
            CHECK(max_y <= 900.0f);
            // Not lost in the distance: the camera aims at the box's centre, so perspective leaves the
            // far side some slack, but the box still spans most of the picture one way.
            CHECK(std::max((max_x - min_x) / 1600.0f, (max_y - min_y) / 900.0f) > 0.6f);
        }
    }
}

TEST_CASE("planar_uv lays the rest cloth out on its two widest axes, in metres") {
    // A vertical 2 m x 1 m rectangle in the x-y plane.
    const std::vector<Vec3> rest = {{0, 3, 0}, {2, 3, 0}, {0, 2, 0}, {2, 2, 0}};
    const std::vector<float> uv = render::planar_uv(rest);
    REQUIRE(uv.size() == 8);
    CHECK(uv[0] == doctest::Approx(0.0f));
    CHECK(uv[1] == doctest::Approx(1.0f));
    CHECK(uv[2] == doctest::Approx(2.0f));
    CHECK(uv[7] == doctest::Approx(0.0f));
}

TEST_CASE("the sphere scene's picture: not blank, and the cloth inside its projected bounding box") {
    // 5 frames: the cloth is still falling, above the sphere, so it fills the top of the picture
    // (a picture upside down or mirrored puts it elsewhere).
    Stage stage;
    set_stage("sphere.json", 5, &stage);
    const auto& context = stage.context;
    const auto& renderer = stage.renderer;
    render::Snapshot snapshot = render::snapshot_of_scene(stage.scene, stage.world);
    const render::Camera camera = render::frame_box(render::bounds(snapshot), {35.0f, 30.0f, 0.0f}, float(kWidth) / kHeight);

    context->begin_frame();
    renderer->draw(snapshot, camera, kWidth, kHeight, render::Look::shaded);
    const render::Image shaded = context->read_image();
    // The cloth alone in its flat colour, seen by the same camera: its pixels, unhidden by the sphere.
    snapshot.colliders.clear();
    context->begin_frame();
    renderer->draw(snapshot, camera, kWidth, kHeight, render::Look::cloth_mask);
    const render::Image mask = context->read_image();
    REQUIRE(shaded.rgb.size() == size_t(3 * kWidth * kHeight));

    // Where the particles project to.
    const render::PixelBox box = render::projected_box(camera, snapshot.cloths[0].positions, kWidth, kHeight);
    const float box_x0 = box.min.x, box_x1 = box.max.x, box_y0 = box.min.y, box_y1 = box.max.y;
    INFO("projected cloth box x " << box_x0 << ".." << box_x1 << ", y " << box_y0 << ".." << box_y1);
    REQUIRE(box_x1 - box_x0 > 40.0f);
    REQUIRE(box_y1 - box_y0 > 10.0f);
    CHECK(box_y1 < 0.75f * kHeight);  // above the sphere: the upper part of the picture

    // Every cloth pixel (its centre) lies in the box, give or take one pixel, and the cloth reaches
    // all four sides of it (within 3 pixels: a corner seen edge-on thins below a pixel).
    int cloth_pixels = 0, outside = 0;
    float seen_x0 = 1e9f, seen_x1 = -1e9f, seen_y0 = 1e9f, seen_y1 = -1e9f;
    std::set<uint32_t> colours;
    std::map<uint32_t, int> cloth_colours;  // shaded colour -> pixels
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            colours.insert(packed(shaded.pixel(x, y)));
            if (!is_cloth_mask(mask, x, y)) continue;
            ++cloth_pixels;
            ++cloth_colours[packed(shaded.pixel(x, y))];
            const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
            outside += cx < box_x0 - 1.0f || cx > box_x1 + 1.0f || cy < box_y0 - 1.0f || cy > box_y1 + 1.0f;
            seen_x0 = std::min(seen_x0, cx), seen_x1 = std::max(seen_x1, cx);
            seen_y0 = std::min(seen_y0, cy), seen_y1 = std::max(seen_y1, cy);
        }
    }
    CHECK(outside == 0);
    CHECK(seen_x0 < box_x0 + 3.0f);
    CHECK(seen_x1 > box_x1 - 3.0f);
    CHECK(seen_y0 < box_y0 + 3.0f);
    CHECK(seen_y1 > box_y1 - 3.0f);
    // A flat square seen at an angle covers about half of its box.
    CHECK(cloth_pixels > 0.25f * (box_x1 - box_x0) * (box_y1 - box_y0));

    // Not blank: sky, ground, sphere and cloth make many colours; the cloth (flat and evenly lit
    // while it falls) shows its checker: two colours of about half its pixels each, neither the
    // mask's colour nor the sky's.
    CHECK(colours.size() > 200);
    std::vector<int> counts;
    for (const auto& [colour, pixels] : cloth_colours) counts.push_back(pixels);
    std::sort(counts.rbegin(), counts.rend());
    REQUIRE(counts.size() >= 2);
    CHECK(counts[0] > cloth_pixels / 5);
    CHECK(counts[1] > cloth_pixels / 5);
    CHECK(cloth_colours.count(packed(render::kClothMaskRgb)) == 0);
    CHECK(cloth_colours.count(packed(shaded.pixel(kWidth / 2, 0))) == 0);
}

TEST_CASE("the dressed skirt's picture (figure 14): the body is drawn, the garment inside its projected box") {
    Stage stage;
    set_stage("skirt-wind.json", 5, &stage);
    const auto& context = stage.context;
    const auto& renderer = stage.renderer;
    const render::Snapshot snapshot = render::snapshot_of_scene(stage.scene, stage.world);
    REQUIRE(snapshot.bodies.size() == 1);
    REQUIRE(snapshot.bodies[0].positions.size() == stage.world.body->rest.size());
    // From the front: the garment is framed with the whole body (the box holds the body).
    const render::Camera camera = render::frame_box(render::bounds(snapshot), {0.0f, 10.0f, 0.0f}, float(kWidth) / kHeight);
    context->begin_frame();
    renderer->draw(snapshot, camera, kWidth, kHeight, render::Look::cloth_mask);
    const render::Image mask = context->read_image();

    const render::PixelBox cloth = render::projected_box(camera, snapshot.cloths[0].positions, kWidth, kHeight);
    const render::PixelBox body = render::projected_box(camera, snapshot.bodies[0].positions, kWidth, kHeight);
    INFO("cloth box x " << cloth.min.x << ".." << cloth.max.x << ", y " << cloth.min.y << ".." << cloth.max.y);
    INFO("body box x " << body.min.x << ".." << body.max.x << ", y " << body.min.y << ".." << body.max.y);
    // The skirt hangs from the waist: below the head, above the feet, inside the body's box.
    REQUIRE(cloth.min.y > body.min.y + 0.2f * (body.max.y - body.min.y));
    REQUIRE(cloth.max.y < body.max.y - 0.1f * (body.max.y - body.min.y));
    int cloth_pixels = 0, cloth_outside = 0, body_pixels = 0, body_outside = 0, body_above_cloth = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
            const uint8_t* p = mask.pixel(x, y);
            if (is_cloth_mask(mask, x, y)) {
                ++cloth_pixels;
                cloth_outside += cx < cloth.min.x - 1.0f || cx > cloth.max.x + 1.0f || cy < cloth.min.y - 1.0f || cy > cloth.max.y + 1.0f;
            } else if (p[0] == render::kColliderMaskRgb[0] && p[1] == render::kColliderMaskRgb[1] &&
                       p[2] == render::kColliderMaskRgb[2]) {
                ++body_pixels;
                body_outside += cx < body.min.x - 1.0f || cx > body.max.x + 1.0f || cy < body.min.y - 1.0f || cy > body.max.y + 1.0f;
                body_above_cloth += cy < cloth.min.y;
            }
        }
    }
    CHECK(cloth_outside == 0);
    CHECK(body_outside == 0);
    CHECK(cloth_pixels > 0.3f * (cloth.max.x - cloth.min.x) * (cloth.max.y - cloth.min.y));
    CHECK(body_above_cloth > 200);  // the torso, arms and head above the waistband
    CHECK(body_pixels > body_above_cloth);  // and the legs below the hem
}
