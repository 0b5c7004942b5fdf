// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/prior_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <exception>

namespace cellguard {

namespace {

/// Owns a POSIX file descriptor; closes it on destruction unless released.
class Fd {
public:
    explicit Fd(int fd) noexcept : fd_(fd) {}
    ~Fd() {
        if (fd_ >= 0) {
            static_cast<void>(::close(fd_));
        }
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    Fd(Fd&&) = delete;
    Fd& operator=(Fd&&) = delete;
    [[nodiscard]] int get() const noexcept { return fd_; }
    [[nodiscard]] bool valid() const noexcept { return fd_ >= 0; }
    /// Closes now; returns close()'s result.
    int close_now() noexcept {
        const int fd = fd_;
        fd_ = -1;
        return ::close(fd);
    }

private:
    int fd_;
};

IoStatus os_error(const char* what, const char* path) noexcept {
    return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot %s: %s", path, what, std::strerror(errno));
}

/// Writes all @p size bytes, retrying partial writes and EINTR. False with errno set on failure.
bool write_all(int fd, const std::uint8_t* data, std::size_t size) noexcept {
    while (size > 0U) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return false;
        }
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

/// Reads up to @p size bytes, retrying partial reads and EINTR, until end of
/// file. Returns the bytes read, or -1 with errno set.
ssize_t read_all(int fd, std::uint8_t* data, std::size_t size) noexcept {
    std::size_t got = 0U;
    while (got < size) {
        const ssize_t n = ::read(fd, data + got, size - got);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return -1;
        }
        if (n == 0) {
            break;
        }
        got += static_cast<std::size_t>(n);
    }
    return static_cast<ssize_t>(got);
}

/// Writes @p size bytes to "<path>.tmp", fsyncs, renames over @p path.
IoStatus write_file_atomically(const char* path, const std::uint8_t* data, std::size_t size) noexcept {
    std::string tmp;
    try {
        tmp = std::string(path) + ".tmp";
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: cannot allocate the file name", path);
    }
    // NOLINTNEXTLINE(hicpp-signed-bitwise): POSIX flags are int
    constexpr int kFlags = O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC;
    Fd fd(::open(tmp.c_str(), kFlags, 0644));
    if (!fd.valid()) {
        return os_error("create", tmp.c_str());
    }
    const char* failed = nullptr;
    if (!write_all(fd.get(), data, size)) {
        failed = "write";
    } else if (::fsync(fd.get()) != 0) {
        failed = "fsync";
    } else if (fd.close_now() != 0) {
        failed = "close";
    }
    if (failed != nullptr) {
        const IoStatus st = os_error(failed, tmp.c_str());
        static_cast<void>(::unlink(tmp.c_str()));
        return st;
    }
    if (std::rename(tmp.c_str(), path) != 0) {
        const IoStatus st = os_error("rename the temporary file to", path);
        static_cast<void>(::unlink(tmp.c_str()));
        return st;
    }
    return IoStatus{};
}

bool is_identifier_start(char c) noexcept { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }

bool is_identifier_char(char c) noexcept { return is_identifier_start(c) || (c >= '0' && c <= '9'); }

/// True when @p s is one or more identifiers joined by "::" (at most 200 characters).
bool valid_namespace(const char* s) noexcept {
    if (s == nullptr) {
        return false;
    }
    const std::size_t n = std::strlen(s);
    if (n == 0U || n > 200U) {
        return false;
    }
    bool at_start = true;
    for (std::size_t i = 0U; i < n; ++i) {
        const char c = s[i];
        if (at_start) {
            if (!is_identifier_start(c)) {
                return false;
            }
            at_start = false;
        } else if (c == ':') {
            if (i + 1U >= n || s[i + 1U] != ':') {
                return false;
            }
            ++i;
            at_start = true;
        } else if (!is_identifier_char(c)) {
            return false;
        }
    }
    return !at_start;
}

/// True when @p s can stand between the quotes of an #include (at most 200 characters).
bool valid_include(const char* s) noexcept {
    const std::size_t n = std::strlen(s);
    if (n == 0U || n > 200U) {
        return false;
    }
    for (std::size_t i = 0U; i < n; ++i) {
        const char c = s[i];
        if (c < ' ' || c > '~' || c == '"' || c == '\\' || c == '<' || c == '>') {
            return false;
        }
    }
    return true;
}

const char* method_name(std::uint8_t method) noexcept {
    switch (static_cast<PriorMethod>(method)) {
        case PriorMethod::kThresholded: return "thresholded";
        case PriorMethod::kProbabilistic: return "probabilistic";
        case PriorMethod::kThresholdedBaseline: return "thresholded baseline";
        case PriorMethod::kProbabilisticBaseline: return "probabilistic baseline";
    }
    return "unknown";
}

/// "0x" and @p value in lower-case hex, @p digits wide, zero-padded.
std::string hex(std::uint64_t value, int digits) {
    char buf[24];
    const int n = std::snprintf(buf, sizeof buf, "0x%0*" PRIx64, digits, value);
    return {buf, n > 0 ? static_cast<std::size_t>(n) : 0U};
}

/// @p value with 17 significant digits (enough to read back the same double).
std::string exact(double value) {
    char buf[40];
    const int n = std::snprintf(buf, sizeof buf, "%.17g", value);
    return {buf, n > 0 ? static_cast<std::size_t>(n) : 0U};
}

/// The file comment: what the file is and the image's header fields in words.
void append_source_comment(const PriorImageView& view, const std::string& ns, std::string& out) {
    const PriorImageHeader& h = view.header();
    const Eigen::Vector3d origin = h.origin();
    const AccessibilityParams params = h.params();
    const std::string voxels = std::to_string(view.voxel_count());
    out +=
        "// Generated by cellguard write_prior_source_file (port/linux prior_files.hpp). Do not edit.\n"
        "// A prior image (format version 1, certification/prior-image-format.md) as a\n"
        "// constant array for the firmware's flash (.rodata). At start-up:\n"
        "//   cellguard::load_prior_image(cellguard::Span<const std::uint8_t>(" +
        ns +
        "::kImage), geometry)\n"
        "// checks both CRCs and the geometry; the static_asserts below tie the bytes\n"
        "// to CELLGUARD_GRID_NX/NY/NZ, the grid the firmware is compiled for.\n"
        "//\n";
    out += "// grid: " + std::to_string(h.nx) + " x " + std::to_string(h.ny) + " x " + std::to_string(h.nz) +
           " voxels (" + voxels + "), voxel size " + exact(h.voxel_size()) + " m,\n";
    out += "//       origin (" + exact(origin.x()) + ", " + exact(origin.y()) + ", " + exact(origin.z()) + ") m\n";
    out += "// method: " + std::string(method_name(h.method)) + " (" + std::to_string(h.method) + "), t_B " +
           exact(params.t_b) + ", t_E " + exact(params.t_e) + ", r " + std::to_string(h.radius_voxels) +
           " voxels, open faces " + hex(h.open_faces, 2) + "\n";
    out += "// payload CRC-32 " + hex(h.payload_crc, 8) + ", header CRC-32 " + hex(h.header_crc, 8) + "\n";
}

/// The include guard's opening, the includes and the check that the grid macros are defined.
void append_source_includes(const PriorSourceOptions& options, const std::string& guard, std::string& out) {
    out += "#ifndef " + guard + "\n#define " + guard + "\n\n";
    out += "#include <cstddef>\n#include <cstdint>\n\n";
    out += "#include \"cellguard/base/crc32.hpp\"\n#include \"cellguard/prior/prior_image.hpp\"\n";
    if (options.config_header != nullptr) {
        out += "#include \"" + std::string(options.config_header) + "\"\n";
    }
    out +=
        "\n#if !defined(CELLGUARD_GRID_NX) || !defined(CELLGUARD_GRID_NY) || !defined(CELLGUARD_GRID_NZ)\n"
        "#error \"define CELLGUARD_GRID_NX, CELLGUARD_GRID_NY and CELLGUARD_GRID_NZ to the grid the firmware is "
        "built for\"\n#endif\n\n";
}

/// The header fields as named constants.
void append_source_constants(const PriorImageView& view, std::string& out) {
    const PriorImageHeader& h = view.header();
    const std::string voxels = std::to_string(view.voxel_count());
    out += "/// Voxels along x, y, z of the grid the prior was computed on.\n";
    out += "inline constexpr std::int32_t kNx = " + std::to_string(h.nx) + ";\n";
    out += "inline constexpr std::int32_t kNy = " + std::to_string(h.ny) + ";\n";
    out += "inline constexpr std::int32_t kNz = " + std::to_string(h.nz) + ";\n";
    out += "/// Number of voxels, and of int16 values in the payload.\n";
    out += "inline constexpr std::size_t kVoxelCount = " + voxels + "U;\n";
    out += "/// Voxel size and origin (x, y, z), metres, as IEEE-754 binary64 bit patterns.\n";
    out += "inline constexpr std::uint64_t kVoxelSizeBits = " + hex(h.voxel_size_bits, 16) + "ULL;\n";
    out += "inline constexpr std::uint64_t kOriginBits[3] = {" + hex(h.origin_bits[0], 16) + "ULL, " +
           hex(h.origin_bits[1], 16) + "ULL, " + hex(h.origin_bits[2], 16) + "ULL};\n";
    out += "/// Method (a cellguard::PriorMethod value) and its parameters; t_B, t_E as binary64 bits.\n";
    out += "inline constexpr std::uint8_t kMethod = " + std::to_string(h.method) + "U;\n";
    out += "inline constexpr std::uint64_t kTbBits = " + hex(h.t_b_bits, 16) + "ULL;\n";
    out += "inline constexpr std::uint64_t kTeBits = " + hex(h.t_e_bits, 16) + "ULL;\n";
    out += "inline constexpr std::int32_t kRadiusVoxels = " + std::to_string(h.radius_voxels) + ";\n";
    out += "inline constexpr std::uint8_t kOpenFaces = " + hex(h.open_faces, 2) + "U;\n";
    out += "/// CRC-32 of the payload and of header bytes 0..83, as stored in the header.\n";
    out += "inline constexpr std::uint32_t kPayloadCrc = " + hex(h.payload_crc, 8) + "U;\n";
    out += "inline constexpr std::uint32_t kHeaderCrc = " + hex(h.header_crc, 8) + "U;\n\n";
}

/// The image bytes as the array kImage, 16 to a line.
void append_source_image(const PriorImageView& view, std::string& out) {
    const Span<const std::uint8_t> image = view.image();
    out += "/// The image, byte for byte as cellguard::write_prior_image makes it.\n";
    out += "inline constexpr std::uint8_t kImage[cellguard::prior_image_size(kVoxelCount)] = {\n";
    for (std::size_t i = 0U; i < image.size(); ++i) {
        if (i % 16U == 0U) {
            out += "   ";
        }
        out += ' ';
        out += hex(image[i], 2);
        out += ',';
        if (i % 16U == 15U || i + 1U == image.size()) {
            out += '\n';
        }
    }
    out += "};\n\n";
}

/// The static_asserts that tie the bytes to the firmware's grid, the library's format and the constants.
void append_source_asserts(std::string& out) {
    for (const char axis : {'x', 'y', 'z'}) {
        const char upper = static_cast<char>(axis - 'a' + 'A');
        out += "static_assert(kN";
        out += axis;
        out += " == static_cast<std::int32_t>(CELLGUARD_GRID_N";
        out += upper;
        out += "), \"prior computed for another grid: n";
        out += axis;
        out += " differs from CELLGUARD_GRID_N";
        out += upper;
        out += "\");\n";
    }
    out +=
        "static_assert(kVoxelCount == static_cast<std::size_t>(kNx) * static_cast<std::size_t>(kNy) * "
        "static_cast<std::size_t>(kNz), \"voxel count\");\n";
    out +=
        "static_assert(cellguard::kPriorImageFormatVersion == 1U && cellguard::kPriorImageHeaderSize == 88U,\n"
        "              \"the library reads another prior image format than these bytes have\");\n";
    out += "static_assert(sizeof kImage == cellguard::kPriorImageHeaderSize + 2U * kVoxelCount, \"image size\");\n";
    out += "namespace detail {\n";
    out += "inline constexpr cellguard::Span<const std::uint8_t> kImageBytes{kImage};\n";
    out += "}  // namespace detail\n";
    const auto field = [&out](const std::string& width, const std::string& offset, const std::string& constant) {
        out += "static_assert(cellguard::load_le_" + width +
               "(detail::kImageBytes, cellguard::prior_image_layout::" + offset + ") == " + constant +
               ",\n              \"header field " + offset + " differs from " + constant + "\");\n";
    };
    field("u16", "kVersion", "cellguard::kPriorImageFormatVersion");
    field("u32", "kNx", "static_cast<std::uint32_t>(kNx)");
    field("u32", "kNy", "static_cast<std::uint32_t>(kNy)");
    field("u32", "kNz", "static_cast<std::uint32_t>(kNz)");
    field("u64", "kVoxelSize", "kVoxelSizeBits");
    field("u64", "kOriginX", "kOriginBits[0]");
    field("u64", "kOriginY", "kOriginBits[1]");
    field("u64", "kOriginZ", "kOriginBits[2]");
    field("u64", "kTb", "kTbBits");
    field("u64", "kTe", "kTeBits");
    field("u32", "kRadius", "static_cast<std::uint32_t>(kRadiusVoxels)");
    field("u32", "kPayloadLength", "2U * kVoxelCount");
    field("u32", "kPayloadCrc", "kPayloadCrc");
    field("u32", "kHeaderCrc", "kHeaderCrc");
    out +=
        "static_assert(kImage[cellguard::prior_image_layout::kMethod] == kMethod && "
        "kImage[cellguard::prior_image_layout::kOpenFaces] == kOpenFaces,\n"
        "              \"header method or open faces differ\");\n";
    out +=
        "static_assert(cellguard::crc32(detail::kImageBytes.subspan(0U, cellguard::prior_image_layout::kHeaderCrc)) "
        "== kHeaderCrc,\n              \"header bytes do not match the header CRC\");\n\n";
}

/// Builds the text; may throw std::bad_alloc (caught by the caller).
void build_source(const PriorImageView& view, const PriorSourceOptions& options, std::string& out) {
    const std::string ns = options.name_space;
    std::string guard = "CELLGUARD_GENERATED_PRIOR_";
    for (const char c : ns) {
        guard += (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : (c == ':' ? '_' : c);
    }
    guard += "_HPP";
    out.clear();
    out.reserve(8192U + 6U * view.image().size());
    append_source_comment(view, ns, out);
    append_source_includes(options, guard, out);
    out += "namespace " + ns + " {\n\n";
    append_source_constants(view, out);
    append_source_image(view, out);
    append_source_asserts(out);
    out += "}  // namespace " + ns + "\n\n#endif  // " + guard + "\n";
}

}  // namespace

IoStatus encode_prior_image(const GridGeometry& geometry, const AccessibilityParams& params,
                            Span<const std::int16_t> prior, std::vector<std::uint8_t>& image) noexcept {
    const std::size_t size = prior_image_size(geometry.voxel_count());
    try {
        image.assign(size, 0U);
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "prior image: cannot allocate %zu bytes", size);
    }
    const Result<std::size_t> written = write_prior_image(geometry, params, prior,
                                                          Span<std::uint8_t>(image.data(), size));
    if (!written.ok()) {
        image.clear();
        return IoStatus::failure(written.error(), "prior image: cannot encode: %s (%zu values for %zu voxels)",
                                 to_string(written.error()), prior.size(), geometry.voxel_count());
    }
    return IoStatus{};
}

IoStatus write_prior_image_file(const char* path, const PriorImageView& image) noexcept {
    if (image.empty()) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: no prior image to write", path);
    }
    return write_file_atomically(path, image.image().data(), image.image().size());
}

