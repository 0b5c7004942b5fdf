// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/candump_log.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cellguard {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";

bool interface_name_valid(const char* name) noexcept {
    if (name == nullptr || name[0] == '\0') {
        return false;
    }
    const std::size_t n = std::strlen(name);
    if (n > kCandumpMaxInterfaceName) {
        return false;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        const char c = name[i];
        if (c == ' ' || c == '(' || c == ')' || c == '#' || c == '\n' || c == '\r' || c == '\t') {
            return false;
        }
    }
    return true;
}

/// Value of hex digit @p c (either case), or -1.
int hex_value(char c) noexcept {
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    return -1;
}

/// Reads @p count decimal digits at @p p into @p value; false when one is not a digit.
bool read_decimal(const char*& p, std::size_t count, std::uint64_t& value) noexcept {
    value = 0U;
    for (std::size_t i = 0U; i < count; ++i) {
        if (p[i] < '0' || p[i] > '9') {
            return false;
        }
        value = value * 10U + static_cast<std::uint64_t>(p[i] - '0');
    }
    p += count;
    return true;
}

}  // namespace

std::size_t format_candump_line(char* out, std::size_t capacity, std::uint64_t timestamp_us, const char* interface_name,
                                const CanFrame& frame) noexcept {
    if (out == nullptr || !interface_name_valid(interface_name) || frame.id > kCanMaxStandardId ||
        frame.dlc > kCanMaxDataLength) {
        return 0U;
    }
    char data[2U * kCanMaxDataLength + 1U] = {};
    for (std::size_t k = 0U; k < frame.dlc; ++k) {
        data[2U * k] = kHex[frame.data[k] >> 4U];
        data[2U * k + 1U] = kHex[frame.data[k] & 0x0FU];
    }
    const int n = std::snprintf(out, capacity, "(%llu.%06llu) %s %03X#%s",
                                static_cast<unsigned long long>(timestamp_us / 1000000U),
                                static_cast<unsigned long long>(timestamp_us % 1000000U), interface_name,
                                static_cast<unsigned>(frame.id), data);
    if (n <= 0 || static_cast<std::size_t>(n) >= capacity) {
        return 0U;
    }
    return static_cast<std::size_t>(n);
}

IoStatus parse_candump_line(const char* line, CandumpRecord& out) noexcept {
    if (line == nullptr) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: no line");
    }
    const char* p = line;
    if (*p != '(') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: expected '(' at column 1");
    }
    ++p;
    std::size_t digits = 0U;
    while (p[digits] >= '0' && p[digits] <= '9') {
        ++digits;
    }
    std::uint64_t seconds = 0U;
    if (digits == 0U || digits > 13U || !read_decimal(p, digits, seconds) || *p != '.') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: timestamp seconds missing or too long");
    }
    ++p;
    std::uint64_t micros = 0U;
    if (!read_decimal(p, 6U, micros) || *p != ')' || p[1] != ' ') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: timestamp needs six decimals, then ') '");
    }
    p += 2;
    CandumpRecord r;
    r.timestamp_us = seconds * 1000000U + micros;
    std::size_t name_len = 0U;
    while (p[name_len] != ' ' && p[name_len] != '\0') {
        ++name_len;
    }
    if (name_len == 0U || name_len > kCandumpMaxInterfaceName || p[name_len] != ' ') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: interface name missing or longer than %zu",
                                 kCandumpMaxInterfaceName);
    }
    std::memcpy(r.interface_name, p, name_len);
    r.interface_name[name_len] = '\0';
    p += name_len + 1U;
    std::uint32_t id = 0U;
    for (int i = 0; i < 3; ++i) {
        const int v = hex_value(p[i]);
        if (v < 0) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: CAN ID must be three hex digits");
        }
        id = id * 16U + static_cast<std::uint32_t>(v);
    }
    p += 3;
    if (*p != '#' || id > kCanMaxStandardId) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "candump line: expected a standard (3-digit, <= 7FF) CAN ID and '#'");
    }
    ++p;
    std::uint8_t dlc = 0U;
    while (hex_value(p[0]) >= 0) {
        const int lo = hex_value(p[1]);
        if (lo < 0) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: odd number of data hex digits");
        }
        if (dlc == kCanMaxDataLength) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: more than 8 data bytes");
        }
        r.frame.data[dlc] = static_cast<std::uint8_t>(hex_value(p[0]) * 16 + lo);
        ++dlc;
        p += 2;
    }
    if (*p == '\r') {
        ++p;
    }
    if (*p == '\n') {
        ++p;
    }
    if (*p != '\0') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "candump line: unexpected text after the data");
    }
    r.frame.id = id;
    r.frame.dlc = dlc;
    out = r;
    return IoStatus{};
}

CandumpLogWriter::~CandumpLogWriter() { (void)close(); }

IoStatus CandumpLogWriter::open(const char* path, const char* interface_name, MonotonicClock& clock) noexcept {
    (void)close();
    failed_ = false;
    lines_ = 0U;
    if (!interface_name_valid(interface_name)) {
        return IoStatus::failure(
            ErrorCode::kInvalidArgument,
            "candump log: interface name must be 1..%zu characters without blanks, '(', ')' or '#'",
            kCandumpMaxInterfaceName);
    }
    if (path == nullptr || path[0] == '\0') {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "candump log: empty path");
    }
    // Opened for appending, not truncated: a run refused after this (a later
    // argument, a missing prior) leaves the previous run's log as it was; the
    // first frame empties it (issue 32).
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): file_ owns it; close() releases it
    std::FILE* f = std::fopen(path, "a");
    if (f == nullptr) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot create: %s", path, std::strerror(errno));
    }
    file_ = f;
    emptied_ = false;
    clock_ = &clock;
    std::memcpy(interface_, interface_name, std::strlen(interface_name) + 1U);
    return IoStatus{};
}

bool CandumpLogWriter::close() noexcept {
    if (file_ == nullptr) {
        return !failed_;
    }
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): file_ is the FILE* this writer opened
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    failed_ = failed_ || !closed;
    return !failed_;
}

bool CandumpLogWriter::send(const CanFrame& frame) noexcept {
    if (file_ == nullptr) {
        return false;
    }
    char line[kCandumpLineCapacity];
    const std::size_t n = format_candump_line(line, sizeof(line), clock_->now_us(), interface_, frame);
    if (n == 0U) {
        return false;
    }
    if (!emptied_) {  // the first frame: the previous content goes (a pipe or device has none to keep)
        struct stat st {};
        const int fd = fileno(file_);
        if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ftruncate(fd, 0) != 0) {
            failed_ = true;
            return false;
        }
        emptied_ = true;
    }
    line[n] = '\n';
    if (std::fwrite(line, 1U, n + 1U, file_) != n + 1U) {
        failed_ = true;
        return false;
    }
    ++lines_;
    return true;
}

}  // namespace cellguard
