// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// One set of defaults: the values that an option of a program and its twin
// keyword argument of the Python module both take when the user gives
// none. The flags (apps/) and the kwargs (python/) read them from here;
// tests/output_cli_test.sh checks every program's --help against this
// file and python/tests/test_defaults.py the module's signatures.
// docs/user_guide.md ("Defaults") lists them with the reasons.
//
// Units: m, rad, m per rad.

#ifndef ACTIVECAL_CALIBRATION_DEFAULTS_H_
#define ACTIVECAL_CALIBRATION_DEFAULTS_H_

#include <cstdint>

namespace activecal {
namespace defaults {

// Design (activecal_select, activecal.select).
// Fedorov exchange: the standard exchange algorithm of optimal design, the
// one the README's examples use (eae, the paper's, stays a choice).
inline constexpr char kSelectAlgorithm[] = "fedorov";
inline constexpr char kSelectCriterion[] = "det";  // D-optimal ("d" too)
inline constexpr int kNumPoses = 30;
inline constexpr int kLevels = 5;                   // lattice values per joint
inline constexpr int64_t kPoolSize = 100000;        // sampled pools
inline constexpr double kDesignNoiseM = 1e-4;       // sigma per coordinate
inline constexpr int kInitialPoses = 12;            // eae
inline constexpr int kRandomDesigns = 5000;         // random
inline constexpr double kApproxTolerance = 2e-3;    // approx, certificate
inline constexpr int64_t kPolishPoolSize = 20000;   // fedorov
inline constexpr int64_t kMaxDoublePoolMib = 2048;  // pool storage

// Simulated measurements (activecal_simulate, activecal.simulate): a
// tracker-class device, 1 mm and 1 mrad per axis.
inline constexpr double kSimulationNoiseM = 1e-3;
inline constexpr double kSimulationRotationNoiseRad = 1e-3;

// Weight of a pose row's orientation (m per rad) for the fit and the
// design: sigma_position / sigma_rotation of the device. 1 when the user
// states none; activecal_identify then notes what it assumed.
inline constexpr double kRotationWeightMPerRad = 1.0;

// Identification (activecal_identify, activecal.identify).
inline constexpr char kModelSelection[] = "auto";
inline constexpr char kSelectionRule[] = "1se_most";
inline constexpr char kSelectionRanking[] = "significance";
inline constexpr int kFolds = 5;
inline constexpr char kRobustLoss[] = "none";

// Every random choice.
inline constexpr uint64_t kSeed = 1;

}  // namespace defaults
}  // namespace activecal

#endif  // ACTIVECAL_CALIBRATION_DEFAULTS_H_
