// A bump allocator over the caller's block. Used only while a world is created and filled; the
// step never allocates. Running out is reported, not fatal.
#pragma once

#include <cstddef>
#include <cstdint>

namespace weft {

inline constexpr size_t kCacheLine = 64;

inline size_t align_up(size_t value, size_t alignment) {
    return (value + alignment - 1) & ~(alignment - 1);
}

struct Arena {
    uint8_t* base = nullptr;
    size_t capacity = 0;
    size_t used = 0;

    // Null when the block is exhausted (the caller reports capacity_exceeded).
    void* allocate(size_t bytes, size_t alignment = kCacheLine) {
        const uintptr_t start = align_up(reinterpret_cast<uintptr_t>(base) + used, alignment);
        const size_t offset = start - reinterpret_cast<uintptr_t>(base);
        if (offset > capacity || bytes > capacity - offset) return nullptr;
        used = offset + bytes;
        return base + offset;
    }

    template <class T>
    T* allocate_array(size_t count) {
        return static_cast<T*>(allocate(sizeof(T) * count, alignof(T) > kCacheLine ? alignof(T) : kCacheLine));
    }
};

// Counts bytes the way Arena will use them, for world_memory_requirements.
struct ArenaSizer {
    size_t bytes = 0;
    void add(size_t size) { bytes = align_up(bytes, kCacheLine) + size; }
};

}  // namespace weft
