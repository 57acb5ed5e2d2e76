// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Column maps: how to read a measurements file as a device's software
// exports it (docs/formats.md, "Column maps"), without converting it by
// hand first. A small YAML file:
//
//   delimiter: ";"        # ",", ";" or "\t" (also "tab"); left out: the
//                         # header's most frequent of the three, with a note
//   decimal: ","          # "." (default) or ","; "," needs another delimiter
//   columns:              # activecal column: the file's column
//     x_mm: measurement_x
//     shoulder_pan_joint_rad: shoulder_pan_joint
//   orientation: {convention: XYZ, intrinsic: true, unit: deg,
//                 columns: [measurement_rx, measurement_ry, measurement_rz]}
//
// Every field is optional. Columns the map does not name keep their own
// names, so a file may mix mapped and activecal-named columns. The
// orientation's three columns are the angles (a, b, c) of any of the 12
// Euler/Tait-Bryan axis orders (core/euler_angles.h: intrinsic
// R = R_a(a) R_b(b) R_c(c), extrinsic R = R_c(c) R_b(b) R_a(a)), in
// degrees or radians; each row's angles become a rotation matrix and so the
// measurement's rotation vector, never activecal's own roll/pitch/yaw.
//
// The map is applied to the file's text: the result is the same file in
// activecal's own form (',' separated, '.' decimals, activecal's column
// names, the orientation as rx_rad,ry_rad,rz_rad written to 17 digits),
// line for line, so that the measurements reader's messages keep the
// file's line numbers. Numbers other than the angles are passed on as
// written (a decimal comma becomes a point): a file read through a map
// gives bit for bit the measurements of the same file converted by hand.

#ifndef ACTIVECAL_IO_COLUMN_MAP_H_
#define ACTIVECAL_IO_COLUMN_MAP_H_

#include <string>
#include <vector>

#include "activecal/core/euler_angles.h"
#include "activecal/core/robot_model.h"

namespace activecal {

struct ColumnMap {
  std::string source;     // the map file, for messages
  char delimiter = '\0';  // ',', ';' or '\t'; '\0': detected from the header
  int delimiter_line = 0;
  char decimal = '.';  // '.' or ','
  int decimal_line = 0;

  struct Column {
    std::string activecal;  // x_mm, q1_rad, shoulder_pan_joint_rad, ...
    std::string file;       // the file's header name
    int line = 0;           // of the map
  };
  std::vector<Column> columns;

  bool has_orientation = false;
  EulerConvention convention;
  std::vector<std::string> orientation_columns;  // three, in (a, b, c) order
  int orientation_line = 0;
};

// Parses a map. On failure false with "<source>:<line>:<column>: <field>:
// <what>" in *error (unknown fields, a delimiter or decimal not listed
// above, decimal ',' with delimiter ',', an orientation without exactly 3
// columns, an unknown convention or unit).
bool ParseColumnMap(const std::string& text, const std::string& source,
                    ColumnMap* map, std::string* error);
bool ReadColumnMap(const std::string& path, ColumnMap* map, std::string* error);

// Rewrites the measurements file `text` (named `source`) into activecal's
// own form as described above, into *out; notes (the detected delimiter)
// are appended to *notes (may be null). False with one line in *error: an
// activecal column of the map that no reader knows (for `model`'s joints)
// "<map>:<line>: columns: <name>: ...", a mapped or orientation column not
// in the file's header "<source>:<line>: <column>: ...", a file whose
// header holds rx_rad, ry_rad or rz_rad besides a mapped orientation, an
// angle that is not a number, or part of a row's angles left empty.
bool ApplyColumnMap(const ColumnMap& map, const RobotModel& model,
                    const std::string& text, const std::string& source,
                    std::string* out, std::vector<std::string>* notes,
                    std::string* error);

// "measurement_rx, measurement_ry, measurement_rz as intrinsic XYZ, deg
// (map.yaml)": how the map reads orientations, for messages. Empty without
// an orientation.
std::string ColumnMapOrientationText(const ColumnMap& map);

}  // namespace activecal

#endif  // ACTIVECAL_IO_COLUMN_MAP_H_
