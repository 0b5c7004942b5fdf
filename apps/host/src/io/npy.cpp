// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/npy.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>

#include "cellguard/grid/log_odds.hpp"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "npy.cpp copies little-endian .npy data as is: it needs a little-endian host");

namespace cellguard {

namespace {

constexpr std::uint8_t kMagic[6] = {0x93U, 'N', 'U', 'M', 'P', 'Y'};
/// numpy aligns the preamble plus header to this many bytes.
constexpr std::size_t kArrayAlign = 64;
/// numpy leaves room for the growth axis to reach this many digits.
constexpr std::size_t kGrowthAxisMaxDigits = 21;
/// Longest descr string the parser keeps.
constexpr std::size_t kMaxDescr = 16;

/// Closes a FILE* on scope exit.
struct FileCloser {
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): the deleter of FilePtr, which owns the FILE*
    void operator()(std::FILE* f) const noexcept { static_cast<void>(std::fclose(f)); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

/// Reads the bytes of a header dict with a position, for error messages.
class HeaderCursor {
public:
    HeaderCursor(const std::uint8_t* begin, const std::uint8_t* end) noexcept : begin_(begin), pos_(begin), end_(end) {}

    [[nodiscard]] bool at_end() const noexcept { return pos_ == end_; }
    [[nodiscard]] std::size_t offset() const noexcept { return static_cast<std::size_t>(pos_ - begin_); }
    [[nodiscard]] int peek() const noexcept { return at_end() ? -1 : static_cast<int>(*pos_); }
    void advance() noexcept { ++pos_; }
    void skip_spaces() noexcept {
        while (!at_end() && (*pos_ == ' ' || *pos_ == '\t')) {
            ++pos_;
        }
    }
    bool consume(char c) noexcept {
        if (!at_end() && *pos_ == static_cast<std::uint8_t>(c)) {
            ++pos_;
            return true;
        }
        return false;
    }
    /// True (and advances) when the next bytes are @p word.
    bool consume_word(const char* word) noexcept {
        const std::size_t n = std::strlen(word);
        if (static_cast<std::size_t>(end_ - pos_) < n || std::memcmp(pos_, word, n) != 0) {
            return false;
        }
        pos_ += n;
        return true;
    }

private:
    const std::uint8_t* begin_;
    const std::uint8_t* pos_;
    const std::uint8_t* end_;
};

IoStatus header_error(const HeaderCursor& c, const char* what) noexcept {
    return IoStatus::failure(ErrorCode::kMalformedInput, "npy: header offset %zu: %s", c.offset(), what);
}

/// A Python string literal in single or double quotes, without escapes,
/// of at most kMaxDescr - 1 characters.
IoStatus parse_string(HeaderCursor& c, char (&out)[kMaxDescr]) noexcept {
    const int quote = c.peek();
    if (quote != '\'' && quote != '"') {
        return header_error(c, "expected a quoted string");
    }
    c.advance();
    std::size_t n = 0;
    while (true) {
        const int ch = c.peek();
        if (ch < 0) {
            return header_error(c, "string not closed");
        }
        c.advance();
        if (ch == quote) {
            break;
        }
        if (ch == '\\' || ch < 0x20 || ch > 0x7E) {
            return header_error(c, "unexpected character in a string");
        }
        if (n + 1U >= kMaxDescr) {
            return header_error(c, "string too long");
        }
        out[n++] = static_cast<char>(ch);
    }
    out[n] = '\0';
    return IoStatus{};
}

/// A non-negative decimal integer as Python writes it (no sign, no leading zero).
IoStatus parse_dimension(HeaderCursor& c, std::uint64_t& value) noexcept {
    const int first = c.peek();
    if (first < '0' || first > '9') {
        return header_error(c, "expected a non-negative integer in shape");
    }
    value = 0;
    std::size_t digits = 0;
    while (c.peek() >= '0' && c.peek() <= '9') {
        const auto digit = static_cast<std::uint64_t>(c.peek() - '0');
        if (digits == 1U && value == 0U) {
            return header_error(c, "integer with a leading zero in shape");
        }
        if (value > (UINT64_MAX - digit) / 10U) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded, "npy: header offset %zu: dimension too large",
                                     c.offset());
        }
        value = value * 10U + digit;
        ++digits;
        c.advance();
    }
    return IoStatus{};
}

/// A Python tuple of integers: (), (5,), (2, 3), (2, 3,).
IoStatus parse_shape(HeaderCursor& c, NpyHeader& header) noexcept {
    if (!c.consume('(')) {
        return header_error(c, "shape is not a tuple");
    }
    header.ndim = 0;
    c.skip_spaces();
    if (c.consume(')')) {
        return IoStatus{};
    }
    bool trailing_comma = false;
    while (true) {
        if (header.ndim == kNpyMaxDims) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded, "npy: shape has more than %zu dimensions",
                                     kNpyMaxDims);
        }
        IoStatus st = parse_dimension(c, header.shape[header.ndim]);
        if (!st) {
            return st;
        }
        ++header.ndim;
        c.skip_spaces();
        trailing_comma = c.consume(',');
        c.skip_spaces();
        if (c.consume(')')) {
            break;
        }
        if (!trailing_comma) {
            return header_error(c, "expected ',' or ')' in shape");
        }
    }
    if (header.ndim == 1U && !trailing_comma) {
        return header_error(c, "shape (n) is not a tuple; a 1-d shape is written (n,)");
    }
    return IoStatus{};
}

