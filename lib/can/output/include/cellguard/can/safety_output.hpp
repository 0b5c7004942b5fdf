// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file safety_output.hpp
/// The CAN side of the cycle executive: turns each CycleReport into the CAN
/// frames of one cycle and hands them to a CanSender.
///
/// Frames of one cycle, in the order they are sent:
/// 1. the safety frame (safety_frame.hpp): protective stop = the report's
///    stop_requested (or the robot's speed request kProtectiveStop), warning,
///    fault = any fault latched, the active monitoring case, reduced speed =
///    the robot's speed request kReduced, the zone intrusion and unseen bits
///    of the configured zones, the zone count;
/// 2. its inverted copy (inverted_copy);
/// 3. the diagnostics frame: the previous cycle's duration and the worst so
///    far (the current one is still running when it is published), the
///    latched safety logic faults on ActiveFaults bits 0..8 and the CAN
///    sender's details (CanSender::detail_faults, asked once per cycle) on
///    bits 9..14, and one byte of the prior CRC-32, the
///    page rotating 0, 1, 2, 3, 0, ... per cycle;
/// 4. in a cell with a robot (the report's robot.configured), the separation
///    frame (separation_frame.hpp): distance, required distance, case, speed
///    request, the command's counter and validity. A cell without a robot
///    sends the first three only, as before the robot was added: the set of
///    frames is fixed by the commissioned configuration, not by the cycle.
/// Protocol 0.2: with the session link (SafetyOutputConfig::session_link, on
/// by default) the controller's link frame follows the copy (frame 2b): its
/// E2E counter the safety frame's, its CRC bound to the safety frame, its
/// fields from the controller's LinkEndpoint (LinkEndpoint::next, stamped
/// with the cycle's start, which is earlier than the send: the round trip
/// the endpoint measures is never shorter than the real one). The endpoint
/// is the caller's (the CommandReceiver's in a cell with a robot); an output
/// configured with the link but given no endpoint is refused.
/// The safety frame (with its copy), the diagnostics and the separation
/// frame each have their own E2E counter, advancing by one per cycle in
/// which the frame is encoded (0..14, wrapping 14 -> 0) whether or not the
/// send succeeded, so a frame lost on the way shows at the PLC as a counter jump.
///
/// A safety frame carries at most kMaxZonesInFrame (16) zones: a
/// configuration with more zones, or with an invalid channel config, is
/// refused at construction (check_config); a refused output sends nothing
/// and every publish() returns false, so the controller latches a CAN fault
/// and stays in the safe state.
#ifndef CELLGUARD_SAFETY_OUTPUT_HPP
#define CELLGUARD_SAFETY_OUTPUT_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"
#include "cellguard/can/can_frame.hpp"
#include "cellguard/can/can_sender.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/can/separation_frame.hpp"
#include "cellguard/can/session_link.hpp"
#include "cellguard/safety/cycle_output.hpp"

