// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/pcd.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "pcd.cpp reads little-endian binary PCD data as is: it needs a little-endian host");

namespace cellguard {

namespace {

/// The header keywords, in the order PCD v0.7 requires.
enum Keyword : int {
    kVersion = 0,
    kFields,
    kSize,
    kType,
    kCount,
    kWidth,
    kHeight,
    kViewpoint,
    kPoints,
    kData,
    kKeywordCount,
};

constexpr const char* kKeywordNames[kKeywordCount] = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                                      "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};

/// LZF: a back-reference of 3 bytes yields at most 264 bytes.
constexpr std::uint64_t kLzfMaxExpansion = 88;

/// Tokens of one line: keyword plus up to kPcdMaxFields values.
constexpr std::size_t kMaxTokens = kPcdMaxFields + 1U;

struct FileCloser {
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): the deleter of FilePtr, which owns the FILE*
    void operator()(std::FILE* f) const noexcept { static_cast<void>(std::fclose(f)); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

bool is_blank(char c) noexcept { return c == ' ' || c == '\t' || c == '\r'; }

/// Splits [begin, end) at spaces and tabs.
struct Tokens {
    std::string_view items[kMaxTokens];
    std::size_t count = 0;
    bool overflow = false;
};

void tokenize(const char* begin, const char* end, Tokens& tokens) noexcept {
    tokens.count = 0;
    tokens.overflow = false;
    const char* p = begin;
    while (p != end) {
        while (p != end && is_blank(*p)) {
            ++p;
        }
        if (p == end) {
            break;
        }
        const char* start = p;
        while (p != end && !is_blank(*p)) {
            ++p;
        }
        if (tokens.count == kMaxTokens) {
            tokens.overflow = true;
            return;
        }
        tokens.items[tokens.count++] = std::string_view(start, static_cast<std::size_t>(p - start));
    }
}

/// A whole token as an unsigned decimal integer.
bool parse_u64(std::string_view token, std::uint64_t& value) noexcept {
    if (token.empty() || token.front() < '0' || token.front() > '9') {
        return false;
    }
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, value);
    return r.ec == std::errc() && r.ptr == end;
}

/// A whole token as a signed decimal integer.
bool parse_i64(std::string_view token, std::int64_t& value) noexcept {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
        if (token.empty() || token.front() == '-') {
            return false;
        }
    }
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, value);
    return !token.empty() && r.ec == std::errc() && r.ptr == end;
}

/// A whole token as a double (decimal, exponent, "nan", "inf"; a leading '+' is allowed).
bool parse_double(std::string_view token, double& value) noexcept {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
        if (token.empty() || token.front() == '-') {
            return false;
        }
    }
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, value, std::chars_format::general);
    return !token.empty() && r.ec == std::errc() && r.ptr == end;
}

/// A short printable copy of a token for a message.
struct TokenText {
    char text[40] = {};
    explicit TokenText(std::string_view token) noexcept {
        std::size_t n = std::min(token.size(), sizeof text - 4U);
        for (std::size_t i = 0; i < n; ++i) {
            const char c = token[i];
            text[i] = (c >= 0x20 && c <= 0x7E) ? c : '?';
        }
        if (n < token.size()) {
            text[n++] = '.';
            text[n++] = '.';
            text[n++] = '.';
        }
        text[n] = '\0';
    }
};

const char* type_letter(PcdFieldType type) noexcept {
    switch (type) {
        case PcdFieldType::kFloat: return "F";
        case PcdFieldType::kSigned: return "I";
        case PcdFieldType::kUnsigned: return "U";
    }
    return "?";
}

IoStatus line_error(ErrorCode code, std::size_t line, const char* what) noexcept {
    return IoStatus::failure(code, "pcd: line %zu: %s", line, what);
}

/// Checks a keyword line's value count.
IoStatus expect_values(const Tokens& t, std::size_t values, std::size_t line) noexcept {
    if (t.count != values + 1U) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: %s takes %zu value%s, found %zu", line,
                                 TokenText(t.items[0]).text, values, values == 1U ? "" : "s", t.count - 1U);
    }
    return IoStatus{};
}

/// Checks that a per-field line (SIZE, TYPE, COUNT) has one value per field.
IoStatus expect_per_field(const Tokens& t, const PcdHeader& h, const char* keyword, std::size_t line) noexcept {
    if (t.count - 1U != h.field_count) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: FIELDS has %zu names but %s has %zu", line,
                                 h.field_count, keyword, t.count - 1U);
    }
    return IoStatus{};
}

IoStatus parse_version(std::string_view v, PcdHeader& h, std::size_t line) noexcept {
    if (v == "0.7" || v == ".7") {
        h.version_minor = 7;
    } else if (v == "0.6" || v == ".6") {
        h.version_minor = 6;
    } else if (v == "0.5" || v == ".5") {
        h.version_minor = 5;
    } else {
        return IoStatus::failure(ErrorCode::kUnsupportedVersion, "pcd: line %zu: VERSION %s (reads 0.5, 0.6, 0.7)",
                                 line, TokenText(v).text);
    }
    return IoStatus{};
}