IoStatus dtype_from_descr(const char* descr, NpyDtype& dtype) noexcept {
    if (std::strcmp(descr, "<i2") == 0) {
        dtype = NpyDtype::kInt16;
    } else if (std::strcmp(descr, "<f4") == 0) {
        dtype = NpyDtype::kFloat32;
    } else if (std::strcmp(descr, "<u2") == 0) {
        dtype = NpyDtype::kUInt16;
    } else if (std::strcmp(descr, "|u1") == 0 || std::strcmp(descr, "<u1") == 0 || std::strcmp(descr, ">u1") == 0) {
        dtype = NpyDtype::kUInt8;
    } else if (descr[0] == '>') {
        return IoStatus::failure(ErrorCode::kUnsupportedType, "npy: big-endian dtype '%s' is not supported", descr);
    } else {
        return IoStatus::failure(ErrorCode::kUnsupportedType,
                                 "npy: dtype '%s' is not supported (only '<i2', '<f4', '|u1', '<u2')", descr);
    }
    return IoStatus{};
}

/// The dict `{'descr': ..., 'fortran_order': False, 'shape': (...), }`,
/// keys in any order, each exactly once.
IoStatus parse_dict(HeaderCursor& c, NpyHeader& header) noexcept {
    c.skip_spaces();
    if (!c.consume('{')) {
        return header_error(c, "header does not start with '{'");
    }
    bool have_descr = false;
    bool have_order = false;
    bool have_shape = false;
    while (true) {
        c.skip_spaces();
        if (c.consume('}')) {
            break;
        }
        char key[kMaxDescr] = {};
        IoStatus st = parse_string(c, key);
        if (!st) {
            return st;
        }
        c.skip_spaces();
        if (!c.consume(':')) {
            return header_error(c, "expected ':' after a key");
        }
        c.skip_spaces();
        if (std::strcmp(key, "descr") == 0) {
            if (have_descr) {
                return header_error(c, "key 'descr' appears twice");
            }
            have_descr = true;
            char descr[kMaxDescr] = {};
            st = parse_string(c, descr);
            if (!st) {
                return IoStatus::failure(ErrorCode::kUnsupportedType, "npy: descr is not a simple dtype string (%s)",
                                         st.message());
            }
            st = dtype_from_descr(descr, header.dtype);
        } else if (std::strcmp(key, "fortran_order") == 0) {
            if (have_order) {
                return header_error(c, "key 'fortran_order' appears twice");
            }
            have_order = true;
            if (c.consume_word("True")) {
                return IoStatus::failure(ErrorCode::kMalformedInput,
                                         "npy: fortran_order is True; only C-order arrays are read");
            }
            if (!c.consume_word("False")) {
                return header_error(c, "fortran_order is neither True nor False");
            }
        } else if (std::strcmp(key, "shape") == 0) {
            if (have_shape) {
                return header_error(c, "key 'shape' appears twice");
            }
            have_shape = true;
            st = parse_shape(c, header);
        } else {
            return IoStatus::failure(ErrorCode::kMalformedInput, "npy: unknown key '%s' in header", key);
        }
        if (!st) {
            return st;
        }
        c.skip_spaces();
        if (c.consume('}')) {
            break;
        }
        if (!c.consume(',')) {
            return header_error(c, "expected ',' or '}' after a value");
        }
    }
    if (!have_descr || !have_order || !have_shape) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "npy: header has no key '%s'",
                                 !have_descr   ? "descr"
                                 : !have_order ? "fortran_order"
                                               : "shape");
    }
    while (c.consume(' ')) {
    }
    if (!c.at_end()) {
        return header_error(c, "unexpected bytes after the header dict");
    }
    return IoStatus{};
}

