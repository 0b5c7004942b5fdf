// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file safety_controller.hpp
/// The cycle executive: one call per period runs the fixed stages
/// fuse -> subtract and zones -> safety logic -> output, measures each,
/// checks the deadline, and turns every fault it can detect into the safe
/// state through the safety logic.
///
/// Faults detected, and when:
/// - a configured sensor without a frame (kSensorMissing), a frame older
///   than max_frame_age_us or stamped in the future (kSensorStale), a frame
///   whose description fails its checks or that no longer shows its
///   commissioned background (kFrameInconsistent): this cycle;
/// - a changed background (background_changed) in changed_cycles frames of a
///   sensor in a row (kPriorCheckFailed): in that cycle, latched for good;
/// - the prior in RAM no longer matching its CRC (kPriorCheckFailed): at the
///   end of the pass of the periodic check that reads the changed byte
///   (prior_check_slice_bytes per cycle); a prior or zones that do not
///   match the grid: at construction, latched for good;
/// - the zones' membership mask in RAM no longer matching its CRC
///   (kInternalCheck): at the end of the pass of the periodic check
///   (zone_check_slice_bytes per cycle); their settings (kinds, thresholds,
///   voxel counts): every cycle; latched for good;
/// - a sensor's ray table no longer matching its CRC (kInternalCheck): at
///   the end of the pass of the periodic check that reads the changed byte
///   (table_check_slice_bytes of one sensor's table per cycle, the sensors
///   in turn; a SignatureCheck per sensor slot over the table's
///   signature_regions() against its storage_crc()); a table object whose
///   limits or regions changed: at its next turn; latched for good;
/// - zone evaluation failing (kZoneEvaluation): this cycle;
/// - the output failing (kCanError) and the cycle overrunning its budget
///   (kCycleOverrun): reported in the next cycle, since the current one has
///   already been sent;
/// - the PLC's command missing, stale, naming an unknown case or speed
///   class, another robot, or joints that do not fit (kCommandInvalid,
///   command_check.hpp): this cycle;
/// - the robot model in RAM or flash no longer matching its CRC
///   (kInternalCheck): at the end of the pass of the periodic check
///   (robot_check_slice_bytes per cycle); the monitoring cases, the robot
///   settings (separation parameters, margin, image CRC, command age): every
///   cycle; a robot model that fails check_robot_model, a robot mask storage
///   smaller than the grid, a bad margin or separation parameters, cases
///   that do not fit the zones: at construction; latched for good;
/// - memory (hazards H-MEM-2, H-MEM-3; kInternalCheck, latched for good):
///   a CRC-32 table entry that no longer matches its definition, at the
///   cycle that tests it (crc_table_check_values byte values per cycle, a
///   pass in 256 / that many cycles); the controller's own state and its
///   copy of the configuration changed between two cycles (a StateSeal,
///   compared at the start of each cycle); the cycle thread's stack grown
///   into the guard band of the port's painting (ControllerConfig::stack),
///   every cycle. The safety logic seals its own state (safety_logic.hpp).
///
/// The robot side (robot_command.hpp, robot/*.hpp). A cell expects the PLC's
/// command when it has a robot or a case set (ControllerConfig::robot.model
/// or ::cases); then every cycle, after fusion and in this order:
/// 1. the command is checked (check_command) at the cycle's start time. A
///    command that passes applies its monitoring case from this cycle on,
///    and this cycle's report echoes it (RobotReport::active_case). One that
///    fails is kCommandInvalid (the stop, this cycle); the case in force
///    stays the last good one (echoed), and no pose is used at all: not the
///    previous good one, whose joints may be stale. The cycle then has no
///    robot mask, so the robot's own voxels are foreground in any zone it
///    reaches, and the separation request is kProtectiveStop (distance 0);
/// 2. with a robot: place_robot, then mark_robot_voxels into the robot mask
///    storage, grown by mask_margin_m;
/// 3. zone evaluation of the active case's zones, the robot's voxels left out;
/// 4. compute_separation against the robot's capsules, in the command's speed class;
/// 5. the safety logic (only the active case's zones; the separation's request;
///    the reset level: the caller's input OR the command's ResetRequest, held
///    high while the command is refused or missing, RobotReport::command_reset).
/// These steps run inside the kSubtractAndZones stage. The legacy
/// run_cycle(sensors, reset) passes no command: fine for a cell that
/// expects none, kCommandInvalid for one that does.
/// The controller allocates nothing; its work per cycle is bounded by
/// compute_work_bound (cycle.hpp).
#ifndef CELLGUARD_SAFETY_CONTROLLER_HPP
#define CELLGUARD_SAFETY_CONTROLLER_HPP

#include <array>
#include <cstdint>

