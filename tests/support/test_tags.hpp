// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file test_tags.hpp
/// Decorators that group unit test cases for the runs that select by group.
#ifndef CELLGUARD_TESTS_TEST_TAGS_HPP
#define CELLGUARD_TESTS_TEST_TAGS_HPP

#include <doctest/doctest.h>

/// A case that replays a scene over tens to hundreds of cycles (or a whole demo) to show that a
/// decision holds over time, whose per-cycle code shorter cases run too. tools/cross.sh leaves the
/// group out of the aarch64 unit tests under qemu-user (an emulated run there takes about ten
/// times the native time, and the group was two thirds of it), and tools/evidence.sh leaves it out
/// of the coverage run (most of that run's time; without it lib/'s coverage was 1 line and about 2
/// branches lower, 2026-12-07); README's ctest and the clang build run it natively, and the
/// firmware digests compare the scenarios bit for bit on all three targets. Written `TEST_CASE("..." * CELLGUARD_LONG_REPLAY)`.
#define CELLGUARD_LONG_REPLAY doctest::test_suite("long replay")

#endif  // CELLGUARD_TESTS_TEST_TAGS_HPP