/// Writes "(a, b, c)" (or "(a,)") for the first @p ndim entries of @p shape.
void format_shape(const std::uint64_t* shape, std::size_t ndim, char* out, std::size_t capacity) noexcept {
    std::size_t used = 0;
    auto put = [&](const char* text) {
        const int n = std::snprintf(out + used, capacity - used, "%s", text);
        if (n > 0) {
            used = std::min(capacity - 1U, used + static_cast<std::size_t>(n));
        }
    };
    put("(");
    for (std::size_t i = 0; i < ndim; ++i) {
        char number[24];
        static_cast<void>(std::snprintf(number, sizeof number, "%" PRIu64, shape[i]));
        put(number);
        put(i + 1U < ndim ? ", " : (ndim == 1U ? "," : ""));
    }
    put(")");
}

bool dims_valid(GridDims dims) noexcept { return dims.nx >= 1 && dims.ny >= 1 && dims.nz >= 1; }

std::size_t element_count_of(GridDims dims) noexcept {
    return static_cast<std::size_t>(dims.nx) * static_cast<std::size_t>(dims.ny) * static_cast<std::size_t>(dims.nz);
}

IoStatus os_error(const char* what, const char* path) noexcept {
    return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot %s: %s", path, what, std::strerror(errno));
}

/// Decodes a file held in memory: parse, check, copy.
IoStatus decode_npy(const std::uint8_t* data, std::size_t size, NpyDtype dtype, GridDims dims, void* out,
                    std::size_t out_elements) noexcept {
    NpyHeader header;
    IoStatus st = parse_npy_header(data, size, header);
    if (!st) {
        return st;
    }
    st = check_npy_layout(header, dtype, dims, size);
    if (!st) {
        return st;
    }
    if (out_elements < header.element_count) {
        return IoStatus::failure(ErrorCode::kStorageTooSmall, "npy: storage holds %zu elements, the array has %" PRIu64,
                                 out_elements, header.element_count);
    }
    std::memcpy(out, data + header.data_offset, static_cast<std::size_t>(header.data_bytes));
    return IoStatus{};
}

/// Reads a file: the header into a small buffer, the data straight into @p out.
IoStatus read_npy(const char* path, NpyDtype dtype, GridDims dims, void* out, std::size_t out_elements) noexcept {
    const FilePtr file(std::fopen(path, "rb"));
    if (!file) {
        return os_error("open", path);
    }
    struct stat info {};
    if (::fstat(::fileno(file.get()), &info) != 0) {
        return os_error("stat", path);
    }
    const auto file_size = static_cast<std::uint64_t>(info.st_size);
    std::uint8_t preamble[kNpyPreambleV2] = {};
    const std::size_t got = std::fread(preamble, 1, sizeof preamble, file.get());
    NpyHeader header;
    IoStatus st = parse_npy_header(preamble, got, header);
    if (st.error() == ErrorCode::kTruncatedInput && got == sizeof preamble) {
        // The preamble is fine; read the whole header and parse again.
        const std::size_t prefix_size = std::min<std::size_t>(file_size, kNpyPreambleV2 + kNpyMaxHeaderBytes);
        const std::unique_ptr<std::uint8_t[]> prefix(new (std::nothrow) std::uint8_t[prefix_size]);
        if (!prefix) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: npy: cannot allocate the header buffer", path);
        }
        std::memcpy(prefix.get(), preamble, sizeof preamble);
        const std::size_t rest = std::fread(prefix.get() + sizeof preamble, 1, prefix_size - sizeof preamble,
                                            file.get());
        st = parse_npy_header(prefix.get(), sizeof preamble + rest, header);
    }
    if (!st) {
        return st.prefixed(path);
    }
    st = check_npy_layout(header, dtype, dims, file_size);
    if (!st) {
        return st.prefixed(path);
    }
    if (out_elements < header.element_count) {
        return IoStatus::failure(ErrorCode::kStorageTooSmall,
                                 "%s: npy: storage holds %zu elements, the array has %" PRIu64, path, out_elements,
                                 header.element_count);
    }
    if (std::fseek(file.get(), static_cast<long>(header.data_offset), SEEK_SET) != 0) {
        return os_error("seek", path);
    }
    const auto bytes = static_cast<std::size_t>(header.data_bytes);
    if (std::fread(out, 1, bytes, file.get()) != bytes) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "%s: npy: data ends early", path);
    }
    return IoStatus{};
}

