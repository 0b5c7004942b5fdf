// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
/* The firmware's generated data, embedded byte for byte from
 * apps/firmware/generated/ (written by cellguard-firmware-gen): the same
 * files on every target (x86-64, aarch64, Cortex-M7). Declared for C++ in
 * embedded_data.hpp. The build passes the folder to the assembler
 * (-Wa,-I, apps/firmware/CMakeLists.txt), which resolves .incbin there.
 *
 * Read-only (.rodata: flash on the MCU), 16-byte aligned, each blob a
 * sized object symbol with its size as a u32 next to it. The prior image's
 * payload (its int16 values, from byte 88 = kPriorImageHeaderSize on) gets a
 * second symbol on the same bytes, not a copy: the controller reads the
 * values in place; run_scenario checks that this symbol is the payload
 * load_prior_image found. The frames blob likewise gets a second symbol at
 * its start for its binary32 depth images. The robot-cell run's three
 * files (robot.cgrobot, robot_prior.cgprior, robot_frames.bin) likewise. */

    .section .rodata.cellguard_firmware_prior, "a", %progbits
    .balign 16
    .global cellguard_firmware_prior_image
    .type cellguard_firmware_prior_image, %object
cellguard_firmware_prior_image:
    .incbin "prior.cgprior"
.Lprior_end:
    .size cellguard_firmware_prior_image, .Lprior_end - cellguard_firmware_prior_image

    .global cellguard_firmware_prior_values
    .type cellguard_firmware_prior_values, %object
    .set cellguard_firmware_prior_values, cellguard_firmware_prior_image + 88
    .size cellguard_firmware_prior_values, .Lprior_end - cellguard_firmware_prior_values

    .balign 4
    .global cellguard_firmware_prior_image_size
    .type cellguard_firmware_prior_image_size, %object
cellguard_firmware_prior_image_size:
    .4byte .Lprior_end - cellguard_firmware_prior_image
    .size cellguard_firmware_prior_image_size, 4

    .section .rodata.cellguard_firmware_frames, "a", %progbits
    .balign 16
    .global cellguard_firmware_frames
    .type cellguard_firmware_frames, %object
cellguard_firmware_frames:
    .incbin "frames.bin"
.Lframes_end:
    .size cellguard_firmware_frames, .Lframes_end - cellguard_firmware_frames

    .global cellguard_firmware_frames_f32
    .type cellguard_firmware_frames_f32, %object
    .set cellguard_firmware_frames_f32, cellguard_firmware_frames
    .size cellguard_firmware_frames_f32, .Lframes_end - cellguard_firmware_frames

    .balign 4
    .global cellguard_firmware_frames_size
    .type cellguard_firmware_frames_size, %object
cellguard_firmware_frames_size:
    .4byte .Lframes_end - cellguard_firmware_frames
    .size cellguard_firmware_frames_size, 4

    /* The robot-cell run (robot_scenario.hpp): the demo arm's robot image,
     * the robot cell's prior (payload symbol as above) and its frames. */
    .section .rodata.cellguard_firmware_robot, "a", %progbits
    .balign 16
    .global cellguard_firmware_robot_image
    .type cellguard_firmware_robot_image, %object
cellguard_firmware_robot_image:
    .incbin "robot.cgrobot"
.Lrobot_end:
    .size cellguard_firmware_robot_image, .Lrobot_end - cellguard_firmware_robot_image

    .balign 4
    .global cellguard_firmware_robot_image_size
    .type cellguard_firmware_robot_image_size, %object
cellguard_firmware_robot_image_size:
    .4byte .Lrobot_end - cellguard_firmware_robot_image
    .size cellguard_firmware_robot_image_size, 4

    .section .rodata.cellguard_firmware_robot_prior, "a", %progbits
    .balign 16
    .global cellguard_firmware_robot_prior_image
    .type cellguard_firmware_robot_prior_image, %object
cellguard_firmware_robot_prior_image:
    .incbin "robot_prior.cgprior"
.Lrobot_prior_end:
    .size cellguard_firmware_robot_prior_image, .Lrobot_prior_end - cellguard_firmware_robot_prior_image

    .global cellguard_firmware_robot_prior_values
    .type cellguard_firmware_robot_prior_values, %object
    .set cellguard_firmware_robot_prior_values, cellguard_firmware_robot_prior_image + 88
    .size cellguard_firmware_robot_prior_values, .Lrobot_prior_end - cellguard_firmware_robot_prior_values

    .balign 4
    .global cellguard_firmware_robot_prior_image_size
    .type cellguard_firmware_robot_prior_image_size, %object
cellguard_firmware_robot_prior_image_size:
    .4byte .Lrobot_prior_end - cellguard_firmware_robot_prior_image
    .size cellguard_firmware_robot_prior_image_size, 4

    .section .rodata.cellguard_firmware_robot_frames, "a", %progbits
    .balign 16
    .global cellguard_firmware_robot_frames
    .type cellguard_firmware_robot_frames, %object
cellguard_firmware_robot_frames:
    .incbin "robot_frames.bin"
.Lrobot_frames_end:
    .size cellguard_firmware_robot_frames, .Lrobot_frames_end - cellguard_firmware_robot_frames

    .global cellguard_firmware_robot_frames_f32
    .type cellguard_firmware_robot_frames_f32, %object
    .set cellguard_firmware_robot_frames_f32, cellguard_firmware_robot_frames
    .size cellguard_firmware_robot_frames_f32, .Lrobot_frames_end - cellguard_firmware_robot_frames

    .balign 4
    .global cellguard_firmware_robot_frames_size
    .type cellguard_firmware_robot_frames_size, %object
cellguard_firmware_robot_frames_size:
    .4byte .Lrobot_frames_end - cellguard_firmware_robot_frames
    .size cellguard_firmware_robot_frames_size, 4

#if defined(__linux__)
    /* No executable stack on the Linux hosts (bare metal has no such note). */
    .section .note.GNU-stack, "", %progbits
#endif
