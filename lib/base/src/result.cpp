// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/base/result.hpp"

namespace cellguard {

const char* to_string(ErrorCode code) noexcept {
    switch (code) {
        case ErrorCode::kOk: return "ok";
        case ErrorCode::kInvalidArgument: return "invalid argument";
        case ErrorCode::kCapacityExceeded: return "capacity exceeded";
        case ErrorCode::kStorageTooSmall: return "storage too small";
        case ErrorCode::kGeometryMismatch: return "geometry mismatch";
        case ErrorCode::kTruncatedInput: return "truncated input";
        case ErrorCode::kBadMagic: return "bad magic";
        case ErrorCode::kUnsupportedVersion: return "unsupported version";
        case ErrorCode::kCrcMismatch: return "CRC mismatch";
        case ErrorCode::kMalformedInput: return "malformed input";
        case ErrorCode::kSensorIndexOutOfRange: return "sensor index out of range";
        case ErrorCode::kNonFiniteValue: return "non-finite value";
        case ErrorCode::kOutOfGrid: return "outside the grid";
        case ErrorCode::kUnsupportedType: return "unsupported type";
    }
    return "unknown error";
}

}  // namespace cellguard
