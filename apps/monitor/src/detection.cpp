// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// The detection-capability experiment (detection.hpp).
#include "cellguard/monitor/detection.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

#include "cellguard/host/cell/filtered_frame_source.hpp"
#include "cellguard/host/cell/frame_source.hpp"
#include "cellguard/host/sim/experiment.hpp"
#include "cellguard/host/sim/workcell.hpp"
#include "cellguard/monitor/can_port.hpp"
#include "cellguard/monitor/command_link.hpp"
#include "cellguard/monitor/cycle_clock.hpp"
#include "cellguard/monitor/monitor_cell.hpp"
#include "cellguard/monitor/monitor_loop.hpp"
#include "cellguard/monitor/robot_cell_demo.hpp"
#include "cellguard/port/clock.hpp"

namespace cellguard::monitor {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A simulated camera of the experiment: its view of the empty cell (the one
/// the monitor's start-up cast, MonitorCell::layout), with the current piece
/// drawn over it and the camera's noise on top. The depth filter, when on,
/// is the monitor's own (FilteredFrameSource around this source).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class PieceFrameSource final : public cell::FrameSource {
public:
    PieceFrameSource(const sim::SensorSpec& spec, const std::vector<float>& empty_view,
                     const DetectionSettings& settings, std::size_t index, std::uint64_t cycle_offset)
        : spec_(spec),
          rays_(spec),
          noise_(settings.noise),
          index_(index),
          seed_(settings.seed),
          cycle_offset_(cycle_offset),
          background_(empty_view),
          image_(empty_view.size()),
          ideal_(empty_view.size()) {}

    /// The piece of the frames from now on (nullptr: the empty cell).
    void show(const sim::TestPiece* piece) noexcept {
        has_piece_ = piece != nullptr;
        if (has_piece_) {
            piece_ = *piece;
        }
    }

    bool load_frame(std::uint64_t cycle, SensorReading& reading, cell::FrameStatus& status) noexcept override {
        std::copy(background_.begin(), background_.end(), image_.begin());
        if (has_piece_) {
            draw_piece();
        }
        const Span<float> image(image_.data(), image_.size());
        if (noise_.kind == sim::SensorKind::kIdeal) {
            cell::dither_depth(cycle, image);  // else the frozen-sensor check takes it for frozen
        } else {
            sim::Rng rng(sim::sensor_seed(seed_ * 1000003U + cycle_offset_ + cycle, index_));
            static_cast<void>(sim::apply_noise(spec_, noise_, image, {ideal_.data(), ideal_.size()}, rng));
        }
        reading = sim::depth_reading(spec_, {image_.data(), image_.size()});
        status = cell::FrameStatus{};
        status.ok = true;
        return true;
    }

    void write_summary(std::FILE* /*out*/) const noexcept override {}

private:
    /// The piece over the empty cell's image: every pixel whose ray meets it
    /// before the background (pixels outside its bounding sphere's image skipped).
    void draw_piece() noexcept {
        std::int32_t u0 = 0;
        std::int32_t u1 = spec_.width - 1;
        std::int32_t v0 = 0;
        std::int32_t v1 = spec_.height - 1;
        bounding_rect(u0, u1, v0, v1);
        for (std::int32_t v = v0; v <= v1; ++v) {
            for (std::int32_t u = u0; u <= u1; ++u) {
                const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(spec_.width) +
                                      static_cast<std::size_t>(u);
                const double t = sim::intersect_piece(piece_, spec_.position, rays_.direction(i));
                const auto bg = static_cast<double>(background_[i]);
                const double bg_range = bg > 0.0 ? bg * rays_.ray_length(i) : std::numeric_limits<double>::infinity();
                if (t < bg_range) {
                    image_[i] = static_cast<float>(t / rays_.ray_length(i));
                }
            }
        }
    }

    /// The pixels of the box around the piece's bounding sphere in the camera
    /// frame, projected (every pixel when the sphere reaches the image plane).
    void bounding_rect(std::int32_t& u0, std::int32_t& u1, std::int32_t& v0, std::int32_t& v1) const noexcept {
        const Eigen::Vector3d c = spec_.pose().inverse() * piece_.centre;
        const double r = piece_.bounding_radius();
        if (!(c.z() - r > 0.01)) {
            return;
        }
        const PinholeIntrinsics k = spec_.intrinsics();
        const double near = c.z() - r;
        const double far = c.z() + r;
        const auto lo = [near, far](double a) { return std::min(a / near, a / far); };
        const auto hi = [near, far](double a) { return std::max(a / near, a / far); };
        const auto clip = [](double x, std::int32_t last) {
            return static_cast<std::int32_t>(std::clamp(x, 0.0, static_cast<double>(last)));
        };
        u0 = clip(std::floor(k.cx + k.fx * lo(c.x() - r)) - 1.0, spec_.width - 1);
        u1 = clip(std::ceil(k.cx + k.fx * hi(c.x() + r)) + 1.0, spec_.width - 1);
        v0 = clip(std::floor(k.cy + k.fy * lo(c.y() - r)) - 1.0, spec_.height - 1);
        v1 = clip(std::ceil(k.cy + k.fy * hi(c.y() + r)) + 1.0, spec_.height - 1);
    }

    sim::SensorSpec spec_;
    sim::SensorRays rays_;
    sim::NoiseModel noise_;
    std::size_t index_;
    std::uint64_t seed_;  ///< the run's seed: frame noise of cycle c from sensor_seed(seed * 1000003 + c, index)
    std::uint64_t cycle_offset_;  ///< added to c: the shard's own noise (0 for the first)
    const std::vector<float>& background_;
    std::vector<float> image_;
    std::vector<float> ideal_;
    sim::TestPiece piece_{};
    bool has_piece_ = false;
};

/// A CAN sender that drops every frame (the experiment reads the cycle's report).
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, never deleted through the base
class DroppingSender final : public CanSender {
public:
    bool send(const CanFrame& /*frame*/) noexcept override { return true; }
};

/// Points of the piece's surface and axis, at most 2 cm apart along the
/// piece: a cylinder's rings of 16 points from end to end with its axis, a
/// sphere's centre and 26 points of its surface (the fit and clearance tests).
std::vector<Eigen::Vector3d> outline(const sim::TestPiece& p) {
    std::vector<Eigen::Vector3d> points;
    const double r = 0.5 * p.diameter;
    if (p.shape == sim::PieceShape::kSphere) {
        points.push_back(p.centre);
        for (int x = -1; x <= 1; ++x) {
            for (int y = -1; y <= 1; ++y) {
                for (int z = -1; z <= 1; ++z) {
                    if (x != 0 || y != 0 || z != 0) {
                        points.emplace_back(p.centre + r * Eigen::Vector3d(x, y, z).normalized());
                    }
                }
            }
        }
        return points;
    }
    const Eigen::Vector3d e1 = p.axis.unitOrthogonal();
    const Eigen::Vector3d e2 = p.axis.cross(e1);
    const int rings = 1 + static_cast<int>(std::ceil(p.length / 0.02));
    for (int k = 0; k <= rings; ++k) {
        const Eigen::Vector3d c = p.centre + (static_cast<double>(k) / rings - 0.5) * p.length * p.axis;
        points.push_back(c);
        for (int i = 0; i < 16; ++i) {
            const double phi = 2.0 * kPi * static_cast<double>(i) / 16.0;
            points.emplace_back(c + r * (std::cos(phi) * e1 + std::sin(phi) * e2));
        }
    }
    return points;
}

/// The zone's bounding box.
void zone_bounds(const ZoneConfig& zone, Eigen::Vector3d& lo, Eigen::Vector3d& hi) noexcept {
    if (zone.shape == ZoneShape::kBox) {
        lo = zone.box_min;
        hi = zone.box_max;
        return;
    }
    lo = Eigen::Vector3d(zone.polygon[0].x, zone.polygon[0].y, zone.z_min);
    hi = Eigen::Vector3d(zone.polygon[0].x, zone.polygon[0].y, zone.z_max);
    for (std::size_t i = 1U; i < zone.polygon_size; ++i) {
        lo = lo.cwiseMin(Eigen::Vector3d(zone.polygon[i].x, zone.polygon[i].y, zone.z_min));
        hi = hi.cwiseMax(Eigen::Vector3d(zone.polygon[i].x, zone.polygon[i].y, zone.z_max));
    }
}

/// Fits: every outline point inside the zone, above the floor, outside every box.
bool fits(const sim::TestPiece& piece, const ZoneConfig& zone, const std::vector<sim::Box>& boxes) {
    if (piece.lowest_z() < -1e-9) {
        return false;
    }
    for (const Eigen::Vector3d& p : outline(piece)) {
        if (!zone_contains(zone, p)) {
            return false;
        }
        for (const sim::Box& b : boxes) {
            if (sim::box_contains(b, p)) {
                return false;
            }
        }
    }
    return true;
}

/// A uniformly distributed unit vector.
Eigen::Vector3d random_direction(sim::Rng& rng) {
    for (;;) {
        const Eigen::Vector3d v(rng.normal(), rng.normal(), rng.normal());
        const double n = v.norm();
        if (n > 1e-9) {
            return v / n;
        }
    }
}

/// Binomial P(X >= k) for n trials of probability p, by its terms in log space.
double tail_at_least(int k, int n, double p) noexcept {
    if (k <= 0) {
        return 1.0;
    }
    if (p <= 0.0) {
        return 0.0;
    }
    if (p >= 1.0) {
        return 1.0;
    }
    const double lp = std::log(p);
    const double lq = std::log1p(-p);
    double sum = 0.0;
    for (int i = k; i <= n; ++i) {
        const double log_term = std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) + i * lp +
                                (n - i) * lq;
        sum += std::exp(log_term);
    }
    return std::min(1.0, sum);
}

}  // namespace

