// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Verifies io_status.hpp: success and failure values, formatted messages, truncation and prefixing.
#include <doctest/doctest.h>

#include <cstring>
#include <string>

#include "cellguard/host/io/io_status.hpp"

using namespace cellguard;

// verifies: SR-IO-003
TEST_CASE("io status: a default status is success with an empty message") {
    const IoStatus st;
    CHECK(st.ok());
    CHECK(static_cast<bool>(st));
    CHECK(st.error() == ErrorCode::kOk);
    CHECK(std::string(st.message()).empty());
    CHECK(st.status().ok());
    CHECK(st.prefixed("file").ok());
}

// verifies: SR-IO-003
TEST_CASE("io status: a failure carries its code and formatted message, and a prefix goes in front") {
    const IoStatus st = IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %d: %s", 7, "bad");
    CHECK_FALSE(st.ok());
    CHECK(st.error() == ErrorCode::kMalformedInput);
    CHECK(st.status().error() == ErrorCode::kMalformedInput);
    CHECK(std::string(st.message()) == "pcd: line 7: bad");
    const IoStatus p = st.prefixed("/tmp/a.pcd");
    CHECK(p.error() == ErrorCode::kMalformedInput);
    CHECK(std::string(p.message()) == "/tmp/a.pcd: pcd: line 7: bad");
}

// verifies: SR-IO-003
TEST_CASE("io status: a message longer than the buffer is cut, not overrun") {
    const std::string long_text(1000, 'x');
    const IoStatus st = IoStatus::failure(ErrorCode::kInvalidArgument, "%s", long_text.c_str());
    CHECK(std::strlen(st.message()) == IoStatus::kMessageCapacity - 1U);
    const IoStatus p = st.prefixed("prefix");
    CHECK(std::strlen(p.message()) == IoStatus::kMessageCapacity - 1U);
    CHECK(std::strncmp(p.message(), "prefix: xxx", 11) == 0);
}
