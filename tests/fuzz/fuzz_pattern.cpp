// libFuzzer harness: parse_pattern, then mesh_garment with a small particle cap (it bounds each
// panel's refinement too) so every input stays fast. Any crash, hang, leak or sanitizer report is a bug; errors are the expected outcome.
// Build and run: see tools/bake/CMakeLists.txt (WEFT_FUZZ); corpus in tests/fuzz/corpus/pattern/.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "bake/garment.h"
#include "bake/pattern.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace weft::bake;
    Pattern pattern;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (!parse_pattern(text, ParseOptions{}, &pattern).ok()) return 0;
    MeshOptions options;
    options.max_particles = 5000;
    MeshedGarment garment;
    (void)mesh_garment(pattern, options, &garment);
    return 0;
}