const char* to_string(Placement placement) noexcept {
    switch (placement) {
        case Placement::kFloor: return "floor";
        case Placement::kBoxTop: return "box top";
        case Placement::kFree: break;
    }
    return "free";
}

std::vector<PieceSize> DetectionSettings::default_sizes() {
    std::vector<PieceSize> sizes;
    for (const sim::PieceShape shape : {sim::PieceShape::kCylinder, sim::PieceShape::kSphere}) {
        for (const double d_mm : {20.0, 30.0, 40.0, 55.0, 70.0, 100.0, 150.0, 200.0}) {
            sizes.push_back(PieceSize{shape, d_mm / 1000.0, shape == sim::PieceShape::kCylinder ? 0.3 : 0.0});
        }
    }
    return sizes;
}

double clopper_pearson_lower(int successes, int trials, double confidence) noexcept {
    if (trials <= 0 || trials > 1000000 || successes <= 0) {
        return 0.0;
    }
    const int k = std::min(successes, trials);
    const double alpha = 1.0 - confidence;
    // P(X >= k) grows with p: bisect for the p where it equals alpha.
    double lo = 0.0;
    double hi = 1.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (tail_at_least(k, trials, mid) < alpha ? lo : hi) = mid;
    }
    return lo;
}

double clopper_pearson_upper(int events, int trials, double confidence) noexcept {
    if (trials <= 0) {
        return 1.0;
    }
    return 1.0 - clopper_pearson_lower(trials - std::clamp(events, 0, trials), trials, confidence);
}

