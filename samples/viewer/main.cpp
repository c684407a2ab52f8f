// weft-viewer: a window onto any scene file or baked asset (GLFW + OpenGL 3.3 + Dear ImGui, drawn
// by tools/render's Renderer, the same one as weft-sim's pictures).
//
//   weft-viewer SCENE.json|ASSET.weft [--assets DIR] [--size WxH] [--paused]
//               [--frames N --screenshot FILE.png]
//
// Left mouse drag orbits, right (or middle) drag pans, the wheel zooms; space plays and pauses,
// S or the right arrow steps once, R resets, F frames the scene again. The panel changes the wind,
// gravity, the solver's budget, the tethers and the colliders' inflation while the cloth runs, and
// shows what each pass of the step costs against a frame budget, with the live max strain and
// penetration. With --frames N the viewer steps exactly once per drawn frame, and after N frames
// writes --screenshot (the whole window, panel included) and exits: the test runs it under Xvfb.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <CLI/CLI.hpp>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "render/image.h"
#include "viewer/orbit.h"
#include "render/renderer.h"
#include "viewer/session.h"

namespace {

using namespace weft;

// The panel's colours for the four pass groups (no reds: the cloth's front is red, and the
// screenshot test counts red pixels).
constexpr ImU32 kPassColours[] = {IM_COL32(96, 190, 120, 255), IM_COL32(80, 140, 230, 255), IM_COL32(170, 120, 220, 255),
                                  IM_COL32(70, 200, 210, 255)};

struct Input {
    bool dragging_left = false, dragging_right = false;
    double last_x = 0.0, last_y = 0.0;
};

// The per-pass bar: segments per pass group, scaled so that the whole width is twice the budget,
// with a line at the budget.
void timing_bar(const double (&smoothed_ms)[int(viewer::PassGroup::count)], double budget_ms) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x, height = 22.0f;
    const double full_ms = 2.0 * budget_ms;
    draw->AddRectFilled(origin, {origin.x + width, origin.y + height}, IM_COL32(40, 42, 48, 255), 3.0f);
    float x = origin.x;
    double total = 0.0;
    for (int g = 0; g < int(viewer::PassGroup::count); ++g) {
        const float w = float(std::min(smoothed_ms[g], std::max(0.0, full_ms - total)) / full_ms) * width;
        draw->AddRectFilled({x, origin.y}, {x + w, origin.y + height}, kPassColours[g]);
        x += w;
        total += smoothed_ms[g];
    }
    const float budget_x = origin.x + 0.5f * width;
    draw->AddLine({budget_x, origin.y - 3.0f}, {budget_x, origin.y + height + 3.0f}, IM_COL32(255, 255, 255, 255), 2.0f);
    ImGui::Dummy({width, height + 4.0f});
    for (int g = 0; g < int(viewer::PassGroup::count); ++g) {
        if (g % 2) ImGui::SameLine(0.5f * width);
        const ImVec2 p = ImGui::GetCursorScreenPos();
        const float size = ImGui::GetTextLineHeight() * 0.7f;
        draw->AddRectFilled({p.x, p.y + 0.2f * size}, {p.x + size, p.y + 1.2f * size}, kPassColours[g]);
        ImGui::Dummy({size, size});
        ImGui::SameLine();
        ImGui::Text("%s %.3f ms", viewer::kPassGroupNames[g], smoothed_ms[g]);
    }
    ImGui::Text("passes %.3f ms = %.0f%% of the %.2f ms budget", total, 100.0 * total / budget_ms, budget_ms);
}

render::Image read_window(int width, int height) {
    render::Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(size_t(3) * size_t(width) * size_t(height));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
    const size_t row = size_t(3) * size_t(width);  // OpenGL's rows go bottom to top
    for (int y = 0; y < height / 2; ++y)
        std::swap_ranges(image.rgb.begin() + ptrdiff_t(y * row), image.rgb.begin() + ptrdiff_t((y + 1) * row),
                         image.rgb.begin() + ptrdiff_t((height - 1 - y) * row));
    return image;
}

