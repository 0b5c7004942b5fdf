// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzz target: the robot image loader (certification/robot-image-format.md).
// No crash, no read outside the input (ASan: the image is copied into a heap
// buffer of exactly its size), a refusal always carries an error code and a
// reason, every accepted image re-encodes to the identical bytes and holds a
// model that passes check_robot_model, and forward kinematics, the robot
// mask and the work bound run on it without fault.
//
// Input: one mode byte, then the image bytes.
// - mode bit 0: recompute the CRC (the last four bytes, over all before
//   them) first, so mutations reach the checks behind it.
// - mode bit 1: also set the size field to the input's length, so
//   mutations of the counts reach the records.
// - mode bits 2..7: the joint positions' fraction of each joint's range
//   (0..63 of 63) for the kinematics.
// Seeds: tests/fuzz/corpus/fuzz_robot_image/ (the test arm's image, as is and
// with the CRC fix-up mode; a palletizer with mimic joints, format version 2).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "cellguard/base/crc32.hpp"
#include "cellguard/robot/kinematics.hpp"
#include "cellguard/robot/robot_image.hpp"
#include "cellguard/robot/robot_mask.hpp"

using namespace cellguard;

namespace {

void require_at(bool condition, int line) {
    if (!condition) {
        std::fprintf(stderr, "fuzz_robot_image: requirement at line %d failed\n", line);
        std::abort();
    }
}
#define require(condition) require_at((condition), __LINE__)

void put_u32(std::vector<std::uint8_t>& img, std::size_t offset, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i)
        img[offset + i] = static_cast<std::uint8_t>(v >> (8U * i));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1U) {
        return 0;
    }
    const std::uint8_t mode = data[0];
    std::vector<std::uint8_t> img(data + 1, data + size);

    if ((mode & 2U) != 0U && img.size() >= kRobotImageHeaderBytes) {
        put_u32(img, robot_image_layout::kImageSize, static_cast<std::uint32_t>(img.size()));
    }
    if ((mode & 3U) != 0U && img.size() >= 4U) {
        put_u32(img, img.size() - 4U, crc32(Span<const std::uint8_t>(img.data(), img.size() - 4U)));
    }

    const Result<LoadedRobot, RobotModelError> r = load_robot_image(Span<const std::uint8_t>(img.data(), img.size()));
    if (!r.ok()) {
        require(r.error().code != ErrorCode::kOk);
        require(r.error().reason != nullptr && r.error().reason[0] != '\0');
        return 0;
    }
    const RobotModel& model = r.value().model;
    require(is_no_error(check_robot_model(model)));
    require(img.size() == robot_image_size(model.link_count, model.capsule_count, robot_image_version(model)));
    require(r.value().crc == crc32(Span<const std::uint8_t>(img.data(), img.size() - 4U)));

    // Re-encode what was accepted: the bytes must come out identical.
    std::vector<std::uint8_t> again(kRobotImageMaxBytes);
    const Result<std::size_t, RobotModelError> w = write_robot_image(model,
                                                                     Span<std::uint8_t>(again.data(), again.size()));
    require(w.ok() && w.value() == img.size());
    require(std::memcmp(again.data(), img.data(), img.size()) == 0);

    // Place the robot somewhere in its joints' ranges and mark its voxels on a small grid.
    JointPositions q;
    q.count = model.joint_count;
    const double share = static_cast<double>(mode >> 2U) / 63.0;
    for (std::size_t i = 1; i < model.link_count; ++i) {
        const RobotLink& l = model.links[i];
        if (l.joint != JointType::kFixed && !l.mimic) {  // a mimic follows its master's position
            q.q[l.command_index] = l.lower + share * (l.upper - l.lower);
        }
    }
    RobotPose pose;
    place_robot(model, q, pose);
    require(pose.count == model.capsule_count);
    // Within the checked limits (+-100 rad, +-10 m) every position is finite; were one not, the mask would
    // refuse the pose and mark the whole grid.
    bool finite = true;
    for (std::size_t c = 0; c < pose.count; ++c) {
        for (int k = 0; k < 3; ++k) {
            finite = finite && std::isfinite(pose.capsules[c].a[k]) && std::isfinite(pose.capsules[c].b[k]);
        }
    }
    const GridGeometry g = GridGeometry::make(Eigen::Vector3d(-1.0, -1.0, 0.0), 0.1, GridDims{20, 20, 20}).value();
    std::vector<std::uint8_t> mask(g.voxel_count());
    RobotMaskStats stats;
    const Status m = mark_robot_voxels(g, pose, 0.05, Span<std::uint8_t>(mask.data(), mask.size()), stats);
    require(m.ok() == finite);
    if (m.ok()) {
        require(stats.tested <= robot_mask_work_bound(model, 0.05, 0.1));
    } else {
        require(stats.marked == g.voxel_count());
    }
    return 0;
}