IoStatus parse_fields(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    if (t.count < 2U) {
        return line_error(ErrorCode::kMalformedInput, line, "FIELDS names no field");
    }
    h.field_count = t.count - 1U;
    for (std::size_t i = 0; i < h.field_count; ++i) {
        const std::string_view name = t.items[i + 1U];
        if (name.size() >= kPcdMaxFieldName) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: field name '%s' longer than %zu characters", line,
                                     TokenText(name).text, kPcdMaxFieldName - 1U);
        }
        std::memcpy(h.fields[i].name, name.data(), name.size());
        h.fields[i].name[name.size()] = '\0';
        h.fields[i].size = 4;  // defaults of old headers without SIZE/TYPE are never used: both are required
        h.fields[i].count = 1;
    }
    return IoStatus{};
}

IoStatus parse_sizes(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    IoStatus st = expect_per_field(t, h, "SIZE", line);
    if (!st) {
        return st;
    }
    for (std::size_t i = 0; i < h.field_count; ++i) {
        std::uint64_t size = 0;
        if (!parse_u64(t.items[i + 1U], size) || (size != 1U && size != 2U && size != 4U && size != 8U)) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: SIZE '%s' of field '%s' is not 1, 2, 4 or 8", line,
                                     TokenText(t.items[i + 1U]).text, h.fields[i].name);
        }
        h.fields[i].size = static_cast<std::uint32_t>(size);
    }
    return IoStatus{};
}

IoStatus parse_types(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    IoStatus st = expect_per_field(t, h, "TYPE", line);
    if (!st) {
        return st;
    }
    for (std::size_t i = 0; i < h.field_count; ++i) {
        const std::string_view v = t.items[i + 1U];
        PcdField& f = h.fields[i];
        if (v == "F") {
            f.type = PcdFieldType::kFloat;
        } else if (v == "I") {
            f.type = PcdFieldType::kSigned;
        } else if (v == "U") {
            f.type = PcdFieldType::kUnsigned;
        } else {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: TYPE '%s' of field '%s' is not F, I or U", line, TokenText(v).text,
                                     f.name);
        }
        const bool ok = f.type == PcdFieldType::kFloat ? (f.size == 4U || f.size == 8U) : f.size <= 4U;
        if (!ok) {
            return IoStatus::failure(ErrorCode::kUnsupportedType,
                                     "pcd: line %zu: field '%s' has TYPE %s with SIZE %u (F: 4 or 8; I, U: 1, 2 or 4)",
                                     line, f.name, type_letter(f.type), static_cast<unsigned>(f.size));
        }
    }
    return IoStatus{};
}

IoStatus parse_counts(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    IoStatus st = expect_per_field(t, h, "COUNT", line);
    if (!st) {
        return st;
    }
    for (std::size_t i = 0; i < h.field_count; ++i) {
        std::uint64_t count = 0;
        if (!parse_u64(t.items[i + 1U], count) || count < 1U || count > kPcdMaxCount) {
            return IoStatus::failure(
                ErrorCode::kMalformedInput, "pcd: line %zu: COUNT '%s' of field '%s' is not in [1, %u]", line,
                TokenText(t.items[i + 1U]).text, h.fields[i].name, static_cast<unsigned>(kPcdMaxCount));
        }
        h.fields[i].count = static_cast<std::uint32_t>(count);
    }
    return IoStatus{};
}

IoStatus parse_dimension(const Tokens& t, std::uint32_t& value, std::size_t line) noexcept {
    IoStatus st = expect_values(t, 1U, line);
    if (!st) {
        return st;
    }
    std::uint64_t v = 0;
    if (!parse_u64(t.items[1], v) || v < 1U || v > UINT32_MAX) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: %s '%s' is not an integer in [1, 2^32)",
                                 line, TokenText(t.items[0]).text, TokenText(t.items[1]).text);
    }
    value = static_cast<std::uint32_t>(v);
    return IoStatus{};
}

IoStatus parse_viewpoint(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    IoStatus st = expect_values(t, 7U, line);
    if (!st) {
        return st;
    }
    double v[7] = {};
    for (std::size_t i = 0; i < 7U; ++i) {
        if (!parse_double(t.items[i + 1U], v[i]) || !std::isfinite(v[i])) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: VIEWPOINT value '%s' is not a finite number", line,
                                     TokenText(t.items[i + 1U]).text);
        }
    }
    const double norm2 = v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6];
    if (std::fabs(std::sqrt(norm2) - 1.0) > 1e-3) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: line %zu: VIEWPOINT quaternion (%g %g %g %g) is not a unit quaternion", line,
                                 v[3], v[4], v[5], v[6]);
    }
    h.viewpoint = PcdViewpoint{v[0], v[1], v[2], v[3], v[4], v[5], v[6]};
    return IoStatus{};
}

