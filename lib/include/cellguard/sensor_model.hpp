/// @file sensor_model.hpp
/// The paper's parametric 1-D sensor evidence profile along each ray, turned
/// once into an integer lookup table so that fusion does no floating point
/// per voxel beyond one distance comparison.
///
/// The profile (our reading of the paper's "peak 0.56 at the reading, trough
/// 0.44 at the sensor origin", Moravec-style). For a ray from the sensor
/// origin to a reading at range R, a voxel whose segment part ends at t_exit
/// (metres from the origin) gets:
/// - the voxel holding the reading (the last voxel of the segment: t_enter
///   <= R <= t_exit): P(occ) = p_reading (0.56), "at the reading";
/// - every voxel before it with d = R - t_exit >= ramp_length:
///   P(occ) = p_origin (0.44), the constant part of the profile;
/// - a voxel before it within ramp_length of the reading: P(occ) rises
///   linearly in d from p_origin (at d = ramp_length) to 0.5 (at d = 0), so
///   space just in front of a surface is not called free with full weight,
///   and no voxel other than the reading's gets occupied evidence (surfaces
///   do not thicken when many frames are summed);
/// - past the reading: nothing (the segment ends at the reading; those
///   voxels stay unobserved unless another ray sees them).
/// The ramp is tabulated in kRampSteps steps of ramp_length / kRampSteps;
/// a voxel uses the entry of floor(d / step), i.e. the value at the far end
/// of its step (rounding towards the free end by at most one step).
#ifndef CELLGUARD_SENSOR_MODEL_HPP
#define CELLGUARD_SENSOR_MODEL_HPP

#include <cstdint>

#include "cellguard/result.hpp"

namespace cellguard {

/// Parameters of the 1-D evidence profile; defaults are the paper's values
/// with a ramp of 10 cm (two of the paper's voxels).
struct SensorModelParams {
    double p_origin = 0.44;     ///< P(occ) of free space from the sensor origin up to the ramp (the trough)
    double p_reading = 0.56;    ///< P(occ) of the voxel holding the reading (the peak)
    double ramp_length = 0.10;  ///< metres before the reading over which P(occ) rises from p_origin to 0.5
};

/// Number of tabulated steps of the ramp.
constexpr std::int32_t kRampSteps = 32;

/// The integer form of a sensor model, built once by make().
class SensorModelTable {
public:
    /// A table of the default parameters.
    SensorModelTable() noexcept;

    /// Validates @p params and tabulates them. Errors: kNonFiniteValue,
    /// kInvalidArgument unless 0 < p_origin < 0.5 < p_reading < 1 and
    /// 0 <= ramp_length <= 10 m.
    static Result<SensorModelTable> make(const SensorModelParams& params) noexcept;

    /// Log-odds added to a voxel at distance @p d_before (metres, >= 0)
    /// before the reading, measured from the voxel's exit point.
    [[nodiscard]] std::int16_t free_evidence(double d_before) const noexcept {
        if (d_before >= ramp_length_) {
            return free_;
        }
        const double scaled = (d_before > 0.0 ? d_before : 0.0) * steps_per_metre_;
        const auto step = static_cast<std::int32_t>(scaled);
        return ramp_[step < kRampSteps ? step : kRampSteps - 1];
    }
    /// Log-odds of the constant part (p_origin).
    [[nodiscard]] std::int16_t constant_free_evidence() const noexcept { return free_; }
    /// Log-odds added to the voxel holding the reading (p_reading).
    [[nodiscard]] std::int16_t reading_evidence() const noexcept { return reading_; }
    /// Length of the ramp, metres.
    [[nodiscard]] double ramp_length() const noexcept { return ramp_length_; }
    /// The parameters the table was built from.
    [[nodiscard]] const SensorModelParams& params() const noexcept { return params_; }

private:
    void tabulate(const SensorModelParams& params) noexcept;
    SensorModelParams params_{};
    double ramp_length_ = 0.0;
    double steps_per_metre_ = 0.0;
    std::int16_t free_ = 0;
    std::int16_t reading_ = 0;
    std::int16_t ramp_[kRampSteps] = {};
};

}  // namespace cellguard

#endif  // CELLGUARD_SENSOR_MODEL_HPP
