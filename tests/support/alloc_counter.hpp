// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Counts heap allocations made by this test process, to show that a piece of
// lib/ allocates nothing (operator new and, on glibc, malloc itself).
#ifndef CELLGUARD_TESTS_ALLOC_COUNTER_HPP
#define CELLGUARD_TESTS_ALLOC_COUNTER_HPP

#include <cstddef>

namespace cellguard::test {

/// Allocations (operator new, malloc, calloc, realloc) since the process started.
std::size_t allocation_count() noexcept;

/// Allocations made by the calling thread since it started.
std::size_t thread_allocation_count() noexcept;

/// Counts the allocations the calling thread makes during its lifetime
/// (other threads' are not counted).
class ThreadAllocationScope {
public:
    ThreadAllocationScope() noexcept : start_(thread_allocation_count()) {}
    /// This thread's allocations since construction.
    [[nodiscard]] std::size_t allocations() const noexcept { return thread_allocation_count() - start_; }

private:
    std::size_t start_;
};

/// Counts the allocations made during its lifetime.
class AllocationScope {
public:
    AllocationScope() noexcept : start_(allocation_count()) {}
    /// Allocations since construction.
    [[nodiscard]] std::size_t allocations() const noexcept { return allocation_count() - start_; }

private:
    std::size_t start_;
};

}  // namespace cellguard::test

#endif