/// Opens @p path and writes the header; the caller writes the data and calls finish_file.
IoStatus begin_file(const char* path, NpyDtype dtype, GridDims dims, std::size_t elements, FilePtr& file) noexcept {
    if (!dims_valid(dims)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: npy: dimensions %d x %d x %d are not all >= 1", path,
                                 dims.nx, dims.ny, dims.nz);
    }
    if (elements != element_count_of(dims)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: npy: %zu elements given for dimensions %d x %d x %d",
                                 path, elements, dims.nx, dims.ny, dims.nz);
    }
    std::uint8_t header[256];
    std::size_t length = 0;
    IoStatus st = format_npy_header(dtype, dims, Span<std::uint8_t>(header), length);
    if (!st) {
        return st.prefixed(path);
    }
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): FilePtr owns the FILE*
    file.reset(std::fopen(path, "wb"));
    if (!file) {
        return os_error("create", path);
    }
    if (std::fwrite(header, 1, length, file.get()) != length) {
        return os_error("write", path);
    }
    return IoStatus{};
}

IoStatus finish_file(const char* path, FilePtr& file) noexcept {
    std::FILE* f = file.release();
    if (std::ferror(f) != 0) {
        // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): released from FilePtr above
        static_cast<void>(std::fclose(f));
        return os_error("write", path);
    }
    // NOLINTNEXTLINE(cppcoreguidelines-owning-memory): released from FilePtr above
    if (std::fclose(f) != 0) {
        return os_error("close", path);
    }
    return IoStatus{};
}

IoStatus write_npy(const char* path, NpyDtype dtype, GridDims dims, const void* data, std::size_t elements) noexcept {
    FilePtr file;
    IoStatus st = begin_file(path, dtype, dims, elements, file);
    if (!st) {
        return st;
    }
    const std::size_t bytes = elements * npy_item_size(dtype);
    if (std::fwrite(data, 1, bytes, file.get()) != bytes) {
        return os_error("write", path);
    }
    return finish_file(path, file);
}

IoStatus write_probability(const char* path, const EvidenceGrid& grid) noexcept {
    FilePtr file;
    const Span<std::int16_t> log_odds = grid.log_odds();
    IoStatus st = begin_file(path, NpyDtype::kFloat32, grid.geometry().dims(), log_odds.size(), file);
    if (!st) {
        return st;
    }
    constexpr std::size_t kChunk = 4096;
    float chunk[kChunk];
    for (std::size_t start = 0; start < log_odds.size(); start += kChunk) {
        const std::size_t n = std::min(kChunk, log_odds.size() - start);
        for (std::size_t i = 0; i < n; ++i) {
            chunk[i] = static_cast<float>(probability_from_log_odds(log_odds[start + i]));
        }
        if (std::fwrite(chunk, sizeof(float), n, file.get()) != n) {
            return os_error("write", path);
        }
    }
    return finish_file(path, file);
}

/// Builds "<prefix><suffix>" into @p out.
IoStatus join_path(const char* prefix, const char* suffix, char (&out)[kNpyMaxPath]) noexcept {
    const int n = std::snprintf(out, kNpyMaxPath, "%s%s", prefix, suffix);
    if (n < 0 || static_cast<std::size_t>(n) >= kNpyMaxPath) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: path '%s%s' longer than %zu bytes", prefix, suffix,
                                 kNpyMaxPath - 1U);
    }
    return IoStatus{};
}

}  // namespace

const char* npy_descr(NpyDtype dtype) noexcept {
    switch (dtype) {
        case NpyDtype::kInt16: return "<i2";
        case NpyDtype::kFloat32: return "<f4";
        case NpyDtype::kUInt8: return "|u1";
        case NpyDtype::kUInt16: return "<u2";
    }
    return "?";
}

