// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Records the sensors' views of the empty cell (background_recording.hpp).
#include "cellguard/monitor/background_recording.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <functional>

#include "cellguard/host/io/background_files.hpp"
#include "cellguard/host/io/depth_npy.hpp"

namespace cellguard::monitor {

namespace {

constexpr const char* kBackgroundOption = "--write-background";
constexpr const char* kDepthOption = "--record-depth";

SetupError error(const char* option, int status, const std::string& text) {
    return SetupError{status, std::string(option) + ": " + text};
}

/// One sensor's polling state: a live camera's frame counts once.
struct PollState {
    RecordedSensor counts;
    bool has_stamp = false;
    std::uint64_t last_stamp = 0U;
    std::uint64_t next_cycle = 0U;  ///< the frame index asked of the source next
};

/// Takes a new frame's reading; false with @p e set refuses it for good.
using FrameSink = std::function<bool(const SensorReading&, SetupError&)>;

/// Polls @p source once; true when a new depth image went to @p sink. @p e is set on a fatal refusal.
bool poll_once(const char* option, cell::FrameSource& source, PollState& r, const std::string& name,
               const FrameSink& sink, SetupError& e) {
    SensorReading reading;
    cell::FrameStatus status;
    const bool ok = source.load_frame(r.next_cycle++, reading, status);
    if (!ok) {
        ++r.counts.refused;
        return false;
    }
    if (status.has_stamp && r.has_stamp && status.stamp_us == r.last_stamp) {
        ++r.counts.repeated;  // the live camera's frame already taken: wait for the next
        return false;
    }
    if (!is_depth_image(reading.kind)) {
        e = error(option, 2,
                  "sensor '" + name +
                      "' delivers point sets (.pcd): no per-pixel view; record it with cellguard-prior from its "
                      "frames");
        return false;
    }
    if (!sink(reading, e)) {
        return false;
    }
    r.has_stamp = status.has_stamp;
    r.last_stamp = status.stamp_us;
    ++r.counts.frames;
    return true;
}

/// Polls every source until it gave @p wanted new frames, sensor after sensor, within @p deadline_us.
SetupError poll_sources(const char* option, const MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                        std::size_t wanted, std::uint64_t deadline_us, std::uint64_t poll_us, RecordingTime& time,
                        const std::vector<FrameSink>& sinks, std::vector<PollState>& states) {
    states.assign(sources.size(), PollState{});
    const std::uint64_t start = time.now_us();
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        SetupError e;
        while (states[s].counts.frames < wanted && !e.failed()) {
            if (!poll_once(option, *sources[s], states[s], cell.specs[s].name, sinks[s], e) && !e.failed()) {
                if (time.now_us() - start > deadline_us) {
                    char text[160];
                    static_cast<void>(std::snprintf(text, sizeof text, "%zu of %zu frames, %zu refused",
                                                    states[s].counts.frames, wanted, states[s].counts.refused));
                    return error(
                        option, 1,
                        "sensor '" + cell.specs[s].name + "' gave too few frames before the deadline: " + text);
                }
                time.pause(poll_us);
            }
        }
        if (e.failed()) {
            return e;
        }
    }
    return {};
}

}  // namespace

