// Pictures in memory and on disk: PNG through stb_image_write, animations through ffmpeg.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace weft::render {

// 8-bit RGB, rows top to bottom.
struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // 3 * width * height
    const uint8_t* pixel(int x, int y) const { return &rgb[3 * (size_t(y) * size_t(width) + size_t(x))]; }
};

// Writes a PNG; false when the file cannot be written.
bool write_png(const std::string& path, const Image& image);

// An animated GIF or an MP4 (H.264, yuv420p: the format every player takes), chosen by the file's
// extension, made by piping raw RGB frames into Debian's ffmpeg.
class AnimationWriter {
public:
    // Null (and *error) for an unknown extension, an odd size for MP4, or when ffmpeg cannot start.
    static std::unique_ptr<AnimationWriter> open(const std::string& path, int width, int height,
                                                 double frames_per_second, std::string* error);
    ~AnimationWriter();
    AnimationWriter(const AnimationWriter&) = delete;
    AnimationWriter& operator=(const AnimationWriter&) = delete;

    bool add_frame(const Image& frame);  // same size as opened
    // Waits for ffmpeg; false (and *error) when it failed.
    bool close(std::string* error);

private:
    AnimationWriter() = default;
    std::FILE* pipe_ = nullptr;
    int width_ = 0, height_ = 0;
};

}  // namespace weft::render
