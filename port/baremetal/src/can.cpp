// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The semihosting CAN backend (semihosting_can.hpp).
#include "cellguard/port/can.hpp"

#include <cstddef>

#include "cellguard/port/semihosting.hpp"

namespace cellguard::baremetal {
namespace {

constexpr char kHex[] = "0123456789abcdef";

}  // namespace

void format_can_frame(const CanFrame& frame, char (&out)[48]) noexcept {
    std::size_t n = 0U;
    const char* prefix = "can 0x";
    while (*prefix != '\0') {
        out[n++] = *prefix++;
    }
    out[n++] = kHex[(frame.id >> 8U) & 0xFU];
    out[n++] = kHex[(frame.id >> 4U) & 0xFU];
    out[n++] = kHex[frame.id & 0xFU];
    out[n++] = ' ';
    out[n++] = '[';
    out[n++] = static_cast<char>('0' + static_cast<int>(frame.dlc % 10U));
    out[n++] = ']';
    for (std::size_t i = 0U; i < sizeof(frame.data) && i < frame.dlc; ++i) {
        out[n++] = ' ';
        const auto byte = static_cast<unsigned>(frame.data[i]);
        out[n++] = kHex[(byte >> 4U) & 0xFU];
        out[n++] = kHex[byte & 0xFU];
    }
    out[n++] = '\n';
    out[n] = '\0';
}

bool SemihostingCanSender::send(const CanFrame& frame) noexcept {
    char line[48];
    format_can_frame(frame, line);
    semihosting_write(line);
    return true;
}

}  // namespace cellguard::baremetal
