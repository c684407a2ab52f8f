// A small thread pool that runs a world's step stages (weft/world.h, StepScheduler): what the
// tools and samples use where a game would plug in its own job system.
//
//   ThreadPool pool(threads);            // threads - 1 workers; the stepping thread is the last one
//   desc.scheduler = pool.scheduler();   // before create_world
//
// One task at a time (the step enqueues a stage and finishes it before the next); the caller runs
// items too, so ThreadPool(1) runs everything on the calling thread. Workers take ranges of items
// from a shared counter; enqueue and finish allocate nothing.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "weft/world.h"

namespace weft::tools {

class ThreadPool {
public:
    explicit ThreadPool(uint32_t threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    uint32_t threads() const { return uint32_t(workers_.size()) + 1; }
    StepScheduler scheduler();

private:
    struct Task {
        StepTaskFn fn = nullptr;
        void* context = nullptr;
        uint32_t items = 0, range = 1;
        std::atomic<uint32_t> next{0};  // first item not yet taken
        std::atomic<uint32_t> done{0};  // items finished
    };
    static void* enqueue(StepTaskFn task, uint32_t item_count, uint32_t min_range, void* task_context, void* user);
    static void finish(void* task, void* user);
    void run_ranges();  // takes ranges of the current task until none is left
    void work();        // a worker's loop

    std::vector<std::thread> workers_;
    Task task_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::atomic<uint32_t> active_{0};  // workers inside run_ranges
    uint64_t generation_ = 0;  // bumped for every task the workers should join
    bool busy_ = false;        // a task is enqueued and not yet finished
    bool stop_ = false;
};

}  // namespace weft::tools