/// Lays out the fields and finds x, y, z once the header is complete.
IoStatus finish_header(PcdHeader& h) noexcept {
    std::size_t offset = 0;
    for (std::size_t i = 0; i < h.field_count; ++i) {
        h.fields[i].offset = offset;
        offset += static_cast<std::size_t>(h.fields[i].size) * h.fields[i].count;  // <= 64 * 2^16 * 8: no overflow
    }
    h.point_bytes = offset;
    const char* names[3] = {"x", "y", "z"};
    std::size_t* slots[3] = {&h.x_field, &h.y_field, &h.z_field};
    for (std::size_t k = 0; k < 3U; ++k) {
        std::size_t found = 0;
        for (std::size_t i = 0; i < h.field_count; ++i) {
            if (std::strcmp(h.fields[i].name, names[k]) == 0) {
                *slots[k] = i;
                ++found;
            }
        }
        if (found == 0U) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: no field '%s' in FIELDS", names[k]);
        }
        if (found > 1U) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: field '%s' appears %zu times in FIELDS",
                                     names[k], found);
        }
        if (h.fields[*slots[k]].count != 1U) {
            return IoStatus::failure(ErrorCode::kUnsupportedType,
                                     "pcd: field '%s' has COUNT %u; x, y and z need COUNT 1", names[k],
                                     static_cast<unsigned>(h.fields[*slots[k]].count));
        }
    }
    if (h.points > kPcdMaxDataBytes / h.point_bytes) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                 "pcd: %" PRIu64 " points of %zu bytes exceed the limit of %" PRIu64 " bytes", h.points,
                                 h.point_bytes, kPcdMaxDataBytes);
    }
    return IoStatus{};
}

/// Reads one value of field @p f at @p p as a double.
double load_value(const std::uint8_t* p, const PcdField& f) noexcept {
    switch (f.type) {
        case PcdFieldType::kFloat:
            if (f.size == 4U) {
                float v = 0.0F;
                std::memcpy(&v, p, sizeof v);
                return static_cast<double>(v);
            } else {
                double v = 0.0;
                std::memcpy(&v, p, sizeof v);
                return v;
            }
        case PcdFieldType::kSigned:
            if (f.size == 1U) {
                return static_cast<double>(static_cast<std::int8_t>(p[0]));
            } else if (f.size == 2U) {
                std::int16_t v = 0;
                std::memcpy(&v, p, sizeof v);
                return static_cast<double>(v);
            } else {
                std::int32_t v = 0;
                std::memcpy(&v, p, sizeof v);
                return static_cast<double>(v);
            }
        case PcdFieldType::kUnsigned:
            if (f.size == 1U) {
                return static_cast<double>(p[0]);
            } else if (f.size == 2U) {
                std::uint16_t v = 0;
                std::memcpy(&v, p, sizeof v);
                return static_cast<double>(v);
            } else {
                std::uint32_t v = 0;
                std::memcpy(&v, p, sizeof v);
                return static_cast<double>(v);
            }
    }
    return 0.0;
}

/// double to float without undefined behaviour: out-of-range finite values
/// become +-infinity, NaN stays NaN.
float narrow(double v) noexcept {
    if (std::isnan(v)) {
        return std::numeric_limits<float>::quiet_NaN();
    }
    if (v > static_cast<double>(FLT_MAX)) {
        return std::numeric_limits<float>::infinity();
    }
    if (v < -static_cast<double>(FLT_MAX)) {
        return -std::numeric_limits<float>::infinity();
    }
    return static_cast<float>(v);
}

/// Collects points into the caller's buffer and counts them.
class PointSink {
public:
    PointSink(Span<PcdPoint> out, PcdCloudInfo& info, PcdReadOptions options) noexcept
        : out_(out), info_(info), options_(options) {}

    void add(double x, double y, double z) noexcept {
        const PcdPoint p{narrow(x), narrow(y), narrow(z)};
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        if (finite) {
            ++info_.finite_points;
        } else {
            ++info_.nonfinite_points;
        }
        if (finite || options_.keep_nonfinite) {
            if (info_.written < out_.size()) {
                out_[static_cast<std::size_t>(info_.written)] = p;
                ++info_.written;
            } else {
                ++overflow_;
            }
        }
    }

    [[nodiscard]] IoStatus finish() const noexcept {
        if (overflow_ != 0U) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                     "pcd: %" PRIu64 " points to write, the buffer holds %zu",
                                     info_.written + overflow_, out_.size());
        }
        return IoStatus{};
    }

private:
    Span<PcdPoint> out_;
    PcdCloudInfo& info_;
    PcdReadOptions options_;
    std::uint64_t overflow_ = 0;
};

/// Only zero bytes may follow binary data (PCL pads its files with zeros).
IoStatus check_slack(const std::uint8_t* data, std::size_t from, std::size_t size) noexcept {
    for (std::size_t i = from; i < size; ++i) {
        if (data[i] != 0U) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: byte offset %zu: data continues past what the header declares "
                                     "(%zu bytes after the data, not all zero)",
                                     i, size - from);
        }
    }
    return IoStatus{};
}

