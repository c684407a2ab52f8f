// weft-bench baked: per-constraint step cost of a baked garment against the same garment's mesh
// cooked in memory, without lattice coordinates (what a game handing Weft a plain triangle mesh
// gets) and with them.
//
//   weft-bench baked PATTERN.json[@Y_OFFSET] ... [--iterations 10] [--steps 200] [--warmup 20]
//                      [--repeat 5] [--paths avx2] [--json]
#pragma once

#include <CLI/CLI.hpp>

namespace weft::bench {

// Registers the subcommand on `app`; run_baked() runs it once the command line is parsed.
CLI::App* add_baked_subcommand(CLI::App& app);
int run_baked();

}  // namespace weft::bench
