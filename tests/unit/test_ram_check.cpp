// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Requirements: the one periodic CRC signature check of constant memory (the
// prior values, the zone membership mask, the ray tables' regions) reads its
// regions as one stream, finds a changed byte within two passes, latches,
// and reads at most its slice per step.
#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/base/ram_check.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

namespace {

/// Region sizes with empty regions first, between and last: 59 bytes in all.
constexpr std::array<std::size_t, 7> kRegionSizes = {0U, 5U, 0U, 13U, 1U, 40U, 0U};

/// Separate buffers, one per region, and their concatenation.
struct Regions {
    std::array<std::vector<std::uint8_t>, kRegionSizes.size()> bytes;
    std::array<SignatureRegion, kRegionSizes.size()> views{};
    std::vector<std::uint8_t> stream;
    Regions() {
        for (std::size_t r = 0; r < bytes.size(); ++r) {
            bytes[r].resize(kRegionSizes[r]);
            for (std::size_t i = 0; i < bytes[r].size(); ++i) {
                bytes[r][i] = static_cast<std::uint8_t>(r * 31U + i * 7U + 1U);
                stream.push_back(bytes[r][i]);
            }
            views[r] = SignatureRegion(bytes[r].data(), bytes[r].size());
        }
    }
    [[nodiscard]] Span<const SignatureRegion> list() const { return {views.data(), views.size()}; }
};

}  // namespace

// verifies: SR-CTRL-003, SR-CTRL-010
TEST_CASE("ram check: an unchanged block passes every pass, and the reference is the block's CRC-32") {
    std::vector<std::uint8_t> block(1000U);
    for (std::size_t i = 0; i < block.size(); ++i)
        block[i] = static_cast<std::uint8_t>(i * 7U + 3U);
    SignatureCheck check(SignatureRegion(block.data(), block.size()));
    CHECK(check.reference() == crc32(SignatureRegion(block.data(), block.size())));
    CHECK(check.total_bytes() == 1000U);
    CHECK(check.steps_per_pass(64U) == 16U);  // ceil(1000 / 64)
    for (int step = 0; step < 5 * 16; ++step) {
        CHECK_FALSE(check.step(64U));
        CHECK(check.position() == static_cast<std::size_t>((step + 1) % 16) * 64U);
    }
    CHECK_FALSE(check.failed());
}

// verifies: SR-PRIOR-012, SR-FUSE-007
TEST_CASE(
    "ram check: regions are one stream: the reference is the CRC-32 of their concatenation and a slice runs across region boundaries") {
    const Regions r;
    REQUIRE(r.stream.size() == 59U);
    const SignatureCheck taken(r.list());
    CHECK(taken.reference() == crc32(SignatureRegion(r.stream.data(), r.stream.size())));
    CHECK(taken.total_bytes() == 59U);
    for (const std::size_t slice : {1U, 3U, 5U, 6U, 8U, 18U, 19U, 58U, 59U, 60U, 4096U}) {
        CAPTURE(slice);
        SignatureCheck check(r.list());
        const std::size_t steps = (59U + slice - 1U) / slice;
        CHECK(check.steps_per_pass(slice) == steps);
        for (int pass = 0; pass < 2; ++pass) {
            // Every step covers min(slice, bytes left) bytes; the pass ends
            // with exactly the last of its steps, and not before.
            for (std::size_t k = 1U; k <= steps; ++k) {
                CHECK_FALSE(check.step(slice));
                CHECK(check.position() == (k == steps ? 0U : k * slice));
            }
        }
        CHECK_FALSE(check.failed());
    }
}

// verifies: SR-FUSE-007
TEST_CASE("ram check: a reference given by the caller is used as given") {
    const Regions r;
    const std::uint32_t crc = crc32(SignatureRegion(r.stream.data(), r.stream.size()));
    SignatureCheck right(r.list(), crc);
    SignatureCheck wrong(r.list(), crc ^ 1U);
    CHECK(right.reference() == crc);
    CHECK(wrong.reference() == (crc ^ 1U));
    for (std::size_t k = 0; k + 1U < right.steps_per_pass(16U); ++k) {
        CHECK_FALSE(right.step(16U));
        CHECK_FALSE(wrong.step(16U));  // no verdict before the pass ends
    }
    CHECK_FALSE(right.step(16U));
    CHECK(wrong.step(16U));
}

// verifies: SR-CTRL-003, SR-CTRL-010, SR-PRIOR-012
TEST_CASE("ram check: one flipped bit anywhere is found within two passes from any point of a pass, and stays found") {
    std::vector<std::uint8_t> block(300U, 0x5AU);
    const std::size_t slice = 32U;
    const std::size_t pass = (block.size() + slice - 1U) / slice;
    for (std::size_t start = 0; start < pass; ++start) {  // where in the pass the flip happens
        for (const std::size_t at : {std::size_t{0}, std::size_t{31}, std::size_t{32}, std::size_t{299}}) {
            SignatureCheck check(SignatureRegion(block.data(), block.size()));
            for (std::size_t k = 0; k < start; ++k)
                REQUIRE_FALSE(check.step(slice));
            block[at] ^= 0x10U;
            std::size_t steps = 0U;
            while (!check.step(slice)) {
                ++steps;
                REQUIRE(steps <= 2U * pass);
            }
            CHECK(steps < 2U * pass);
            block[at] ^= 0x10U;  // repaired: the verdict stays
            for (std::size_t k = 0; k < 2U * pass; ++k)
                CHECK(check.step(slice));
            CHECK(check.failed());
        }
    }
}

