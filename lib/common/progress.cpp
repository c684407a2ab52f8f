#include "common/progress.h"

#include <cmath>
#include <cstdio>

#include <unistd.h>

namespace weft::progress {

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

bool wanted(bool json) { return !json && isatty(STDOUT_FILENO) == 1 && stderr_is_terminal(); }

std::string format_duration(double seconds) {
    char text[32];
    if (!std::isfinite(seconds) || seconds < 0.0) return "?";
    if (seconds < 60.0) {
        std::snprintf(text, sizeof text, "%.1f s", seconds);
    } else {
        const long s = std::lround(seconds);
        std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
    }
    return text;
}

std::string format_line(std::string_view label, uint64_t done, uint64_t total, double elapsed_s,
                        std::string_view note, int width) {
    std::string line(label);
    char text[96];
    if (total > 0) {
        if (done > total) done = total;
        const double fraction = double(done) / double(total);
        const int filled = int(fraction * width);
        line += " [";
        line.append(size_t(filled), '#');
        line.append(size_t(width - filled), '.');
        line += ']';
        // The estimate assumes the remaining steps cost what the finished ones did on average.
        const std::string left = done > 0 ? format_duration(elapsed_s * double(total - done) / double(done)) : "?";
        std::snprintf(text, sizeof text, " %llu/%llu %3.0f%%, %s left", static_cast<unsigned long long>(done),
                      static_cast<unsigned long long>(total), 100.0 * fraction, left.c_str());
    } else {
        std::snprintf(text, sizeof text, " %llu done, %s", static_cast<unsigned long long>(done),
                      format_duration(elapsed_s).c_str());
    }
    line += text;
    if (!note.empty()) line.append(" - ").append(note);
    return line;
}

Bar::Bar(std::string label, uint64_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

Bar::~Bar() { finish(); }

void Bar::update(uint64_t done, std::string_view note) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100) && (total_ == 0 || done < total_) && note == note_)
        return;
    last_draw_ = now;
    note_ = note;
    drawn_ = true;
    const double elapsed_s = std::chrono::duration<double>(now - start_).count();
    // \r back to the line's start, \033[K clears what a longer previous line left.
    std::fprintf(stderr, "\r%s\033[K", format_line(label_, done, total_, elapsed_s, note).c_str());
    std::fflush(stderr);
}

void Bar::finish() {
    if (!enabled_ || !drawn_) return;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    drawn_ = false;
}

}  // namespace weft::progress
