// Layered garments (ClothDesc::worn_over, runtime/src/collide/layers.h): the overshirt worn over
// the tee on the walking mannequin (samples/scenes/layers-walk.json) never passes through it, and
// does without the layers; the inner cloth is not moved by the outer; the stages give the same bits
// however the game runs them; the settings and ids are checked.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "common/metrics.h"
#include "common/scene_json.h"
#include "support/test_support.h"
#include "weft/debug.h"

using namespace weft;

namespace {

std::string layers_scene() { return std::string(WEFT_SOURCE_DIR) + "/samples/scenes/layers-walk.json"; }

void build_layers(bool worn_over, scenes::SceneWorld* w, scenes::Scene* scene) {
    REQUIRE(scenes::load_scene_file(layers_scene(), scene).empty());
    REQUIRE(scene->cloths.size() == 2);
    if (!worn_over) scene->cloths[1].worn_over.clear();
    const std::string e = scenes::build_scene(*scene, w, {WEFT_SAMPLE_ASSETS_DIR});
    INFO(e);
    REQUIRE(e.empty());
}

ClothView view(const scenes::SceneWorld& w, uint32_t i) {
    ClothView v;
    REQUIRE(view_cloth(w.world, w.cloths[i].id, &v).ok());
    return v;
}

}  // namespace

// The overshirt is baked over the tee (samples/assets.json: weft-bake --over), so it starts outside
// it. Worn over the tee it never passes through it in ten seconds of the walk (the first one its
// ramp; the crossings counted every sixth frame); worn over nothing it goes into the tee at once.
TEST_CASE("layers: the overshirt baked and worn over the tee never passes through it on the walking mannequin") {
    for (bool worn_over : {true, false}) {
        CAPTURE(worn_over);
        scenes::Scene scene;
        scenes::SceneWorld w;
        build_layers(worn_over, &w, &scene);
        CHECK(metrics::layer_crossings(view(w, 0), view(w, 1)) == 0);  // dressed in layer order
        const uint32_t frames = worn_over ? 600 : 120;
        uint32_t crossing_frames = 0, counted = 0;
        uint64_t contacts = 0;
        for (uint32_t f = 1; f <= frames; ++f) {
            REQUIRE(scenes::animate_body(w, float(f) * scene.dt_s).empty());
            REQUIRE(step(w.world, scene.dt_s).ok());
            contacts += world_stats(w.world).layer_contacts;
            if (f % 6 != 0) continue;
            counted += 1;
            crossing_frames += metrics::layer_crossings(view(w, 0), view(w, 1)) > 0;
        }
        CHECK(metrics::bounds(view(w, 1)).finite);
        if (worn_over) {
            CHECK(crossing_frames == 0);
            CHECK(contacts > 0);
        } else {
            CHECK(crossing_frames > counted / 2);
            CHECK(contacts == 0);
        }
    }
}

// weft-bake --over reports the crossings of a layered garment's dressed pose with those under it
// (SewReport::layer_crossings, this count on the two assets' start poses): none for the sample
// overshirt, and the tee pushed 4 cm out from the body's axis shows through it.
TEST_CASE("layers: the dressed overshirt's crossings with the tee are counted on the assets, none in layer order") {
    scenes::Scene scene;
    scenes::SceneWorld w;
    build_layers(true, &w, &scene);
    const ClothAsset &tee = *w.cloths[0].asset, &overshirt = *w.cloths[1].asset;
    CHECK(metrics::layer_crossings(overshirt, tee) == 0);
    CHECK(metrics::layer_crossings(overshirt, tee) == metrics::layer_crossings(view(w, 1), view(w, 0)));
    std::vector<float> x(tee.start_x, tee.start_x + tee.slot_count), z(tee.start_z, tee.start_z + tee.slot_count);
    for (uint32_t s = 0; s < tee.slot_count; ++s) {
        const float r = std::sqrt(x[s] * x[s] + z[s] * z[s]);
        if (r > 0.0f) x[s] *= (r + 0.04f) / r, z[s] *= (r + 0.04f) / r;
    }
    ClothAsset pushed = tee;
    pushed.start_x = x.data();
    pushed.start_z = z.data();
    CHECK(metrics::layer_crossings(overshirt, pushed) > 0);
}

// The inner cloth steps before the outer one and is never written by it: the tee moves the same
// with the overshirt worn over it as alone.
TEST_CASE("layers: the inner cloth wins: the tee moves the same bits under the overshirt as without it") {
    scenes::Scene scene;
    scenes::SceneWorld with, alone;
    build_layers(true, &with, &scene);
    scenes::Scene tee_only = scene;
    tee_only.cloths.resize(1);
    REQUIRE(scenes::build_scene(tee_only, &alone, {WEFT_SAMPLE_ASSETS_DIR}).empty());
    for (uint32_t f = 1; f <= 60; ++f) {
        for (scenes::SceneWorld* w : {&with, &alone}) {
            REQUIRE(scenes::animate_body(*w, float(f) * scene.dt_s).empty());
            REQUIRE(step(w->world, scene.dt_s).ok());
        }
    }
    const uint32_t n = with.cloths[0].asset->particle_count;
    CHECK(test::same_bits(test::read_all(with.world, with.cloths[0].id, n), test::read_all(alone.world, alone.cloths[0].id, n)));
    CHECK(world_stats(with.world).layer_contacts > 0);
}

