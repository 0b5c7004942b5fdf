// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// envelope_capsule() of stroke_envelope.hpp: a capsule over a gripper's stroke.
#include "cellguard/host/io/stroke_envelope.hpp"

#include <algorithm>
#include <cmath>

namespace cellguard::host {

namespace {

/// The variables @p chain uses, in first-use order.
std::vector<std::size_t> used_variables(const std::vector<StrokeStep>& chain) {
    std::vector<std::size_t> used;
    for (const StrokeStep& step : chain) {
        if (step.type != JointType::kFixed && std::find(used.begin(), used.end(), step.variable) == used.end()) {
            used.push_back(step.variable);
        }
    }
    return used;
}

/// Largest |position| a movable step takes over its variable's range.
double largest_travel(const StrokeStep& step, const StrokeRange& range) {
    return std::max(std::abs(step.multiplier * range.lower + step.offset),
                    std::abs(step.multiplier * range.upper + step.offset));
}

/// A bound, valid in every pose, on |p - origin of the child frame of step
/// @p j|, p being @p local in the last link's frame: the later origins'
/// lengths, the later prismatic travels and |local|.
double reach_after(const std::vector<StrokeStep>& chain, const std::vector<StrokeRange>& ranges, std::size_t j,
                   const Eigen::Vector3d& local) {
    double reach = local.norm();
    for (std::size_t k = j + 1U; k < chain.size(); ++k) {
        reach += chain[k].origin.translation().norm();
        if (chain[k].type == JointType::kPrismatic) {
            reach += largest_travel(chain[k], ranges[chain[k].variable]);
        }
    }
    return reach;
}

/// How far @p local (last link's frame) can move between neighbouring grid
/// points whose variables step by @p steps.
double movement_between(const std::vector<StrokeStep>& chain, const std::vector<StrokeRange>& ranges,
                        const std::vector<double>& steps, const Eigen::Vector3d& local) {
    double delta = 0.0;
    for (std::size_t j = 0U; j < chain.size(); ++j) {
        const StrokeStep& step = chain[j];
        if (step.type == JointType::kFixed) {
            continue;
        }
        const double speed = step.type == JointType::kPrismatic ? 1.0 : reach_after(chain, ranges, j, local);
        delta += 0.5 * steps[step.variable] * std::abs(step.multiplier) * speed;
    }
    return delta;
}

IoStatus check_ranges(const std::vector<StrokeStep>& chain, const std::vector<StrokeRange>& ranges, std::size_t used) {
    if (used > kMaxStrokeVariables) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%zu stroke joints move one capsule, at most %zu", used,
                                 kMaxStrokeVariables);
    }
    for (const StrokeStep& step : chain) {
        if (step.type == JointType::kFixed) {
            continue;
        }
        if (step.variable >= ranges.size()) {
            return IoStatus::failure(ErrorCode::kInvalidArgument, "stroke variable %zu of %zu", step.variable,
                                     ranges.size());
        }
        const StrokeRange& r = ranges[step.variable];
        if (!std::isfinite(r.lower) || !std::isfinite(r.upper) || r.lower > r.upper ||
            !std::isfinite(step.multiplier) || !std::isfinite(step.offset)) {
            return IoStatus::failure(ErrorCode::kInvalidArgument, "stroke range %g .. %g (x %g + %g) is not usable",
                                     r.lower, r.upper, step.multiplier, step.offset);
        }
    }
    return {};
}

}  // namespace

std::size_t stroke_samples(std::size_t variables) noexcept {
    switch (variables) {
        case 0U: return 1U;
        case 1U: return 1025U;
        case 2U: return 129U;
        default: return 33U;
    }
}

Eigen::Isometry3d stroke_pose(const std::vector<StrokeStep>& chain, const std::vector<double>& v) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (const StrokeStep& step : chain) {
        pose = pose * step.origin;
        if (step.type == JointType::kFixed) {
            continue;
        }
        const double q = step.multiplier * v[step.variable] + step.offset;
        if (step.type == JointType::kRevolute) {
            pose.rotate(Eigen::AngleAxisd(q, step.axis));
        } else {
            pose.translate(q * step.axis);
        }
    }
    return pose;
}

IoStatus envelope_capsule(const std::vector<StrokeStep>& chain, const std::vector<StrokeRange>& ranges,
                          const Capsule& capsule, StrokeEnvelope& out) {
    out = StrokeEnvelope{};
    const std::vector<std::size_t> used = used_variables(chain);
    if (const IoStatus st = check_ranges(chain, ranges, used.size()); !st) {
        return st;
    }
    const std::size_t n = stroke_samples(used.size());
    std::vector<double> steps(ranges.size(), 0.0);
    for (const std::size_t u : used) {
        steps[u] = (ranges[u].upper - ranges[u].lower) / static_cast<double>(n - 1U);
    }
    std::size_t poses = 1U;
    for (std::size_t k = 0U; k < used.size(); ++k) {
        poses *= n;
    }
    std::vector<Eigen::Vector3d> ends;
    ends.reserve(2U * poses);
    std::vector<double> v(ranges.size(), 0.0);
    for (std::size_t index = 0U; index < poses; ++index) {
        std::size_t rest = index;
        for (const std::size_t u : used) {
            const std::size_t i = rest % n;
            rest /= n;
            v[u] = i + 1U == n ? ranges[u].upper : ranges[u].lower + static_cast<double>(i) * steps[u];
        }
        const Eigen::Isometry3d pose = stroke_pose(chain, v);
        ends.push_back(pose * capsule.a);
        ends.push_back(pose * capsule.b);
    }
    Capsule c = bounding_capsule(ends);
    out.sample_radius = c.radius;
    out.between = std::max(movement_between(chain, ranges, steps, capsule.a),
                           movement_between(chain, ranges, steps, capsule.b));
    c.radius += out.between + capsule.radius;
    out.capsule = c;
    out.poses = poses;
    return {};
}

}  // namespace cellguard::host
