// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The project's own STL reader, kept as the tests' independent reference (stl_reference.hpp).
#include "stl_reference.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "cellguard/host/io/file.hpp"
#include "cellguard/host/io/io_status.hpp"

namespace cellguard::test {

namespace {

constexpr std::size_t kBinaryHeaderBytes = 84U;
constexpr std::size_t kBinaryTriangleBytes = 50U;
/// Longest ASCII number token (digits, sign, exponent).
constexpr std::size_t kMaxNumberChars = 63U;

float read_float(const std::uint8_t* p) {
    std::uint32_t bits = static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8U) |
                         (static_cast<std::uint32_t>(p[2]) << 16U) | (static_cast<std::uint32_t>(p[3]) << 24U);
    float f = 0.0F;
    static_assert(sizeof(f) == sizeof(bits), "IEEE-754 binary32 float");
    std::memcpy(&f, &bits, sizeof(f));
    return f;
}

std::uint32_t binary_count(const std::uint8_t* data) {
    return static_cast<std::uint32_t>(data[80]) | (static_cast<std::uint32_t>(data[81]) << 8U) |
           (static_cast<std::uint32_t>(data[82]) << 16U) | (static_cast<std::uint32_t>(data[83]) << 24U);
}

bool is_binary_size(const std::uint8_t* data, std::size_t size) {
    if (size < kBinaryHeaderBytes) {
        return false;
    }
    const std::uint64_t expected = kBinaryHeaderBytes + std::uint64_t{binary_count(data)} * kBinaryTriangleBytes;
    return expected == size;
}

IoStatus parse_binary(const std::uint8_t* data, StlMesh& mesh) {
    const std::size_t count = binary_count(data);
    if (count > kStlMaxTriangles) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "binary STL: %zu triangles, at most %zu", count,
                                 kStlMaxTriangles);
    }
    if (count == 0U) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "binary STL: no triangles");
    }
    mesh.vertices.reserve(count * 3U);
    for (std::size_t t = 0U; t < count; ++t) {
        const std::uint8_t* tri = data + kBinaryHeaderBytes + t * kBinaryTriangleBytes;
        for (std::size_t k = 0U; k < 12U; ++k) {  // normal, then three vertices
            if (!std::isfinite(read_float(tri + 4U * k))) {
                return IoStatus::failure(ErrorCode::kNonFiniteValue, "binary STL: triangle %zu: %s is not finite", t,
                                         k < 3U ? "the normal" : "a vertex");
            }
        }
        for (std::size_t v = 0U; v < 3U; ++v) {
            const std::uint8_t* p = tri + 12U + 12U * v;
            mesh.vertices.emplace_back(read_float(p), read_float(p + 4U), read_float(p + 8U));
        }
    }
    mesh.triangle_count = count;
    mesh.ascii = false;
    return {};
}

/// Whitespace-separated tokens of an ASCII STL, with the line of each.
class Tokens {
public:
    Tokens(const std::uint8_t* data, std::size_t size) : text_(reinterpret_cast<const char*>(data), size) {}

    /// The next token ("" at the end of the input).
    std::string_view next() {
        skip_space();
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !is_space(text_[pos_])) {
            ++pos_;
        }
        return text_.substr(start, pos_ - start);
    }
    /// Skips the rest of the current line (a solid's name).
    void skip_line() {
        while (pos_ < text_.size() && text_[pos_] != '\n') {
            ++pos_;
        }
    }
    /// True when only white space is left.
    bool at_end() {
        skip_space();
        return pos_ == text_.size();
    }
    /// Line number (1-based) of the last token.
    [[nodiscard]] std::size_t line() const { return line_; }

private:
    static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
    void skip_space() {
        while (pos_ < text_.size() && is_space(text_[pos_])) {
            if (text_[pos_] == '\n') {
                ++line_;
            }
            ++pos_;
        }
    }
    std::string_view text_;
    std::size_t pos_ = 0U;
    std::size_t line_ = 1U;
};

IoStatus expect(Tokens& tokens, const char* keyword) {
    const std::string_view t = tokens.next();
    if (t != keyword) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "ASCII STL: line %zu: expected '%s', got '%.*s'",
                                 tokens.line(), keyword, static_cast<int>(std::min<std::size_t>(t.size(), 40U)),
                                 t.data());
    }
    return {};
}

IoStatus read_number(Tokens& tokens, double& value) {
    const std::string_view t = tokens.next();
    if (t.empty()) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "ASCII STL: line %zu: a number expected, input ends",
                                 tokens.line());
    }
    char buf[kMaxNumberChars + 1U] = {};
    if (t.size() > kMaxNumberChars) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "ASCII STL: line %zu: number too long", tokens.line());
    }
    std::memcpy(buf, t.data(), t.size());
    char* end = nullptr;
    errno = 0;
    value = std::strtod(buf, &end);
    if (end != buf + t.size()) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "ASCII STL: line %zu: '%s' is not a number", tokens.line(),
                                 buf);
    }
    if (!std::isfinite(value) || errno == ERANGE) {
        return IoStatus::failure(ErrorCode::kNonFiniteValue, "ASCII STL: line %zu: '%s' is not finite", tokens.line(),
                                 buf);
    }
    return {};
}

