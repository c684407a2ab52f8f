// weft-draw-obj: draws OBJ files with the renderer (tools/render) into a PNG, headless. The figure
// of the sewing (make-figures' figure 13) draws the frames weft-bake --sewing-frames writes: the
// garment as a cloth (checker from its vt, metres on the flat panel) and the body beside it.
//
//   weft-draw-obj CLOTH.obj... --png OUT.png [--body BODY.obj] [--frame-with OBJ...]
//                 [--camera AZIMUTH,ELEVATION[,DISTANCE]] [--size WxH] [--json]
//
// --frame-with: more OBJ files the camera frames as well (not drawn), so that several pictures of
// one sequence share one camera. --json prints where the cloths project to (pixels).
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "body/body_mesh.h"
#include "render/headless.h"
#include "sim/pictures.h"
#include "render/renderer.h"

namespace {

using namespace weft;

int fail(const std::string& message) {
    std::fprintf(stderr, "weft-draw-obj: %s\n", message.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-draw-obj: OBJ cloths (and a body) drawn by Weft's renderer into a PNG"};
    std::vector<std::string> cloth_paths, frame_with;
    std::string png, body_path, camera_text = "35,20", size_text = "1280x720";
    bool as_json = false;
    app.add_option("cloths", cloth_paths, "OBJ files drawn as cloth (vt: the checker's coordinates, metres)")->required();
    app.add_option("--png", png, "the picture to write")->required();
    app.add_option("--body", body_path, "an OBJ (or glTF) file drawn as the body");
    app.add_option("--frame-with", frame_with, "OBJ files the camera frames too (not drawn)");
    app.add_option("--camera", camera_text, "AZIMUTH,ELEVATION[,DISTANCE]: degrees, degrees, metres (0: frame the scene)");
    app.add_option("--size", size_text, "WIDTHxHEIGHT in pixels");
    app.add_flag("--json", as_json, "print the cloths' projected pixel box as JSON");
    CLI11_PARSE(app, argc, argv);

    sim::PictureOptions options;  // weft-sim's parsing of --camera and --size
    if (std::string e = sim::parse_camera(camera_text, &options); !e.empty()) return fail(e);
    if (std::string e = sim::parse_size(size_text, &options); !e.empty()) return fail(e);

    render::Snapshot snapshot;
    std::vector<Vec3> cloth_points;
    for (const std::string& path : cloth_paths) {
        body::BodyMesh mesh;
        if (std::string e = body::load_body_mesh(path, &mesh); !e.empty()) return fail(e);
        cloth_points.insert(cloth_points.end(), mesh.positions.begin(), mesh.positions.end());
        std::vector<float> uv = mesh.uv.empty() ? render::planar_uv(mesh.positions) : mesh.uv;
        snapshot.cloths.push_back({std::move(mesh.positions), std::move(mesh.triangles), std::move(uv)});
    }
    if (!body_path.empty()) {
        body::BodyMesh mesh;
        if (std::string e = body::load_body_mesh(body_path, &mesh); !e.empty()) return fail(e);
        snapshot.bodies.push_back({std::move(mesh.positions), std::move(mesh.triangles)});
    }
    render::Box box = render::bounds(snapshot);
    for (const std::string& path : frame_with) {
        body::BodyMesh mesh;
        if (std::string e = body::load_body_mesh(path, &mesh); !e.empty()) return fail(e);
        for (const Vec3& p : mesh.positions) box.add({p.x, p.y, p.z});
    }

    const int width = options.width, height = options.height;
    std::string error;
    const std::unique_ptr<render::HeadlessContext> context = render::HeadlessContext::create(width, height, &error);
    if (!context) return fail(error);
    const std::unique_ptr<render::Renderer> renderer = render::Renderer::create(&error);
    if (!renderer) return fail(error);
    const render::Camera camera = render::frame_box(
        box, {options.azimuth_deg, options.elevation_deg, options.distance_m}, float(width) / float(height));
    context->begin_frame();
    renderer->draw(snapshot, camera, width, height);
    if (!render::write_png(png, context->read_image())) return fail("cannot write " + png);
    if (as_json) {
        const render::PixelBox b = render::projected_box(camera, cloth_points, width, height);
        std::printf("{\"png\":\"%s\",\"cloth_box_px\":[%.1f,%.1f,%.1f,%.1f]}\n", png.c_str(), b.min.x, b.min.y, b.max.x,
                    b.max.y);
    }
    return 0;
}
