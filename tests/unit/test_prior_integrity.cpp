// Requirements: run-time re-verification of the prior image in bounded slices; detection, latching, work bound.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "cellguard/log_odds.hpp"
#include "cellguard/prior_image.hpp"
#include "cellguard/prior_integrity.hpp"

using namespace cellguard;

namespace {

GridGeometry geometry() { return GridGeometry::make(Eigen::Vector3d(0.0, 0.0, 0.0), 0.05, GridDims{5, 4, 3}).value(); }

// A valid image of 88 + 120 = 208 bytes.
std::vector<std::uint8_t> image() {
    const GridGeometry g = geometry();
    std::vector<std::int16_t> prior(g.voxel_count());
    for (std::size_t i = 0; i < prior.size(); ++i) {
        prior[i] = i % 3U == 0U ? kNeverForeground : static_cast<std::int16_t>(-static_cast<int>(i) * 11);
    }
    std::vector<std::uint8_t> out(prior_image_size(prior.size()));
    REQUIRE(write_prior_image(g, AccessibilityParams{}, Span<const std::int16_t>(prior.data(), prior.size()),
                              Span<std::uint8_t>(out.data(), out.size()))
                .ok());
    return out;
}

PriorImageView view_of(const std::vector<std::uint8_t>& img) {
    const Result<PriorImageView> v = load_prior_image(Span<const std::uint8_t>(img.data(), img.size()), geometry());
    REQUIRE(v.ok());
    return v.value();
}

// Runs one full pass; returns the status after each step.
std::vector<PriorIntegrityStatus> run_pass(PriorIntegrityMonitor& m) {
    std::vector<PriorIntegrityStatus> s;
    for (std::size_t i = 0; i < m.steps_per_pass(); ++i) s.push_back(m.step());
    return s;
}

}  // namespace

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: steps per pass is ceil(image size / slice)") {
    CHECK(prior_integrity_steps_per_pass(208, 1) == 208U);
    CHECK(prior_integrity_steps_per_pass(208, 7) == 30U);
    CHECK(prior_integrity_steps_per_pass(208, 104) == 2U);
    CHECK(prior_integrity_steps_per_pass(208, 207) == 2U);
    CHECK(prior_integrity_steps_per_pass(208, 208) == 1U);
    CHECK(prior_integrity_steps_per_pass(208, 1000) == 1U);
    CHECK(prior_integrity_steps_per_pass(61288, 1024) == 60U);
    CHECK(prior_integrity_steps_per_pass(208, 0) == 0U);

    const std::vector<std::uint8_t> img = image();
    REQUIRE(img.size() == 208U);
    for (const std::size_t slice : {1U, 4U, 7U, 83U, 84U, 88U, 89U, 100U, 207U, 208U, 209U, 4096U}) {
        PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), slice).value();
        const std::size_t expected = (img.size() + slice - 1U) / slice;
        CHECK(m.steps_per_pass() == expected);
        // The pass ends exactly after that many steps: the counter moves then and not before.
        for (std::size_t i = 0; i + 1U < expected; ++i) {
            CHECK(m.step() == PriorIntegrityStatus::kOk);
            CHECK(m.passes_completed() == 0U);
        }
        CHECK(m.step() == PriorIntegrityStatus::kOk);
        CHECK(m.passes_completed() == 1U);
        CHECK(m.position() == 0U);
    }
}

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: every step covers exactly min(slice, bytes left) bytes and a pass covers the image once") {
    const std::vector<std::uint8_t> img = image();
    for (const std::size_t slice : {1U, 5U, 64U, 85U, 208U, 500U}) {
        PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), slice).value();
        CHECK(m.last_step_bytes() == 0U);
        for (int pass = 0; pass < 2; ++pass) {
            std::size_t covered = 0;
            for (std::size_t i = 0; i < m.steps_per_pass(); ++i) {
                const std::size_t left = img.size() - covered;
                CHECK(m.position() == covered);
                (void)m.step();
                CHECK(m.last_step_bytes() == (slice < left ? slice : left));
                CHECK(m.last_step_bytes() <= m.slice_bytes());
                covered += m.last_step_bytes();
            }
            CHECK(covered == img.size());
        }
        CHECK(m.passes_completed() == 2U);
        CHECK(m.status() == PriorIntegrityStatus::kOk);
    }
}