bool random_pose(const ZoneConfig& zone, const PieceSize& size, Placement placement, const std::vector<sim::Box>& boxes,
                 sim::Rng& rng, sim::TestPiece& out) {
    Eigen::Vector3d lo;
    Eigen::Vector3d hi;
    zone_bounds(zone, lo, hi);
    for (int attempt = 0; attempt < 10000; ++attempt) {
        sim::TestPiece p;
        p.shape = size.shape;
        p.diameter = size.diameter;
        p.length = size.length;
        const Eigen::Vector3d at(lo.x() + rng.uniform() * (hi.x() - lo.x()), lo.y() + rng.uniform() * (hi.y() - lo.y()),
                                 lo.z() + rng.uniform() * (hi.z() - lo.z()));
        p.centre = at;
        if (placement != Placement::kFree) {
            const double yaw = 2.0 * kPi * rng.uniform();
            p.axis = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
            p.centre.z() = 0.5 * size.diameter;  // resting on the floor
            if (placement == Placement::kBoxTop) {
                if (boxes.empty()) {
                    return false;
                }
                // On a random box's top face, 1 mm above it (clear of the box's inside test).
                const sim::Box& b = boxes[std::min(
                    boxes.size() - 1U, static_cast<std::size_t>(rng.uniform() * static_cast<double>(boxes.size())))];
                const Eigen::Vector3d local(b.size.x() * (rng.uniform() - 0.5), b.size.y() * (rng.uniform() - 0.5),
                                            0.0);
                p.centre = b.center + Eigen::AngleAxisd(b.yaw, Eigen::Vector3d::UnitZ()) * local;
                p.centre.z() = b.center.z() + 0.5 * b.size.z() + 0.5 * size.diameter + 0.001;
            }
        } else {
            p.axis = random_direction(rng);
            if (p.lowest_z() < 0.01) {
                continue;  // free: clear of the floor
            }
        }
        if (fits(p, zone, boxes)) {
            out = p;
            return true;
        }
    }
    return false;
}

double DetectionResult::smallest_always_detected(PriorMethod method, sim::PieceShape shape,
                                                 std::size_t min_voxels) const noexcept {
    // Sizes from the largest down: the smallest of the unbroken run detected every time.
    std::vector<double> diameters;
    for (const DetectionRow& r : rows) {
        if (r.method == method && r.size.shape == shape) {
            diameters.push_back(r.size.diameter);
        }
    }
    std::sort(diameters.begin(), diameters.end());
    diameters.erase(std::unique(diameters.begin(), diameters.end()), diameters.end());
    double smallest = 0.0;
    for (auto it = diameters.rbegin(); it != diameters.rend(); ++it) {
        // Every placement where the size fits (a row without poses was not tried), at least one.
        bool all = true;
        bool tried = false;
        for (const DetectionRow& r : rows) {
            if (r.method == method && r.size.shape == shape && r.size.diameter == *it && r.poses > 0) {
                tried = true;
                all = all && r.detected_at(min_voxels) == r.poses;
            }
        }
        if (!all || !tried) {
            break;
        }
        smallest = *it;
    }
    return smallest;
}