std::size_t npy_item_size(NpyDtype dtype) noexcept {
    switch (dtype) {
        case NpyDtype::kInt16: return 2U;
        case NpyDtype::kFloat32: return 4U;
        case NpyDtype::kUInt8: return 1U;
        case NpyDtype::kUInt16: return 2U;
    }
    return 1U;
}

IoStatus parse_npy_header(const std::uint8_t* data, std::size_t size, NpyHeader& header) noexcept {
    header = NpyHeader{};
    if (data == nullptr && size != 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: null input");
    }
    if (size < sizeof kMagic || std::memcmp(data, kMagic, sizeof kMagic) != 0) {
        return IoStatus::failure(ErrorCode::kBadMagic, R"(npy: input does not start with "\x93NUMPY")");
    }
    if (size < 8U) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "npy: input ends inside the version");
    }
    header.major_version = data[6];
    header.minor_version = data[7];
    if ((header.major_version != 1U && header.major_version != 2U) || header.minor_version != 0U) {
        return IoStatus::failure(
            ErrorCode::kUnsupportedVersion, "npy: format version %u.%u (only 1.0 and 2.0 are read)",
            static_cast<unsigned>(header.major_version), static_cast<unsigned>(header.minor_version));
    }
    const std::size_t preamble = header.major_version == 1U ? kNpyPreambleV1 : kNpyPreambleV2;
    if (size < preamble) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "npy: input ends inside the header length");
    }
    std::size_t header_len = static_cast<std::size_t>(data[8]) | (static_cast<std::size_t>(data[9]) << 8U);
    if (header.major_version == 2U) {
        header_len |= (static_cast<std::size_t>(data[10]) << 16U) | (static_cast<std::size_t>(data[11]) << 24U);
    }
    if (header_len > kNpyMaxHeaderBytes) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "npy: header length %zu above the limit of %zu",
                                 header_len, kNpyMaxHeaderBytes);
    }
    if (header_len == 0U) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "npy: header length 0");
    }
    if (header_len > size - preamble) {
        return IoStatus::failure(ErrorCode::kTruncatedInput,
                                 "npy: header length %zu runs past the end of the input (%zu bytes after the preamble)",
                                 header_len, size - preamble);
    }
    header.data_offset = preamble + header_len;
    const std::uint8_t* begin = data + preamble;
    const std::uint8_t* end = begin + header_len;
    if (end[-1] != '\n') {
        return IoStatus::failure(ErrorCode::kMalformedInput, "npy: header does not end in '\\n'");
    }
    HeaderCursor cursor(begin, end - 1);
    IoStatus st = parse_dict(cursor, header);
    if (!st) {
        return st;
    }
    std::uint64_t count = 1;
    for (std::size_t i = 0; i < header.ndim; ++i) {
        if (__builtin_mul_overflow(count, header.shape[i], &count)) {
            return IoStatus::failure(ErrorCode::kCapacityExceeded, "npy: the shape's element count overflows");
        }
    }
    header.element_count = count;
    if (__builtin_mul_overflow(count, static_cast<std::uint64_t>(npy_item_size(header.dtype)), &header.data_bytes)) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "npy: the data size overflows");
    }
    return IoStatus{};
}

IoStatus check_npy_layout(const NpyHeader& header, NpyDtype dtype, GridDims dims, std::uint64_t total_size) noexcept {
    if (!dims_valid(dims)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: expected dimensions %d x %d x %d are not all >= 1",
                                 dims.nx, dims.ny, dims.nz);
    }
    if (header.dtype != dtype) {
        return IoStatus::failure(ErrorCode::kUnsupportedType, "npy: dtype is '%s', expected '%s'",
                                 npy_descr(header.dtype), npy_descr(dtype));
    }
    const std::uint64_t expected[3] = {static_cast<std::uint64_t>(dims.nz), static_cast<std::uint64_t>(dims.ny),
                                       static_cast<std::uint64_t>(dims.nx)};
    if (header.ndim != 3U || header.shape[0] != expected[0] || header.shape[1] != expected[1] ||
        header.shape[2] != expected[2]) {
        char got[128];
        char want[128];
        format_shape(header.shape, header.ndim, got, sizeof got);
        format_shape(expected, 3U, want, sizeof want);
        return IoStatus::failure(ErrorCode::kGeometryMismatch,
                                 "npy: shape %s differs from the expected (nz, ny, nx) %s", got, want);
    }
    return check_npy_data_size(header, total_size);
}