// verifies: SR-PRIOR-012, SR-FUSE-007
TEST_CASE(
    "ram check: a flip in any region before a pass is found by the step that ends it, one behind the position by the end of the next") {
    for (const std::size_t slice : {1U, 7U, 16U, 59U}) {
        for (std::size_t region = 0; region < kRegionSizes.size(); ++region) {
            if (kRegionSizes[region] == 0U)
                continue;
            for (const std::size_t at : {std::size_t{0}, kRegionSizes[region] - 1U}) {
                CAPTURE(slice);
                CAPTURE(region);
                CAPTURE(at);
                Regions r;
                SignatureCheck check(r.list());
                const std::size_t pass = check.steps_per_pass(slice);
                r.bytes[region][at] ^= 0x01U;  // before the pass: found by its last step
                for (std::size_t k = 0; k + 1U < pass; ++k)
                    CHECK_FALSE(check.step(slice));
                CHECK(check.step(slice));
                r.bytes[region][at] ^= 0x01U;

                // Behind the position: flipped after the pass read it, so this
                // pass ends intact and the next one's last step reports it.
                std::size_t offset = at;  // in the stream
                for (std::size_t q = 0; q < region; ++q)
                    offset += kRegionSizes[q];
                SignatureCheck behind(r.list());
                std::size_t taken = 0U;
                while (behind.position() <= offset) {
                    REQUIRE_FALSE(behind.step(slice));
                    ++taken;
                    if (behind.position() == 0U)
                        break;  // read by the pass's last step: the case above
                }
                if (behind.position() == 0U)
                    continue;
                r.bytes[region][at] ^= 0x01U;
                std::size_t calls = 1U;
                while (!behind.step(slice)) {
                    ++calls;
                    REQUIRE(calls <= 2U * pass);
                }
                CHECK(calls == (pass - taken) + pass);
            }
        }
    }
}

// verifies: SR-GEN-003
TEST_CASE(
    "ram check: a slice of zero bytes or more regions than kMaxSignatureRegions violates the contract, an empty check never fails") {
    std::uint8_t b[4] = {1, 2, 3, 4};
    SignatureCheck check{SignatureRegion(b)};
    CHECK(test::violates_contract([&] { (void)check.step(0U); }));
    CHECK(test::violates_contract([&] { (void)check.steps_per_pass(0U); }));

    std::array<SignatureRegion, kMaxSignatureRegions + 1U> many{};
    for (SignatureRegion& region : many)
        region = SignatureRegion(b);
    CHECK(
        test::violates_contract([&] { (void)SignatureCheck(Span<const SignatureRegion>(many.data(), many.size())); }));
    CHECK(test::violates_contract(
        [&] { (void)SignatureCheck(Span<const SignatureRegion>(many.data(), many.size()), 0U); }));
    const SignatureCheck full(
        Span<const SignatureRegion>(many.data(), kMaxSignatureRegions));  // the capacity itself is fine
    CHECK(full.total_bytes() == 4U * kMaxSignatureRegions);

    SignatureCheck none;
    CHECK_FALSE(none.step(16U));
    CHECK(none.steps_per_pass(16U) == 0U);
    CHECK_FALSE(none.failed());
    SignatureCheck empty_regions(Span<const SignatureRegion>(many.data(), 0U), 0x1234U);  // nothing to read: no verdict
    CHECK_FALSE(empty_regions.step(16U));
    CHECK(empty_regions.position() == 0U);
}

// verifies: SR-CTRL-007
TEST_CASE("ram check: a check reads exactly the regions it was made of, by address and size") {
    Regions r;
    const SignatureCheck check(r.list());
    CHECK(check.reads(r.list()));
    std::array<SignatureRegion, kRegionSizes.size()> moved = r.views;
    moved[3] = SignatureRegion(r.bytes[3].data() + 1, r.bytes[3].size() - 1U);  // shorter
    CHECK_FALSE(check.reads(Span<const SignatureRegion>(moved.data(), moved.size())));
    moved = r.views;
    const std::vector<std::uint8_t> copy = r.bytes[5];
    moved[5] = SignatureRegion(copy.data(), copy.size());  // same bytes elsewhere
    CHECK_FALSE(check.reads(Span<const SignatureRegion>(moved.data(), moved.size())));
    CHECK_FALSE(check.reads(Span<const SignatureRegion>(r.views.data(), r.views.size() - 1U)));  // fewer
}

// verifies: SR-GEN-002
TEST_CASE("ram check: making and stepping a check allocates nothing") {
    const Regions r;
    const test::AllocationScope scope;
    SignatureCheck check(r.list());
    bool failed = false;
    for (int i = 0; i < 1000; ++i)
        failed = check.step(16U) || failed;
    CHECK(scope.allocations() == 0U);
    CHECK_FALSE(failed);
}

// verifies: SR-CTRL-007
TEST_CASE("ram check: a region at the same address but of another size is not a region the check reads") {
    Regions r;
    const SignatureCheck check(r.list());
    std::array<SignatureRegion, kRegionSizes.size()> resized = r.views;
    resized[2] = SignatureRegion(r.bytes[2].data(), r.bytes[2].size() - 1U);
    CHECK_FALSE(check.reads(Span<const SignatureRegion>(resized.data(), resized.size())));
    resized[2] = r.views[2];
    CHECK(check.reads(Span<const SignatureRegion>(resized.data(), resized.size())));
}