// verifies: SR-PRIOR-012, SR-GEN-002
TEST_CASE("prior integrity: an intact image stays ok pass after pass, without allocating") {
    const std::vector<std::uint8_t> img = image();
    PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), 16).value();
    CHECK(m.status() == PriorIntegrityStatus::kOk);  // verified by the loader at start-up
    const test::AllocationScope scope;
    bool all_ok = true;
    for (int i = 0; i < 1000; ++i) all_ok = all_ok && m.step() == PriorIntegrityStatus::kOk;
    CHECK(scope.allocations() == 0U);
    CHECK(all_ok);
    CHECK(m.passes_completed() == 1000U / 13U);
}

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: a bit flip anywhere in the header or payload is detected at the end of the pass") {
    const std::vector<std::uint8_t> clean = image();
    const std::size_t last = clean.size() - 1U;
    // Magic, version, dims, method, voxel size, CRC fields, first and last payload bytes.
    for (const std::size_t pos : {std::size_t{0}, std::size_t{4}, std::size_t{9}, std::size_t{20}, std::size_t{30},
                                  std::size_t{79}, std::size_t{80}, std::size_t{83}, std::size_t{84},
                                  std::size_t{87}, std::size_t{88}, std::size_t{150}, last}) {
        for (const std::size_t slice : {1U, 7U, 64U, 208U}) {
            for (const unsigned bit : {0U, 7U}) {
                std::vector<std::uint8_t> img = clean;
                PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), slice).value();
                img[pos] = static_cast<std::uint8_t>(img[pos] ^ (1U << bit));  // after start-up, before the pass
                const std::vector<PriorIntegrityStatus> s = run_pass(m);
                for (std::size_t i = 0; i + 1U < s.size(); ++i) CHECK(s[i] == PriorIntegrityStatus::kOk);
                CHECK(s.back() == PriorIntegrityStatus::kCrcMismatch);
            }
        }
    }
}

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: a flip behind the current position is detected by the end of the next pass") {
    const std::vector<std::uint8_t> clean = image();
    std::vector<std::uint8_t> img = clean;
    PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), 10).value();
    for (int i = 0; i < 15; ++i) (void)m.step();  // 150 bytes covered
    img[100] ^= 0x04U;                            // already covered in this pass
    std::size_t steps = 0;
    while (m.status() == PriorIntegrityStatus::kOk && steps < 100U) {
        (void)m.step();
        ++steps;
    }
    CHECK(m.status() == PriorIntegrityStatus::kCrcMismatch);
    CHECK(steps == 6U + m.steps_per_pass());  // rest of this pass (passes) + the whole next one
    CHECK(15U + steps <= 2U * m.steps_per_pass());
}

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: a mismatch is latched until a new monitor is made") {
    const std::vector<std::uint8_t> clean = image();
    std::vector<std::uint8_t> img = clean;
    PriorIntegrityMonitor m = PriorIntegrityMonitor::make(view_of(img), 50).value();
    img[120] ^= 0x80U;
    (void)run_pass(m);
    CHECK(m.status() == PriorIntegrityStatus::kCrcMismatch);
    const std::uint32_t passes = m.passes_completed();
    img[120] ^= 0x80U;  // the memory reads right again
    for (int i = 0; i < 20; ++i) {
        CHECK(m.step() == PriorIntegrityStatus::kCrcMismatch);
        CHECK(m.last_step_bytes() == 0U);  // no more work once latched
    }
    CHECK(m.passes_completed() == passes);
    m = PriorIntegrityMonitor::make(view_of(img), 50).value();
    const std::vector<PriorIntegrityStatus> s = run_pass(m);
    CHECK(s.back() == PriorIntegrityStatus::kOk);
}

// verifies: SR-PRIOR-012
TEST_CASE("prior integrity: a monitor needs a loaded image and a slice of at least one byte") {
    const std::vector<std::uint8_t> img = image();
    CHECK(PriorIntegrityMonitor::make(view_of(img), 0).error() == ErrorCode::kInvalidArgument);
    CHECK(PriorIntegrityMonitor::make(PriorImageView{}, 16).error() == ErrorCode::kInvalidArgument);
    PriorIntegrityMonitor unbound;
    CHECK(unbound.status() == PriorIntegrityStatus::kNotInitialised);
    CHECK(unbound.step() == PriorIntegrityStatus::kNotInitialised);
    CHECK(unbound.steps_per_pass() == 0U);
    CHECK(unbound.last_step_bytes() == 0U);
    CHECK(std::string(to_string(PriorIntegrityStatus::kCrcMismatch)) == "prior integrity CRC mismatch");
    CHECK(std::string(to_string(PriorIntegrityStatus::kOk)) != std::string(to_string(PriorIntegrityStatus::kNotInitialised)));
}
