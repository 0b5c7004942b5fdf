// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
#include "cellguard/host/io/background_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include <Eigen/Geometry>

#include "cellguard/base/crc32.hpp"

namespace cellguard {

namespace {

/// A value as a view stores it: a reading, or 0 for none.
float stored_depth(float d) noexcept { return (std::isfinite(d) && d > 0.0F) ? d : 0.0F; }

/// A file descriptor closed when it goes out of scope.
class Fd {
public:
    explicit Fd(int fd) noexcept : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    Fd(Fd&&) = delete;
    Fd& operator=(Fd&&) = delete;
    ~Fd() { close(); }
    [[nodiscard]] int get() const noexcept { return fd_; }
    /// Closes now; false when close() failed.
    bool close() noexcept {
        const bool ok = fd_ < 0 || ::close(fd_) == 0;
        fd_ = -1;
        return ok;
    }

private:
    int fd_;
};

/// The whole file at @p path into @p bytes (at most kMaxBackgroundImageFileSize).
IoStatus read_whole_file(const char* path, std::vector<std::uint8_t>& bytes) noexcept {
    Fd fd(::open(path, O_RDONLY | O_CLOEXEC));  // NOLINT(hicpp-signed-bitwise): POSIX flags are int
    if (fd.get() < 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open for reading", path);
    }
    try {
        bytes.clear();
        std::vector<std::uint8_t> chunk(65536U);
        for (;;) {
            const ssize_t got = ::read(fd.get(), chunk.data(), chunk.size());
            if (got < 0) {
                return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: read error", path);
            }
            if (got == 0) {
                break;
            }
            if (bytes.size() + static_cast<std::size_t>(got) > kMaxBackgroundImageFileSize) {
                return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: larger than %zu bytes", path,
                                         kMaxBackgroundImageFileSize);
            }
            bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + got);
        }
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: cannot allocate its bytes", path);
    }
    return {};
}

/// @p bytes to @p path through "<path>.tmp", fsync-ed, then renamed.
IoStatus write_atomically(const char* path, const std::vector<std::uint8_t>& bytes) noexcept {
    const std::string tmp = std::string(path) + ".tmp";
    // NOLINTNEXTLINE(hicpp-signed-bitwise): POSIX flags are int
    Fd fd(::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    if (fd.get() < 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open for writing", tmp.c_str());
    }
    std::size_t done = 0U;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd.get(), bytes.data() + done, bytes.size() - done);
        if (n <= 0) {
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    const bool synced = done == bytes.size() && ::fsync(fd.get()) == 0;
    if (!fd.close() || !synced || std::rename(tmp.c_str(), path) != 0) {
        static_cast<void>(std::remove(tmp.c_str()));
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot write", path);
    }
    return {};
}

}  // namespace

BackgroundSensorIdentity background_identity(const std::string& name, const SensorReading& reading) noexcept {
    BackgroundSensorIdentity id;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the name's bytes, as the CRC reads them
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(name.data());
    id.name_crc = crc32(Span<const std::uint8_t>(bytes, name.size()));
    id.width = static_cast<std::uint32_t>(std::max(reading.intrinsics.width, 0));
    id.height = static_cast<std::uint32_t>(std::max(reading.intrinsics.height, 0));
    const Eigen::Vector3d t = reading.pose.translation();
    const Eigen::Quaterniond q(reading.pose.linear());
    for (int i = 0; i < 3; ++i) {
        id.position[i] = t[i];
    }
    id.rotation[0] = q.w();
    id.rotation[1] = q.x();
    id.rotation[2] = q.y();
    id.rotation[3] = q.z();
    id.intrinsics[0] = reading.intrinsics.fx;
    id.intrinsics[1] = reading.intrinsics.fy;
    id.intrinsics[2] = reading.intrinsics.cx;
    id.intrinsics[3] = reading.intrinsics.cy;
    return id;
}

DirectionGrid recorded_view_grid(double hfov_deg, double vfov_deg, int width, int height) noexcept {
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    constexpr std::uint32_t kMarginBins = 2U;
    DirectionGrid g;
    if (width <= 0 || height <= 0 || !(hfov_deg > 0.0) || !(vfov_deg > 0.0) || !(hfov_deg <= 360.0) ||
        !(vfov_deg <= 180.0)) {
        return g;  // bin 0: refused by check_direction_grid
    }
    double bin_deg = std::max(hfov_deg / width, vfov_deg / height);
    for (;;) {  // bins twice as wide until they fit kMaxDirectionBins (a 640 x 480 camera: once)
        g.azimuth_bins = static_cast<std::uint32_t>(std::ceil(hfov_deg / bin_deg - 1e-9)) + 2U * kMarginBins;
        g.elevation_bins = static_cast<std::uint32_t>(std::ceil(vfov_deg / bin_deg - 1e-9)) + 2U * kMarginBins;
        if (g.bin_count() <= kMaxDirectionBins) {
            break;
        }
        bin_deg *= 2.0;
    }
    g.bin_rad = static_cast<float>(bin_deg * kDegree);
    g.azimuth_min_rad = -0.5F * static_cast<float>(g.azimuth_bins) * g.bin_rad;
    g.elevation_min_rad = -0.5F * static_cast<float>(g.elevation_bins) * g.bin_rad;
    return g;
}

BackgroundSensorIdentity point_view_identity(const std::string& name, const Eigen::Isometry3d& pose,
                                             const DirectionGrid& grid) noexcept {
    SensorReading r;
    r.pose = pose;
    return with_direction_grid(background_identity(name, r), grid);
}