IoStatus check_npy_data_size(const NpyHeader& header, std::uint64_t total_size) noexcept {
    if (total_size < header.data_offset || total_size - header.data_offset < header.data_bytes) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "npy: data is %" PRIu64 " bytes, the shape needs %" PRIu64,
                                 total_size < header.data_offset ? 0U : total_size - header.data_offset,
                                 header.data_bytes);
    }
    if (total_size - header.data_offset != header.data_bytes) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "npy: %" PRIu64 " bytes after the data",
                                 total_size - header.data_offset - header.data_bytes);
    }
    return IoStatus{};
}

IoStatus format_npy_header(NpyDtype dtype, GridDims dims, Span<std::uint8_t> out, std::size_t& length) noexcept {
    length = 0;
    if (!dims_valid(dims)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: dimensions %d x %d x %d are not all >= 1", dims.nx,
                                 dims.ny, dims.nz);
    }
    const std::uint64_t shape[3] = {static_cast<std::uint64_t>(dims.nz), static_cast<std::uint64_t>(dims.ny),
                                    static_cast<std::uint64_t>(dims.nx)};
    return format_npy_header_shape(dtype, shape, 3U, out, length);
}

IoStatus format_npy_header_shape(NpyDtype dtype, const std::uint64_t* shape, std::size_t ndim, Span<std::uint8_t> out,
                                 std::size_t& length) noexcept {
    length = 0;
    if (ndim < 1U || ndim > 3U || std::any_of(shape, shape + ndim, [](std::uint64_t e) { return e < 1U; })) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: a shape of 1 to 3 extents, each >= 1, expected");
    }
    char shape_text[96];
    format_shape(shape, ndim, shape_text, sizeof shape_text);
    char dict[160];
    const int n = std::snprintf(dict, sizeof dict, "{'descr': '%s', 'fortran_order': False, 'shape': %s, }",
                                npy_descr(dtype), shape_text);
    if (n < 0 || static_cast<std::size_t>(n) >= sizeof dict) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: header does not fit");
    }
    char growth_text[24];
    const int growth_digits = std::snprintf(growth_text, sizeof growth_text, "%" PRIu64, shape[0]);
    // numpy: spare spaces for the growth axis, then pad (with the final '\n')
    // so that preamble + header is a multiple of 64; a full block when it already is.
    const std::size_t unpadded = static_cast<std::size_t>(n) + kGrowthAxisMaxDigits -
                                 static_cast<std::size_t>(growth_digits) + 1U;  // + '\n'
    const std::size_t pad = kArrayAlign - (kNpyPreambleV1 + unpadded) % kArrayAlign;
    const std::size_t header_len = unpadded + pad;
    const std::size_t total = kNpyPreambleV1 + header_len;
    if (out.size() < total) {
        return IoStatus::failure(ErrorCode::kStorageTooSmall, "npy: header needs %zu bytes, buffer has %zu", total,
                                 out.size());
    }
    std::uint8_t* p = out.data();
    std::memcpy(p, kMagic, sizeof kMagic);
    p[6] = 1U;
    p[7] = 0U;
    p[8] = static_cast<std::uint8_t>(header_len & 0xFFU);
    p[9] = static_cast<std::uint8_t>(header_len >> 8U);
    std::memcpy(p + kNpyPreambleV1, dict, static_cast<std::size_t>(n));
    std::memset(p + kNpyPreambleV1 + static_cast<std::size_t>(n), ' ', header_len - static_cast<std::size_t>(n) - 1U);
    p[total - 1U] = '\n';
    length = total;
    return IoStatus{};
}

IoStatus decode_npy_int16(const std::uint8_t* data, std::size_t size, GridDims dims, Span<std::int16_t> out) noexcept {
    return decode_npy(data, size, NpyDtype::kInt16, dims, out.data(), out.size());
}

IoStatus decode_npy_float32(const std::uint8_t* data, std::size_t size, GridDims dims, Span<float> out) noexcept {
    return decode_npy(data, size, NpyDtype::kFloat32, dims, out.data(), out.size());
}

