// XXH64 (Yann Collet, xxHash; the published algorithm, github.com/Cyan4973/xxHash/doc/xxhash_spec.md).
// Written out here because the runtime links Embree, glm and the standard library only; a test
// checks it bit for bit against libxxhash's XXH64().
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace weft {
namespace xxh64_detail {

inline constexpr uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
inline constexpr uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
inline constexpr uint64_t kPrime3 = 0x165667B19E3779F9ull;
inline constexpr uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
inline constexpr uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

inline uint64_t rotl(uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }

// Little-endian reads at any alignment (the runtime is little-endian only: asset/load.cpp).
inline uint64_t read64(const uint8_t* p) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}
inline uint32_t read32(const uint8_t* p) {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

inline uint64_t round(uint64_t accumulator, uint64_t input) {
    accumulator += input * kPrime2;
    return rotl(accumulator, 31) * kPrime1;
}

inline uint64_t merge_round(uint64_t hash, uint64_t accumulator) {
    hash ^= round(0, accumulator);
    return hash * kPrime1 + kPrime4;
}

}  // namespace xxh64_detail

inline uint64_t xxh64(const void* data, size_t size, uint64_t seed) {
    using namespace xxh64_detail;
    const uint8_t* p = static_cast<const uint8_t*>(data);
    size_t i = 0;  // indices, not pointers: `data` may be null when size is 0
    uint64_t h;
    if (size >= 32) {  // four lanes over 32-byte stripes
        uint64_t v[4] = {seed + kPrime1 + kPrime2, seed + kPrime2, seed, seed - kPrime1};
        for (; i + 32 <= size; i += 32)
            for (int lane = 0; lane < 4; ++lane) v[lane] = round(v[lane], read64(p + i + 8 * lane));
        h = rotl(v[0], 1) + rotl(v[1], 7) + rotl(v[2], 12) + rotl(v[3], 18);
        for (int lane = 0; lane < 4; ++lane) h = merge_round(h, v[lane]);
    } else {
        h = seed + kPrime5;
    }
    h += uint64_t(size);
    for (; i + 8 <= size; i += 8) h = rotl(h ^ round(0, read64(p + i)), 27) * kPrime1 + kPrime4;
    if (i + 4 <= size) {
        h = rotl(h ^ (uint64_t(read32(p + i)) * kPrime1), 23) * kPrime2 + kPrime3;
        i += 4;
    }
    for (; i < size; ++i) h = rotl(h ^ (uint64_t(p[i]) * kPrime5), 11) * kPrime1;
    h ^= h >> 33;  // avalanche
    h *= kPrime2;
    h ^= h >> 29;
    h *= kPrime3;
    h ^= h >> 32;
    return h;
}

}  // namespace weft