namespace {

/// One method's monitor: the cell, its sources, a PLC selecting the first case, the loop.
struct MethodRun {
    MethodRun(cell::MonitorConfig config, PriorMethod method, const DetectionSettings& settings,
              std::uint64_t cycle_offset, std::string& error)
        : cfg(std::move(config)), clock(false, real_clock) {
        cfg.budget_us = 60000000U;  // the decisions, not this host's speed
        SetupError e;
        if ((e = monitor_cell.configure(cfg)).failed() || (e = monitor_cell.configure_robot(cfg, nullptr)).failed() ||
            (e = monitor_cell.build_prior(cfg, nullptr, method)).failed() ||
            (e = monitor_cell.build_tables(cfg, nullptr)).failed()) {
            error = "the configuration's cell could not be set up: " + e.message;
            return;
        }
        for (std::size_t s = 0U; s < monitor_cell.specs.size(); ++s) {
            const sim::SensorSpec& spec = monitor_cell.specs[s];
            auto piece = std::make_unique<PieceFrameSource>(spec, monitor_cell.layout.depth[s], settings, s,
                                                            cycle_offset);
            pieces.push_back(piece.get());
            if (settings.conditioning.on()) {  // the monitor's filter, against the view it would use
                owned.push_back(std::make_unique<cell::FilteredFrameSource>(
                    std::move(piece), monitor_cell.backgrounds[s].depth, spec.width, spec.height, settings.conditioning,
                    cfg.sensors[s].name));
            } else {
                owned.push_back(std::move(piece));
            }
            sources.push_back(owned.back().get());
        }
        can.use_sender(sender);
        plc = std::make_unique<SimulatedPlcLink>(command_receiver_config(cfg), plc_receiver_config(cfg), &can);
        hook = std::make_unique<CaseCellDemo>(
            cfg.cases.empty() ? std::uint8_t{0U} : static_cast<std::uint8_t>(cfg.cases.front().number), *plc);
        loop = std::make_unique<MonitorLoop>(cfg, monitor_cell, sources, can, clock, nullptr, plc.get(), hook.get());
        if (!loop->status().ok()) {
            error = "the monitor's loop refused the configuration";
        }
    }

    /// Shows @p piece (nullptr: the empty cell) in every source.
    void show(const sim::TestPiece* piece) noexcept {
        for (PieceFrameSource* s : pieces) {
            s->show(piece);
        }
    }

    /// Runs the next cycle; true when zone @p zone was evaluated and INTRUDED.
    /// Keeps the zone's foreground count (0 when not evaluated) and whether
    /// its unseen voxels were over its limit.
    bool intruded(std::size_t zone) noexcept {
        const CycleReport& r = loop->run_cycle(next++);
        const std::uint32_t bit = 1U << zone;
        const bool active = (r.zones.active_mask & bit) != 0U;
        const ZoneReport& z = r.zones.zones[zone];
        foreground = active ? z.foreground : 0U;
        unseen_over = active && z.unseen > cfg.zones[zone].zone.max_unseen_voxels;
        return active && (r.zones.intruded_mask & bit) != 0U;
    }

    cell::MonitorConfig cfg;
    linux_port::LinuxMonotonicClock real_clock;
    CycleClock clock;
    MonitorCell monitor_cell;
    std::vector<std::unique_ptr<cell::FrameSource>> owned;  ///< the pieces' sources, filtered when the filter is on
    std::vector<PieceFrameSource*> pieces;                  ///< the pieces' sources in owned
    std::vector<cell::FrameSource*> sources;
    DroppingSender sender;
    CanPort can;
    std::unique_ptr<SimulatedPlcLink> plc;
    std::unique_ptr<CaseCellDemo> hook;
    std::unique_ptr<MonitorLoop> loop;
    int next = 0;
    std::uint32_t foreground = 0U;  ///< the zone's foreground voxels in the last cycle
    bool unseen_over = false;       ///< the zone's unseen voxels over its limit in the last cycle
};

/// The index of the zone named @p name, or -1.
int zone_index(const cell::MonitorConfig& cfg, const std::string& name) {
    for (std::size_t z = 0U; z < cfg.zones.size(); ++z) {
        if (cfg.zones[z].name == name) {
            return static_cast<int>(z);
        }
    }
    return -1;
}

/// The run's progress: a line at every whole per cent of its cycles (at most
/// 100 lines), with the time since the first cycle and an estimate of the
/// time left. Shared by the shards' threads.
class Progress {
public:
    Progress(std::FILE* out, std::uint64_t total) : out_(out), total_(std::max<std::uint64_t>(total, 1U)) {}