IoStatus read_vector(Tokens& tokens, Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) {
        IoStatus st = read_number(tokens, v[k]);
        if (!st) {
            return st;
        }
    }
    return {};
}

/// One facet after its "facet" keyword.
IoStatus parse_facet(Tokens& tokens, StlMesh& mesh) {
    Eigen::Vector3d v;
    IoStatus st = expect(tokens, "normal");
    st = st ? read_vector(tokens, v) : st;
    st = st ? expect(tokens, "outer") : st;
    st = st ? expect(tokens, "loop") : st;
    for (int k = 0; k < 3 && st; ++k) {
        st = expect(tokens, "vertex");
        st = st ? read_vector(tokens, v) : st;
        if (st) {
            mesh.vertices.push_back(v);
        }
    }
    st = st ? expect(tokens, "endloop") : st;
    st = st ? expect(tokens, "endfacet") : st;
    return st;
}

IoStatus parse_ascii(const std::uint8_t* data, std::size_t size, StlMesh& mesh) {
    Tokens tokens(data, size);
    IoStatus st = expect(tokens, "solid");
    tokens.skip_line();
    while (st) {
        const std::string_view t = tokens.next();
        if (t == "facet") {
            if (mesh.triangle_count == kStlMaxTriangles) {
                return IoStatus::failure(ErrorCode::kCapacityExceeded, "ASCII STL: line %zu: more than %zu triangles",
                                         tokens.line(), kStlMaxTriangles);
            }
            st = parse_facet(tokens, mesh);
            mesh.triangle_count += st ? 1U : 0U;
        } else if (t == "endsolid") {
            tokens.skip_line();
            if (tokens.at_end()) {
                break;
            }
            st = expect(tokens, "solid");
            tokens.skip_line();
        } else if (t.empty()) {
            return IoStatus::failure(ErrorCode::kTruncatedInput, "ASCII STL: line %zu: input ends before 'endsolid'",
                                     tokens.line());
        } else {
            return IoStatus::failure(ErrorCode::kMalformedInput,
                                     "ASCII STL: line %zu: expected 'facet' or 'endsolid', got '%.*s'", tokens.line(),
                                     static_cast<int>(std::min<std::size_t>(t.size(), 40U)), t.data());
        }
    }
    if (st && mesh.triangle_count == 0U) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "ASCII STL: no triangles");
    }
    mesh.ascii = true;
    return st;
}

bool starts_with_solid(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    return first != std::string_view::npos && text.compare(first, 5U, "solid") == 0;
}

}  // namespace

IoStatus parse_stl(const std::uint8_t* data, std::size_t size, StlMesh& mesh) {
    mesh = StlMesh{};
    if (size > kStlMaxBytes) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "STL: %zu bytes, at most %zu", size, kStlMaxBytes);
    }
    if (is_binary_size(data, size)) {
        return parse_binary(data, mesh);
    }
    if (starts_with_solid(data, size)) {
        return parse_ascii(data, size, mesh);
    }
    if (size < kBinaryHeaderBytes) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "STL: %zu bytes: shorter than a binary header and not ASCII ('solid')", size);
    }
    const std::uint64_t expected = kBinaryHeaderBytes + std::uint64_t{binary_count(data)} * kBinaryTriangleBytes;
    return IoStatus::failure(expected > size ? ErrorCode::kTruncatedInput : ErrorCode::kMalformedInput,
                             "binary STL: %u triangles need %llu bytes, the input has %zu", binary_count(data),
                             static_cast<unsigned long long>(expected), size);
}

IoStatus read_stl_file(const std::string& path, StlMesh& mesh) {
    host::FilePtr file = host::open_file(path.c_str(), "rb");
    if (!file) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open: %s", path.c_str(),
                                 std::strerror(errno));
    }
    long length = -1;
    if (std::fseek(file.get(), 0, SEEK_END) == 0) {
        length = std::ftell(file.get());
    }
    if (length < 0 || std::fseek(file.get(), 0, SEEK_SET) != 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot tell its size", path.c_str());
    }
    if (static_cast<unsigned long>(length) > kStlMaxBytes) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: STL: %ld bytes, at most %zu", path.c_str(), length,
                                 kStlMaxBytes);
    }
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(length));
    const std::size_t n = std::fread(bytes.data(), 1U, bytes.size(), file.get());
    if (n != bytes.size() || std::ferror(file.get()) != 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: read error", path.c_str());
    }
    return parse_stl(bytes.data(), n, mesh).prefixed(path.c_str());
}

}  // namespace cellguard::test