std::vector<Eigen::Vector3f> depth_image_points(const SensorReading& reading) {
    std::vector<Eigen::Vector3f> points;
    if (!is_depth_image(reading.kind)) {
        return points;
    }
    const PinholeIntrinsics& k = reading.intrinsics;
    for (int v = 0; v < k.height; ++v) {
        for (int u = 0; u < k.width; ++u) {
            const auto i = static_cast<std::size_t>(v) * static_cast<std::size_t>(k.width) +
                           static_cast<std::size_t>(u);
            const float z = depth_value(reading, i);
            if (std::isfinite(z) && z > 0.0F) {
                points.emplace_back(static_cast<float>((u - k.cx) / k.fx) * z,
                                    static_cast<float>((v - k.cy) / k.fy) * z, z);
            }
        }
    }
    return points;
}

PointViewBuilder::PointViewBuilder(const DirectionGrid& grid)
    : grid_(grid), values_(check_direction_grid(grid).ok() ? 2U * grid.bin_count() : 0U, 0.0F) {}

bool PointViewBuilder::add(Span<const Eigen::Vector3f> points) {
    const std::size_t bins = values_.size() / 2U;
    const Result<DirectionViewAdded> added = add_to_direction_view(points, grid_, Span<float>(values_.data(), bins),
                                                                   Span<float>(values_.data() + bins, bins));
    if (!added.ok()) {
        return false;
    }
    outside_ += added.value().outside;
    ++frames_;
    return true;
}

bool PointViewBuilder::add(const SensorReading& reading) {
    if (reading.kind == SensorDataKind::kPointSet) {
        return add(reading.points);
    }
    const std::vector<Eigen::Vector3f> points = depth_image_points(reading);
    return is_depth_image(reading.kind) && add(Span<const Eigen::Vector3f>(points.data(), points.size()));
}

BackgroundViewBuilder::BackgroundViewBuilder(std::size_t pixels) : pixels_(pixels) {}

bool BackgroundViewBuilder::add(const SensorReading& reading) {
    if (!is_depth_image(reading.kind)) {
        return false;
    }
    const std::size_t n = reading.kind == SensorDataKind::kDepthImage ? reading.depth.size() : reading.depth_u16.size();
    if (n != pixels_) {
        return false;
    }
    values_.reserve(values_.size() + n);
    for (std::size_t i = 0U; i < n; ++i) {
        values_.push_back(stored_depth(depth_value(reading, i)));
    }
    ++frames_;
    return true;
}

std::vector<float> BackgroundViewBuilder::median() const {
    std::vector<float> out(pixels_, 0.0F);
    if (frames_ == 0U) {
        return out;
    }
    std::vector<float> column(frames_);
    for (std::size_t i = 0U; i < pixels_; ++i) {
        for (std::size_t k = 0U; k < frames_; ++k) {
            column[k] = values_[k * pixels_ + i];
        }
        const auto mid = column.begin() + static_cast<std::ptrdiff_t>((frames_ - 1U) / 2U);
        std::nth_element(column.begin(), mid, column.end());
        out[i] = *mid;
    }
    return out;
}

IoStatus write_background_image_file(const char* path, Span<const BackgroundViewRecord> views, std::uint32_t prior_crc,
                                     std::uint32_t frames, std::vector<std::uint8_t>& bytes) noexcept {
    const std::size_t size = background_image_size(views);
    try {
        bytes.assign(size, 0U);
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: cannot allocate %zu bytes", path, size);
    }
    const Result<std::size_t> written = write_background_image(views, prior_crc, frames,
                                                               Span<std::uint8_t>(bytes.data(), bytes.size()));
    if (!written.ok()) {
        return IoStatus::failure(written.error(), "%s: the background views cannot be encoded (%s)", path,
                                 to_string(written.error()));
    }
    const IoStatus st = write_atomically(path, bytes);
    if (!st.ok()) {
        return st;
    }
    std::vector<std::uint8_t> back;
    const IoStatus read = read_whole_file(path, back);
    if (!read.ok()) {
        return read;
    }
    const Result<BackgroundImageInfo, BackgroundImageError> checked = check_background_image(
        Span<const std::uint8_t>(back.data(), back.size()), static_cast<std::uint32_t>(views.size()), prior_crc);
    if (back != bytes || !checked.ok()) {
        return IoStatus::failure(ErrorCode::kCrcMismatch, "%s: read back differs from what was written", path);
    }
    return {};
}

IoStatus read_background_views(const char* path, std::uint32_t prior_crc,
                               const std::vector<BackgroundSensorIdentity>& expected,
                               std::vector<std::vector<float>>& views) noexcept {
    std::vector<std::uint8_t> bytes;
    const IoStatus read = read_whole_file(path, bytes);
    if (!read.ok()) {
        return read;
    }
    const Span<const std::uint8_t> image(bytes.data(), bytes.size());
    const auto count = static_cast<std::uint32_t>(expected.size());
    const Result<BackgroundImageInfo, BackgroundImageError> info = check_background_image(image, count, prior_crc);
    if (!info.ok()) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "%s: %s", path, to_string(info.error()));
    }
    try {
        views.assign(expected.size(), {});
        for (std::uint32_t s = 0U; s < count; ++s) {
            views[s].assign(background_view_values(expected[s]), 0.0F);
            const Result<std::size_t, BackgroundImageError> got = load_background_view(
                image, count, prior_crc, s, expected[s], Span<float>(views[s].data(), views[s].size()));
            if (!got.ok()) {
                return IoStatus::failure(ErrorCode::kMalformedInput, "%s: sensor %u: %s", path, s,
                                         to_string(got.error()));
            }
        }
    } catch (const std::exception&) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: cannot allocate the views", path);
    }
    return {};
}

}  // namespace cellguard
