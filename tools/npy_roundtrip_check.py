#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 The cellguard authors
# SPDX-License-Identifier: Apache-2.0
"""Checks grid exports (write_grid_npy, port/linux/npy.hpp) against numpy itself.

Usage: tools/npy_roundtrip_check.py PREFIX [PREFIX ...]

For each PREFIX, reads PREFIX_log_odds.npy, PREFIX_probability.npy and
PREFIX_observed.npy with numpy.load (allow_pickle=False) and checks that:
  - the dtypes are int16, float32 and uint8, all three C-order with one 3-d shape;
  - each file is byte for byte what numpy.save writes for the loaded array
    (so the C++ writer matches numpy's header and padding exactly);
  - probability == logistic(log_odds / 256) to float32 precision, and 0 where
    log_odds is the never-foreground sentinel -32768 (log_odds.hpp);
  - observed flags are 0 or 1.

Exit status: 0 all checks pass, 1 a check failed, 2 usage error,
77 numpy is not installed (nothing checked; the C++ unit tests do not need it).
"""
import io
import sys

try:
    import numpy as np
except ImportError:
    print("npy_roundtrip_check: numpy is not installed; skipped", file=sys.stderr)
    sys.exit(77)

LOG_ODDS_SCALE = 256.0
NEVER_FOREGROUND = -32768


def numpy_bytes(array):
    """The bytes numpy.save writes for array."""
    buf = io.BytesIO()
    np.save(buf, array, allow_pickle=False)
    return buf.getvalue()


def check_prefix(prefix):
    failures = []
    arrays = {}
    for suffix, dtype in (("log_odds", np.int16), ("probability", np.float32), ("observed", np.uint8)):
        path = f"{prefix}_{suffix}.npy"
        with open(path, "rb") as f:
            raw = f.read()
        array = np.load(io.BytesIO(raw), allow_pickle=False)
        if array.dtype != np.dtype(dtype):
            failures.append(f"{path}: dtype {array.dtype}, expected {np.dtype(dtype)}")
        if array.ndim != 3:
            failures.append(f"{path}: {array.ndim} dimensions, expected 3 (nz, ny, nx)")
        if not array.flags.c_contiguous:
            failures.append(f"{path}: not C order")
        if raw != numpy_bytes(array):
            failures.append(f"{path}: bytes differ from what numpy.save writes for the same array")
        arrays[suffix] = array
    if failures:
        return failures
    lo, pr, ob = arrays["log_odds"], arrays["probability"], arrays["observed"]
    if not (lo.shape == pr.shape == ob.shape):
        return [f"{prefix}: shapes differ: {lo.shape}, {pr.shape}, {ob.shape}"]
    nats = lo.astype(np.float64) / LOG_ODDS_SCALE
    expected = np.where(lo == NEVER_FOREGROUND, 0.0, 1.0 / (1.0 + np.exp(-nats))).astype(np.float32)
    worst = float(np.max(np.abs(pr.astype(np.float64) - expected.astype(np.float64)))) if lo.size else 0.0
    if worst > 1e-6:
        failures.append(f"{prefix}: probability differs from logistic(log_odds / 256) by up to {worst:g}")
    bad_flags = int(np.count_nonzero(ob > 1))
    if bad_flags:
        failures.append(f"{prefix}: {bad_flags} observed flags are neither 0 nor 1")
    return failures


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    status = 0
    for prefix in argv[1:]:
        try:
            failures = check_prefix(prefix)
        except (OSError, ValueError) as error:
            failures = [f"{prefix}: {error}"]
        for failure in failures:
            print(f"npy_roundtrip_check: FAIL {failure}", file=sys.stderr)
        if failures:
            status = 1
        else:
            shape = np.load(f"{prefix}_log_odds.npy", allow_pickle=False).shape
            print(f"npy_roundtrip_check: ok {prefix} (shape {shape})")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
