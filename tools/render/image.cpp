#include "render/image.h"

#include <csignal>

#include <stb_image_write.h>  // the implementation is in Debian's libstb

namespace weft::render {

bool write_png(const std::string& path, const Image& image) {
    stbi_write_png_compression_level = 9;
    return stbi_write_png(path.c_str(), image.width, image.height, 3, image.rgb.data(), 3 * image.width) != 0;
}

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The path as one word for the shell that popen runs.
std::string shell_quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

std::unique_ptr<AnimationWriter> AnimationWriter::open(const std::string& path, int width, int height,
                                                       double frames_per_second, std::string* error) {
    std::string encode;
    if (ends_with(path, ".gif")) {
        // One palette made from the whole animation (much better than the default web palette).
        encode = "-filter_complex 'split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse'";
    } else if (ends_with(path, ".mp4")) {
        if (width % 2 || height % 2) {
            *error = "an MP4 needs an even width and height (yuv420p)";
            return nullptr;
        }
        encode = "-c:v libx264 -pix_fmt yuv420p -crf 23 -movflags +faststart";
    } else {
        *error = "animations are .gif or .mp4: " + path;
        return nullptr;
    }
    const std::string command = "ffmpeg -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " +
                                std::to_string(width) + "x" + std::to_string(height) + " -framerate " +
                                std::to_string(frames_per_second) + " -i - " + encode + " " + shell_quoted(path);
    // If ffmpeg stops early, writing to it must fail rather than kill this process.
    std::signal(SIGPIPE, SIG_IGN);
    std::unique_ptr<AnimationWriter> w(new AnimationWriter());
    w->pipe_ = popen(command.c_str(), "w");
    if (!w->pipe_) {
        *error = "cannot start ffmpeg";
        return nullptr;
    }
    w->width_ = width;
    w->height_ = height;
    return w;
}

AnimationWriter::~AnimationWriter() {
    if (pipe_) pclose(pipe_);
}

bool AnimationWriter::add_frame(const Image& frame) {
    if (!pipe_ || frame.width != width_ || frame.height != height_) return false;
    return std::fwrite(frame.rgb.data(), 1, frame.rgb.size(), pipe_) == frame.rgb.size();
}

bool AnimationWriter::close(std::string* error) {
    const int status = pipe_ ? pclose(pipe_) : -1;
    pipe_ = nullptr;
    if (status != 0) *error = "ffmpeg failed (is Debian's ffmpeg installed?), status " + std::to_string(status);
    return status == 0;
}

}  // namespace weft::render
