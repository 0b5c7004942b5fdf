// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file pcd_input.hpp
/// Sensor input from recorded PCD files (PCL's ASCII, binary and
/// binary_compressed formats, read by port/linux's pcd.hpp): a sensor with
/// `pcd_files` in the configuration takes its frames from those files, one
/// per cycle, in order, starting again after the last.
///
/// Points are in the sensor's frame (x right, y down, z along the optical
/// axis), as a depth camera such as the Kinect records them. Every frame is
/// checked before use; a frame that fails a check is not fused: its
/// description is made invalid on purpose, so the controller's own check
/// (validate_sensor_reading) refuses it and latches kFrameInconsistent, as
/// for any other inconsistent frame. Checks, in order:
/// - the file reads and decodes (header, data, sizes: pcd.hpp's checks);
/// - at most the sensor's configured width x height points, finite or not
///   (its capacity: compute_work_bound counts that many rays for it);
/// - an organised cloud (HEIGHT > 1) has the sensor's configured resolution;
/// - VIEWPOINT either has a zero translation (not recorded in cell
///   coordinates: the identity, or a capture driver's own convention such as
///   OpenNI's 180 degrees about x in the Kinect frames) or is the sensor's
///   configured pose (within 1 cm and 1 degree): a frame recorded by another
///   sensor of the cell is refused;
/// - only finite points are fused (NaN / infinite points, which depth
///   cameras deliver for pixels without a reading, are skipped and counted).
///
/// Its buffers are allocated when the source is made: the points (the
/// sensor's width x height) and the file's bytes (the largest of its files
/// at that time; a file that has grown beyond that since is refused). A
/// frame then loads without allocating (load_frame), except that port/linux's
/// decode_pcd allocates to decompress binary_compressed data.
#ifndef CELLGUARD_HOST_CELL_PCD_INPUT_HPP
#define CELLGUARD_HOST_CELL_PCD_INPUT_HPP

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "cellguard/grid/sensor_frame.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/io/pcd.hpp"

namespace cellguard::cell {

/// What the check of one recorded frame found.
struct PcdFrameCheck {
    bool ok = false;               ///< true: the frame is fused
    std::string file;              ///< the file it came from
    std::string reason;            ///< why it was refused (empty when ok)
    std::uint64_t points = 0U;     ///< finite points fused
    std::uint64_t nonfinite = 0U;  ///< points skipped as NaN or infinite
};

/// The recorded frames of one sensor.
class PcdFrameSource final : public FrameSource {
public:
    /// Frames from @p files (at least one) for the sensor named @p name at
    /// @p pose with a @p width x @p height image and @p max_range metres.
    PcdFrameSource(std::string name, std::vector<std::string> files, const Eigen::Isometry3d& pose, int width,
                   int height, float max_range);

    /// Reads and checks the frame of cycle @p cycle (file cycle % count) and
    /// describes it in @p reading (the points stay in this object until the
    /// next call). A refused frame leaves @p reading with a non-finite pose,
    /// which the controller reports as kFrameInconsistent.
    PcdFrameCheck load(std::uint64_t cycle, SensorReading& reading);

    /// load() without allocating: what it found goes to @p status
    /// (status.file points into this source's file list).
    bool load_frame(std::uint64_t cycle, SensorReading& reading, FrameStatus& status) noexcept override;
    /// "summary: sensor 'NAME': U recorded frames used, R refused (frame inconsistent)".
    void write_summary(std::FILE* out) const noexcept override;

    /// The sensor's name.
    [[nodiscard]] const std::string& name() const { return name_; }
    /// Frames used (passed every check) so far.
    [[nodiscard]] std::uint64_t used() const { return used_; }
    /// Frames refused so far.
    [[nodiscard]] std::uint64_t refused() const { return refused_; }

private:
    bool check_frame(const IoStatus& read, const PcdCloudInfo& info, FrameStatus& status) const noexcept;
    IoStatus read_file(const char* path, PcdCloudInfo& info) noexcept;

    std::string name_;
    std::vector<std::string> files_;
    Eigen::Isometry3d pose_;
    int width_;
    int height_;
    float max_range_;
    std::vector<std::uint8_t> bytes_;  ///< a file's bytes, room for the largest file at start-up
    std::vector<PcdPoint> buffer_;     ///< the decoded points, room for width x height
    std::vector<Eigen::Vector3f> points_;
    std::uint64_t used_ = 0U;
    std::uint64_t refused_ = 0U;
};

/// True when @p v has a zero translation (within 1e-9 m): the cloud does not
/// say where in the cell it was recorded.
bool is_unplaced_viewpoint(const PcdViewpoint& v);
/// True when @p v lies within @p max_distance metres and @p max_angle_deg
/// degrees of @p pose.
bool viewpoint_matches(const PcdViewpoint& v, const Eigen::Isometry3d& pose, double max_distance = 0.01,
                       double max_angle_deg = 1.0);

}  // namespace cellguard::cell

#endif  // CELLGUARD_HOST_CELL_PCD_INPUT_HPP