void style_panel(float scale) {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 6.0f;
    style.FrameRounding = 4.0f;
    style.GrabRounding = 4.0f;
    style.WindowBorderSize = 0.0f;
    style.WindowPadding = {12.0f, 10.0f};
    style.ItemSpacing = {8.0f, 6.0f};
    style.Colors[ImGuiCol_WindowBg] = {0.11f, 0.12f, 0.14f, 0.90f};
    style.ScaleAllSizes(scale);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini left in the working folder
    const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";  // fonts-dejavu-core
    if (std::filesystem::exists(font)) io.Fonts->AddFontFromFileTTF(font, 15.0f * scale);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"weft-viewer: a scene file or baked asset in a window, with live controls"};
    std::string path, size = "1280x720", screenshot;
    std::vector<std::string> asset_dirs;
    uint32_t frames = 0;
    bool paused = false;
    app.add_option("scene", path, "scene file (.json, docs/scene-format.md) or baked asset (.weft)")->required();
    app.add_option("--assets", asset_dirs, "folders to look for the scene's relative asset paths in");
    app.add_option("--size", size, "window size WxH");
    app.add_option("--frames", frames, "step once per drawn frame, and exit after N frames")->check(CLI::Range(1u, 100000u));
    app.add_option("--screenshot", screenshot, "with --frames: write the window to this PNG before exiting");
    app.add_flag("--paused", paused, "start paused");
    CLI11_PARSE(app, argc, argv);
    int width = 0, height = 0;
    char end = 0;
    if (std::sscanf(size.c_str(), "%dx%d%c", &width, &height, &end) != 2 || width < 320 || height < 240 || width > 8192 ||
        height > 8192) {
        std::fprintf(stderr, "weft-viewer: --size: expected WIDTHxHEIGHT, at least 320x240, got '%s'\n", size.c_str());
        return 1;
    }
    if (!screenshot.empty() && frames == 0) {
        std::fprintf(stderr, "weft-viewer: --screenshot needs --frames N\n");
        return 1;
    }

    viewer::Session session;
    if (std::string e = session.open(path, asset_dirs); !e.empty()) {
        std::fprintf(stderr, "weft-viewer: %s: %s\n", path.c_str(), e.c_str());
        return 1;
    }

    glfwSetErrorCallback([](int, const char* message) { std::fprintf(stderr, "weft-viewer: GLFW: %s\n", message); });
    if (!glfwInit()) {
        std::fprintf(stderr, "weft-viewer: no display (set DISPLAY, or run under xvfb-run)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    const std::string title = "weft-viewer - " + session.scene().name;
    GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window) {  // some displays (Xvfb) have no multisampled configuration
        glfwWindowHint(GLFW_SAMPLES, 0);
        window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    }
    if (!window) {
        std::fprintf(stderr, "weft-viewer: cannot open an OpenGL 3.3 core window\n");
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(frames > 0 ? 0 : 1);

    std::string error;
    std::unique_ptr<render::Renderer> renderer = render::Renderer::create(&error);
    if (!renderer) {
        std::fprintf(stderr, "weft-viewer: %s\n", error.c_str());
        return 1;
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    float scale = 1.0f;
    glfwGetWindowContentScale(window, &scale, nullptr);
    style_panel(std::max(1.0f, scale));
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    int fb_width = width, fb_height = height;
    glfwGetFramebufferSize(window, &fb_width, &fb_height);
    const float panel_width = viewer::kPanelWidth * std::max(1.0f, scale);
    bool panel_open = true;
    // The fraction of the window the panel covers (the camera centres the scene right of it).
    const auto panel_fraction = [&] { return panel_open ? std::min(0.5f, panel_width / float(fb_width)) : 0.0f; };
    const auto frame_scene = [&] {
        const float free_aspect = (1.0f - panel_fraction()) * float(fb_width) / float(fb_height);
        return viewer::frame_orbit(render::bounds(session.snapshot()), free_aspect);
    };
    viewer::Orbit orbit = frame_scene();
    double simulated_s = 0.0;  // simulated time owed to the wall clock while playing
    const auto reset = [&] {
        if (std::string e = session.reset(); !e.empty()) std::fprintf(stderr, "weft-viewer: reset: %s\n", e.c_str());
        simulated_s = 0.0;
    };
    Input input;
    bool playing = !paused || frames > 0, step_once = false;
    double budget_ms = 1.0;  // what a game might give its cloth out of a 16.7 ms frame
    double smoothed_ms[int(viewer::PassGroup::count)] = {}, smoothed_step_ms = 0.0;
    std::deque<float> strain_history;
    double wall_last = glfwGetTime();
    uint32_t drawn = 0;
    int exit_code = 0;

    while (!glfwWindowShouldClose(window)) {
        glfwPollEvents();
        glfwGetFramebufferSize(window, &fb_width, &fb_height);
        if (fb_width <= 0 || fb_height <= 0) {  // minimised
            glfwWaitEvents();
            continue;
        }
        const float aspect = float(fb_width) / float(fb_height);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();  // first: the mouse, wheel and keys below are this frame's
        ImGuiIO& io = ImGui::GetIO();

        // Camera and keys, unless the panel has the mouse or the keyboard.
        double mx = 0.0, my = 0.0;
        glfwGetCursorPos(window, &mx, &my);
        if (!io.WantCaptureMouse) {
            input.dragging_left = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
            input.dragging_right = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                                   glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
            const float dx = float(mx - input.last_x), dy = float(my - input.last_y);
            if (input.dragging_left) viewer::rotate(&orbit, dx, dy);
            if (input.dragging_right) viewer::pan(&orbit, viewer::orbit_camera(orbit, aspect), dx, dy, float(fb_height));
            if (io.MouseWheel != 0.0f) viewer::zoom(&orbit, io.MouseWheel);
        }
        input.last_x = mx, input.last_y = my;
        if (!io.WantCaptureKeyboard) {  // ImGui 1.86 indexes keys by the backend's (GLFW's) key codes
            if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) playing = !playing;
            if (ImGui::IsKeyPressed(GLFW_KEY_S) || ImGui::IsKeyPressed(GLFW_KEY_RIGHT)) step_once = true, playing = false;
            if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) reset();
            if (ImGui::IsKeyPressed(GLFW_KEY_F, false)) orbit = frame_scene();
        }

        // Steps: at the scene's pace while playing (at most 4 per drawn frame), once per drawn
        // frame with --frames, one when asked.
        const double wall_now = glfwGetTime();
        int steps = 0;
        if (frames > 0) {
            steps = 1;
        } else if (playing) {
            simulated_s += wall_now - wall_last;
            steps = std::min(4, int(simulated_s / session.scene().dt_s));
            simulated_s = std::max(0.0, simulated_s - steps * double(session.scene().dt_s));
            if (steps == 4) simulated_s = 0.0;  // too slow for real time: do not build up a debt
        }
        wall_last = wall_now;
        if (step_once) steps = 1, step_once = false;
        for (int s = 0; s < steps; ++s) {
            if (!session.step(&error)) {
                std::fprintf(stderr, "weft-viewer: step refused: %s\n", error.c_str());
                playing = false;
                break;
            }
            const viewer::StepReport& r = session.last();
            const double k = smoothed_step_ms == 0.0 ? 1.0 : 0.1;  // a tenth of each new step: readable numbers
            for (int g = 0; g < int(viewer::PassGroup::count); ++g) smoothed_ms[g] += k * (r.pass_ms[g] - smoothed_ms[g]);
            smoothed_step_ms += k * (r.step_ms - smoothed_step_ms);
            strain_history.push_back(float(100.0 * r.max_strain));
            if (strain_history.size() > 240) strain_history.pop_front();
        }

        // The scene.
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        renderer->draw(session.snapshot(), viewer::orbit_camera(orbit, aspect, panel_fraction()), fb_width, fb_height);

        // The panel.
        ImGui::SetNextWindowPos({12.0f, 12.0f}, ImGuiCond_Once);
        ImGui::SetNextWindowSizeConstraints({panel_width - 24.0f, 0.0f}, {panel_width - 24.0f, float(fb_height) - 24.0f});
        panel_open = ImGui::Begin("Weft", nullptr, ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::Text("%s: %u particles, %s", session.scene().name.c_str(), session.particles(), session.simd());
        ImGui::Text("frame %u, %.2f s (dt %.1f ms)", session.frame(), session.frame() * session.scene().dt_s,
                    1000.0 * session.scene().dt_s);
        if (ImGui::Button(playing ? "Pause" : "Play", {70.0f, 0.0f})) playing = !playing;
        ImGui::SameLine();
        if (ImGui::Button("Step")) step_once = true, playing = false;
        ImGui::SameLine();
        if (ImGui::Button("Reset")) reset();
        ImGui::SameLine();
        if (ImGui::Button("Frame")) orbit = frame_scene();

        viewer::Controls c = session.controls();
        bool changed = false;
        if (ImGui::CollapsingHeader("Forces", ImGuiTreeNodeFlags_DefaultOpen)) {
            changed |= ImGui::Checkbox("wind (resets)", &c.wind_on);
            ImGui::BeginDisabled(!c.wind_on);
            changed |= ImGui::SliderFloat("speed m/s", &c.wind_speed_m_s, 0.0f, 60.0f, "%.1f");
            changed |= ImGui::SliderFloat("direction deg", &c.wind_direction_deg, -180.0f, 180.0f, "%.0f");
            ImGui::EndDisabled();
            changed |= ImGui::SliderFloat("gravity m/s2", &c.gravity_m_s2, 0.0f, 20.0f, "%.2f");
        }
        if (ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) {
            if (!c.explicit_split) {
                const SolverSplit s = session.split();
                c.substeps = int(s.substeps), c.iterations = int(s.iterations);
            }
            const bool moved = ImGui::SliderInt("substeps", &c.substeps, 1, 16) |
                               ImGui::SliderInt("iterations", &c.iterations, 1, 64);
            if (moved) c.explicit_split = true, changed = true;
            changed |= ImGui::Checkbox("tethers", &c.tethers);
            ImGui::SameLine();
            if (c.explicit_split) {
                if (ImGui::SmallButton("automatic budget")) c.explicit_split = false, changed = true;
            } else {
                ImGui::TextDisabled("(automatic budget)");
            }
            if (!session.scene().colliders.empty()) {
                float inflation_mm = 1000.0f * c.inflation_m;
                if (ImGui::SliderFloat("inflation mm", &inflation_mm, 0.0f, 50.0f, "%.1f"))
                    c.inflation_m = 0.001f * inflation_mm, changed = true;
            }
        }
        if (changed)
            if (std::string e = session.apply(c); !e.empty()) std::fprintf(stderr, "weft-viewer: %s\n", e.c_str());
        if (ImGui::CollapsingHeader("Step cost", ImGuiTreeNodeFlags_DefaultOpen)) {
            float budget = float(budget_ms);
            if (ImGui::SliderFloat("budget ms", &budget, 0.05f, 33.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
                budget_ms = budget;
            timing_bar(smoothed_ms, budget_ms);
            ImGui::Text("step %.3f ms wall", smoothed_step_ms);
        }
        if (ImGui::CollapsingHeader("Cloth", ImGuiTreeNodeFlags_DefaultOpen)) {
            const viewer::StepReport& r = session.last();
            ImGui::Text("max strain %.2f%%   penetration %.1f mm", 100.0 * r.max_strain, 1000.0 * r.max_penetration_m);
            const std::vector<float> history(strain_history.begin(), strain_history.end());
            ImGui::TextDisabled("max strain, last %zu steps", history.size());
            ImGui::PlotLines("##strain", history.data(), int(history.size()), 0, nullptr, 0.0f, FLT_MAX,
                             {ImGui::GetContentRegionAvail().x, 48.0f});
        }
        ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom\nspace: play, S: step, R: reset, F: frame");
        ImGui::End();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

        ++drawn;
        if (frames > 0 && drawn >= frames) {
            if (!screenshot.empty() && !render::write_png(screenshot, read_window(fb_width, fb_height))) {
                std::fprintf(stderr, "weft-viewer: cannot write %s\n", screenshot.c_str());
                exit_code = 1;
            }
            break;
        }
        glfwSwapBuffers(window);
    }

    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    renderer.reset();
    glfwDestroyWindow(window);
    glfwTerminate();
    return exit_code;
}
