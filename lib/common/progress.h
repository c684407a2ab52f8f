// Progress of a long command on a terminal: one line on stderr, redrawn in place, with a bar, a
// count and an estimate of the time left. Quiet (draws nothing) when stdout or stderr is not a
// terminal or the command was asked for --json, so logs, pipes and CI output stay clean. Shared by weft-bench
// sweep, weft-bake, weft-sim's exports and (through weft-sim) samples/figures/make-figures.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace weft::progress {

// Whether a command should draw progress: stdout and stderr are both terminals (so a log, a pipe
// or a captured output never gets a bar) and `json` output was not asked for.
bool wanted(bool json);
// Whether stderr, where the bar is drawn, is a terminal (a caller that captures stdout and still
// wants the bar: weft-sim --progress-label).
bool stderr_is_terminal();

class Bar {
public:
    // `total` steps of work; 0 = unknown (a plain counter). Draws nothing unless `enabled`.
    Bar(std::string label, uint64_t total, bool enabled);
    ~Bar();
    Bar(const Bar&) = delete;
    Bar& operator=(const Bar&) = delete;

    // `done` steps finished, optionally what is being done now; redraws at most 10 times a second
    // (and always for the last step or a new note).
    void update(uint64_t done, std::string_view note = {});
    // Clears the line (also done by the destructor): what the command prints next starts clean.
    void finish();
    bool enabled() const { return enabled_; }

private:
    std::string label_, note_;
    uint64_t total_ = 0;
    bool enabled_ = false, drawn_ = false;
    std::chrono::steady_clock::time_point start_, last_draw_;
};

// "4.2 s", "3 min 05 s": an estimate's text (the bar uses it; exposed for the tests).
std::string format_duration(double seconds);
// The bar's line without the carriage return, `width` characters of bar.
std::string format_line(std::string_view label, uint64_t done, uint64_t total, double elapsed_s,
                        std::string_view note, int width = 24);

}  // namespace weft::progress
