// weft-bench corpus: a folder of sewing patterns baked flat and sewn, one garment per child process
// (a crash or a hang fails that garment, never the batch), --jobs at a time.
//   weft-bench corpus DIR [--body BODY] [--jobs N] [--json] [--filter TEXT] [--timeout S]
#pragma once

#include <cstdint>
#include <string>

namespace weft::bench {

struct CorpusOptions {
    std::string dir;           // every *_specification.json (GarmentCode) or *.json pattern in it
    std::string body;          // OBJ / glTF / "mannequin"; empty: flat bakes only
    uint32_t jobs = 0;         // 0: one per core
    uint32_t sweeps = 8;       // the sewing and drape budget (weft-bake --sweeps)
    double timeout_s = 600.0;  // a garment still baking after this fails with "timed out"
    std::string filter;        // only the files whose name contains one of these comma-separated parts
    bool json = false;
};

// Stays on (issue 21): the top drops less than this between closed seams and the dressed pose.
inline constexpr double kStaysOnMaxTopDrop_m = 0.05;

int run_corpus(const CorpusOptions& options);

}  // namespace weft::bench
