// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file candump_log.hpp
/// CAN frames as a candump log file: the format `candump -L` writes and
/// `canplayer` replays, one frame per line:
///
///     (1700000000.123456) vcan0 101#0011223344556677
///
/// timestamp in seconds with exactly six decimals, the interface name, the
/// CAN ID in three upper-case hex digits (standard IDs) and the data bytes
/// in upper-case hex, two digits each, nothing after `#` for DLC 0. The
/// writer implements CanSender, so the monitor can log instead of sending on
/// a bus; the parser reads such a line back (for tests and for checking a
/// log with the PLC receiver).
#ifndef CELLGUARD_HOST_IO_CANDUMP_LOG_HPP
#define CELLGUARD_HOST_IO_CANDUMP_LOG_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/safety_output.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/safety/safety_controller.hpp"

namespace cellguard {

/// Longest interface name written (IFNAMSIZ - 1).
constexpr std::size_t kCandumpMaxInterfaceName = 15U;
/// Buffer size that holds any line format_candump_line writes, NUL included.
constexpr std::size_t kCandumpLineCapacity = 64U;

/// Writes the candump line of @p frame at @p timestamp_us (microseconds) on
/// @p interface_name into @p out (capacity @p capacity), without the newline.
/// Returns the line length, or 0 when the interface name is empty or longer
/// than kCandumpMaxInterfaceName, the ID exceeds 11 bits, the DLC exceeds 8,
/// or the line does not fit.
[[nodiscard]] std::size_t format_candump_line(char* out, std::size_t capacity, std::uint64_t timestamp_us,
                                              const char* interface_name, const CanFrame& frame) noexcept;

/// One parsed candump line.
struct CandumpRecord {
    std::uint64_t timestamp_us = 0U;                          ///< timestamp, microseconds
    char interface_name[kCandumpMaxInterfaceName + 1U] = {};  ///< interface, NUL-terminated
    CanFrame frame{0U, 0U, {}};                               ///< the frame
};

/// Parses one line (without or with a trailing newline) in the format above:
/// standard 3-digit IDs only, 0..8 data bytes, six-digit fraction.
/// kMalformedInput (with what was wrong) for anything else.
[[nodiscard]] IoStatus parse_candump_line(const char* line, CandumpRecord& out) noexcept;

/// A CanSender that appends candump lines to a file, timestamped by a clock.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class CandumpLogWriter final : public CanSender {
public:
    /// A writer with no file; send() fails until open() succeeds.
    CandumpLogWriter() noexcept = default;
    /// Closes the file.
    ~CandumpLogWriter();
    CandumpLogWriter(const CandumpLogWriter&) = delete;
    CandumpLogWriter& operator=(const CandumpLogWriter&) = delete;
    CandumpLogWriter(CandumpLogWriter&&) = delete;
    CandumpLogWriter& operator=(CandumpLogWriter&&) = delete;

    /// Opens @p path for writing, creating it when missing; an existing file
    /// keeps its content until the first frame is sent, which empties it
    /// first (a run refused before its first cycle loses no earlier log).
    /// Lines name @p interface_name and take their time from @p clock (must
    /// outlive the writer). kInvalidArgument for a bad interface name or when
    /// the file cannot be opened for writing.
    IoStatus open(const char* path, const char* interface_name, MonotonicClock& clock) noexcept;
    /// Flushes and closes the file; false when a write or the close failed.
    bool close() noexcept;
    /// Appends the line of @p frame; false when not open, the frame is not
    /// a standard frame of at most 8 bytes, or the write failed.
    bool send(const CanFrame& frame) noexcept override;
    /// Lines written so far.
    [[nodiscard]] std::size_t lines() const noexcept { return lines_; }

private:
    std::FILE* file_ = nullptr;
    MonotonicClock* clock_ = nullptr;
    char interface_[kCandumpMaxInterfaceName + 1U] = {};
    std::size_t lines_ = 0U;
    bool failed_ = false;
    bool emptied_ = false;  ///< the first frame emptied the file
};

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_CANDUMP_LOG_HPP