// The game running the stages itself, in ranges of one item, gives the bits step() gives; the layer
// stage has items only while a cloth is in it.
TEST_CASE("layers: the stages run item by item give step()'s bits") {
    scenes::Scene scene;
    scenes::SceneWorld a, b;
    build_layers(true, &a, &scene);
    build_layers(true, &b, &scene);
    CHECK(step_stage_items(a.world, StepStage::second_layer) == 2);
    CHECK(step_stage_items(a.world, StepStage::third_layer) == 0);
    for (uint32_t f = 1; f <= 20; ++f) {
        REQUIRE(scenes::animate_body(a, float(f) * scene.dt_s).empty());
        REQUIRE(scenes::animate_body(b, float(f) * scene.dt_s).empty());
        REQUIRE(step(a.world, scene.dt_s).ok());
        REQUIRE(begin_step(b.world, scene.dt_s).ok());
        for (StepStage stage : {StepStage::bodies, StepStage::cloths, StepStage::second_layer, StepStage::third_layer})
            for (uint32_t i = 0; i < step_stage_items(b.world, stage); ++i) REQUIRE(run_step_items(b.world, stage, i, i + 1).ok());
        REQUIRE(end_step(b.world).ok());
    }
    for (uint32_t c = 0; c < 2; ++c) {
        const uint32_t n = a.cloths[c].asset->particle_count;
        CHECK(test::same_bits(test::read_all(a.world, a.cloths[c].id, n), test::read_all(b.world, b.cloths[c].id, n)));
    }
}

TEST_CASE("layers: worn_over is checked: live ids, the layer limit, the memory, the removal order") {
    scenes::Scene scene;
    scenes::SceneWorld w;
    build_layers(false, &w, &scene);
    const ClothAsset& tee = *w.cloths[0].asset;
    // A world of its own, with room for four cloths and their layers.
    WorldDesc wd;
    wd.max_cloths = 0;
    ClothDesc cd;
    cd.asset = &tee;
    for (int i = 0; i < 4; ++i) reserve_cloth(wd, cd);
    test::OwnedWorld owned;
    REQUIRE(test::make_world(wd, &owned).ok());  // no layer memory yet
    ClothId inner{}, outer{};
    REQUIRE(add_cloth(owned.world, cd, &inner).ok());
    ClothDesc over = cd;
    over.worn_over[0] = inner;
    over.worn_over_count = 1;
    CHECK(add_cloth(owned.world, over, &outer).code == ErrorCode::capacity_exceeded);

    for (int i = 0; i < 3; ++i) reserve_layer(wd, tee, tee);
    test::OwnedWorld layered;
    REQUIRE(test::make_world(wd, &layered).ok());
    REQUIRE(add_cloth(layered.world, cd, &inner).ok());
    ClothDesc bad = over;
    bad.worn_over[0] = {inner.index, inner.generation + 1};
    CHECK(add_cloth(layered.world, bad, &outer).code == ErrorCode::stale_id);
    bad = over;
    bad.worn_over_count = kMaxWornOver + 1;
    CHECK(add_cloth(layered.world, bad, &outer).code == ErrorCode::out_of_range);
    bad = over;
    bad.layer_thickness_m = -1.0f;
    CHECK(add_cloth(layered.world, bad, &outer).code == ErrorCode::out_of_range);
    over.worn_over[0] = inner;
    REQUIRE(add_cloth(layered.world, over, &outer).ok());
    CHECK(step_stage_items(layered.world, StepStage::second_layer) == 2);
    ClothId third{};
    ClothDesc over_over = cd;
    over_over.worn_over[0] = outer;
    over_over.worn_over_count = 1;
    REQUIRE(add_cloth(layered.world, over_over, &third).ok());  // the third layer
    CHECK(step_stage_items(layered.world, StepStage::third_layer) == 3);
    ClothId fourth{};
    over_over.worn_over[0] = third;
    CHECK(add_cloth(layered.world, over_over, &fourth).code == ErrorCode::out_of_range);  // beyond kMaxClothLayers
    // worn_over is fixed at add_cloth.
    ClothDesc changed = over;
    changed.worn_over_count = 0;
    CHECK(set_cloth_settings(layered.world, outer, changed).code == ErrorCode::invalid_argument);
    // Removal: the outer layers first.
    CHECK(remove_cloth(layered.world, inner).code == ErrorCode::invalid_argument);
    CHECK(remove_cloth(layered.world, outer).code == ErrorCode::invalid_argument);
    REQUIRE(step(layered.world, 1.0f / 60.0f).ok());
    REQUIRE(remove_cloth(layered.world, third).ok());
    REQUIRE(remove_cloth(layered.world, outer).ok());
    REQUIRE(remove_cloth(layered.world, inner).ok());
    CHECK(step_stage_items(layered.world, StepStage::second_layer) == 0);
    // The pools are whole again: the three go back in.
    REQUIRE(add_cloth(layered.world, cd, &inner).ok());
    over.worn_over[0] = inner;
    REQUIRE(add_cloth(layered.world, over, &outer).ok());
    over_over.worn_over[0] = outer;
    REQUIRE(add_cloth(layered.world, over_over, &third).ok());
}