    /// Counts one cycle run.
    void cycle() noexcept {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (done_++ == 0U) {
            start_ = std::chrono::steady_clock::now();  // from the first cycle: the cell's set-up is not a cycle's
        }
        show();
    }

    /// Takes @p cycles out of the plan (a row whose piece does not fit).
    void drop(std::uint64_t cycles) noexcept {
        const std::lock_guard<std::mutex> lock(mutex_);
        total_ = std::max<std::uint64_t>(total_ - std::min(cycles, total_), 1U);
    }

    /// Writes @p line (a row's result) between the progress lines.
    void line(const char* text) noexcept {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (out_ != nullptr) {
            static_cast<void>(std::fprintf(out_, "detection: %s\n", text));
            static_cast<void>(std::fflush(out_));
        }
    }

private:
    void show() noexcept {
        const std::uint64_t percent = 100U * std::min(done_, total_) / total_;
        if (out_ == nullptr || percent == shown_) {
            return;
        }
        shown_ = percent;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const double left = elapsed * static_cast<double>(total_ - std::min(done_, total_)) /
                            static_cast<double>(done_);
        char bar[21] = {};
        for (std::size_t i = 0U; i < 20U; ++i) {
            bar[i] = i < percent / 5U ? '#' : '.';
        }
        static_cast<void>(
            std::fprintf(out_, "detection: [%s] %3llu %% of %llu cycles, %.1f min so far, about %.1f min left\n", bar,
                         static_cast<unsigned long long>(percent), static_cast<unsigned long long>(total_),
                         elapsed / 60.0, left / 60.0));
        static_cast<void>(std::fflush(out_));
    }

