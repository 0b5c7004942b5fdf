// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file worker_pool.hpp
/// The Linux port's threaded TaskRunner (cellguard/base/task_runner.hpp):
/// WorkerPool runs the tasks of one computation on N workers, the thread
/// that calls run() being worker 0 and N - 1 std::threads the others.
///
/// Memory: everything is made at construction. The N - 1 std::thread objects
/// live in a fixed std::array of kMaxWorkers - 1 (the threads' own start-up
/// state and stacks are allocated by the standard library and the OS once,
/// when they start). run() allocates nothing, takes no std::function and
/// starts no thread.
///
/// One run(count, task, context):
/// - count 0 returns at once; with one worker (or one task) the calling
///   thread runs every task in index order, as SequentialRunner does;
/// - otherwise it publishes the computation, bumps a generation counter under
///   the pool's mutex and wakes the workers; each worker wakes once per
///   generation. Every worker, worker 0 included, takes task indices from
///   one atomic counter until they run out, then reports done; run() returns
///   when all N - 1 threads have reported (condition variable). The mutex
///   orders every task's writes before run()'s return.
/// Which worker runs which index is not fixed; the result does not depend on
/// it when the tasks write disjoint memory (TaskRunner's rule for lib/).
///
/// The destructor stops the workers and joins them. run() and the destructor
/// must not be called concurrently (TaskRunner's rule), nor from a task.
///
/// Optional placement: pin_worker(i, cpu) pins worker i to one CPU where the
/// OS allows it (pthread_setaffinity_np on glibc); a refusal is reported,
/// never fatal, and the pool runs unpinned as before.
#ifndef CELLGUARD_PORT_WORKER_POOL_HPP
#define CELLGUARD_PORT_WORKER_POOL_HPP

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>

#include "cellguard/base/task_runner.hpp"

namespace cellguard::linux_port {

/// Most workers of one pool (the calling thread included).
inline constexpr std::size_t kMaxWorkers = 16U;

/// Why pin_worker did not pin.
enum class PinError : std::uint8_t {
    kOk = 0,        ///< pinned
    kNoSuchWorker,  ///< worker index >= concurrency()
    kNoSuchCpu,     ///< cpu negative or beyond what the OS's CPU set can name
    kRefused,       ///< the OS refused (cpu offline, not allowed by cgroup/cpuset, ...)
    kNotSupported,  ///< this C library offers no affinity call
};
/// A short, static description of @p error (never nullptr).
[[nodiscard]] const char* to_string(PinError error) noexcept;

/// A TaskRunner on N worker threads (see the file comment).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class WorkerPool final : public TaskRunner {
public:
    /// Starts @p workers - 1 threads; the caller of run() is the remaining
    /// worker. @p workers must be in [1, kMaxWorkers] (a contract,
    /// CG_ENFORCE). When the OS refuses a thread (std::system_error), the
    /// pool keeps the threads it got: concurrency() then says how many.
    explicit WorkerPool(std::size_t workers);
    /// Stops the workers and joins them.
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;
    WorkerPool(WorkerPool&&) = delete;
    WorkerPool& operator=(WorkerPool&&) = delete;

    /// Runs @p task(@p context, i) for every i in [0, @p count) on the
    /// workers and returns when all have finished. Allocates nothing.
    void run(std::size_t count, TaskFunction task, void* context) noexcept override;
    /// The workers running, the calling thread included (the constructor's
    /// count unless the OS refused a thread).
    [[nodiscard]] std::size_t concurrency() const noexcept override { return started_ + 1U; }

    /// Pins worker @p worker to CPU @p cpu. Worker 0 is the thread that calls
    /// run(), so pin_worker(0, cpu) pins the calling thread. Call it between
    /// runs (not from a task).
    [[nodiscard]] PinError pin_worker(std::size_t worker, int cpu) noexcept;

private:
    /// A started thread's loop: one drain() per generation until stop_.
    void worker_loop() noexcept;
    /// Takes indices from next_ and runs them until none is left.
    void drain() noexcept;

    std::size_t requested_;     ///< the constructor's count (checked first: nothing else built yet)
    std::size_t started_ = 0U;  ///< threads running (workers besides the caller)
    std::mutex mutex_;
    std::condition_variable wake_;                         ///< workers wait here for the next generation or stop
    std::condition_variable done_;                         ///< run() waits here for pending_ to reach 0
    std::uint64_t generation_ = 0U;                        ///< bumped once per threaded run (under mutex_)
    std::size_t pending_ = 0U;                             ///< threads not yet done with this generation (under mutex_)
    bool stop_ = false;                                    ///< set by the destructor (under mutex_)
    TaskFunction task_ = nullptr;                          ///< this generation's task (written under mutex_)
    void* context_ = nullptr;                              ///< this generation's context (written under mutex_)
    std::size_t count_ = 0U;                               ///< this generation's task count (written under mutex_)
    std::atomic<std::size_t> next_{0U};                    ///< next task index to hand out
    std::array<std::thread, kMaxWorkers - 1U> threads_{};  ///< the threads, made once
};

}  // namespace cellguard::linux_port

#endif  // CELLGUARD_PORT_WORKER_POOL_HPP