#include "cellguard/base/ram_check.hpp"
#include "cellguard/base/stack_paint.hpp"
#include "cellguard/base/state_seal.hpp"
#include "cellguard/base/task_runner.hpp"
#include "cellguard/grid/footprint_fusion.hpp"
#include "cellguard/grid/fusion.hpp"
#include "cellguard/grid/ray_table.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_model.hpp"
#include "cellguard/robot/separation.hpp"
#include "cellguard/safety/background_check.hpp"
#include "cellguard/safety/clock.hpp"
#include "cellguard/safety/command_check.hpp"
#include "cellguard/safety/cycle.hpp"
#include "cellguard/safety/cycle_output.hpp"
#include "cellguard/safety/monitoring_cases.hpp"
#include "cellguard/safety/robot_command.hpp"
#include "cellguard/safety/safety_logic.hpp"
#include "cellguard/safety/zone_evaluation.hpp"

namespace cellguard {

/// One sensor's input to a cycle.
struct SensorInput {
    SensorReading reading{};          ///< what the sensor delivered
    std::uint64_t captured_us = 0U;   ///< when it was captured, on the controller's clock
    bool present = false;             ///< false: no frame arrived for this cycle
    const RayTable* table = nullptr;  ///< optional precomputed rays of this (static) depth sensor
    /// Optional commissioned view of the empty cell of this static sensor (per
    /// pixel of a depth image, per direction bin of a point set):
    /// too little of it shown is kFrameInconsistent, not fused; a changed one
    /// latches kPriorCheckFailed (background_check.hpp, BackgroundChangeTracker).
    const BackgroundReference* background = nullptr;
    /// Optional: the frame as the sensor delivered it, when a filter before
    /// the controller changed @ref reading (a depth filter that puts readings
    /// near the empty cell's depth onto it makes a live camera's frames
    /// repeat). The frozen-sensor check fingerprints this one; nullptr:
    /// @ref reading. Fusion and the background checks use @ref reading.
    const SensorReading* delivered = nullptr;
};

/// The robot side of a cell. The default is a cell without a robot.
struct RobotCellConfig {
    /// The robot model (it must pass check_robot_model and outlive the
    /// controller: in flash, or the LoadedRobot of the image); nullptr: no robot.
    const RobotModel* model = nullptr;
    std::uint32_t image_crc = 0U;  ///< CRC-32 of the robot image the model came from (robot id: its low 16 bits)
    /// Growth of every capsule for the robot mask, metres (finite, >= 0): the
    /// safety manual derives it from the robot's speed, the command's age,
    /// the cycle time and the sensors' uncertainty.
    double mask_margin_m = 0.05;
    SeparationParams separation{};  ///< speed and separation monitoring (check_separation_params)
    Span<std::uint8_t> mask{};      ///< robot mask storage, one byte per voxel (at least the grid's voxels)
};

/// How the cycle fuses its depth images.
enum class FusionMethod : std::uint8_t {
    kRay = 0,        ///< per ray (fuse_sensor), or through the sensor's ray table when it has one: the reference
    kFootprint = 1,  ///< footprint fusion (footprint_fusion.hpp) for depth images; point sets stay per ray
};

/// Footprint fusion's settings and working memory for the cycle.
struct FootprintFusionConfig {
    FusionMethod method = FusionMethod::kRay;  ///< kFootprint turns it on
    FootprintParams params{};                  ///< its exact step's limit (0: none, the same work every frame)
    /// One workspace per sensor lets the sensors run as parallel tasks; one
    /// suffices (sensor after sensor). Empty: every depth image is refused
    /// (kFrameInconsistent) while the method is kFootprint.
    Span<const FootprintWorkspace> workspaces{};
    /// The port's runner (port/linux: WorkerPool); nullptr: one core, in order.
    TaskRunner* runner = nullptr;
};

/// Configuration of the cycle executive.
struct ControllerConfig {
    SafetyLogicConfig logic{};                 ///< safety logic and restart interlock
    ZoneEvaluationParams zones{};              ///< t_f and the accessibility threshold for unseen
    std::size_t sensor_count = 0U;             ///< sensors configured (1..kMaxSensors)
    std::uint64_t max_frame_age_us = 200000U;  ///< a frame older than this is stale
    /// A sensor whose data are bit-identical (reading_fingerprint) in this
    /// many new frames in a row (new: a time stamp other than the previous
    /// frame's) is frozen: kSensorStale, and its frame is not fused. On by
    /// default (3, as the monitor's cycle.max_repeated_frames); 0 turns the
    /// check off: only for noise-free sources (the simulator's ideal frames,
    /// a recording replayed frame by frame) whose frames repeat by design.
    std::uint32_t max_repeated_frames = 3U;
    std::uint64_t cycle_budget_us = 5000U;           ///< deadline of one cycle
    std::size_t prior_check_slice_bytes = 4096U;     ///< bytes of the prior re-checked per cycle (> 0)
    std::size_t table_check_slice_bytes = 1048576U;  ///< bytes of one sensor's ray table re-checked per cycle (> 0)
    std::size_t zone_check_slice_bytes = 16384U;     ///< bytes of the zone membership mask re-checked per cycle (> 0)
    Rasterization rasterization = Rasterization::kExact;  ///< for sensors without a ray table
    FootprintFusionConfig footprint{};                    ///< footprint fusion of depth images, if chosen
    RobotCellConfig robot{};                              ///< the robot, if any
    /// The monitoring cases (copied at construction); nullptr: one case 0 = all zones.
    const MonitoringCases* cases = nullptr;
    /// A command that arrived longer ago than this at a cycle's start is stale (kCommandInvalid).
    std::uint64_t max_command_age_us = 200000U;
    std::size_t robot_check_slice_bytes = 4096U;  ///< bytes of the robot model re-checked per cycle (> 0)
    /// Byte values of the CRC-32 tables tested per cycle (1..256; 8 entries each): a pass in 256 / this cycles.
    std::uint32_t crc_table_check_values = 32U;
    /// The port's painting of the cycle thread's stack (cellguard/port/stack.hpp), its guard band checked
    /// every cycle; nullptr: no stack check. It must outlive the controller.
    const StackPaint* stack = nullptr;
};

/// The cycle executive. All references must outlive it.
class SafetyController {
public:
    /// Binds the parts. A prior that does not hold one value per voxel, or
    /// zones compiled for another grid, latch kPriorCheckFailed or
    /// kInternalCheck: the controller then stays in the safe state. The
    /// prior's and the zone mask's bytes and the zones' settings are CRC'd
    /// now; the periodic checks compare against these. @p fusion_scratch is
    /// fuse_sensor's working memory for sensors without a ray table (at least
    /// frame_grid.voxel_count() elements; may be empty when every sensor has
    /// a table): a sensor that needs it and finds it too small is refused
    /// every cycle (kFrameInconsistent), so the safe state follows.
    SafetyController(const ControllerConfig& config, EvidenceGrid& frame_grid, Span<std::int16_t> fusion_scratch,
                     Span<const std::int16_t> prior, const CompiledZones& zones, const SensorModelTable& model,
                     MonotonicClock& clock, CycleOutput* output) noexcept;

