// Work run in child processes, a few at a time: weft-bake's folders and manifests and weft-bench
// corpus bake each pattern in a child of its own (fork), so a crash, a hang or an allocation
// failure in one pattern is that pattern's error and the batch goes on. POSIX only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace weft::jobs {

// How one piece of work ended.
struct Outcome {
    std::string output;  // what the work returned (sent from the child through a pipe)
    std::string error;   // empty when the child returned normally; else "crashed: Segmentation fault",
                         // "timed out", "cannot start a process", "no result (exit status N)"
};

struct Options {
    uint32_t jobs = 0;        // children at once; 0: one per core
    double timeout_s = 0.0;   // a child still running after this is killed ("timed out"); 0: no limit
};

// One per core (std::thread::hardware_concurrency, at least 1).
uint32_t every_core();

// Runs work(k) for k = 0 .. count-1, each in a forked child, up to options.jobs at a time and in
// order of k. The child sends work's string back; the parent calls done(k, outcome) as each ends
// (in the order they end). work runs in the child: it sees the parent's memory as it was at the
// fork and changes nothing in it. The parent must not be running other threads.
void run_in_children(size_t count, const Options& options, const std::function<std::string(size_t)>& work,
                     const std::function<void(size_t, Outcome)>& done);

}  // namespace weft::jobs
