// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The points file (--points): known geometry between the fixed points of
// type=point rows (point_constraints.h), for a calibration without a
// tracker.
//
//   distances:
//     - {from: hole_0, to: hole_1, distance_m: 0.05}     # sigma_m optional
//     - {from: hole_1, to: hole_2, distance_mm: 80.0, sigma_mm: 0.01}
//
// Each entry becomes a point-distance measurement (1 residual row,
// |c(from) - c(to)| - distance): what fixes the scale that points alone
// cannot. Unknown keys, a negative distance, an entry between a label and
// itself, or one given twice are errors "<file>:<line>:<column>: ...".

#ifndef ACTIVECAL_IO_POINTS_FILE_H_
#define ACTIVECAL_IO_POINTS_FILE_H_

#include <string>
#include <vector>

#include "activecal/core/measurement.h"

namespace activecal {

// The known distances of `text` (named `source` in messages) as
// kPointDistance measurements, with their line in *lines (1-based; may be
// null).
bool ParsePointsFile(const std::string& text, const std::string& source,
                     std::vector<Measurement>* distances,
                     std::vector<int>* lines, std::string* error);

// ParsePointsFile of the file at `path`.
bool ReadPointsFile(const std::string& path,
                    std::vector<Measurement>* distances,
                    std::vector<int>* lines, std::string* error);

// Every label of `distances` (from ParsePointsFile, lines as it gave them)
// is a fixed point of `measurements` with two rows at least; false with
// "<source>:<line>: ..." naming the first that is not.
bool CheckPointDistanceLabels(const std::vector<Measurement>& measurements,
                              const std::vector<Measurement>& distances,
                              const std::vector<int>& lines,
                              const std::string& source, std::string* error);

}  // namespace activecal

#endif  // ACTIVECAL_IO_POINTS_FILE_H_
