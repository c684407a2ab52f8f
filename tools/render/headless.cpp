#include "render/headless.h"

#include <algorithm>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace weft::render {

namespace {
constexpr int kSamples = 4;  // multisampling smooths the cloth's silhouette and the grid lines
}

std::unique_ptr<HeadlessContext> HeadlessContext::create(int width, int height, std::string* error) {
    std::unique_ptr<HeadlessContext> c(new HeadlessContext());
    c->width_ = width;
    c->height_ = height;
    // Surfaceless: no window system at all (EGL_MESA_platform_surfaceless).
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) {
        *error = "no EGL surfaceless display (is Mesa's libegl-mesa0 installed?)";
        return nullptr;
    }
    c->display_ = display;
    // The default surface type is a window, which the surfaceless platform has none of.
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglBindAPI(EGL_OPENGL_API) || !eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs < 1) {
        *error = "EGL has no OpenGL configuration";
        return nullptr;
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3,
                                         EGL_CONTEXT_MINOR_VERSION, 3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        *error = "cannot create an OpenGL 3.3 core context";
        if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
        return nullptr;
    }
    c->context_ = context;

    // Drawn into with multisampling, then resolved into a plain framebuffer to read back.
    GLint max_samples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    const int samples = std::min(kSamples, int(max_samples));
    glGenFramebuffers(1, &c->multisampled_framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, c->multisampled_framebuffer_);
    glGenRenderbuffers(1, &c->multisampled_colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, c->multisampled_colour_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->multisampled_colour_);
    glGenRenderbuffers(1, &c->multisampled_depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, c->multisampled_depth_);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, c->multisampled_depth_);
    const bool multisampled_ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;

    glGenFramebuffers(1, &c->resolved_framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, c->resolved_framebuffer_);
    glGenRenderbuffers(1, &c->resolved_colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, c->resolved_colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->resolved_colour_);
    if (!multisampled_ok || glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        *error = "cannot create a " + std::to_string(width) + "x" + std::to_string(height) + " framebuffer";
        return nullptr;
    }
    return c;
}

HeadlessContext::~HeadlessContext() {
    if (context_) {
        glDeleteFramebuffers(1, &multisampled_framebuffer_);
        glDeleteFramebuffers(1, &resolved_framebuffer_);
        glDeleteRenderbuffers(1, &multisampled_colour_);
        glDeleteRenderbuffers(1, &multisampled_depth_);
        glDeleteRenderbuffers(1, &resolved_colour_);
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }
    // The display stays initialised for the process (no eglTerminate): terminating it unloads Mesa's
    // driver, whose process-lifetime caches then read as leaks with no stack LeakSanitizer can name
    // or suppress. eglInitialize on an initialised display is a no-op, so the next context reuses it.
    if (display_) eglReleaseThread();
}

void HeadlessContext::begin_frame() { glBindFramebuffer(GL_FRAMEBUFFER, multisampled_framebuffer_); }

Image HeadlessContext::read_image() {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, multisampled_framebuffer_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolved_framebuffer_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolved_framebuffer_);
    Image image;
    image.width = width_;
    image.height = height_;
    image.rgb.resize(size_t(3) * size_t(width_) * size_t(height_));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
    // OpenGL's rows go bottom to top; pictures' go top to bottom.
    const size_t row = size_t(3) * size_t(width_);
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(image.rgb.begin() + ptrdiff_t(y * row), image.rgb.begin() + ptrdiff_t((y + 1) * row),
                         image.rgb.begin() + ptrdiff_t((height_ - 1 - y) * row));
    return image;
}

}  // namespace weft::render
