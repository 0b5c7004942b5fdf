// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file background_recording.hpp
/// Commissioning: records every sensor's view of the empty cell from the
/// monitor's own frame sources (live cameras, simulated or scene sensors)
/// and writes it as the background view image (background_files.hpp),
/// bound to the prior's payload CRC-32. `cellguard-monitor
/// --write-background FILE` runs it; the monitor then loads the file
/// through `[prior] background_file` and compares every frame with it
/// (SR-BKG-003). cellguard-prior writes the same file for the simulated
/// paper cell; this is the way for sensors only the monitor reads (live
/// GigE cameras), whose real view no render gives.
///
/// A live camera's frame counts once: a frame whose capture stamp equals
/// the previous one is not added again, and the recorder waits for the
/// next (bounded by a deadline). A refused frame (a loss, no frame yet) is
/// skipped and counted; the recording fails when a sensor gives fewer than
/// the asked frames before the deadline. Point-set sensors (.pcd) have no
/// per-pixel view and are refused with a message.
///
/// The same recorder writes the sensors' depth images as files
/// (record_depth_frames, `--record-depth DIR`), to be replayed as `depth_files`.
#ifndef CELLGUARD_MONITOR_BACKGROUND_RECORDING_HPP
#define CELLGUARD_MONITOR_BACKGROUND_RECORDING_HPP

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/monitor/monitor_cell.hpp"

namespace cellguard::monitor {

/// How to record the views.
struct BackgroundRecording {
    std::string path;                       ///< the image file written (through "<path>.tmp", then renamed)
    int frames = 8;                         ///< distinct frames per sensor (1..1000); the view is their median
    std::uint64_t deadline_us = 30000000U;  ///< longest wait for all frames of live sensors
    std::uint64_t poll_us = 5000U;          ///< wait between two polls of a live sensor without a new frame
};

/// What a recording did, per sensor (index = the configuration's order).
struct RecordedSensor {
    std::size_t frames = 0U;    ///< frames added to the view
    std::size_t refused = 0U;   ///< frames the source refused (skipped)
    std::size_t repeated = 0U;  ///< polls that gave the frame already added (live sensors)
};

/// Clock and pause for the recorder (the tests step them; main uses the real ones).
class RecordingTime {
public:
    /// Microseconds on a monotonic clock.
    [[nodiscard]] virtual std::uint64_t now_us() noexcept = 0;
    /// Waits about @p us microseconds.
    virtual void pause(std::uint64_t us) noexcept = 0;
    virtual ~RecordingTime() = default;

protected:
    RecordingTime() = default;
    RecordingTime(const RecordingTime&) = default;
    RecordingTime& operator=(const RecordingTime&) = default;
    RecordingTime(RecordingTime&&) = default;
    RecordingTime& operator=(RecordingTime&&) = default;
};

/// Records @p rec.frames frames from each of @p sources (one per sensor of
/// @p cell, in its order), takes each sensor's per-pixel median, and writes
/// the image to @p rec.path for the prior with payload CRC @p cell.prior_payload_crc;
/// the file is read back and checked. @p sensors receives the per-sensor
/// counts. Errors (exit status 1 for a sensor or file error, 2 for bad
/// arguments) name the sensor or the file.
[[nodiscard]] SetupError record_background_views(const MonitorCell& cell,
                                                 const std::vector<cell::FrameSource*>& sources,
                                                 const BackgroundRecording& rec, RecordingTime& time,
                                                 std::vector<RecordedSensor>& sensors, std::FILE* out);

/// Most frames record_depth_frames records per sensor.
constexpr int kMaxRecordedFrames = 100000;

/// How to record depth images (`cellguard-monitor --record-depth DIR`).
struct DepthRecording {
    std::string dir;                        ///< DIR: one subfolder per sensor, named as the sensor
    int frames = 60;                        ///< distinct frames per sensor (1..kMaxRecordedFrames)
    std::uint64_t deadline_us = 30000000U;  ///< longest wait for all frames of live sensors
    std::uint64_t poll_us = 5000U;          ///< wait between two polls of a live sensor without a new frame
};

/// Records @p rec.frames distinct frames from each of @p sources (one per
/// sensor of @p cell) as depth images, `DIR/<sensor>/frame-NNNNNN.npy`
/// (depth_npy.hpp: '<u2' as a live camera delivers them, '<f4' metres for
/// simulated sensors), which a sensor's `depth_files = "DIR/<sensor>"`
/// replays through the camera path. A live camera's frame counts once
/// (as for record_background_views). Point-set sensors are refused (exit
/// status 2). Errors name the sensor or the file.
[[nodiscard]] SetupError record_depth_frames(const MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                                             const DepthRecording& rec, RecordingTime& time,
                                             std::vector<RecordedSensor>& sensors, std::FILE* out);

}  // namespace cellguard::monitor

#endif  // CELLGUARD_MONITOR_BACKGROUND_RECORDING_HPP