SetupError record_background_views(const MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                                   const BackgroundRecording& rec, RecordingTime& time,
                                   std::vector<RecordedSensor>& sensors, std::FILE* out) {
    if (rec.path.empty() || rec.frames < 1 || rec.frames > 1000 || sources.size() != cell.specs.size() ||
        cell.layout.readings.size() != cell.specs.size()) {
        return error(kBackgroundOption, 2, "a file, 1 to 1000 frames and one source per configured sensor are needed");
    }
    std::vector<BackgroundViewBuilder> builders;
    std::vector<FrameSink> sinks;
    builders.reserve(sources.size());
    for (const SensorReading& layout : cell.layout.readings) {
        builders.emplace_back(layout.depth.size());
    }
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        sinks.emplace_back([&builders, &cell, s](const SensorReading& reading, SetupError& e) {
            if (!builders[s].add(reading)) {
                e = error(kBackgroundOption, 1,
                          "sensor '" + cell.specs[s].name +
                              "' delivered a depth image of another size than its configuration's");
                return false;
            }
            return true;
        });
    }
    std::vector<PollState> recorders;
    if (SetupError e = poll_sources(kBackgroundOption, cell, sources, static_cast<std::size_t>(rec.frames),
                                    rec.deadline_us, rec.poll_us, time, sinks, recorders);
        e.failed()) {
        return e;
    }
    std::vector<std::vector<float>> views;
    std::vector<BackgroundViewRecord> records(sources.size());
    views.reserve(sources.size());
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        views.push_back(builders[s].median());
        records[s].identity = background_identity(cell.specs[s].name, cell.layout.readings[s]);
        records[s].depth = Span<const float>(views[s].data(), views[s].size());
    }
    std::vector<std::uint8_t> bytes;
    const IoStatus st = write_background_image_file(
        rec.path.c_str(), Span<const BackgroundViewRecord>(records.data(), records.size()), cell.prior_payload_crc,
        static_cast<std::uint32_t>(rec.frames), bytes);
    if (!st.ok()) {
        return error(kBackgroundOption, 1, st.message());
    }
    sensors.clear();
    for (const PollState& r : recorders) {
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

SetupError record_depth_frames(const MonitorCell& cell, const std::vector<cell::FrameSource*>& sources,
                               const DepthRecording& rec, RecordingTime& time, std::vector<RecordedSensor>& sensors,
                               std::FILE* out) {
    if (rec.dir.empty() || rec.frames < 1 || rec.frames > kMaxRecordedFrames || sources.size() != cell.specs.size()) {
        return error(kDepthOption, 2,
                     "a directory, 1 to 100000 frames and one source per configured sensor are needed");
    }
    std::vector<std::string> dirs;
    for (const sim::SensorSpec& spec : cell.specs) {
        dirs.push_back(rec.dir + "/" + spec.name);
    }
    if (::mkdir(rec.dir.c_str(), 0777) != 0 && errno != EEXIST) {
        return error(kDepthOption, 1, rec.dir + ": cannot create: " + std::strerror(errno));
    }
    for (const std::string& d : dirs) {
        if (::mkdir(d.c_str(), 0777) != 0 && errno != EEXIST) {
            return error(kDepthOption, 1, d + ": cannot create: " + std::strerror(errno));
        }
    }
    std::vector<std::size_t> written(sources.size(), 0U);
    std::vector<SensorReading> last(sources.size());
    std::vector<FrameSink> sinks;
    for (std::size_t s = 0U; s < sources.size(); ++s) {
        sinks.emplace_back([&dirs, &written, &last, s](const SensorReading& reading, SetupError& e) {
            last[s] = reading;
            char name[32];
            static_cast<void>(std::snprintf(name, sizeof name, "/frame-%06zu.npy", written[s]));
            const std::string path = dirs[s] + name;
            const int w = reading.intrinsics.width;
            const int h = reading.intrinsics.height;
            const IoStatus st = reading.kind == SensorDataKind::kDepthImageU16
                                    ? write_npy_depth_u16(path.c_str(), reading.depth_u16, w, h)
                                    : write_npy_depth_f32(path.c_str(), reading.depth, w, h);
            if (!st) {
                e = error(kDepthOption, 1, st.message());
                return false;
            }
            ++written[s];
            return true;
        });
    }
    std::vector<PollState> states;
    if (SetupError e = poll_sources(kDepthOption, cell, sources, static_cast<std::size_t>(rec.frames), rec.deadline_us,
                                    rec.poll_us, time, sinks, states);
        e.failed()) {
        return e;
    }
    sensors.clear();
    for (const PollState& r : states) {
        sensors.push_back(r.counts);
    }
    if (out != nullptr) {
        for (std::size_t s = 0U; s < sources.size(); ++s) {
            char scale[96] = "";
            if (last[s].kind == SensorDataKind::kDepthImageU16) {
                static_cast<void>(std::snprintf(scale, sizeof scale, ", depth_scale = %.9g, depth_offset = %.9g",
                                                static_cast<double>(last[s].depth_scale),
                                                static_cast<double>(last[s].depth_offset)));
            }
            static_cast<void>(std::fprintf(
                out,
                "recorded depth images: sensor '%s': %zu frames ('%s') into %s/ (%zu "
                "refused, %zu repeated); replay them with depth_files = \"%s\"%s\n",
                cell.specs[s].name.c_str(), written[s], last[s].kind == SensorDataKind::kDepthImageU16 ? "<u2" : "<f4",
                dirs[s].c_str(), states[s].counts.refused, states[s].counts.repeated, dirs[s].c_str(), scale));
        }
    }
    return {};
}

}  // namespace cellguard::monitor
