// Requirements: the periodic CRC signature check of constant RAM blocks
// (the prior values, the zone membership mask) finds a changed byte within
// two passes, latches, and reads at most its slice per step.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "cellguard/ram_check.hpp"
#include "contract_capture.hpp"

using namespace cellguard;

// verifies: SR-CTRL-003, SR-CTRL-010
TEST_CASE("ram check: an unchanged block passes every pass, and the reference is the block's CRC-32") {
    std::vector<std::uint8_t> block(1000U);
    for (std::size_t i = 0; i < block.size(); ++i) block[i] = static_cast<std::uint8_t>(i * 7U + 3U);
    BlockSignatureCheck check(Span<const std::uint8_t>(block.data(), block.size()));
    CHECK(check.reference() == crc32(Span<const std::uint8_t>(block.data(), block.size())));
    CHECK(check.steps_per_pass(64U) == 16U);  // ceil(1000 / 64)
    for (int step = 0; step < 5 * 16; ++step) {
        CHECK_FALSE(check.step(64U));
        CHECK(check.position() == static_cast<std::size_t>((step + 1) % 16) * 64U);
    }
    CHECK_FALSE(check.failed());
}

// verifies: SR-CTRL-003, SR-CTRL-010
TEST_CASE("ram check: one flipped bit anywhere is found within two passes from any point of a pass, and stays found") {
    std::vector<std::uint8_t> block(300U, 0x5AU);
    const std::size_t slice = 32U;
    const std::size_t pass = (block.size() + slice - 1U) / slice;
    for (std::size_t start = 0; start < pass; ++start) {        // where in the pass the flip happens
        for (const std::size_t at : {std::size_t{0}, std::size_t{31}, std::size_t{32}, std::size_t{299}}) {
            BlockSignatureCheck check(Span<const std::uint8_t>(block.data(), block.size()));
            for (std::size_t k = 0; k < start; ++k) REQUIRE_FALSE(check.step(slice));
            block[at] ^= 0x10U;
            std::size_t steps = 0U;
            while (!check.step(slice)) {
                ++steps;
                REQUIRE(steps <= 2U * pass);
            }
            CHECK(steps < 2U * pass);
            block[at] ^= 0x10U;  // repaired: the verdict stays
            for (std::size_t k = 0; k < 2U * pass; ++k) CHECK(check.step(slice));
            CHECK(check.failed());
        }
    }
}

// verifies: SR-GEN-003
TEST_CASE("ram check: a slice of zero bytes violates the contract, an empty block never fails") {
    std::uint8_t b[4] = {1, 2, 3, 4};
    BlockSignatureCheck check{Span<const std::uint8_t>(b)};
    CHECK(test::violates_contract([&] { (void)check.step(0U); }));
    BlockSignatureCheck none;
    CHECK_FALSE(none.step(16U));
    CHECK(none.steps_per_pass(16U) == 0U);
    CHECK_FALSE(none.failed());
}
