// The headless front end: an OpenGL 3.3 core context on EGL's surfaceless platform (Mesa's
// llvmpipe: no display, no GPU needed) drawing into an offscreen, multisampled framebuffer, and the
// pixels read back as an Image. Only the context lives here; the drawing is Renderer's, which a
// window can use as it is.
#pragma once

#include <memory>
#include <string>

#include "render/image.h"

namespace weft::render {

class HeadlessContext {
public:
    // Creates the context, makes it current and allocates a width x height framebuffer.
    // Null (and *error) when EGL or OpenGL 3.3 is not available.
    static std::unique_ptr<HeadlessContext> create(int width, int height, std::string* error);
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    // Binds the offscreen framebuffer: draw after this.
    void begin_frame();
    // Resolves the samples and reads the picture back (rows top to bottom).
    Image read_image();

private:
    HeadlessContext() = default;
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
    int width_ = 0, height_ = 0;
    unsigned multisampled_framebuffer_ = 0, multisampled_colour_ = 0, multisampled_depth_ = 0;
    unsigned resolved_framebuffer_ = 0, resolved_colour_ = 0;
};

}  // namespace weft::render
