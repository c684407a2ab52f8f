// The progress bar of the long commands (lib/common/progress.h): its line, its estimate, and
// that it stays quiet when not asked for. (That the commands draw it on a terminal only: the
// progress.* CTest tests run them on a pseudo-terminal, with --json and through a pipe.)
#include <doctest/doctest.h>

#include "common/progress.h"

using namespace weft;

TEST_CASE("progress lines: bar, count, percentage and the time left at the average pace so far") {
    // 30 of 120 steps in 6 s: 90 more at 0.2 s each.
    CHECK(progress::format_line("sweep", 30, 120, 6.0, "", 8) == "sweep [##......] 30/120  25%, 18.0 s left");
    CHECK(progress::format_line("bake", 2, 4, 1.0, "cooking", 4) == "bake [##..] 2/4  50%, 1.0 s left - cooking");
    CHECK(progress::format_line("sim", 0, 10, 0.5, "", 4) == "sim [....] 0/10   0%, ? left");
    CHECK(progress::format_line("sim", 10, 10, 3.0, "", 4) == "sim [####] 10/10 100%, 0.0 s left");
    CHECK(progress::format_line("sim", 12, 10, 3.0, "", 4) == "sim [####] 10/10 100%, 0.0 s left");  // clamped
    CHECK(progress::format_line("frames", 7, 0, 2.0, "", 4) == "frames 7 done, 2.0 s");             // unknown total
}

TEST_CASE("progress durations read as seconds, then minutes") {
    CHECK(progress::format_duration(4.25) == "4.2 s");
    CHECK(progress::format_duration(185.0) == "3 min 05 s");
    CHECK(progress::format_duration(-1.0) == "?");
}

TEST_CASE("a disabled bar draws nothing and --json never asks for one") {
    CHECK_FALSE(progress::wanted(true));
    progress::Bar bar("quiet", 10, false);
    bar.update(5);
    bar.finish();
    CHECK_FALSE(bar.enabled());
}