/// Checks one ASCII value against its field's type and size.
IoStatus parse_ascii_value(std::string_view token, const PcdField& f, double& value, std::size_t line) noexcept {
    bool ok = false;
    if (f.type == PcdFieldType::kFloat) {
        ok = parse_double(token, value);
        if (ok && f.size == 4U && std::isfinite(value) && std::fabs(value) > static_cast<double>(FLT_MAX)) {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: value '%s' of field '%s' is out of range for F 4", line,
                                     TokenText(token).text, f.name);
        }
    } else if (f.type == PcdFieldType::kSigned) {
        std::int64_t v = 0;
        const auto limit = static_cast<std::int64_t>(std::uint64_t{1} << (8U * f.size - 1U));
        ok = parse_i64(token, v) && v >= -limit && v < limit;
        value = static_cast<double>(v);
    } else {
        std::uint64_t v = 0;
        ok = parse_u64(token, v) && v < (std::uint64_t{1} << (8U * f.size));
        value = static_cast<double>(v);
    }
    if (!ok) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: line %zu: value '%s' of field '%s' is not a valid %s %u", line,
                                 TokenText(token).text, f.name, type_letter(f.type), static_cast<unsigned>(f.size));
    }
    return IoStatus{};
}

IoStatus decode_ascii(const std::uint8_t* data, std::size_t size, const PcdHeader& h, std::size_t header_lines,
                      PointSink& sink) noexcept {
    const char* text = reinterpret_cast<const char*>(data);
    std::size_t pos = h.data_offset;
    std::size_t line = header_lines;
    std::uint64_t point = 0;
    std::size_t values_per_point = 0;
    for (std::size_t i = 0; i < h.field_count; ++i) {
        values_per_point += h.fields[i].count;
    }
    while (pos < size) {
        const auto* nl = static_cast<const std::uint8_t*>(std::memchr(data + pos, '\n', size - pos));
        const std::size_t end = nl != nullptr ? static_cast<std::size_t>(nl - data) : size;
        ++line;
        const char* p = text + pos;
        const char* e = text + end;
        pos = nl != nullptr ? end + 1U : size;
        // Walk the tokens of this line without storing them.
        auto next_token = [&p, e]() noexcept -> std::string_view {
            while (p != e && is_blank(*p)) {
                ++p;
            }
            const char* start = p;
            while (p != e && !is_blank(*p)) {
                ++p;
            }
            return {start, static_cast<std::size_t>(p - start)};
        };
        std::string_view token = next_token();
        if (token.empty()) {
            continue;  // blank line
        }
        if (point == h.points) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: more data lines than POINTS %" PRIu64,
                                     line, h.points);
        }
        double xyz[3] = {};
        std::size_t seen = 0;
        for (std::size_t fi = 0; fi < h.field_count; ++fi) {
            const PcdField& f = h.fields[fi];
            for (std::uint32_t c = 0; c < f.count; ++c) {
                if (token.empty()) {
                    return IoStatus::failure(ErrorCode::kMalformedInput,
                                             "pcd: line %zu: point %" PRIu64 " has %zu values, the fields need %zu",
                                             line, point, seen, values_per_point);
                }
                double value = 0.0;
                IoStatus st = parse_ascii_value(token, f, value, line);
                if (!st) {
                    return st;
                }
                if (fi == h.x_field) {
                    xyz[0] = value;
                } else if (fi == h.y_field) {
                    xyz[1] = value;
                } else if (fi == h.z_field) {
                    xyz[2] = value;
                }
                ++seen;
                token = next_token();
            }
        }
        if (!token.empty()) {
            std::size_t extra = 0;
            while (!token.empty()) {
                ++extra;
                token = next_token();
            }
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "pcd: line %zu: point %" PRIu64 " has %zu values, the fields need %zu", line,
                                     point, seen + extra, values_per_point);
        }
        sink.add(xyz[0], xyz[1], xyz[2]);
        ++point;
    }
    if (point != h.points) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "pcd: ascii data has %" PRIu64 " points, POINTS is %" PRIu64, point, h.points);
    }
    return IoStatus{};
}

IoStatus decode_binary(const std::uint8_t* data, std::size_t size, const PcdHeader& h, PointSink& sink) noexcept {
    const std::size_t need = static_cast<std::size_t>(h.points) * h.point_bytes;
    const std::size_t have = size - h.data_offset;
    if (have < need) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "pcd: binary data is %zu bytes, POINTS x point size = %" PRIu64 " x %zu = %zu", have,
                                 h.points, h.point_bytes, need);
    }
    IoStatus st = check_slack(data, h.data_offset + need, size);
    if (!st) {
        return st;
    }
    const PcdField& fx = h.fields[h.x_field];
    const PcdField& fy = h.fields[h.y_field];
    const PcdField& fz = h.fields[h.z_field];
    const std::uint8_t* record = data + h.data_offset;
    for (std::uint64_t i = 0; i < h.points; ++i, record += h.point_bytes) {
        sink.add(load_value(record + fx.offset, fx), load_value(record + fy.offset, fy),
                 load_value(record + fz.offset, fz));
    }
    return IoStatus{};
}

