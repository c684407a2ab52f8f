// Regions of a block that instances come and go in (remove_cloth, remove_body, skin constraints
// rebound): each live instance holds one region [begin, end) of bytes from the block's start. A new
// one takes the first gap between the live regions that fits; when none does though the block has
// the room, the live regions slide down to close every gap first (compact_regions), so the world
// holds what its capacities promise however instances came and went. Same calls, same layout.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "memory/arena.h"

namespace weft {

struct Region {
    size_t begin = 0, end = 0;  // bytes from the block's start; begin is cache-line aligned
    uint32_t owner = 0;         // who holds it (the caller's tag: a kind and an index)
};

inline void sort_regions(Region* live, uint32_t count) {
    std::sort(live, live + count, [](const Region& l, const Region& r) { return l.begin < r.begin; });
}

// The first cache-line aligned offset in [low, high) with `bytes` free after it between the
// `live` regions (sorted by begin), or SIZE_MAX. `base` is the block's address (alignment is of
// addresses, not offsets).
inline size_t first_fit(const uint8_t* base, const Region* live, uint32_t count, size_t low, size_t high,
                        size_t bytes) {
    auto fits = [&](size_t from, size_t to, size_t* at) {
        const size_t start = align_up(reinterpret_cast<uintptr_t>(base) + from, kCacheLine) -
                             reinterpret_cast<uintptr_t>(base);
        if (start > to || to - start < bytes) return false;
        *at = start;
        return true;
    };
    size_t from = low, at = 0;
    for (uint32_t i = 0; i < count; ++i) {
        if (fits(from, live[i].begin, &at)) return at;
        from = std::max(from, live[i].end);
    }
    return fits(from, high, &at) ? at : SIZE_MAX;
}

// Where the live regions (sorted by begin) would end after compact_regions, without moving them:
// an add checks it first, so a compaction never runs for nothing.
inline size_t compacted_end(const uint8_t* base, const Region* live, uint32_t count, size_t low) {
    size_t next = low;
    for (uint32_t i = 0; i < count; ++i)
        next = align_up(reinterpret_cast<uintptr_t>(base) + next, kCacheLine) - reinterpret_cast<uintptr_t>(base) +
               (live[i].end - live[i].begin);
    return next;
}

// Slides the live regions (sorted by begin) down to `low`, each on a cache line, in order: every
// gap closes. `move(region, delta)` is called after each region's bytes moved by `delta` bytes
// (negative or zero) so its owner can rebase its pointers. Returns the end of the last region.
template <class Move>
size_t compact_regions(uint8_t* base, Region* live, uint32_t count, size_t low, Move&& move) {
    size_t next = low;
    for (uint32_t i = 0; i < count; ++i) {
        Region& r = live[i];
        const size_t start = align_up(reinterpret_cast<uintptr_t>(base) + next, kCacheLine) -
                             reinterpret_cast<uintptr_t>(base);
        const size_t length = r.end - r.begin;
        if (start != r.begin) {
            std::memmove(base + start, base + r.begin, length);
            const ptrdiff_t delta = ptrdiff_t(start) - ptrdiff_t(r.begin);
            r.begin = start, r.end = start + length;
            move(r, delta);
        }
        next = r.end;
    }
    return next;
}

// A place in an instance array (cloths, bodies, colliders): whether an instance holds it, and the
// generation its id carries, bumped by each removal so that an id of a removed instance is refused.
inline constexpr uint32_t kGenerations = 1u << 16;  // the C API packs 16 bits of generation into an id
struct InstanceSlot {
    bool live = false;
    uint32_t generation = 0;  // < kGenerations
    Region memory;            // its arrays in the world's block (cloths and bodies)
};

// Moves a pointer into a region that moved by `delta` bytes.
template <class T>
inline void rebase(T*& pointer, ptrdiff_t delta) {
    if (pointer != nullptr) pointer = reinterpret_cast<T*>(reinterpret_cast<uint8_t*>(pointer) + delta);
}

}  // namespace weft