    /// Runs one cycle on @p sensors (exactly config.sensor_count entries,
    /// else kSensorMissing) with the reset input's level @p reset_input and
    /// no command (see the file comment).
    const CycleReport& run_cycle(Span<const SensorInput> sensors, bool reset_input) noexcept;

    /// Runs one cycle as above with the PLC's @p command as the receiver
    /// holds it at the cycle's start (ignored by a cell that expects none);
    /// its ResetRequest joins @p reset_input (step 5 of the file comment).
    const CycleReport& run_cycle(Span<const SensorInput> sensors, bool reset_input,
                                 const CommandInput& command) noexcept;

    /// Faults a check outside the controller found (the port's clock-rate
    /// check against the PLC's samples: kClockFault): counted among the
    /// detected faults of the next run_cycle (bits beyond kAllFaults ignored).
    /// The pending faults are sealed state (H-MEM-3): the seal is renewed
    /// only if it held before the change, so a corruption since the last
    /// cycle is still found by the next one.
    void report_faults(std::uint32_t faults) noexcept;

    /// The last cycle's report.
    [[nodiscard]] const CycleReport& report() const noexcept { return report_; }
    /// The deadline monitor.
    [[nodiscard]] const CycleMonitor& monitor() const noexcept { return monitor_; }
    /// CRC-32 of the prior's bytes taken at construction.
    [[nodiscard]] std::uint32_t prior_crc() const noexcept { return prior_check_.reference(); }
    /// The monitoring cases in force (the configuration's copy, or the default).
    [[nodiscard]] const MonitoringCases& cases() const noexcept { return cases_; }
    /// The robot's capsules as the last cycle placed them (meaningful when its report's command_valid).
    [[nodiscard]] const RobotPose& robot_pose() const noexcept { return pose_; }
    /// CRC-32 of the sealed configuration and state as they are now (public
    /// for the benchmark of its cost; the safety logic's own is separate).
    [[nodiscard]] std::uint32_t state_crc() const noexcept;
    /// The changed-background check: each slot's last comparison and the latch.
    [[nodiscard]] const BackgroundChangeTracker& background_change() const noexcept { return background_change_; }

private:
    friend struct SafetyControllerTestAccess;  ///< tests corrupt the sealed fields (tests/support)