std::uint32_t load_u32(const std::uint8_t* p) noexcept {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
           (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
}

IoStatus decode_compressed(const std::uint8_t* data, std::size_t size, const PcdHeader& h, PointSink& sink) noexcept {
    const std::size_t have = size - h.data_offset;
    if (have < 8U) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "pcd: binary_compressed data ends inside its two size fields (%zu bytes)", have);
    }
    const std::uint8_t* sizes = data + h.data_offset;
    const std::uint32_t compressed = load_u32(sizes);
    const std::uint32_t uncompressed = load_u32(sizes + 4);
    const std::uint64_t need = h.points * h.point_bytes;
    if (uncompressed != need) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: uncompressed size %" PRIu32 " differs from POINTS x point size = %" PRIu64
                                 " x %zu = %" PRIu64,
                                 uncompressed, h.points, h.point_bytes, need);
    }
    if (compressed > have - 8U) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "pcd: compressed size %" PRIu32 " runs past the end of the input (%zu bytes left)",
                                 compressed, have - 8U);
    }
    if (compressed == 0U || static_cast<std::uint64_t>(uncompressed) > kLzfMaxExpansion * compressed) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: compressed size %" PRIu32 " cannot expand to %" PRIu32
                                 " bytes (LZF expands at most %" PRIu64 "-fold)",
                                 compressed, uncompressed, kLzfMaxExpansion);
    }
    IoStatus st = check_slack(data, h.data_offset + 8U + compressed, size);
    if (!st) {
        return st;
    }
    std::vector<std::uint8_t> soa;
    try {
        soa.resize(uncompressed);
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "pcd: cannot allocate %" PRIu32 " bytes to decompress",
                                 uncompressed);
    }
    st = lzf_decompress(sizes + 8, compressed, soa.data(), soa.size());
    if (!st) {
        return st;
    }
    // Structure of arrays: field f's values start at POINTS * (offset of f).
    const auto n = static_cast<std::size_t>(h.points);
    const PcdField& fx = h.fields[h.x_field];
    const PcdField& fy = h.fields[h.y_field];
    const PcdField& fz = h.fields[h.z_field];
    const std::uint8_t* xs = soa.data() + n * fx.offset;
    const std::uint8_t* ys = soa.data() + n * fy.offset;
    const std::uint8_t* zs = soa.data() + n * fz.offset;
    for (std::size_t i = 0; i < n; ++i) {
        sink.add(load_value(xs + i * fx.size, fx), load_value(ys + i * fy.size, fy), load_value(zs + i * fz.size, fz));
    }
    return IoStatus{};
}

/// Header lines are printable ASCII (tab and CR allowed): anything else is not a PCD header.
IoStatus check_header_text(const std::uint8_t* data, std::size_t begin, std::size_t end, std::size_t line) noexcept {
    for (std::size_t i = begin; i < end; ++i) {
        const std::uint8_t c = data[i];
        if ((c < 0x20U && c != '\t' && c != '\r') || c > 0x7EU) {
            return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: byte 0x%02x is not header text", line,
                                     static_cast<unsigned>(c));
        }
    }
    return IoStatus{};
}

/// The keyword a header line starts with, checked against the keywords before it (order, repeats, prerequisites).
IoStatus classify_keyword(const Tokens& t, const PcdHeader& h, const bool (&seen)[kKeywordCount], int last,
                          std::size_t line, int& kw) noexcept {
    kw = -1;
    for (int k = 0; k < kKeywordCount; ++k) {
        if (t.items[0] == kKeywordNames[k]) {
            kw = k;
        }
    }
    if (t.items[0] == "COLUMNS" && seen[kVersion] && h.version_minor < 7U) {
        kw = kFields;
    }
    if (kw < 0) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: unknown keyword '%s'", line,
                                 TokenText(t.items[0]).text);
    }
    if (last < 0 && kw != kVersion) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: %s before VERSION", line,
                                 kKeywordNames[kw]);
    }
    if (seen[kw]) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: second %s line", line, kKeywordNames[kw]);
    }
    if (kw < last) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: line %zu: %s after %s (the order is VERSION FIELDS SIZE TYPE COUNT WIDTH "
                                 "HEIGHT VIEWPOINT POINTS DATA)",
                                 line, kKeywordNames[kw], kKeywordNames[last]);
    }
    // The keyword each one needs before it (FIELDS, SIZE, TYPE are required; COUNT is optional).
    static constexpr int kNeeds[kKeywordCount] = {-1,    kVersion, kFields, kSize, kType,
                                                  kType, kWidth,   kType,   kType, kPoints};
    if (kNeeds[kw] >= 0 && !seen[kNeeds[kw]]) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: %s without a %s line before it", line,
                                 kKeywordNames[kw], kKeywordNames[kNeeds[kw]]);
    }
    return IoStatus{};
}