    std::mutex mutex_;
    std::FILE* out_;
    std::uint64_t total_;
    std::uint64_t done_ = 0U;
    std::uint64_t shown_ = 0U;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// The cycles a run of @p settings takes at most (a row whose piece does not fit takes fewer).
std::uint64_t planned_cycles(const DetectionSettings& settings) {
    const auto n = [](int v) { return static_cast<std::uint64_t>(std::max(v, 0)); };
    const std::uint64_t rows = settings.sizes.size() * settings.placements.size();
    const std::uint64_t warmups = n(settings.warmup_cycles) * n(settings.jobs);
    return settings.methods.size() *
           (warmups + n(settings.empty_cycles) + rows * n(settings.poses) * n(settings.cycles));
}

/// One shard's share of one prior's run: shard j of J runs an even share of
/// the empty cell's cycles (the first empty_cycles mod J shards one more)
/// and of every row the poses p with p mod J = j.
struct Shard {
    EmptyCellRow empty;
    std::vector<DetectionRow> rows;
    std::uint64_t cycles = 0U;
    std::string error;
};

/// Runs the empty cell's share of shard @p j of @p jobs on @p run.
void run_empty(MethodRun& run, const DetectionSettings& settings, std::size_t zone, int j, int jobs, Progress& bar,
               EmptyCellRow& empty) {
    run.show(nullptr);
    for (int i = 0; i < settings.warmup_cycles; ++i) {
        static_cast<void>(run.intruded(zone));
        bar.cycle();
    }
    empty.cycles = settings.empty_cycles / jobs + (j < settings.empty_cycles % jobs ? 1 : 0);
    for (int i = 0; i < empty.cycles; ++i) {
        empty.intruded += run.intruded(zone) ? 1 : 0;
        bar.cycle();
        empty.max_foreground = std::max(empty.max_foreground, run.foreground);
        empty.foreground_sum += run.foreground;
        empty.unseen += run.unseen_over ? 1 : 0;
        for (std::size_t n = 1U; n <= kMinVoxelsColumns; ++n) {
            empty.stops_with[n - 1U] += run.foreground >= n || run.unseen_over ? 1 : 0;
        }
    }
}

/// Runs shard @p j of @p jobs of @p method: the whole poses of each row are
/// drawn in order (the same poses at every J), the shard runs its own.
Shard run_shard(const cell::MonitorConfig& cfg, PriorMethod method, const DetectionSettings& settings, std::size_t zone,
                int j, Progress& bar) {
    Shard out;
    const int jobs = settings.jobs;
    MethodRun run(cfg, method, settings, static_cast<std::uint64_t>(j) << 40U, out.error);
    if (!out.error.empty()) {
        return out;
    }
    const ZoneConfig& zc = cfg.zones[zone].zone;
    const std::vector<sim::Box> boxes = run.monitor_cell.background_scene().boxes;
    out.empty.method = method;
    run_empty(run, settings, zone, j, jobs, bar, out.empty);
    std::uint64_t row_seed = 0U;
    for (const PieceSize& size : settings.sizes) {
        for (const Placement placement : settings.placements) {
            DetectionRow row{method, size, placement, 0, 0, 0.0, {}};
            sim::Rng rng(sim::sensor_seed(settings.seed, row_seed++));
            int p = 0;
            for (; p < settings.poses; ++p) {
                sim::TestPiece piece;
                if (!random_pose(zc, size, placement, boxes, rng, piece)) {
                    break;  // does not fit: the row has fewer poses (0: not tried)
                }
                if (p % jobs != j) {
                    continue;  // another shard's
                }
                run.show(&piece);
                bool seen = false;
                std::uint32_t most = 0U;  // the zone's most foreground voxels in the k cycles
                for (int c = 0; c < settings.cycles; ++c) {
                    seen = run.intruded(zone) || seen;
                    most = std::max(most, run.foreground);
                    bar.cycle();
                }
                ++row.poses;
                row.detected += seen ? 1 : 0;
                for (std::size_t n = 1U; n <= kMinVoxelsColumns; ++n) {
                    row.detected_with[n - 1U] += most >= n ? 1 : 0;
                }
            }
            const int left = settings.poses - p;  // poses not drawn: the piece did not fit
            const int mine = left / jobs + (j < left % jobs ? 1 : 0);
            bar.drop(static_cast<std::uint64_t>(mine) * static_cast<std::uint64_t>(settings.cycles));
            char text[160];
            int at = std::snprintf(text, sizeof text, "%s %s %.0f mm %s: %d of %d", sim::method_name(method),
                                   sim::to_string(size.shape), size.diameter * 1000.0, to_string(placement),
                                   row.detected, row.poses);
            if (jobs > 1 && at > 0 && static_cast<std::size_t>(at) < sizeof text) {
                static_cast<void>(std::snprintf(text + at, sizeof text - static_cast<std::size_t>(at),
                                                " (shard %d of %d)", j + 1, jobs));
            }
            bar.line(text);
            out.rows.push_back(row);
        }
    }
    out.cycles = static_cast<std::uint64_t>(run.next);
    return out;
}

/// Adds shard @p s into @p total (the rows in the same order; bounds after the last).
void merge(Shard& total, const Shard& s) {
    total.empty.method = s.empty.method;
    if (total.rows.empty()) {
        total.rows = s.rows;
        for (DetectionRow& r : total.rows) {
            r.poses = r.detected = 0;
            r.detected_with = {};
        }
    }
    EmptyCellRow& e = total.empty;
    e.cycles += s.empty.cycles;
    e.intruded += s.empty.intruded;
    e.max_foreground = std::max(e.max_foreground, s.empty.max_foreground);
    e.foreground_sum += s.empty.foreground_sum;
    e.unseen += s.empty.unseen;
    for (std::size_t n = 0U; n < kMinVoxelsColumns; ++n) {
        e.stops_with[n] += s.empty.stops_with[n];
    }
    for (std::size_t i = 0U; i < total.rows.size() && i < s.rows.size(); ++i) {
        total.rows[i].poses += s.rows[i].poses;
        total.rows[i].detected += s.rows[i].detected;
        for (std::size_t n = 0U; n < kMinVoxelsColumns; ++n) {
            total.rows[i].detected_with[n] += s.rows[i].detected_with[n];
        }
    }
    total.cycles += s.cycles;
}

}  // namespace

DetectionResult run_detection(const cell::MonitorConfig& cfg, const DetectionSettings& settings, std::FILE* progress) {
    DetectionResult result;
    const int zone = zone_index(cfg, settings.zone);
    if (zone < 0) {
        result.error = "no zone named '" + settings.zone + "' in the configuration";
        return result;
    }
    if (settings.poses < 1 || settings.cycles < 1 || settings.empty_cycles < 0 || settings.warmup_cycles < 0 ||
        settings.jobs < 1 || settings.jobs > kMaxDetectionJobs) {
        result.error = "poses, cycles and jobs (up to " + std::to_string(kMaxDetectionJobs) +
                       ") must be at least 1, empty and warm-up cycles at least 0";
        return result;
    }
    Progress bar(progress, planned_cycles(settings));
    for (const PriorMethod method : settings.methods) {
        std::vector<Shard> shards(static_cast<std::size_t>(settings.jobs));
        std::vector<std::thread> threads;
        for (int j = 1; j < settings.jobs; ++j) {
            threads.emplace_back([&, j] {
                shards[static_cast<std::size_t>(j)] = run_shard(cfg, method, settings, static_cast<std::size_t>(zone),
                                                                j, bar);
            });
        }
        shards[0] = run_shard(cfg, method, settings, static_cast<std::size_t>(zone), 0, bar);
        for (std::thread& t : threads) {
            t.join();
        }
        Shard total;
        for (const Shard& s : shards) {
            if (!s.error.empty()) {
                result.error = s.error;
                return result;
            }
            merge(total, s);
        }
        for (DetectionRow& r : total.rows) {
            r.lower_bound = clopper_pearson_lower(r.detected, r.poses);
        }
        result.empty.push_back(total.empty);
        result.rows.insert(result.rows.end(), total.rows.begin(), total.rows.end());
        result.cycles_run += total.cycles;
    }
    return result;
}

namespace {

/// A smallest diameter as the tables print it: "70 mm", or "none" for 0.
struct DiameterText {
    char text[16] = "none";
};

DiameterText diameter_text(double d) noexcept {
    DiameterText t;
    if (d > 0.0) {
        static_cast<void>(std::snprintf(t.text, sizeof t.text, "%.0f mm", d * 1000.0));
    }
    return t;
}

/// The trade-off over the zone's min_foreground_voxels: per prior and n, the
/// empty cell's false stops (a count, per hour at @p cycle_hz and its one-sided
/// 95 % upper bound) beside the smallest sizes detected every time.
void write_trade_off(std::FILE* out, const DetectionResult& result, double cycle_hz) {
    static_cast<void>(std::fprintf(
        out,
        "\nTrade-off over the zone's min_foreground_voxels (n; the zone's foreground count does not depend on it, so "
        "one run gives each): false stops of the empty cell (INTRUDED or UNSEEN) and the smallest diameters "
        "detected in every pose, at %.1f cycles a second:\n\n"
        "| prior | n | false stops | of cycles | per hour | 95 %% upper, per hour | rods | spheres |\n"
        "|---|---|---|---|---|---|---|---|\n",
        cycle_hz));
    const double per_hour = 3600.0 * cycle_hz;
    for (const EmptyCellRow& e : result.empty) {
        for (std::size_t n = 1U; n <= kMinVoxelsColumns; ++n) {
            const int stops = e.stops_with[n - 1U];
            const double rate = e.cycles > 0 ? static_cast<double>(stops) / e.cycles : 0.0;
            const DiameterText rods = diameter_text(
                result.smallest_always_detected(e.method, sim::PieceShape::kCylinder, n));
            const DiameterText spheres = diameter_text(
                result.smallest_always_detected(e.method, sim::PieceShape::kSphere, n));
            static_cast<void>(std::fprintf(out, "| %s | %zu | %d | %d | %.2f | %.2f | %s | %s |\n",
                                           sim::method_name(e.method), n, stops, e.cycles, rate * per_hour,
                                           clopper_pearson_upper(stops, e.cycles) * per_hour, rods.text, spheres.text));
        }
    }
}

}  // namespace

void write_detection_table(std::FILE* out, const DetectionSettings& settings, const DetectionResult& result,
                           double cycle_hz) {
    const sim::FlashLidarNoise& n = settings.noise.lidar;
    const bool noisy = settings.noise.kind == sim::SensorKind::kFlashLidar;
    const cell::DepthConditioning& c = settings.conditioning;
    static_cast<void>(std::fprintf(
        out,
        "zone '%s', %d poses per row, k = %d cycles, seed %llu; noise: %s%.1f %% of range, flying pixels %.0f %%, "
        "dropouts %.1f %%; edge filter %.1f %% of depth (at least %.0f mm, radius %d), background tolerance "
        "%.1f %%, speckle filter %d neighbours\n\n",
        settings.zone.c_str(), settings.poses, settings.cycles, static_cast<unsigned long long>(settings.seed),
        noisy ? "" : "none: ", noisy ? 100.0 * n.range_sigma_per_m : 0.0,
        noisy ? 100.0 * n.mixed_pixel_probability : 0.0, noisy ? 100.0 * n.missing_probability : 0.0,
        100.0 * c.edge_jump_per_m, 1000.0 * c.edge_jump_min_m, c.edge_radius, 100.0 * c.background_tolerance_per_m,
        c.speckle_min_neighbours));
    static_cast<void>(std::fprintf(
        out, "| prior | piece | diameter mm | length mm | placement | detected | of | rate | 95 %% lower bound |\n"));
    static_cast<void>(std::fprintf(out, "|---|---|---|---|---|---|---|---|---|\n"));
    for (const DetectionRow& r : result.rows) {
        static_cast<void>(std::fprintf(
            out, "| %s | %s | %.0f | %.0f | %s | %d | %d | %.3f | %.3f |\n", sim::method_name(r.method),
            sim::to_string(r.size.shape), r.size.diameter * 1000.0, r.size.length * 1000.0, to_string(r.placement),
            r.detected, r.poses, r.poses > 0 ? static_cast<double>(r.detected) / r.poses : 0.0, r.lower_bound));
    }
    static_cast<void>(std::fprintf(out, "\nEmpty cell (zone '%s', the same noise), cycles with the zone INTRUDED:\n\n",
                                   settings.zone.c_str()));
    static_cast<void>(std::fprintf(
        out,
        "| prior | cycles | INTRUDED | unseen over the limit | foreground voxels, mean | most |\n|---|---|---|---|---|---|\n"));
    for (const EmptyCellRow& e : result.empty) {
        static_cast<void>(std::fprintf(
            out, "| %s | %d | %d | %d | %.1f | %u |\n", sim::method_name(e.method), e.cycles, e.intruded, e.unseen,
            e.cycles > 0 ? static_cast<double>(e.foreground_sum) / e.cycles : 0.0, e.max_foreground));
    }
    static_cast<void>(
        std::fprintf(out, "\nSmallest diameter detected in every pose of every placement, every larger one too:\n\n"));
    for (const PriorMethod m : settings.methods) {
        for (const sim::PieceShape shape : {sim::PieceShape::kCylinder, sim::PieceShape::kSphere}) {
            static_cast<void>(std::fprintf(out, "- %s, %s: %s\n", sim::method_name(m), sim::to_string(shape),
                                           diameter_text(result.smallest_always_detected(m, shape)).text));
        }
    }
    write_trade_off(out, result, cycle_hz);
}

void write_detection_csv(std::FILE* out, const std::string& cell, const DetectionResult& result) {
    static_assert(kMinVoxelsColumns == 4U, "the CSV has four detected_min columns");
    static_cast<void>(std::fprintf(out,
                                   "cell,prior,shape,diameter_mm,length_mm,placement,detected,poses,rate,lower_bound,"
                                   "detected_min1,detected_min2,detected_min3,detected_min4\n"));
    for (const DetectionRow& r : result.rows) {
        if (r.poses == 0) {
            continue;  // the piece did not fit: no rate
        }
        static_cast<void>(std::fprintf(out, "%s,%s,%s,%.0f,%.0f,%s,%d,%d,%.4f,%.4f,%d,%d,%d,%d\n", cell.c_str(),
                                       sim::method_name(r.method), sim::to_string(r.size.shape),
                                       r.size.diameter * 1000.0, r.size.length * 1000.0, to_string(r.placement),
                                       r.detected, r.poses, static_cast<double>(r.detected) / r.poses, r.lower_bound,
                                       r.detected_with[0], r.detected_with[1], r.detected_with[2], r.detected_with[3]));
    }
}

std::string detection_plot_script(const std::string& png_path, const std::string& title,
                                  const DetectionResult& result) {
    std::vector<std::string> keys;    // one line per prior, shape and placement with poses, in the rows' order
    std::vector<std::string> points;  // per key: its "diameter rate" lines
    for (const DetectionRow& r : result.rows) {
        if (r.poses == 0) {
            continue;
        }
        const std::string key = std::string(sim::method_name(r.method)) + ", " + sim::to_string(r.size.shape) + ", " +
                                to_string(r.placement);
        const auto k = static_cast<std::size_t>(std::find(keys.begin(), keys.end(), key) - keys.begin());
        if (k == keys.size()) {
            keys.push_back(key);
            points.emplace_back();
        }
        char point[64];
        static_cast<void>(std::snprintf(point, sizeof point, "%.0f %.4f\n", r.size.diameter * 1000.0,
                                        static_cast<double>(r.detected) / r.poses));
        points[k] += point;
    }
    std::string data;
    for (std::size_t k = 0U; k < keys.size(); ++k) {
        data += "$line" + std::to_string(k) + " << EOD\n" + points[k] + "EOD\n";
    }
    std::string s = "# gnuplot script written by cellguard-detection: detection rate against diameter\n" + data +
                    "set terminal pngcairo size 800,600 font 'sans,11'\n"
                    "set output '" +
                    png_path +
                    "'\n"
                    "set title '" +
                    title +
                    "'\n"
                    "set xlabel 'diameter (mm)'\nset ylabel 'share of poses detected'\n"
                    "set logscale x\nset xrange [18:220]\nset yrange [-0.02:1.05]\n"
                    "set xtics (20,30,40,55,70,100,150,200)\nset grid\nset key below\nplot ";
    for (std::size_t k = 0U; k < keys.size(); ++k) {
        s += std::string(k > 0U ? ", \\\n     " : "") + "$line" + std::to_string(k) +
             " using 1:2 with linespoints lw 2 title '" + keys[k] + "'";
    }
    return s + "\n";
}

}  // namespace cellguard::monitor
