// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Records the sensors' views of the empty cell (background_recording.hpp).
#include "cellguard/monitor/background_recording.hpp"

#include "cellguard/host/io/background_files.hpp"

namespace cellguard::monitor {

namespace {

SetupError error(int status, const std::string& text) { return SetupError{status, "--write-background: " + text}; }

/// One sensor's recording state.
struct SensorRecorder {
    explicit SensorRecorder(std::size_t pixels) : builder(pixels) {}
    BackgroundViewBuilder builder;
    RecordedSensor counts;
    bool has_stamp = false;
    std::uint64_t last_stamp = 0U;
    std::uint64_t next_cycle = 0U;  ///< the frame index asked of the source next
};

/// Polls source @p s once; true when a new frame was added. @p e is set on a fatal refusal.
bool poll_once(cell::FrameSource& source, SensorRecorder& r, const std::string& name, SetupError& e) {
    SensorReading reading;
    cell::FrameStatus status;
    const bool ok = source.load_frame(r.next_cycle++, reading, status);
    if (!ok) {
        ++r.counts.refused;
        return false;
    }
    if (status.has_stamp && r.has_stamp && status.stamp_us == r.last_stamp) {
        ++r.counts.repeated;  // the live camera's frame already added: wait for the next
        return false;
    }
    if (!is_depth_image(reading.kind)) {
        e = error(2, "sensor '" + name +
                         "' delivers point sets (.pcd): no per-pixel view; record it with "
                         "cellguard-prior from its frames");
        return false;
    }
    if (!r.builder.add(reading)) {
        e = error(1, "sensor '" + name + "' delivered a depth image of another size than its configuration's");
        return false;
    }
    r.has_stamp = status.has_stamp;
    r.last_stamp = status.stamp_us;
    ++r.counts.frames;
    return true;
}

}  // namespace

SetupError record_background_views(const MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                                   const BackgroundRecording& rec, RecordingTime& time,
                                   std::vector<RecordedSensor>& sensors, std::FILE* out) {
    if (rec.path.empty() || rec.frames < 1 || rec.frames > 1000 || sources.size() != cell.specs.size() ||
        cell.layout.readings.size() != cell.specs.size()) {
        return error(2, "a file, 1 to 1000 frames and one source per configured sensor are needed");
    }
    std::vector<SensorRecorder> recorders;
    recorders.reserve(sources.size());
    for (const SensorReading& layout : cell.layout.readings) {
        recorders.emplace_back(layout.depth.size());
    }
    const auto wanted = static_cast<std::size_t>(rec.frames);
    const std::uint64_t start = time.now_us();
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        SetupError e;
        while (recorders[s].counts.frames < wanted && !e.failed()) {
            if (!poll_once(*sources[s], recorders[s], cell.specs[s].name, e) && !e.failed()) {
                if (time.now_us() - start > rec.deadline_us) {
                    char text[160];
                    static_cast<void>(std::snprintf(text, sizeof text, "%zu of %d frames, %zu refused",
                                                    recorders[s].counts.frames, rec.frames,
                                                    recorders[s].counts.refused));
                    return error(
                        1, "sensor '" + cell.specs[s].name + "' gave too few frames before the deadline: " + text);
                }
                time.pause(rec.poll_us);
            }
        }
        if (e.failed()) {
            return e;
        }
    }
    std::vector<std::vector<float>> views;
    std::vector<BackgroundViewRecord> records(sources.size());
    views.reserve(sources.size());
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        views.push_back(recorders[s].builder.median());
        records[s].identity = background_identity(cell.specs[s].name, cell.layout.readings[s]);
        records[s].depth = Span<const float>(views[s].data(), views[s].size());
    }
    std::vector<std::uint8_t> bytes;
    const IoStatus st = write_background_image_file(
        rec.path.c_str(), Span<const BackgroundViewRecord>(records.data(), records.size()), cell.prior_payload_crc,
        static_cast<std::uint32_t>(rec.frames), bytes);
    if (!st.ok()) {
        return error(1, st.message());
    }
    sensors.clear();
    for (const SensorRecorder& r : recorders) {
        sensors.push_back(r.counts);
    }
    if (out != nullptr) {
        static_cast<void>(std::fprintf(out,
                                       "background views: wrote %s (%zu bytes): %zu sensors' views of the empty cell, "
                                       "median of %d frames each, for the prior with payload CRC-32 0x%08X; read back "
                                       "and checked\n",
                                       rec.path.c_str(), bytes.size(), sources.size(), rec.frames,
                                       cell.prior_payload_crc));
        for (std::size_t s = 0U; s < sources.size(); ++s) {
            static_cast<void>(std::fprintf(out,
                                           "background views: sensor '%s': %zu frames, %zu refused, %zu repeated\n",
                                           cell.specs[s].name.c_str(), recorders[s].counts.frames,
                                           recorders[s].counts.refused, recorders[s].counts.repeated));
        }
    }
    return {};
}

}  // namespace cellguard::monitor
