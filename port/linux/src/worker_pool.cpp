// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/port/worker_pool.hpp"

#include <limits>
#include <system_error>

#include "cellguard/base/contract.hpp"

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace cellguard::linux_port {

namespace {
/// @p workers, after the constructor's contract: the first member's initialiser,
/// so a violation leaves nothing half-built behind.
std::size_t checked_workers(std::size_t workers) noexcept {
    CG_ENFORCE(workers >= 1U && workers <= kMaxWorkers, "WorkerPool: workers must be in [1, kMaxWorkers]");
    return workers;
}
}  // namespace

const char* to_string(PinError error) noexcept {
    switch (error) {
        case PinError::kOk: return "pinned";
        case PinError::kNoSuchWorker: return "no such worker";
        case PinError::kNoSuchCpu: return "no such CPU";
        case PinError::kRefused: return "the OS refused the affinity";
        case PinError::kNotSupported: return "thread affinity not supported here";
    }
    return "unknown pin error";
}

WorkerPool::WorkerPool(std::size_t workers) : requested_(checked_workers(workers)) {
    for (std::size_t i = 0U; i + 1U < requested_; ++i) {
        try {
            threads_[i] = std::thread([this]() noexcept { worker_loop(); });
        } catch (const std::system_error&) {
            break;  // keep the threads we got; concurrency() says how many
        }
        ++started_;
    }
}

WorkerPool::~WorkerPool() {
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (std::size_t i = 0U; i < started_; ++i) {
        threads_[i].join();
    }
}

void WorkerPool::drain() noexcept {
    // task_, context_ and count_ do not change until every thread has
    // reported this generation done; the counter only hands out indices.
    for (std::size_t i = next_.fetch_add(1U, std::memory_order_relaxed); i < count_;
         i = next_.fetch_add(1U, std::memory_order_relaxed)) {
        task_(context_, i);
    }
}

void WorkerPool::run(std::size_t count, TaskFunction task, void* context) noexcept {
    if (count == 0U) {
        return;
    }
    CG_ENFORCE(task != nullptr, "WorkerPool::run: null task");
    if (started_ == 0U || count == 1U) {
        for (std::size_t i = 0U; i < count; ++i) {
            task(context, i);
        }
        return;
    }
    // Every worker may take one index past count: keep the counter from wrapping.
    CG_ENFORCE(count <= std::numeric_limits<std::size_t>::max() - kMaxWorkers, "WorkerPool::run: count too large");
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        task_ = task;
        context_ = context;
        count_ = count;
        next_.store(0U, std::memory_order_relaxed);
        pending_ = started_;
        ++generation_;
    }
    wake_.notify_all();
    drain();
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this]() noexcept { return pending_ == 0U; });
}

void WorkerPool::worker_loop() noexcept {
    std::uint64_t seen = 0U;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this, seen]() noexcept { return stop_ || generation_ != seen; });
        if (stop_) {
            return;
        }
        seen = generation_;
        lock.unlock();
        drain();
        lock.lock();
        --pending_;
        if (pending_ == 0U) {
            done_.notify_one();
        }
    }
}

PinError WorkerPool::pin_worker(std::size_t worker, int cpu) noexcept {
    if (worker >= concurrency()) {
        return PinError::kNoSuchWorker;
    }
#if defined(__linux__) && defined(__GLIBC__)
    if (cpu < 0 || cpu >= CPU_SETSIZE) {
        return PinError::kNoSuchCpu;
    }
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<std::size_t>(cpu), &set);
    const pthread_t handle = worker == 0U ? pthread_self() : threads_[worker - 1U].native_handle();
    return pthread_setaffinity_np(handle, sizeof(set), &set) == 0 ? PinError::kOk : PinError::kRefused;
#else
    (void)cpu;
    return PinError::kNotSupported;
#endif
}

}  // namespace cellguard::linux_port