IoStatus decode_npy_uint8(const std::uint8_t* data, std::size_t size, GridDims dims, Span<std::uint8_t> out) noexcept {
    return decode_npy(data, size, NpyDtype::kUInt8, dims, out.data(), out.size());
}

IoStatus write_npy_int16(const char* path, Span<const std::int16_t> data, GridDims dims) noexcept {
    return write_npy(path, NpyDtype::kInt16, dims, data.data(), data.size());
}

IoStatus write_npy_float32(const char* path, Span<const float> data, GridDims dims) noexcept {
    return write_npy(path, NpyDtype::kFloat32, dims, data.data(), data.size());
}

IoStatus write_npy_uint8(const char* path, Span<const std::uint8_t> data, GridDims dims) noexcept {
    return write_npy(path, NpyDtype::kUInt8, dims, data.data(), data.size());
}

IoStatus read_npy_int16(const char* path, GridDims dims, Span<std::int16_t> out) noexcept {
    return read_npy(path, NpyDtype::kInt16, dims, out.data(), out.size());
}

IoStatus read_npy_float32(const char* path, GridDims dims, Span<float> out) noexcept {
    return read_npy(path, NpyDtype::kFloat32, dims, out.data(), out.size());
}

IoStatus read_npy_uint8(const char* path, GridDims dims, Span<std::uint8_t> out) noexcept {
    return read_npy(path, NpyDtype::kUInt8, dims, out.data(), out.size());
}

IoStatus write_grid_npy(const char* path_prefix, const EvidenceGrid& grid) noexcept {
    if (grid.voxel_count() == 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: npy: the grid is empty", path_prefix);
    }
    char path[kNpyMaxPath];
    const GridDims dims = grid.geometry().dims();
    IoStatus st = join_path(path_prefix, "_log_odds.npy", path);
    if (st) {
        st = write_npy(path, NpyDtype::kInt16, dims, grid.log_odds().data(), grid.voxel_count());
    }
    if (st) {
        st = join_path(path_prefix, "_probability.npy", path);
    }
    if (st) {
        st = write_probability(path, grid);
    }
    if (st) {
        st = join_path(path_prefix, "_observed.npy", path);
    }
    if (st) {
        st = write_npy(path, NpyDtype::kUInt8, dims, grid.observed().data(), grid.voxel_count());
    }
    return st;
}

IoStatus read_background_npy(const char* log_odds_path, const char* observed_path, EvidenceGrid& grid) noexcept {
    if (grid.voxel_count() == 0U) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "npy: the grid is empty");
    }
    const GridDims dims = grid.geometry().dims();
    IoStatus st = read_npy_int16(log_odds_path, dims, grid.log_odds());
    if (st) {
        st = read_npy_uint8(observed_path, dims, grid.observed());
    }
    if (st) {
        for (std::size_t i = 0; i < grid.voxel_count(); ++i) {
            if (grid.log_odds()[i] == kNeverForeground) {
                const VoxelCoord c = grid.geometry().coord_of(i);
                st = IoStatus::failure(ErrorCode::kMalformedInput,
                                       "%s: npy: voxel (%d, %d, %d) holds the never-foreground sentinel %d, "
                                       "which a background grid cannot hold",
                                       log_odds_path, c.x, c.y, c.z, static_cast<int>(kNeverForeground));
                break;
            }
            if (grid.observed()[i] > 1U) {
                const VoxelCoord c = grid.geometry().coord_of(i);
                st = IoStatus::failure(ErrorCode::kMalformedInput,
                                       "%s: npy: voxel (%d, %d, %d) has observed flag %u (must be 0 or 1)",
                                       observed_path, c.x, c.y, c.z, static_cast<unsigned>(grid.observed()[i]));
                break;
            }
        }
    }
    if (!st) {
        grid.clear();
    }
    return st;
}

IoStatus read_grid_npy(const char* path_prefix, EvidenceGrid& grid) noexcept {
    char log_odds_path[kNpyMaxPath];
    char observed_path[kNpyMaxPath];
    IoStatus st = join_path(path_prefix, "_log_odds.npy", log_odds_path);
    if (st) {
        st = join_path(path_prefix, "_observed.npy", observed_path);
    }
    if (!st) {
        grid.clear();
        return st;
    }
    return read_background_npy(log_odds_path, observed_path, grid);
}

}  // namespace cellguard