/// POINTS: checked against WIDTH x HEIGHT, or (before 0.7, without them) taken as an unorganised cloud's width.
IoStatus parse_points(const Tokens& t, PcdHeader& h, const bool (&seen)[kKeywordCount], std::size_t line) noexcept {
    IoStatus st = expect_values(t, 1U, line);
    if (!st) {
        return st;
    }
    if (!parse_u64(t.items[1], h.points) || h.points < 1U) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: POINTS '%s' is not an integer >= 1", line,
                                 TokenText(t.items[1]).text);
    }
    if (seen[kWidth] != seen[kHeight]) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "pcd: line %zu: WIDTH without HEIGHT", line);
    }
    if (!seen[kWidth]) {
        if (h.version_minor >= 7U) {
            return line_error(ErrorCode::kMalformedInput, line, "VERSION 0.7 needs WIDTH and HEIGHT before POINTS");
        }
        if (h.points > UINT32_MAX) {
            return line_error(ErrorCode::kMalformedInput, line, "POINTS above 2^32 - 1 without WIDTH");
        }
        h.width = static_cast<std::uint32_t>(h.points);
        h.height = 1U;
        return IoStatus{};
    }
    if (static_cast<std::uint64_t>(h.width) * h.height != h.points) {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: line %zu: POINTS %" PRIu64 " but WIDTH x HEIGHT = %u x %u = %" PRIu64, line,
                                 h.points, static_cast<unsigned>(h.width), static_cast<unsigned>(h.height),
                                 static_cast<std::uint64_t>(h.width) * h.height);
    }
    return IoStatus{};
}

/// DATA: ascii, binary or (from 0.7) binary_compressed.
IoStatus parse_data_kind(const Tokens& t, PcdHeader& h, std::size_t line) noexcept {
    IoStatus st = expect_values(t, 1U, line);
    if (!st) {
        return st;
    }
    if (t.items[1] == "ascii") {
        h.data = PcdDataKind::kAscii;
    } else if (t.items[1] == "binary") {
        h.data = PcdDataKind::kBinary;
    } else if (t.items[1] == "binary_compressed") {
        h.data = PcdDataKind::kBinaryCompressed;
        if (h.version_minor < 7U) {
            return line_error(ErrorCode::kUnsupportedVersion, line, "DATA binary_compressed needs VERSION 0.7");
        }
    } else {
        return IoStatus::failure(ErrorCode::kMalformedInput,
                                 "pcd: line %zu: DATA '%s' is not ascii, binary or binary_compressed", line,
                                 TokenText(t.items[1]).text);
    }
    return IoStatus{};
}

/// The values of one header line, by its keyword.
IoStatus parse_keyword_values(int kw, const Tokens& t, PcdHeader& h, const bool (&seen)[kKeywordCount],
                              std::size_t line) noexcept {
    switch (kw) {
        case kVersion: {
            IoStatus st = expect_values(t, 1U, line);
            if (st) {
                st = parse_version(t.items[1], h, line);
            }
            return st;
        }
        case kFields: return parse_fields(t, h, line);
        case kSize: return parse_sizes(t, h, line);
        case kType: return parse_types(t, h, line);
        case kCount: return parse_counts(t, h, line);
        case kWidth: return parse_dimension(t, h.width, line);
        case kHeight: return parse_dimension(t, h.height, line);
        case kViewpoint: return parse_viewpoint(t, h, line);
        case kPoints: return parse_points(t, h, seen, line);
        case kData: return parse_data_kind(t, h, line);
        default: return IoStatus{};
    }
}

/// The header plus the number of lines it took (for messages about ASCII data).
IoStatus parse_header_lines(const std::uint8_t* data, std::size_t size, PcdHeader& h, std::size_t& lines) noexcept {
    h = PcdHeader{};
    lines = 0;
    if (data == nullptr && size != 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "pcd: null input");
    }
    const char* text = reinterpret_cast<const char*>(data);
    bool seen[kKeywordCount] = {};
    int last = -1;
    std::size_t pos = 0;
    Tokens t;
    while (true) {
        if (pos >= size) {
            return IoStatus::failure(ErrorCode::kTruncatedInput, "pcd: header ends after line %zu without a DATA line",
                                     lines);
        }
        const auto* nl = static_cast<const std::uint8_t*>(std::memchr(data + pos, '\n', size - pos));
        if (nl == nullptr) {
            return IoStatus::failure(ErrorCode::kTruncatedInput,
                                     "pcd: line %zu: header line not ended by a newline before the end of the input",
                                     lines + 1U);
        }
        const auto end = static_cast<std::size_t>(nl - data);
        const std::size_t line_start = pos;
        pos = end + 1U;
        const std::size_t line = ++lines;
        IoStatus st = check_header_text(data, line_start, end, line);
        if (!st) {
            return st;
        }
        tokenize(text + line_start, text + end, t);
        if (t.overflow) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                     "pcd: line %zu: more than %zu values (at most %zu fields)", line, kMaxTokens - 1U,
                                     kPcdMaxFields);
        }
        if (t.count == 0U || t.items[0].front() == '#') {
            continue;
        }
        int kw = -1;
        st = classify_keyword(t, h, seen, last, line, kw);
        if (!st) {
            return st;
        }
        seen[kw] = true;
        last = kw;
        st = parse_keyword_values(kw, t, h, seen, line);
        if (!st) {
            return st;
        }
        if (kw == kData) {
            h.data_offset = pos;
            return finish_header(h);
        }
    }
}

