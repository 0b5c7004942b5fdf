// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// sim::method_name (experiment.hpp), in a file of its own: the monitor and the
// detection program name methods, and with this function in experiment.cpp
// they linked the whole experiment, the paper's sensor model with it (a ctest
// checks that the monitor holds none of that model: it is the evaluation's).
#include "cellguard/host/sim/experiment.hpp"

namespace cellguard::sim {

const char* method_name(PriorMethod method) {
    switch (method) {
        case PriorMethod::kThresholded: return "thresholded";
        case PriorMethod::kProbabilistic: return "probabilistic";
        case PriorMethod::kThresholdedBaseline: return "thresholded-baseline";
        case PriorMethod::kProbabilisticBaseline: return "probabilistic-baseline";
    }
    return "unknown";
}

}  // namespace cellguard::sim
