// Plain value types shared by every part of the public API.
#pragma once

#include <cstddef>
#include <cstdint>

namespace weft {

// A point or vector in metres (positions), m/s (velocities) or m/s^2 (accelerations).
struct Vec3 {
    float x = 0.0f, y = 0.0f, z = 0.0f;
};

// A direction with a fourth component: a tangent and its handedness w (+1 or -1; read_tangents).
struct Vec4 {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

// A rotation as a unit quaternion (x, y, z: the vector part; w: the scalar part).
struct Quat {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 1.0f;
};

// A rigid transform: rotate, then translate (metres). A character's root each frame.
struct Transform {
    Vec3 translation_m{};
    Quat rotation{};
};

// Every fallible call returns one of these; `ok` is zero so `if (code != ErrorCode::ok)` reads naturally.
enum class ErrorCode : uint32_t {
    ok = 0,
    invalid_argument,   // a null pointer, a zero count, a flag combination that makes no sense
    non_finite,         // NaN or infinity in a value that must be finite
    out_of_range,       // an index past its array, a value outside its physical range
    capacity_exceeded,  // the world was created too small for what is being added
    memory_too_small,   // the caller's block is smaller or less aligned than the query said
    unsupported,        // e.g. the AVX2 path requested on a build or CPU without it
    corrupt_asset,      // an asset failed validation
    stale_id,           // the id of a cloth, body or collider that was removed
};

// The outcome of a call: a code and a human-readable message (always NUL-terminated).
// Returned by value so the runtime never needs a global error state.
struct Result {
    ErrorCode code = ErrorCode::ok;
    char message[120] = {};

    bool ok() const { return code == ErrorCode::ok; }
};

// What a caller-provided memory block must be.
struct MemoryRequirements {
    size_t bytes = 0;
    size_t alignment = 0;
};

// Which constraint kernels run. Both are always compiled where the target allows AVX2, so one
// binary can compare them; `automatic` picks the widest the CPU runs.
enum class SimdPath : uint8_t { automatic, scalar, avx2 };

// Spring kinds (seed section 1.1: stretch, shear, bend), each with its own compliance.
inline constexpr uint32_t kConstraintKindCount = 3;

const char* simd_path_name(SimdPath path);

// True when this build contains the AVX2 kernels and this CPU can run them.
bool simd_path_available(SimdPath path);

}  // namespace weft