IoStatus os_error(const char* what, const char* path) noexcept {
    return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot %s: %s", path, what, std::strerror(errno));
}

/// Appends the LZF encoding of @p in made of literal runs only.
void lzf_store_literals(const std::uint8_t* in, std::size_t size, std::vector<std::uint8_t>& out) {
    for (std::size_t i = 0; i < size; i += 32U) {
        const std::size_t n = std::min<std::size_t>(32U, size - i);
        out.push_back(static_cast<std::uint8_t>(n - 1U));
        out.insert(out.end(), in + i, in + i + n);
    }
}

void store_u32(std::vector<std::uint8_t>& out, std::size_t value) {
    for (unsigned shift = 0; shift < 32U; shift += 8U) {
        out.push_back(static_cast<std::uint8_t>((value >> shift) & 0xFFU));
    }
}

/// The bytes after the header, for each DATA kind.
void build_pcd_data(Span<const PcdPoint> points, PcdDataKind kind, std::vector<std::uint8_t>& out) {
    const std::size_t n = points.size();
    if (kind == PcdDataKind::kAscii) {
        char line[3 * 32];
        for (const PcdPoint& p : points) {
            char* q = line;
            char* const end = line + sizeof line;
            const float xyz[3] = {p.x, p.y, p.z};
            for (std::size_t k = 0; k < 3U; ++k) {
                q = std::to_chars(q, end, xyz[k]).ptr;  // shortest form that reads back exactly
                *q++ = k < 2U ? ' ' : '\n';
            }
            out.insert(out.end(), line, q);
        }
        return;
    }
    static_assert(sizeof(PcdPoint) == 12U, "PcdPoint must be three packed floats");
    if (kind == PcdDataKind::kBinary) {
        const auto* bytes = reinterpret_cast<const std::uint8_t*>(points.data());
        out.insert(out.end(), bytes, bytes + n * sizeof(PcdPoint));
        return;
    }
    std::vector<std::uint8_t> soa(n * sizeof(PcdPoint));
    for (std::size_t i = 0; i < n; ++i) {
        std::memcpy(soa.data() + 4U * i, &points[i].x, 4U);
        std::memcpy(soa.data() + 4U * (n + i), &points[i].y, 4U);
        std::memcpy(soa.data() + 4U * (2U * n + i), &points[i].z, 4U);
    }
    store_u32(out, soa.size() + (soa.size() + 31U) / 32U);
    store_u32(out, soa.size());
    lzf_store_literals(soa.data(), soa.size(), out);
}

}  // namespace

IoStatus parse_pcd_header(const std::uint8_t* data, std::size_t size, PcdHeader& header) noexcept {
    std::size_t lines = 0;
    return parse_header_lines(data, size, header, lines);
}

IoStatus lzf_decompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out, std::size_t out_size) noexcept {
    std::size_t ip = 0;
    std::size_t op = 0;
    while (ip < in_size) {
        const std::size_t at = ip;
        const std::size_t ctrl = in[ip++];
        if (ctrl < 32U) {
            const std::size_t len = ctrl + 1U;
            if (len > in_size - ip) {
                return IoStatus::failure(
                    ErrorCode::kTruncatedInput,
                    "lzf: input offset %zu: literal run of %zu bytes runs past the end of the input", at, len);
            }
            if (len > out_size - op) {
                return IoStatus::failure(
                    ErrorCode::kMalformedInput,
                    "lzf: input offset %zu: literal run of %zu bytes overflows the output (%zu bytes)", at, len,
                    out_size);
            }
            std::memcpy(out + op, in + ip, len);
            ip += len;
            op += len;
            continue;
        }
        std::size_t len = ctrl >> 5U;
        if (len == 7U) {
            if (ip >= in_size) {
                return IoStatus::failure(ErrorCode::kTruncatedInput,
                                         "lzf: input offset %zu: back-reference length byte missing", at);
            }
            len += in[ip++];
        }
        if (ip >= in_size) {
            return IoStatus::failure(ErrorCode::kTruncatedInput,
                                     "lzf: input offset %zu: back-reference offset byte missing", at);
        }
        const std::size_t distance = ((ctrl & 0x1FU) << 8U) + in[ip++] + 1U;
        len += 2U;
        if (distance > op) {
            return IoStatus::failure(
                ErrorCode::kMalformedInput,
                "lzf: input offset %zu: back-reference reaches %zu bytes before the start of the output", at,
                distance - op);
        }
        if (len > out_size - op) {
            return IoStatus::failure(
                ErrorCode::kMalformedInput,
                "lzf: input offset %zu: back-reference of %zu bytes overflows the output (%zu bytes)", at, len,
                out_size);
        }
        for (std::size_t i = 0; i < len; ++i, ++op) {
            out[op] = out[op - distance];  // byte by byte: source and destination may overlap
        }
    }
    if (op != out_size) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "lzf: decompressed to %zu bytes, expected %zu", op,
                                 out_size);
    }
    return IoStatus{};
}