namespace cellguard {

/// Configuration of the CAN safety output.
struct SafetyOutputConfig {
    SafetyChannelConfig channel{};  ///< CAN IDs, data IDs, data ID mode
    std::uint8_t zone_count = 0U;   ///< configured zones, 0..kMaxZonesInFrame
    std::uint32_t prior_crc = 0U;   ///< CRC-32 of the prior in use (SafetyController::prior_crc)
    bool session_link = true;       ///< send the link frame (protocol 0.2); off only with a stated reason
};

/// Checks @p config: kInvalidArgument for an invalid channel config,
/// kCapacityExceeded for more zones than one safety frame carries.
[[nodiscard]] Status check_safety_output_config(const SafetyOutputConfig& config) noexcept;

/// The content of the safety frame for @p outputs with @p zone_count zones
/// (at most kMaxZonesInFrame, a contract): zone bits at and above the count
/// are dropped; case 0, no reduced speed (a cell without a robot).
[[nodiscard]] SafetyMessage safety_message(const SafetyOutputs& outputs, std::uint8_t zone_count) noexcept;
/// The same with the robot side of the cycle: ActiveCase = robot.active_case
/// (0..15, a contract), ProtectiveStop also when the speed request is
/// kProtectiveStop, ReducedSpeed when it is kReduced.
[[nodiscard]] SafetyMessage safety_message(const SafetyOutputs& outputs, const RobotReport& robot,
                                           std::uint8_t zone_count) noexcept;
/// The content of the separation frame for @p robot (case 0..15 and command
/// counter 0..14 are contracts; an unknown speed request is sent as kProtectiveStop).
[[nodiscard]] SeparationMessage separation_message(const RobotReport& robot) noexcept;

/// The content of the diagnostics frame for @p report, prior CRC page @p page
/// (0..3, a contract) of @p prior_crc, with the CAN port's detail faults
/// @p can_detail_faults (only bits 9..14 are used).
[[nodiscard]] DiagnosticsMessage diagnostics_message(const CycleReport& report, std::uint8_t page,
                                                     std::uint32_t prior_crc, std::uint16_t can_detail_faults) noexcept;

/// The frames of one cycle.
struct CycleFrames {
    CanFrame safety;       ///< the safety frame
    CanFrame inverted;     ///< its inverted copy
    CanFrame diagnostics;  ///< the diagnostics frame
    CanFrame separation;   ///< the separation frame (only when has_separation)
    bool has_separation;   ///< the cycle sends a separation frame (a robot is configured)
    CanFrame link;         ///< the controller's link frame (only when has_link)
    bool has_link;         ///< the cycle sends a link frame (session link on)
};

/// Encodes the frames of successive cycles: holds the three E2E counters and
/// the prior CRC page. @p config must pass check_safety_output_config (contract).
class CycleFrameEncoder {
public:
    /// Counters and page start at 0.
    explicit CycleFrameEncoder(const SafetyOutputConfig& config) noexcept;

    /// The frames of the cycle in @p report; advances the counters of the
    /// frames it encodes and the page. With @p link, also the link frame
    /// (its fields from link->next(report.started_us)).
    [[nodiscard]] CycleFrames encode(const CycleReport& report, std::uint16_t can_detail_faults,
                                     LinkEndpoint* link = nullptr) noexcept;

    /// Counter the next safety frame will carry.
    [[nodiscard]] std::uint8_t safety_counter() const noexcept { return safety_counter_; }
    /// Counter the next diagnostics frame will carry.
    [[nodiscard]] std::uint8_t diagnostics_counter() const noexcept { return diagnostics_counter_; }
    /// Counter the next separation frame will carry.
    [[nodiscard]] std::uint8_t separation_counter() const noexcept { return separation_counter_; }
    /// Prior CRC page the next diagnostics frame will carry.
    [[nodiscard]] std::uint8_t prior_crc_page() const noexcept { return page_; }

private:
    SafetyOutputConfig config_;
    std::uint8_t safety_counter_ = 0U;
    std::uint8_t diagnostics_counter_ = 0U;
    std::uint8_t separation_counter_ = 0U;
    std::uint8_t page_ = 0U;
};

/// The CycleOutput that sends each cycle's frames through a CanSender.
// NOLINTNEXTLINE(cppcoreguidelines-virtual-class-destructor): final, and the base's destructor is protected: never deleted through the base
class CanSafetyOutput final : public CycleOutput {
public:
    /// Binds @p sender and @p link (both must outlive the output). A @p config
    /// that fails check_safety_output_config, or has session_link on without a
    /// @p link, is refused: status() holds the error and publish() sends
    /// nothing and returns false.
    CanSafetyOutput(const SafetyOutputConfig& config, CanSender& sender, LinkEndpoint* link = nullptr) noexcept;

    /// Asks the sender for its detail faults (ActiveFaults bits 9..14 of this
    /// cycle's diagnostics frame), then sends the safety frame, its copy, the
    /// link frame (session link on), the diagnostics frame and (with a robot) the separation frame in this
    /// order, stopping at the first failed send. False when refused (nothing is asked or sent) or when a send failed.
    bool publish(const CycleReport& report) noexcept override;

    /// kOk, or why the configuration was refused.
    [[nodiscard]] Status status() const noexcept { return status_; }
    /// The encoder (counters and page of the next cycle).
    [[nodiscard]] const CycleFrameEncoder& encoder() const noexcept { return encoder_; }
    /// Frames of the last published cycle.
    [[nodiscard]] const CycleFrames& last_frames() const noexcept { return last_; }

private:
    Status status_;
    CycleFrameEncoder encoder_;
    CanSender* sender_;
    LinkEndpoint* link_;
    CycleFrames last_{};
};

}  // namespace cellguard

#endif  // CELLGUARD_SAFETY_OUTPUT_HPP
