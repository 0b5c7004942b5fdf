// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file task_runner.hpp
/// How lib/ hands independent pieces of one computation to the cores a port
/// has, without knowing about threads: a TaskRunner runs tasks 0..count-1
/// and returns when every one has finished. lib/ splits its work into tasks
/// that write disjoint memory and whose results do not depend on which
/// runner, thread or order ran them, so one core (SequentialRunner, the
/// reference) and any number of workers give the same bits. A port supplies
/// a threaded runner (port/linux: WorkerPool); lib/ itself starts no thread.
#ifndef CELLGUARD_BASE_TASK_RUNNER_HPP
#define CELLGUARD_BASE_TASK_RUNNER_HPP

#include <cstddef>

namespace cellguard {

/// A task: index @p index of a computation over @p context. Must not throw.
using TaskFunction = void (*)(void* context, std::size_t index) noexcept;

/// Runs the tasks of one computation (see the file comment).
class TaskRunner {
public:
    /// Runs @p task(@p context, i) once for every i in [0, @p count), in any
    /// order and on any of the runner's threads, and returns when all have
    /// finished. count 0 returns at once. Must not be called concurrently.
    virtual void run(std::size_t count, TaskFunction task, void* context) noexcept = 0;
    /// How many tasks may run at the same time (>= 1): lib/ sizes its split by it.
    [[nodiscard]] virtual std::size_t concurrency() const noexcept = 0;

protected:
    TaskRunner() = default;
    ~TaskRunner() = default;
    TaskRunner(const TaskRunner&) = default;
    TaskRunner& operator=(const TaskRunner&) = default;
    TaskRunner(TaskRunner&&) = default;
    TaskRunner& operator=(TaskRunner&&) = default;
};

/// The reference runner: every task on the calling thread, in index order.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class SequentialRunner final : public TaskRunner {
public:
    /// Runs the tasks one after another on the calling thread.
    void run(std::size_t count, TaskFunction task, void* context) noexcept override {
        for (std::size_t i = 0U; i < count; ++i) {
            task(context, i);
        }
    }
    /// One.
    [[nodiscard]] std::size_t concurrency() const noexcept override { return 1U; }
};

}  // namespace cellguard

#endif  // CELLGUARD_BASE_TASK_RUNNER_HPP
