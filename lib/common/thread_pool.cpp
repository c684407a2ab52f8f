#include "common/thread_pool.h"

#include <algorithm>

namespace weft::tools {

ThreadPool::ThreadPool(uint32_t threads) {
    const uint32_t workers = threads > 1 ? threads - 1 : 0;
    workers_.reserve(workers);
    for (uint32_t i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

StepScheduler ThreadPool::scheduler() {
    StepScheduler s;
    s.enqueue_task = enqueue;
    s.finish_task = finish;
    s.user_context = this;
    return s;
}

void* ThreadPool::enqueue(StepTaskFn fn, uint32_t items, uint32_t min_range, void* context, void* user) {
    ThreadPool& pool = *static_cast<ThreadPool*>(user);
    if (pool.workers_.empty() || items <= min_range || pool.busy_) {
        fn(0, items, context);  // nothing to share, or a task already out: run it here
        return nullptr;
    }
    // Ranges small enough that a slow item does not leave the other threads idle for long, and no
    // smaller than the world asks.
    const uint32_t range = std::max(min_range, std::max(1u, items / (16 * pool.threads())));
    {
        std::lock_guard<std::mutex> lock(pool.mutex_);
        // A worker still leaving the last task's ranges reads these fields: wait for it.
        while (pool.active_.load(std::memory_order_acquire) != 0) std::this_thread::yield();
        pool.task_.fn = fn;
        pool.task_.context = context;
        pool.task_.items = items;
        pool.task_.range = range;
        pool.task_.next.store(0, std::memory_order_relaxed);
        pool.task_.done.store(0, std::memory_order_relaxed);
        pool.busy_ = true;
        ++pool.generation_;
    }
    pool.wake_.notify_all();
    return &pool.task_;
}

void ThreadPool::finish(void* /*task*/, void* user) {
    ThreadPool& pool = *static_cast<ThreadPool*>(user);
    pool.run_ranges();  // the stepping thread works too
    while (pool.task_.done.load(std::memory_order_acquire) < pool.task_.items) std::this_thread::yield();
    std::lock_guard<std::mutex> lock(pool.mutex_);
    pool.busy_ = false;
}

void ThreadPool::run_ranges() {
    Task& t = task_;
    for (;;) {
        const uint32_t begin = t.next.fetch_add(t.range, std::memory_order_relaxed);
        if (begin >= t.items) return;
        const uint32_t end = std::min(t.items, begin + t.range);
        t.fn(begin, end, t.context);
        t.done.fetch_add(end - begin, std::memory_order_release);
    }
}

void ThreadPool::work() {
    uint64_t seen = 0;
    for (;;) {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            active_.fetch_add(1, std::memory_order_relaxed);
        }
        run_ranges();
        active_.fetch_sub(1, std::memory_order_release);
    }
}

}  // namespace weft::tools
