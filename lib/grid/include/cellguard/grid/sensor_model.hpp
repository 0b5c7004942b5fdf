// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/// @file sensor_model.hpp
/// The sensor model: what one sensor's frame says about each voxel, turned
/// once into integer log-odds so that fusion does no floating point per voxel
/// beyond one distance comparison.
///
/// One opinion per sensor, voxel and frame (OctoMap's "at most one update per
/// scan, occupied wins"), whatever the number of the sensor's rays that reach
/// the voxel. For the rays of one sensor's frame, a voxel gets:
/// - p_hit when it holds at least one valid reading of that sensor: however
///   many other rays of the frame cross it;
/// - otherwise, when rays cross it on the way to their readings, the free
///   profile of the ray that leaves it nearest to its reading: p_miss when
///   that ray's reading lies at least ramp_length beyond the point where the
///   ray leaves the voxel (d = R - t_exit >= ramp_length), rising linearly in
///   d to 0.5 at d = 0 within the ramp, so space just in front of a surface
///   is not called free with full weight;
/// - otherwise nothing (the sensor did not observe it; past a reading the
///   ray ends).
/// The opinions of one frame's sensors are then pooled (pool()): a voxel
/// that any sensor saw occupied is occupied, with the hits of the sensors
/// that saw it added; only a voxel that no sensor saw occupied takes the sum
/// of the free opinions. The pooled value is clamped to
/// [logit(p_clamp_min), logit(p_clamp_max)], so a frame's evidence is bounded
/// whatever the number of sensors (OctoMap states its clamping the same way).
/// Every rule is a maximum or a sum of same-signed terms: the result does not
/// depend on the order of the rays or of the sensors.
///
/// The ramp is tabulated in kRampSteps steps of ramp_length / kRampSteps;
/// a voxel uses the entry of floor(d / step), i.e. the value at the far end
/// of its step (rounding towards the free end by at most one step).
#ifndef CELLGUARD_SENSOR_MODEL_HPP
#define CELLGUARD_SENSOR_MODEL_HPP

#include <cstdint>

#include "cellguard/base/result.hpp"

namespace cellguard {

/// Parameters of the sensor model, as probabilities (see the file comment).
/// The defaults (0.30 / 0.90, clamped to [0.12, 0.97], ramp 10 cm) are
/// chosen with the accessibility prior (certification/requirements.md,
/// SR-FUSE-005): one sensor's hit in accessible space is foreground at the
/// default t_f, the pooled hits of every sensor stay below the prior's
/// background term, and seen-free space falls below t_E = 0.1 in G_B.
struct SensorModelParams {
    double p_miss = 0.30;  ///< P(occ) of a voxel the sensor's rays cross, at least ramp_length before their readings
    double p_hit = 0.90;   ///< P(occ) of a voxel holding at least one of the sensor's valid readings
    double ramp_length = 0.10;  ///< metres before the reading over which P(occ) rises from p_miss to 0.5
    double p_clamp_min = 0.12;  ///< lower clamp of a voxel's pooled frame evidence
    double p_clamp_max = 0.97;  ///< upper clamp of a voxel's pooled frame evidence
};

/// Number of tabulated steps of the ramp.
constexpr std::int32_t kRampSteps = 32;

/// The integer form of a sensor model, built once by make().
class SensorModelTable {
public:
    /// A table of the default parameters.
    SensorModelTable() noexcept;

    /// Validates @p params and tabulates them. Errors: kNonFiniteValue,
    /// kInvalidArgument unless 0 < p_clamp_min <= p_miss < 0.5 < p_hit <=
    /// p_clamp_max < 1 and 0 <= ramp_length <= 10 m.
    static Result<SensorModelTable> make(const SensorModelParams& params) noexcept;

    /// A sensor's free opinion of a voxel that one of its rays leaves
    /// @p d_before metres (>= 0) before its reading.
    [[nodiscard]] std::int16_t free_evidence(double d_before) const noexcept {
        if (d_before >= ramp_length_) {
            return free_;
        }
        const double scaled = (d_before > 0.0 ? d_before : 0.0) * steps_per_metre_;
        const auto step = static_cast<std::int32_t>(scaled);
        return ramp_[step < kRampSteps ? step : kRampSteps - 1];
    }
    /// Log-odds of the constant part (p_miss).
    [[nodiscard]] std::int16_t constant_free_evidence() const noexcept { return free_; }
    /// A sensor's opinion of a voxel holding at least one of its readings (p_hit).
    [[nodiscard]] std::int16_t reading_evidence() const noexcept { return reading_; }
    /// Length of the ramp, metres.
    [[nodiscard]] double ramp_length() const noexcept { return ramp_length_; }
    /// Pools one sensor's @p opinion of a voxel (a value of free_evidence or
    /// reading_evidence) into the @p pooled opinion of the frame's other
    /// sensors (0 when none observed it). Occupied wins: any hit makes the
    /// voxel occupied, hits add up, and free opinions add up only while no
    /// sensor hit. Clamped to [pooled_min(), pooled_max()]. Commutative and
    /// associative over the sensors of one frame.
    [[nodiscard]] std::int16_t pool(std::int16_t pooled, std::int16_t opinion) const noexcept {
        const std::int32_t sum = static_cast<std::int32_t>(pooled) + opinion;
        const std::int32_t v = opinion > 0 ? (pooled > 0 ? sum : opinion) : (pooled > 0 ? pooled : sum);
        return static_cast<std::int16_t>(v < pooled_min_ ? pooled_min_ : v > pooled_max_ ? pooled_max_ : v);
    }
    /// Lower clamp of a pooled opinion (p_clamp_min), log-odds.
    [[nodiscard]] std::int16_t pooled_min() const noexcept { return pooled_min_; }
    /// Upper clamp of a pooled opinion (p_clamp_max), log-odds.
    [[nodiscard]] std::int16_t pooled_max() const noexcept { return pooled_max_; }
    /// The parameters the table was built from.
    [[nodiscard]] const SensorModelParams& params() const noexcept { return params_; }

private:
    void tabulate(const SensorModelParams& params) noexcept;
    SensorModelParams params_{};
    double ramp_length_ = 0.0;
    double steps_per_metre_ = 0.0;
    std::int16_t free_ = 0;
    std::int16_t reading_ = 0;
    std::int16_t pooled_min_ = 0;
    std::int16_t pooled_max_ = 0;
    std::int16_t ramp_[kRampSteps] = {};
};

}  // namespace cellguard

#endif  // CELLGUARD_SENSOR_MODEL_HPP