IoStatus read_prior_image_file(const char* path, const GridGeometry& expected_geometry,
                               std::vector<std::uint8_t>& bytes, PriorImageView& view,
                               PriorImageError* reason) noexcept {
    view = PriorImageView{};
    if (reason != nullptr) {
        *reason = PriorImageError::kNone;
    }
    Fd fd(::open(path, O_RDONLY | O_CLOEXEC));  // NOLINT(hicpp-signed-bitwise): POSIX flags are int
    if (!fd.valid()) {
        return os_error("open", path);
    }
    struct stat info {};
    if (::fstat(fd.get(), &info) != 0) {
        return os_error("stat", path);
    }
    if (!S_ISREG(info.st_mode)) {  // NOLINT(hicpp-signed-bitwise): the POSIX macro masks with an int constant
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: not a regular file", path);
    }
    const auto file_size = static_cast<std::uint64_t>(info.st_size);
    if (file_size > kMaxPriorImageFileSize) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded,
                                 "%s: %" PRIu64 " bytes, more than the largest prior image (%zu bytes)", path,
                                 file_size, kMaxPriorImageFileSize);
    }
    const auto size = static_cast<std::size_t>(file_size);
    try {
        bytes.assign(size, 0U);
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: cannot allocate %zu bytes", path, size);
    }
    const ssize_t got = read_all(fd.get(), bytes.data(), size);
    if (got < 0) {
        return os_error("read", path);
    }
    if (static_cast<std::size_t>(got) != size) {
        return IoStatus::failure(ErrorCode::kTruncatedInput, "%s: file ended after %zd of %zu bytes", path, got, size);
    }
    const Result<PriorImageView, PriorImageError> loaded = load_prior_image(
        Span<const std::uint8_t>(bytes.data(), bytes.size()), expected_geometry);
    if (reason != nullptr) {
        *reason = loaded.error();
    }
    if (!loaded.ok()) {
        return IoStatus::failure(to_error_code(loaded.error()), "%s: %s", path, to_string(loaded.error()));
    }
    view = loaded.value();
    return IoStatus{};
}

IoStatus prior_source_text(const PriorImageView& image, const PriorSourceOptions& options, std::string& text) noexcept {
    if (image.empty()) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "prior source: no prior image");
    }
    if (!valid_namespace(options.name_space)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument,
                                 "prior source: namespace is not identifiers joined by '::'");
    }
    if (options.config_header != nullptr && !valid_include(options.config_header)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument,
                                 "prior source: config header name has a character an #include cannot hold");
    }
    try {
        build_source(image, options, text);
    } catch (const std::exception&) {
        text.clear();
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "prior source: cannot allocate the text");
    }
    return IoStatus{};
}

IoStatus write_prior_source_file(const char* path, const PriorImageView& image,
                                 const PriorSourceOptions& options) noexcept {
    std::string text;
    const IoStatus st = prior_source_text(image, options, text);
    if (!st) {
        return st.prefixed(path);
    }
    return write_file_atomically(path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

}  // namespace cellguard
