// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// A consumer of the cellguard package (tests/consumer/CMakeLists.txt): it
// maps a point into the paper's grid, encodes a safety frame, checks that it decodes to the same message, brings
// a PLC-side receiver up with frame pairs and checks it accepts the "no stop"
// message, and uses a dynamic-size Eigen matrix of its own (which
// EIGEN_NO_MALLOC, lib/'s private flag, would turn into an assertion failure
// in this Debug build); with cellguard::port_linux, it reads the port's
// clock. Exit status 0 exactly when every check passed.
#include <Eigen/Dense>
#include <cstdint>
#include <cstdio>

#include "cellguard/can/plc_receiver.hpp"
#include "cellguard/can/safety_frame.hpp"
#include "cellguard/grid/grid.hpp"
#if CELLGUARD_CONSUMER_PORT_LINUX
#include "cellguard/port/clock.hpp"
#endif

#ifdef EIGEN_NO_MALLOC
#error "EIGEN_NO_MALLOC reached a consumer: it must stay private to cellguard's lib/"
#endif
#if !defined(EIGEN_MAX_STATIC_ALIGN_BYTES) || EIGEN_MAX_STATIC_ALIGN_BYTES != 16
#error "EIGEN_MAX_STATIC_ALIGN_BYTES=16 (part of lib/'s ABI) did not reach the consumer"
#endif

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) {
        ++failures;
    }
}

}  // namespace

int main() {
    using namespace cellguard;

    // The paper's grid: 34 x 30 x 30 voxels of 5 cm from (-0.85, -0.75, 0).
    const Result<GridGeometry> grid = GridGeometry::make(Eigen::Vector3d(-0.85, -0.75, 0.0), 0.05,
                                                         GridDims{34, 30, 30});
    check(grid.ok() && grid.value().voxel_count() == 34U * 30U * 30U, "GridGeometry::make builds the paper's grid");
    if (grid.ok()) {
        const Result<VoxelCoord> v = grid.value().world_to_voxel(Eigen::Vector3d(0.01, 0.01, 0.51));
        check(v.ok() && v.value().x == 17 && v.value().y == 15 && v.value().z == 10, "a point maps to its voxel");
        check(!grid.value().world_to_voxel(Eigen::Vector3d(0.0, 0.0, 2.0)).ok(), "a point outside is refused");
    }

    SafetyMessage clear;
    clear.protective_stop = false;
    clear.zone_count = 4U;
    clear.zone_unseen = 0x2U;

    PlcReceiverConfig config;
    config.expected_zone_count = 4U;
    // Session link off: this consumer check feeds protocol 0.1 pairs only
    config.link.enabled = false;
    check(PlcReceiver::check_config(config).ok(), "the receiver configuration is valid");

    const Result<CanFrame> encoded = encode_safety_frame(clear, 0U, config.channel);
    check(encoded.ok(), "encode_safety_frame succeeds");
    if (encoded.ok()) {
        const Result<SafetyFrameContent> decoded = decode_safety_frame(encoded.value(), config.channel);
        check(decoded.ok() && decoded.value().message == clear && decoded.value().counter == 0U,
              "decode_safety_frame gives back the message and counter");
        CanFrame corrupted = encoded.value();
        corrupted.data[3] ^= 0x10U;
        check(!decode_safety_frame(corrupted, config.channel).ok(), "a corrupted frame is refused");
    }

    // Frame pairs every 10 ms, the inverted copy 1 ms after its frame.
    PlcReceiver receiver(config);
    std::uint64_t now_us = 1000000U;
    std::uint8_t counter = 0U;
    ReceiverStatus status = receiver.poll(now_us);
    check(status.stop_requested && !status.communication_valid, "before any frame the receiver requests a stop");
    for (int pair = 0; pair < 10 && !status.communication_valid; ++pair) {
        const Result<CanFrame> frame = encode_safety_frame(clear, counter, config.channel);
        if (!frame.ok()) {
            break;
        }
        counter = e2e_p01_next_counter(counter);
        now_us += 10000U;
        (void)receiver.on_frame(frame.value(), now_us);
        now_us += 1000U;
        status = receiver.on_frame(inverted_copy(frame.value()), now_us);
    }
    check(status.communication_valid && !status.stop_requested && status.message == clear,
          "the receiver accepts the frame pairs and requests no stop");

    // The consumer's own heap-allocating Eigen code.
    Eigen::MatrixXd m = Eigen::MatrixXd::Identity(5, 5) * 2.0;
    m.conservativeResize(6, 6);
    m.row(5).setZero();
    m.col(5).setZero();
    m(5, 5) = 3.0;
    check(m.determinant() > 95.9 && m.determinant() < 96.1, "a dynamic-size Eigen matrix works in the consumer");

#if CELLGUARD_CONSUMER_PORT_LINUX
    // The Linux port's monotonic clock (cellguard::port_linux).
    linux_port::LinuxMonotonicClock clock;
    const std::uint64_t t0 = clock.now_us();
    std::uint64_t t1 = t0;
    for (int i = 0; i < 1000000 && t1 == t0; ++i) {
        t1 = clock.now_us();
    }
    check(t1 > t0, "the Linux port's monotonic clock advances");
#else
    std::printf("note: no cellguard::port_linux in this package\n");
#endif

    std::printf("%s\n", failures == 0 ? "consumer: PASS" : "consumer: FAIL");
    return failures == 0 ? 0 : 1;
}
