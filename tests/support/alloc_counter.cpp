// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "alloc_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<std::size_t> g_allocations{0};
// Initial-exec TLS of the executable: reading it allocates nothing.
thread_local std::size_t t_allocations = 0U;
void count_one() noexcept {
    g_allocations.fetch_add(1, std::memory_order_relaxed);
    ++t_allocations;
}
}  // namespace

namespace cellguard::test {
std::size_t allocation_count() noexcept { return g_allocations.load(std::memory_order_relaxed); }
std::size_t thread_allocation_count() noexcept { return t_allocations; }
}  // namespace cellguard::test

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
// glibc lets a program interpose malloc; forward to the real allocator.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* malloc(std::size_t size) {
    count_one();
    return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
    count_one();
    return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
    count_one();
    return __libc_realloc(p, size);
}
}
void* operator new(std::size_t size) { return std::malloc(size == 0 ? 1 : size); }  // counted by malloc
void* operator new[](std::size_t size) { return std::malloc(size == 0 ? 1 : size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#else
void* operator new(std::size_t size) {
    count_one();
    void* p = std::malloc(size == 0 ? 1 : size);
    if (p == nullptr)
        throw std::bad_alloc();
    return p;
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#endif