IoStatus decode_pcd(const std::uint8_t* data, std::size_t size, Span<PcdPoint> out, PcdCloudInfo& info,
                    PcdReadOptions options) noexcept {
    info = PcdCloudInfo{};
    PcdHeader h;
    std::size_t lines = 0;
    IoStatus st = parse_header_lines(data, size, h, lines);
    if (!st) {
        return st;
    }
    info.width = h.width;
    info.height = h.height;
    info.viewpoint = h.viewpoint;
    info.data = h.data;
    info.points = h.points;
    PointSink sink(out, info, options);
    switch (h.data) {
        case PcdDataKind::kAscii: st = decode_ascii(data, size, h, lines, sink); break;
        case PcdDataKind::kBinary: st = decode_binary(data, size, h, sink); break;
        case PcdDataKind::kBinaryCompressed: st = decode_compressed(data, size, h, sink); break;
    }
    if (!st) {
        return st;
    }
    return sink.finish();
}

IoStatus read_pcd(const char* path, Span<PcdPoint> out, PcdCloudInfo& info, PcdReadOptions options) noexcept {
    info = PcdCloudInfo{};
    const FilePtr file(std::fopen(path, "rb"));
    if (!file) {
        return os_error("open", path);
    }
    struct stat st_info {};
    if (::fstat(::fileno(file.get()), &st_info) != 0) {
        return os_error("stat", path);
    }
    const auto file_size = static_cast<std::uint64_t>(st_info.st_size);
    if (file_size > kPcdMaxFileBytes) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                 "%s: pcd: file of %" PRIu64 " bytes above the limit of %" PRIu64, path, file_size,
                                 kPcdMaxFileBytes);
    }
    std::vector<std::uint8_t> bytes;
    try {
        bytes.resize(static_cast<std::size_t>(file_size));
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: pcd: cannot allocate %" PRIu64 " bytes", path,
                                 file_size);
    }
    if (std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
        return os_error("read", path);
    }
    return decode_pcd(bytes.data(), bytes.size(), out, info, options).prefixed(path);
}

IoStatus write_pcd(const char* path, Span<const PcdPoint> points, std::uint32_t width, std::uint32_t height,
                   const PcdViewpoint& viewpoint, PcdDataKind kind) noexcept {
    if (width == 0U || height == 0U || static_cast<std::uint64_t>(width) * height != points.size()) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: pcd: %zu points given for WIDTH %u x HEIGHT %u",
                                 path, points.size(), static_cast<unsigned>(width), static_cast<unsigned>(height));
    }
    const double vp[7] = {viewpoint.tx, viewpoint.ty, viewpoint.tz, viewpoint.qw,
                          viewpoint.qx, viewpoint.qy, viewpoint.qz};
    for (const double v : vp) {
        if (!std::isfinite(v)) {
            return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: pcd: viewpoint not finite", path);
        }
    }
    if (points.size() * sizeof(PcdPoint) > kPcdMaxDataBytes) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: pcd: %zu points above the data limit", path,
                                 points.size());
    }
    static constexpr const char* kDataNames[3] = {"ascii", "binary", "binary_compressed"};
    char header[512];
    const int n = std::snprintf(header, sizeof header,
                                "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
                                "TYPE F F F\nCOUNT 1 1 1\nWIDTH %u\nHEIGHT %u\n"
                                "VIEWPOINT %.17g %.17g %.17g %.17g %.17g %.17g %.17g\nPOINTS %zu\nDATA %s\n",
                                static_cast<unsigned>(width), static_cast<unsigned>(height), vp[0], vp[1], vp[2], vp[3],
                                vp[4], vp[5], vp[6], points.size(), kDataNames[static_cast<std::size_t>(kind)]);
    if (n < 0 || static_cast<std::size_t>(n) >= sizeof header) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: pcd: header does not fit", path);
    }
    std::vector<std::uint8_t> body;
    try {
        build_pcd_data(points, kind, body);
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: pcd: cannot allocate the output buffer", path);
    }
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): closed below on every path
    std::FILE* f = std::fopen(path, "wb");
    if (f == nullptr) {
        return os_error("create", path);
    }
    const bool written = std::fwrite(header, 1, static_cast<std::size_t>(n), f) == static_cast<std::size_t>(n) &&
                         std::fwrite(body.data(), 1, body.size(), f) == body.size();
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): f is opened above
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed) {
        return os_error("write", path);
    }
    return IoStatus{};
}

}  // namespace cellguard
