// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file background_files.hpp
/// The background view image on a Linux host (format: lib's
/// background_image.hpp, certification/background-image-format.md): the
/// commissioned view of the empty cell of every depth sensor, made from the
/// same empty frames as the prior (a per-pixel median), written beside the
/// prior image and bound to it by the prior's payload CRC-32; read back and
/// checked at the monitor's start.
#ifndef CELLGUARD_HOST_IO_BACKGROUND_FILES_HPP
#define CELLGUARD_HOST_IO_BACKGROUND_FILES_HPP

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cellguard/base/span.hpp"
#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/io/io_status.hpp"
#include "cellguard/prior/background_image.hpp"

namespace cellguard {

/// Largest background image file read: eight 4096 x 4096 views.
constexpr std::size_t kMaxBackgroundImageFileSize = kBackgroundImageHeaderSize +
                                                    std::size_t{8U} *
                                                        (kBackgroundRecordHeaderSize + std::size_t{4U} * 4096U * 4096U);

/// The identity of the sensor named @p name that delivers depth images
/// like @p reading (its pose, intrinsics and size; the depths are not read):
/// what the image stores and the monitor compares bit for bit.
[[nodiscard]] BackgroundSensorIdentity background_identity(const std::string& name,
                                                           const SensorReading& reading) noexcept;

/// Accumulates one sensor's empty frames and gives their per-pixel median
/// (the lower median of the frames' values, a pixel without a reading
/// counting as 0: a pixel with readings in fewer than half the frames has
/// none in the view).
class BackgroundViewBuilder {
public:
    /// For images of @p pixels pixels.
    explicit BackgroundViewBuilder(std::size_t pixels);
    /// Adds one frame's depths (any of the depth image kinds); false when it
    /// is not a depth image of the right size.
    bool add(const SensorReading& reading);
    /// Frames added.
    [[nodiscard]] std::size_t frames() const noexcept { return frames_; }
    /// The per-pixel median of the frames added (0 where there are none).
    [[nodiscard]] std::vector<float> median() const;

private:
    std::size_t pixels_;
    std::size_t frames_ = 0U;
    std::vector<float> values_;  ///< frame-major: frame k's pixel i at k * pixels_ + i
};

/// The direction grid (direction_grid.hpp) of a recorded (point-set)
/// sensor's view, from its configured field of view (degrees) and
/// resolution: square bins of the larger angular pixel pitch
/// (hfov / width, vfov / height), doubled until the grid has at most
/// kMaxDirectionBins bins, over the field of view plus 2 bins on each
/// side, centred on the optical axis. The commissioning tool and the
/// monitor both derive it so; a grid that check_direction_grid refuses
/// (a field of view beyond the sphere, too many bins) is returned as it is
/// and refused where it is used.
[[nodiscard]] DirectionGrid recorded_view_grid(double hfov_deg, double vfov_deg, int width, int height) noexcept;

/// The identity of the point-set sensor named @p name at @p pose whose
/// view has the bins of @p grid (kind kBackgroundViewDirectionGrid).
[[nodiscard]] BackgroundSensorIdentity point_view_identity(const std::string& name, const Eigen::Isometry3d& pose,
                                                           const DirectionGrid& grid) noexcept;

/// The points, in the sensor frame, of a depth image @p reading (pixel
/// (u, v) with depth z at z * ((u - cx) / fx, (v - cy) / fy, 1)); pixels
/// without a reading are left out. Empty for a point set.
[[nodiscard]] std::vector<Eigen::Vector3f> depth_image_points(const SensorReading& reading);

/// Accumulates one point-set sensor's empty frames into its direction-grid
/// view (add_to_direction_view): per bin the farthest and the nearest range.
class PointViewBuilder {
public:
    /// For views on @p grid (checked by add).
    explicit PointViewBuilder(const DirectionGrid& grid);
    /// Adds one frame's points (a kPointSet reading, or a depth image's
    /// points); false when the grid is refused or the reading is of another kind.
    bool add(const SensorReading& reading);
    /// Adds the points @p points (sensor frame); false when the grid is refused.
    bool add(Span<const Eigen::Vector3f> points);
    /// Frames added.
    [[nodiscard]] std::size_t frames() const noexcept { return frames_; }
    /// Points of all frames outside the grid's field of view (left out).
    [[nodiscard]] std::size_t outside() const noexcept { return outside_; }
    /// The view as a kind-1 record stores it: farthest per bin, then nearest.
    [[nodiscard]] const std::vector<float>& values() const noexcept { return values_; }

private:
    DirectionGrid grid_;
    std::size_t frames_ = 0U;
    std::size_t outside_ = 0U;
    std::vector<float> values_;  ///< 2 x bins: farthest, then nearest
};

/// Encodes @p views with write_background_image into @p bytes (resized to
/// the image's size) and writes them to @p path through "<path>.tmp",
/// flushed, then renamed, and reads the file back and checks it. Errors
/// name the file and the step.
IoStatus write_background_image_file(const char* path, Span<const BackgroundViewRecord> views, std::uint32_t prior_crc,
                                     std::uint32_t frames, std::vector<std::uint8_t>& bytes) noexcept;

/// Reads the image at @p path, checks it (check_background_image with
/// expected.size() sensors and @p prior_crc) and copies view i, after
/// comparing its identity with expected[i], into views[i] (resized to
/// background_view_values(expected[i]): a direction grid's farthest, then
/// nearest ranges).
/// Errors name the file, the sensor index and what is wrong.
IoStatus read_background_views(const char* path, std::uint32_t prior_crc,
                               const std::vector<BackgroundSensorIdentity>& expected,
                               std::vector<std::vector<float>>& views) noexcept;

}  // namespace cellguard

#endif  // CELLGUARD_HOST_IO_BACKGROUND_FILES_HPP
