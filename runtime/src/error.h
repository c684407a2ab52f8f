// Errors as the API returns them. Shared with the cooking library (cook/), which reports its
// refusals the same way.
#pragma once

#include "weft/types.h"

namespace weft {

// Formats a Result (printf-style, truncated to fit).
Result make_error(ErrorCode code, const char* format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace weft