    void add_state(Crc32& crc) const noexcept;
    std::uint32_t fuse_sensors(Span<const SensorInput> sensors, std::uint64_t now, FusionStats& stats) noexcept;
    [[nodiscard]] bool accept_frame(std::size_t slot, const SensorInput& s, std::uint64_t now,
                                    std::uint32_t& faults) noexcept;
    bool step_zone_checks() noexcept;
    std::uint32_t step_integrity_checks(Span<const SensorInput> sensors) noexcept;
    [[nodiscard]] std::uint32_t robot_settings_crc() const noexcept;
    void check_robot_config(const EvidenceGrid& frame_grid) noexcept;
    Span<const std::uint8_t> apply_command(const CommandInput& command, std::uint64_t now, RobotReport& report,
                                           std::uint32_t& detected) noexcept;
    Span<const std::uint8_t> mask_robot(const JointPositions& joints, RobotReport& report,
                                        std::uint32_t& detected) noexcept;
    SpeedRequest separate(Span<const std::uint8_t> robot_mask, std::uint32_t active_zones, RobotReport& report,
                          std::uint32_t& detected) noexcept;
    bool step_table_check(Span<const SensorInput> sensors) noexcept;
    bool frame_is_frozen(std::size_t slot, const SensorInput& input) noexcept;
    bool shows_background(std::size_t slot, const SensorInput& input) noexcept;

    /// What the frozen-sensor check keeps of a sensor slot's last frame.
    struct FrameHistory {
        bool seen = false;               ///< a frame has been fingerprinted
        std::uint64_t captured_us = 0U;  ///< its time stamp
        std::uint64_t fingerprint = 0U;  ///< reading_fingerprint of its data
        std::uint32_t repeats = 0U;      ///< new frames in a row with the same data (saturating)
    };

    /// A sensor slot's ray table check: made from the table's regions and
    /// storage_crc() when the slot first shows that table, remade when the
    /// slot's table pointer changes.
    struct TableCheck {
        const RayTable* table = nullptr;  ///< the table the check is of
        SignatureCheck check{};           ///< its signature regions against its storage_crc()
    };
    /// The turn of @p table in @p slot: @p slice_bytes of its regions, and
    /// whether the table object still has them. True when the check failed.
    static bool step_one_table(TableCheck& slot, const RayTable& table, std::size_t slice_bytes) noexcept;

    ControllerConfig config_;
    EvidenceGrid* grid_;
    Span<std::int16_t> scratch_;     ///< fuse_sensor's working memory
    SequentialRunner sequential_{};  ///< footprint fusion's runner when the port gives none
    Span<const std::int16_t> prior_;
    const CompiledZones* zones_;
    const SensorModelTable* model_;
    MonotonicClock* clock_;
    CycleOutput* output_;
    SafetyLogic logic_;
    CycleMonitor monitor_;
    CycleReport report_{};
    std::uint32_t pending_faults_ = 0U;
    std::uint32_t construction_faults_ = 0U;
    SignatureCheck prior_check_;            ///< the prior's bytes, reference taken at construction
    SignatureCheck zone_mask_check_;        ///< the zones' membership mask, reference taken at construction
    std::uint32_t zone_settings_crc_ = 0U;  ///< CompiledZones::settings_crc() at construction
    bool zone_settings_failed_ = false;
    std::array<TableCheck, kMaxSensors> table_checks_{};  ///< per sensor slot: the check of its table
    std::size_t table_check_sensor_ = 0U;                 ///< the sensor slot whose table the next cycle checks
    bool table_failed_ = false;
    std::array<FrameHistory, kMaxSensors> frame_history_{};  ///< per sensor slot, for max_repeated_frames
    BackgroundChangeTracker background_change_{};            ///< per sensor slot: the changed-background check
    MonitoringCases cases_{};                ///< the configuration's cases (a copy), or one case 0 = all zones
    std::uint32_t cases_crc_ = 0U;           ///< cases_.settings_crc() at construction
    bool command_expected_ = false;          ///< the cell has a robot or a case set
    std::uint8_t active_case_ = 0U;          ///< the case in force: the last good command's
    std::uint8_t speed_class_ = 0U;          ///< the speed class of this cycle's good command
    SignatureCheck robot_check_;             ///< the robot model's bytes, reference taken at construction
    std::uint32_t robot_settings_crc_ = 0U;  ///< robot_settings_crc() at construction
    RobotPose pose_{};                       ///< this cycle's robot pose (valid while the cycle's mask is)
    Crc32TableCheck crc_table_check_{};      ///< the CRC-32 tables, in slices
    bool memory_failed_ = false;             ///< the seal, the CRC tables or the stack guard failed (latched)
    StateSeal seal_{};                       ///< state_crc() at the end of the last cycle (or construction)
};

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_CONTROLLER_HPP
