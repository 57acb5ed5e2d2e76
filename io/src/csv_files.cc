// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/csv_files.h"

#include <glog/logging.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "activecal/core/kinematics.h"
#include "activecal/core/plane_constraints.h"
#include "activecal/core/point_constraints.h"
#include "activecal/core/text_table.h"
#include "csv_columns.h"
#include "line_error.h"
#include "number_text.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;
using internal::Trim;

struct Row {
  int line = 0;
  std::vector<std::string> fields;
};

// Splits a line at its commas into trimmed fields: n commas, n + 1 fields
// (an empty last cell too, whatever follows it: a space, the '\r' of a
// Windows line end). A field may be quoted as spreadsheets write it,
// "P1, north" with "" for a quote inside; the quotes are removed. False
// with the reason for a quote not closed on the line or text after one.
bool SplitFields(const std::string& line, std::vector<std::string>* fields,
                 std::string* why) {
  fields->clear();
  size_t i = 0;
  while (true) {
    const std::string field_number = std::to_string(fields->size() + 1);
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i < line.size() && line[i] == '"') {
      std::string value;
      size_t k = i + 1;
      for (;; ++k) {
        if (k >= line.size()) {
          *why = "field " + field_number +
                 ": the quote opened there is not closed on the line (a "
                 "field may not span lines)";
          return false;
        }
        if (line[k] != '"') {
          value += line[k];
        } else if (k + 1 < line.size() && line[k + 1] == '"') {
          value += '"';
          ++k;
        } else {
          break;
        }
      }
      i = k + 1;
      while (i < line.size() &&
             (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) {
        ++i;
      }
      if (i < line.size() && line[i] != ',') {
        *why = "field " + field_number + ": text after the closing quote";
        return false;
      }
      fields->push_back(Trim(value));
    } else {
      const size_t comma = std::min(line.find(',', i), line.size());
      fields->push_back(Trim(line.substr(i, comma - i)));
      i = comma;
    }
    if (i >= line.size()) return true;
    ++i;  // the comma
  }
}

// A CSV table: header names and rows of trimmed fields.
class Table {
 public:
  bool Parse(const std::string& text, const std::string& source,
             std::string* error) {
    source_ = source;
    // UTF-16 (a spreadsheet's "Unicode text"): NUL bytes everywhere.
    const size_t nul = text.find('\0');
    if (nul != std::string::npos) {
      const int line = 1 + static_cast<int>(std::count(
                               text.begin(), text.begin() + nul, '\n'));
      return Fail(line,
                  "the file holds NUL bytes: not UTF-8 or ASCII text (UTF-16? "
                  "save it as UTF-8 CSV)",
                  error);
    }
    // A UTF-8 byte order mark, as spreadsheets write one, is not part of
    // the first column's name.
    static const std::string kBom = "\xEF\xBB\xBF";
    std::istringstream in(text.compare(0, kBom.size(), kBom) == 0
                              ? text.substr(kBom.size())
                              : text);
    std::string line;
    int number = 0;
    bool have_header = false;
    while (std::getline(in, line)) {
      ++number;
      const std::string trimmed = Trim(line);
      if (trimmed.empty() || trimmed[0] == '#') continue;
      std::vector<std::string> fields;
      std::string why;
      if (!SplitFields(line, &fields, &why)) return Fail(number, why, error);
      // A row of separators only (a spreadsheet's empty row) holds nothing.
      if (std::all_of(fields.begin(), fields.end(),
                      [](const std::string& f) { return f.empty(); })) {
        continue;
      }
      if (!have_header && fields.size() == 1) {
        // One column: a file of another separator, say so.
        for (const auto& [c, name] :
             {std::pair<char, const char*>{';', "';'"}, {'\t', "tabs"}}) {
          if (trimmed.find(c) != std::string::npos) {
            return Fail(number,
                        std::string("the fields are separated by ") + name +
                            ", not ',': activecal reads comma-separated "
                            "files (export with ',' between fields and '.' "
                            "as the decimal point)",
                        error);
          }
        }
      }
      if (!have_header) {
        for (size_t c = 0; c < fields.size(); ++c) {
          if (fields[c].empty()) {
            // An empty column a spreadsheet adds (a ',' ending every
            // line): fine as long as it stays empty.
            nameless_.push_back(static_cast<int>(c));
            continue;
          }
          if (!columns_.emplace(fields[c], static_cast<int>(c)).second) {
            return Fail(number, "header names column '" + fields[c] + "' twice",
                        error);
          }
        }
        header_ = fields;
        header_line_ = number;
        have_header = true;
        continue;
      }
      if (fields.size() != header_.size()) {
        return Fail(number,
                    "expected " + std::to_string(header_.size()) +
                        " fields as in the header, got " +
                        std::to_string(fields.size()),
                    error);
      }
      for (int c : nameless_) {
        if (!fields[c].empty()) {
          return Fail(number,
                      "column " + std::to_string(c + 1) +
                          " has no name in the header, but a value here ('" +
                          fields[c] + "')",
                      error);
        }
      }
      rows_.push_back({number, std::move(fields)});
    }
    if (!have_header) {
      if (error) *error = source + ": empty file: no header line";
      return false;
    }
    return true;
  }

  bool Has(const std::string& column) const { return columns_.count(column); }
  const std::vector<std::string>& header() const { return header_; }
  int Column(const std::string& column) const {
    const auto it = columns_.find(column);
    return it == columns_.end() ? -1 : it->second;
  }
  const std::vector<Row>& rows() const { return rows_; }
  int header_line() const { return header_line_; }

  bool Fail(int line, const std::string& what, std::string* error) const {
    // The field: the column, when `what` does not start with it, or the
    // line itself: the header (or, before it is read, the line that was to
    // be the header), a row.
    const char* field =
        header_line_ == 0 || line == header_line_ ? "header" : "row";
    if (error) *error = internal::LineError(source_, line, field, what);
    return false;
  }

  bool RequireColumn(const std::string& column, std::string* error) const {
    if (Has(column)) return true;
    return Fail(header_line_, "the header has no column '" + column + "'",
                error);
  }

  // The number in `column` of `row`; false with a message if it is empty,
  // not a number or not finite.
  bool Number(const Row& row, const std::string& column, double* value,
              std::string* error) const {
    const int c = Column(column);
    const std::string& text = row.fields[c];
    if (text.empty()) return Fail(row.line, column + ": empty", error);
    std::string why;
    if (!internal::ParseFiniteNumber(text, value, &why)) {
      return Fail(row.line, column + ": " + why, error);
    }
    return true;
  }

  bool Empty(const Row& row, const std::string& column) const {
    const int c = Column(column);
    return c < 0 || row.fields[c].empty();
  }

 private:
  std::string source_;
  std::vector<std::string> header_;
  std::map<std::string, int> columns_;
  std::vector<int> nameless_;  // columns with an empty name: empty cells
  std::vector<Row> rows_;
  int header_line_ = 0;
};

bool Revolute(const RobotModel& model, int j) {
  return model.links[j].joint_type == JointType::kRevolute;
}

// The pendant-unit column of joint j: "q1_deg" or "q1_mm".
std::string DisplayColumn(const RobotModel& model, int j) {
  return "q" + std::to_string(j + 1) + (Revolute(model, j) ? "_deg" : "_mm");
}

double DisplayScale(const RobotModel& model, int j) {
  return Revolute(model, j) ? kDegree : 1e-3;
}

// The two columns joint j may be read from: SI (q1_rad, q3_m) and display
// (q1_deg, q3_mm), or the same after the URDF joint's name.
struct JointColumnPair {
  std::string si, display;
};

JointColumnPair QColumns(const RobotModel& model, int j,
                         const std::string& suffix) {
  return {JointColumn(model, j) + suffix, DisplayColumn(model, j) + suffix};
}

// Reads joint j of a row from its SI column or its display column; checks
// agreement when both are present.
bool ReadJoint(const Table& table, const Row& row, const RobotModel& model,
               int j, const JointColumnPair& columns, double* q,
               std::string* error) {
  const std::string& si = columns.si;
  const std::string& display = columns.display;
  const bool has_si = table.Has(si), has_display = table.Has(display);
  if (!has_si && !has_display) {
    return table.Fail(table.header_line(),
                      "the header has neither '" + si + "' nor '" + display +
                          "' for joint " + std::to_string(j + 1),
                      error);
  }
  double si_value = 0, display_value = 0;
  if (has_si && !table.Number(row, si, &si_value, error)) return false;
  if (has_display && !table.Number(row, display, &display_value, error)) {
    return false;
  }
  display_value *= DisplayScale(model, j);
  if (has_si && has_display &&
      std::abs(si_value - display_value) >
          1e-9 * std::max(1.0, std::abs(si_value))) {
    return table.Fail(row.line,
                      si + " = " + ShortestText(si_value) + " and " + display +
                          " disagree; edit one and delete the other column",
                      error);
  }
  *q = has_si ? si_value : display_value;
  return true;
}

// Every joint of a row from `columns`, checked against the limits.
bool ReadJoints(const Table& table, const Row& row, const RobotModel& model,
                const std::vector<JointColumnPair>& columns, Eigen::VectorXd* q,
                std::string* error) {
  q->resize(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) {
    if (!ReadJoint(table, row, model, j, columns[j], &(*q)[j], error)) {
      return false;
    }
  }
  std::string why;
  if (!model.CheckJointValues(*q, &why)) {
    return table.Fail(row.line, why, error);
  }
  return true;
}

// The columns of each joint's reading: q<j> (q1_rad / q1_deg, q3_m /
// q3_mm) or the joint's name (elbow_joint_rad / _deg, _m / _mm), one
// scheme per file; *second the same with "_2" (a distance's second pose).
// *num_present: the joints that have a column. With `required`, a joint
// without one is an error naming both schemes' columns.
bool ResolveJointColumns(const Table& table, const RobotModel& model,
                         bool required, std::vector<JointColumnPair>* first,
                         std::vector<JointColumnPair>* second, int* num_present,
                         std::string* error) {
  const int n = model.num_joints();
  std::vector<JointColumnPair> q1, q2, n1, n2;
  bool any_q = false, any_name = false;
  std::string a_q, a_name;
  // Names of other quantities' columns: a joint so named is read by q<j>.
  static const std::set<std::string> kFixed = {
      "type",       "marker",      "x_m",     "y_m",
      "z_m",        "x_mm",        "y_mm",    "z_mm",
      "distance_m", "distance_mm", "sigma_m", "sigma_mm",
      "sigma_rad",  "sigma_deg",   "u95_m",   "u95_mm"};
  for (int j = 0; j < n; ++j) {
    const bool rev = Revolute(model, j);
    for (const std::string& suffix : {std::string(""), std::string("_2")}) {
      const JointColumnPair q = QColumns(model, j, suffix);
      const std::string name = model.block_name(j + 1);
      const JointColumnPair by_name = {name + (rev ? "_rad" : "_m") + suffix,
                                       name + (rev ? "_deg" : "_mm") + suffix};
      (suffix.empty() ? q1 : q2).push_back(q);
      (suffix.empty() ? n1 : n2).push_back(by_name);
      for (const std::string& c : {q.si, q.display}) {
        if (table.Has(c)) {
          any_q = true;
          if (a_q.empty()) a_q = c;
        }
      }
      for (const std::string& c : {by_name.si, by_name.display}) {
        if (table.Has(c) && !kFixed.count(c) &&
            name != "q" + std::to_string(j + 1)) {
          any_name = true;
          if (a_name.empty()) a_name = c;
        }
      }
    }
  }
  if (any_q && any_name) {
    return table.Fail(table.header_line(),
                      "joints are named both q<j> ('" + a_q +
                          "') and by joint name ('" + a_name +
                          "'): a file uses one of the two",
                      error);
  }
  *first = any_name ? n1 : q1;
  *second = any_name ? n2 : q2;
  *num_present = 0;
  for (int j = 0; j < n; ++j) {
    if (table.Has((*first)[j].si) || table.Has((*first)[j].display)) {
      ++*num_present;
      continue;
    }
    if (!required) continue;
    const std::string name = model.block_name(j + 1);
    return table.Fail(table.header_line(),
                      "the header has neither '" + q1[j].si + "' nor '" +
                          q1[j].display + "' for joint " +
                          std::to_string(j + 1) +
                          (name == "q" + std::to_string(j + 1)
                               ? std::string()
                               : ", nor '" + n1[j].si + "' or '" +
                                     n1[j].display + "' (its joint name)"),
                      error);
  }
  return true;
}

// A joint column (q<k>_rad, _deg, _m, _mm, with an optional _2) for a joint
// the robot does not have: a file for another robot, not a column to skip.
bool CheckNoExtraJoints(const Table& table, const RobotModel& model,
                        std::string* error) {
  for (const std::string& name : table.header()) {
    if (name.size() < 3 || name[0] != 'q' || !std::isdigit(name[1])) continue;
    size_t end = 1;
    while (end < name.size() && std::isdigit(name[end])) ++end;
    std::string unit = name.substr(end);
    if (unit.size() > 2 && unit.compare(unit.size() - 2, 2, "_2") == 0) {
      unit.resize(unit.size() - 2);
    }
    if (unit != "_rad" && unit != "_deg" && unit != "_m" && unit != "_mm") {
      continue;
    }
    const int k = std::stoi(name.substr(1, std::min<size_t>(end - 1, 6)));
    if (k > model.num_joints() || k < 1) {
      return table.Fail(table.header_line(),
                        "column '" + name + "' is for joint " +
                            std::to_string(k) + ", but robot '" + model.name +
                            "' has " + std::to_string(model.num_joints()) +
                            " joints (a file for another robot?)",
                        error);
    }
  }
  return true;
}

// The header's columns `known` does not name; with `strict` they are an
// error naming them all.
bool UnreadColumns(const Table& table,
                   const std::function<bool(const std::string&)>& known,
                   bool strict, std::vector<std::string>* unread,
                   std::string* error) {
  unread->clear();
  for (const std::string& name : table.header()) {
    if (!name.empty() && !known(name)) unread->push_back(name);
  }
  if (unread->empty() || !strict) return true;
  std::string list;
  for (const std::string& e : *unread) {
    list += (list.empty() ? "'" : ", '") + e + "'";
  }
  return table.Fail(table.header_line(),
                    "column" + std::string(unread->size() > 1 ? "s " : " ") +
                        list +
                        " activecal does not read (strict columns: every "
                        "column must be one activecal reads)",
                    error);
}

// The note on columns that were not read: "<source>: ignored 2 columns
// activecal does not read: a, b".
std::string UnreadNote(const std::string& source,
                       const std::vector<std::string>& unread) {
  std::string list;
  for (const std::string& e : unread) list += (list.empty() ? "" : ", ") + e;
  return source + ": ignored " + std::to_string(unread.size()) + " column" +
         (unread.size() > 1 ? "s" : "") + " activecal does not read: " + list;
}

// The optional pose_index label of a row: an integer >= 0.
bool ReadPoseIndex(const Table& table, const Row& row, int64_t* label,
                   std::string* error) {
  double index;
  if (!table.Number(row, "pose_index", &index, error)) return false;
  if (index < 0 || index != std::floor(index) ||
      index > static_cast<double>(kMaxPoseIndex)) {
    return table.Fail(
        row.line,
        "pose_index: expected an integer >= 0, got " + ShortestText(index),
        error);
  }
  *label = static_cast<int64_t>(index);
  return true;
}

}  // namespace

std::string JointColumn(const RobotModel& model, int j) {
  return "q" + std::to_string(j + 1) + (Revolute(model, j) ? "_rad" : "_m");
}

bool ReadTextFile(const std::string& path, std::string* text,
                  std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error) *error = path + ": cannot open the file";
    return false;
  }
  std::ostringstream out;
  out << in.rdbuf();
  *text = out.str();
  return true;
}

bool CheckPoseIndices(const std::vector<int64_t>& labels, bool unique,
                      std::string* error) {
  std::map<int64_t, size_t> seen;
  for (size_t i = 0; i < labels.size(); ++i) {
    const std::string entry = "pose_indices[" + std::to_string(i) +
                              "] = " + std::to_string(labels[i]);
    if (labels[i] < 0 || labels[i] > kMaxPoseIndex) {
      if (error) {
        *error = entry +
                 ": a pose label must be an integer in [0, 9e15] (the files' "
                 "pose_index; every reader refuses others)";
      }
      return false;
    }
    if (!unique) continue;
    const auto [it, inserted] = seen.emplace(labels[i], i);
    if (!inserted) {
      if (error) {
        *error = entry + ", the same label as pose_indices[" +
                 std::to_string(it->second) +
                 "]: the labels of a pool name its poses, each once";
      }
      return false;
    }
  }
  return true;
}

std::string PosesCsvText(const RobotModel& model, const PoseList& poses) {
  std::ostringstream out;
  out << "pose_index";
  for (int j = 0; j < model.num_joints(); ++j)
    out << "," << JointColumn(model, j);
  for (int j = 0; j < model.num_joints(); ++j) {
    out << "," << DisplayColumn(model, j);
  }
  out << "\n";
  for (int i = 0; i < poses.joints.rows(); ++i) {
    out << (i < static_cast<int>(poses.pose_indices.size())
                ? poses.pose_indices[i]
                : i);
    for (int j = 0; j < model.num_joints(); ++j) {
      out << "," << ShortestText(poses.joints(i, j));
    }
    for (int j = 0; j < model.num_joints(); ++j) {
      out << "," << ShortestText(poses.joints(i, j) / DisplayScale(model, j));
    }
    out << "\n";
  }
  return out.str();
}

bool ParsePosesCsv(const std::string& text, const std::string& source,
                   const RobotModel& model, bool reject_duplicates,
                   PoseList* poses, std::string* error) {
  Table table;
  if (!table.Parse(text, source, error)) return false;
  if (!CheckNoExtraJoints(table, model, error)) return false;
  const int n = static_cast<int>(table.rows().size());
  if (n == 0) {
    return table.Fail(table.header_line(), "no poses after the header", error);
  }
  // q<j> columns or the joints' names, as the measurements CSV.
  std::vector<JointColumnPair> columns, unused;
  int num_present = 0;
  if (!ResolveJointColumns(table, model, /*required=*/true, &columns, &unused,
                           &num_present, error)) {
    return false;
  }
  PoseList out;
  out.joints.resize(n, model.num_joints());
  out.pose_indices.resize(n);
  std::map<std::vector<double>, int> seen;
  std::map<int64_t, int> seen_labels;
  for (int i = 0; i < n; ++i) {
    const Row& row = table.rows()[i];
    Eigen::VectorXd q;
    if (!ReadJoints(table, row, model, columns, &q, error)) return false;
    out.joints.row(i) = q.transpose();
    out.pose_indices[i] = i;
    if (table.Has("pose_index") &&
        !ReadPoseIndex(table, row, &out.pose_indices[i], error)) {
      return false;
    }
    if (reject_duplicates && table.Has("pose_index")) {
      const auto [it, inserted] =
          seen_labels.emplace(out.pose_indices[i], row.line);
      if (!inserted) {
        return table.Fail(row.line,
                          "pose_index: " + std::to_string(out.pose_indices[i]) +
                              " is also the label of line " +
                              std::to_string(it->second) +
                              " (the labels of a pool name its poses, each "
                              "once)",
                          error);
      }
    }
    if (reject_duplicates) {
      const std::vector<double> key(q.data(), q.data() + q.size());
      const auto [it, inserted] = seen.emplace(key, row.line);
      if (!inserted) {
        return table.Fail(row.line,
                          "duplicate pose: the same joint values as line " +
                              std::to_string(it->second),
                          error);
      }
    }
  }
  *poses = std::move(out);
  return true;
}

bool ReadPosesCsv(const std::string& path, const RobotModel& model,
                  bool reject_duplicates, PoseList* poses, std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParsePosesCsv(text, path, model, reject_duplicates, poses, error);
}

// ---------------------------------------------------------------------------
// Measurements.

namespace {

// A quaternion is a unit quaternion up to this much (|norm - 1|); it is
// normalised. Files print 4 to 17 digits: 1e-3 lets any of them through
// and catches a column of another quantity.
constexpr double kQuaternionNormTolerance = 1e-3;

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

// One representation of a quantity: its columns and their factor to SI,
// value * scale / divisor (a division by 1000 turns "1.5" mm into exactly
// the double of "0.0015" m).
struct Form {
  std::vector<std::string> columns;
  double scale = 1.0;
  double divisor = 1.0;
  bool length = false;  // a length: held to kMaxLengthM
};

// No measuring device reaches farther: a length beyond is a corrupt cell or
// a wrong unit (1e200 mm made an evaluation's RMSE inf).
constexpr double kMaxLengthM = 1e6;

// Which of a quantity's forms the header holds (-1: none). Part of a form,
// or two forms, are errors.
bool ChooseForm(const Table& table, const std::string& quantity,
                const std::vector<Form>& forms, int* chosen,
                std::string* error) {
  *chosen = -1;
  for (size_t f = 0; f < forms.size(); ++f) {
    std::vector<std::string> present, missing;
    for (const std::string& c : forms[f].columns) {
      (table.Has(c) ? present : missing).push_back(c);
    }
    if (present.empty()) continue;
    if (!missing.empty()) {
      return table.Fail(table.header_line(),
                        "the header has " + Join(present) + " but not " +
                            Join(missing) + " (" + quantity + ")",
                        error);
    }
    if (*chosen >= 0) {
      return table.Fail(
          table.header_line(),
          quantity + " is given both as " + Join(forms[*chosen].columns) +
              " and as " + Join(forms[f].columns) +
              ": a file holds one representation of each quantity",
          error);
    }
    *chosen = static_cast<int>(f);
  }
  return true;
}

// The forms of each quantity.
const std::vector<Form>& PositionForms() {
  static const std::vector<Form> forms = {
      {{"x_m", "y_m", "z_m"}, 1.0, 1.0, true},
      {{"x_mm", "y_mm", "z_mm"}, 1.0, 1e3, true}};
  return forms;
}
enum OrientationForm { kRotvec, kQuat, kRpyRad, kRpyDeg };
const std::vector<Form>& OrientationForms() {
  static const std::vector<Form> forms = {
      {{"rx_rad", "ry_rad", "rz_rad"}, 1.0},
      {{"qw", "qx", "qy", "qz"}, 1.0},
      {{"roll_rad", "pitch_rad", "yaw_rad"}, 1.0},
      {{"roll_deg", "pitch_deg", "yaw_deg"}, kDegree}};
  return forms;
}
// The commanded pose of an ISO 9283 file (CommandedPosesCsv): its point
// and the orientation, a unit quaternion or a rotation matrix.
const std::vector<Form>& CommandedPositionForms() {
  static const std::vector<Form> forms = {
      {{"commanded_x_m", "commanded_y_m", "commanded_z_m"}, 1.0, 1.0, true},
      {{"commanded_x_mm", "commanded_y_mm", "commanded_z_mm"}, 1.0, 1e3, true}};
  return forms;
}
enum CommandedOrientationForm { kCommandedQuat, kCommandedMatrix };
const std::vector<Form>& CommandedOrientationForms() {
  static const std::vector<Form> forms = {
      {{"commanded_qw", "commanded_qx", "commanded_qy", "commanded_qz"}, 1.0},
      {{"commanded_r11", "commanded_r12", "commanded_r13", "commanded_r21",
        "commanded_r22", "commanded_r23", "commanded_r31", "commanded_r32",
        "commanded_r33"},
       1.0}};
  return forms;
}
const std::vector<Form>& DistanceForms() {
  static const std::vector<Form> forms = {{{"distance_m"}, 1.0, 1.0, true},
                                          {{"distance_mm"}, 1.0, 1e3, true}};
  return forms;
}
// Isotropic standard deviation, or a 95% expanded uncertainty (k = 2).
enum SigmaForm { kSigmaM, kSigmaMm, kU95M, kU95Mm };
const std::vector<Form>& SigmaForms() {
  static const std::vector<Form> forms = {{{"sigma_m"}, 1.0, 1.0, true},
                                          {{"sigma_mm"}, 1.0, 1e3, true},
                                          {{"u95_m"}, 1.0, 2.0, true},
                                          {{"u95_mm"}, 1.0, 2e3, true}};
  return forms;
}
const std::vector<Form>& SigmaAxesForms() {
  static const std::vector<Form> forms = {
      {{"sigma_x_m", "sigma_y_m", "sigma_z_m"}, 1.0, 1.0, true},
      {{"sigma_x_mm", "sigma_y_mm", "sigma_z_mm"}, 1.0, 1e3, true}};
  return forms;
}
const std::vector<Form>& SigmaRotationForms() {
  static const std::vector<Form> forms = {{{"sigma_rad"}, 1.0},
                                          {{"sigma_deg"}, kDegree}};
  return forms;
}

// A position column of the wide (motion capture) form: x2_m -> axis 0,
// marker 2, scale 1; false for other names.
bool WideColumn(const std::string& name, int* axis, int* marker,
                double* scale) {
  if (name.size() < 4 || (name[0] != 'x' && name[0] != 'y' && name[0] != 'z'))
    return false;
  size_t end = 1;
  while (end < name.size() &&
         std::isdigit(static_cast<unsigned char>(name[end])))
    ++end;
  if (end == 1 || end > 7) return false;
  const std::string unit = name.substr(end);
  if (unit != "_m" && unit != "_mm") return false;
  *axis = name[0] - 'x';
  *marker = std::stoi(name.substr(1, end - 1));
  *scale = unit == "_m" ? 1.0 : 1e-3;
  return true;
}

// The rotation vector (angle <= pi) of a unit quaternion, rounded to
// double at the end.
Eigen::Vector3d RotationVectorOf(const Eigen::Quaternion<long double>& q) {
  const Eigen::AngleAxis<long double> aa(q);
  return (aa.angle() * aa.axis()).cast<double>();
}

// The rotation vector of an orientation read in OrientationForms()[form]
// (values v as written): a rotation vector as is; a quaternion (normalised;
// its norm within kQuaternionNormTolerance of 1) or roll, pitch, yaw
// converted in extended precision, so that the conversion adds no more than
// the final rounding to the file's own.
bool RotationVectorFromForm(const Table& table, const Row& row, int form,
                            const double* v, Eigen::Vector3d* rotation,
                            std::string* error) {
  switch (form) {
    case kRotvec:
      *rotation = Eigen::Vector3d(v[0], v[1], v[2]);
      return true;
    case kQuat: {
      const Eigen::Quaterniond quat(v[0], v[1], v[2], v[3]);
      const double norm = quat.norm();
      if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
        return table.Fail(row.line,
                          "qw,qx,qy,qz: the quaternion's norm is " +
                              FormatNumber("%.6g", norm) + ", not 1 (to " +
                              FormatNumber("%.6g", kQuaternionNormTolerance) +
                              "): not a unit quaternion",
                          error);
      }
      *rotation = RotationVectorOf(
          Eigen::Quaternion<long double>(v[0], v[1], v[2], v[3]).normalized());
      return true;
    }
    default:
      *rotation = RotationVectorOf(Eigen::Quaternion<long double>(
          RpyRotation<long double>(v[0], v[1], v[2])));
      return true;
  }
}

// The unit of joint j's readings in the file, for messages.
struct JointUnit {
  std::string column;  // the column the value came from
  std::string name;    // "rad", "deg", "m", "mm"
  double scale;        // file unit to SI
};

// Readings beyond a joint's range, gathered for the file's warning.
struct LimitExcess {
  struct Side {
    double max_excess = 0.0;  // SI
    int rows = 0;
    int first_line = 0;
    int last_counted_line = 0;
  };
  Side side[2];  // above the upper limit, below the lower one
  bool first_pose = false, second_pose = false;  // whose columns
  int rows() const { return side[0].rows + side[1].rows; }
};

class MeasurementsReader {
 public:
  MeasurementsReader(const Table& table, const std::string& source,
                     const RobotModel& model,
                     const MeasurementsCsvOptions& options)
      : table_(table), source_(source), model_(model), options_(options) {}

  bool Read(std::vector<Measurement>* out, MeasurementsCsvReport* report,
            std::string* error);

 private:
  bool ResolveHeader(std::string* error);
  bool ResolveJoints(std::string* error);
  bool ReadRow(const Row& row, std::vector<Measurement>* out,
               std::vector<int>* lines, std::string* error);
  bool ReadJointsOf(const Row& row, const std::vector<JointColumnPair>& cols,
                    bool second, Eigen::VectorXd* q, std::string* error);
  bool CheckLimits(const Row& row, const std::vector<JointColumnPair>& cols,
                   bool second, const Eigen::VectorXd& q, std::string* error);
  bool ReadForm(const Row& row, const std::vector<Form>& forms, int form,
                bool used, const std::string& what, const std::string& type,
                double* values, bool* given, std::string* error,
                double* raw = nullptr);
  bool Known(const std::string& column) const { return known_.count(column); }
  // A length read from `column` (`value` as written, `si` in m) within
  // kMaxLengthM.
  bool WithinReach(const Row& row, const std::string& column, double value,
                   double si, std::string* error) const {
    if (std::abs(si) <= kMaxLengthM) return true;
    const bool mm =
        column.size() > 3 && column.compare(column.size() - 3, 3, "_mm") == 0;
    return table_.Fail(row.line,
                       column + ": " + FormatNumber("%.6g", value) +
                           (mm ? " mm" : " m") + " is more than " +
                           FormatNumber("%.6g", kMaxLengthM / 1e3) +
                           " km: a corrupt cell or a wrong unit",
                       error);
  }
  std::string JointLabel(int j) const {
    return "joint " + std::to_string(j + 1) + " (" + model_.block_name(j + 1) +
           ")";
  }
  JointUnit UnitOf(const JointColumnPair& cols, int j) const;
  std::string Warning(int num_rows) const;

  const Table& table_;
  const std::string source_;
  const RobotModel& model_;
  const MeasurementsCsvOptions& options_;

  std::map<std::string, int> known_;
  std::vector<JointColumnPair> joints_, joints2_;
  bool has_second_ = false;
  int position_ = -1, orientation_ = -1, distance_ = -1;
  int sigma_ = -1, sigma_axes_ = -1, sigma_rad_ = -1;
  // Wide form: marker (1-based) -> column index of x, y, z.
  std::map<int, std::array<int, 3>> wide_;
  double wide_divisor_ = 1.0;  // 1000 for mm
  std::vector<LimitExcess> excess_;
  std::map<int, int> unseen_;  // marker (1-based) -> empty positions
  int rows_beyond_ = 0;
  int last_beyond_line_ = 0;
};

bool MeasurementsReader::ResolveJoints(std::string* error) {
  int num_present = 0;
  if (!ResolveJointColumns(table_, model_, /*required=*/true, &joints_,
                           &joints2_, &num_present, error)) {
    return false;
  }
  for (int j = 0; j < model_.num_joints(); ++j) {
    for (const JointColumnPair* p : {&joints_[j], &joints2_[j]}) {
      for (const std::string& c : {p->si, p->display}) {
        if (table_.Has(c)) {
          known_[c] = 1;
          if (p == &joints2_[j]) has_second_ = true;
        }
      }
    }
  }
  excess_.assign(model_.num_joints(), LimitExcess());
  return true;
}

bool MeasurementsReader::ResolveHeader(std::string* error) {
  if (!ResolveJoints(error)) return false;
  struct Quantity {
    const char* name;
    const std::vector<Form>* forms;
    int* chosen;
  };
  const Quantity quantities[] = {
      {"the measured point", &PositionForms(), &position_},
      {"the orientation", &OrientationForms(), &orientation_},
      {"the distance", &DistanceForms(), &distance_},
      {"the standard deviation", &SigmaForms(), &sigma_},
      {"the standard deviation per axis", &SigmaAxesForms(), &sigma_axes_},
      {"the orientation's standard deviation", &SigmaRotationForms(),
       &sigma_rad_},
  };
  for (const Quantity& q : quantities) {
    if (!ChooseForm(table_, q.name, *q.forms, q.chosen, error)) return false;
    if (*q.chosen >= 0) {
      for (const std::string& c : (*q.forms)[*q.chosen].columns) known_[c] = 1;
    }
  }
  if (sigma_ >= 0 && sigma_axes_ >= 0) {
    const bool mm = sigma_ == kSigmaMm || sigma_ == kU95Mm;
    if (sigma_ == kU95M || sigma_ == kU95Mm || mm != (sigma_axes_ == 1)) {
      return table_.Fail(
          table_.header_line(),
          "the standard deviation is given both as " +
              SigmaForms()[sigma_].columns[0] + " and as " +
              Join(SigmaAxesForms()[sigma_axes_].columns) +
              ": a file holds one representation of each quantity",
          error);
    }
  }
  if (table_.Has("type")) known_["type"] = 1;
  if (table_.Has("marker")) known_["marker"] = 1;
  // A fixed point's label (type=point rows).
  if (table_.Has("point")) known_["point"] = 1;
  // A touched plane's label and the probe ball's radius (type=plane rows).
  for (const char* c : {"plane", "probe_radius_m", "probe_radius_mm"}) {
    if (table_.Has(c)) known_[c] = 1;
  }
  if (table_.Has("probe_radius_m") && table_.Has("probe_radius_mm")) {
    return table_.Fail(table_.header_line(),
                       "the probe radius is given both as probe_radius_m and "
                       "as probe_radius_mm: a file holds one representation "
                       "of each quantity",
                       error);
  }
  // The commanded poses of ISO 9283 cycles (ParseCommandedPosesCsv reads
  // them): known, so neither a note nor an error of strict columns.
  if (table_.Has("pose")) known_["pose"] = 1;
  for (const auto* forms :
       {&CommandedPositionForms(), &CommandedOrientationForms()}) {
    for (const Form& f : *forms) {
      for (const std::string& c : f.columns) {
        if (table_.Has(c)) known_[c] = 1;
      }
    }
  }
  // The wide form of motion capture: x1_m, y1_m, z1_m, x2_m, ...
  std::string unit;
  for (size_t c = 0; c < table_.header().size(); ++c) {
    const std::string& name = table_.header()[c];
    int axis, marker;
    double scale;
    if (Known(name) || !WideColumn(name, &axis, &marker, &scale)) continue;
    const std::string this_unit = scale == 1.0 ? "_m" : "_mm";
    if (!unit.empty() && unit != this_unit) {
      return table_.Fail(table_.header_line(),
                         "marker positions are given both in " +
                             unit.substr(1) + " and in " + this_unit.substr(1) +
                             " ('" + name +
                             "'): a file holds one unit of each quantity",
                         error);
    }
    unit = this_unit;
    wide_divisor_ = scale == 1.0 ? 1.0 : 1e3;
    if (marker < 1 || marker > model_.num_markers()) {
      return table_.Fail(
          table_.header_line(),
          "column '" + name + "' is for marker " + std::to_string(marker) +
              ", but the model has " + std::to_string(model_.num_markers()) +
              " marker(s) (numbered from 1; add markers with --frames or "
              "the robot file)",
          error);
    }
    wide_.emplace(marker, std::array<int, 3>{-1, -1, -1});
    if (wide_[marker][axis] >= 0) {  // x1_m and x01_m
      return table_.Fail(table_.header_line(),
                         "columns '" + table_.header()[wide_[marker][axis]] +
                             "' and '" + name + "' both give marker " +
                             std::to_string(marker) + "'s " +
                             std::string(1, name[0]),
                         error);
    }
    wide_[marker][axis] = static_cast<int>(c);
    known_[name] = 1;
  }
  for (const auto& [marker, columns] : wide_) {
    static const char kAxis[] = "xyz";
    for (int a = 0; a < 3; ++a) {
      if (columns[a] < 0) {
        return table_.Fail(table_.header_line(),
                           "marker " + std::to_string(marker) +
                               " has no column '" + kAxis[a] +
                               std::to_string(marker) + unit + "'",
                           error);
      }
    }
  }
  if (!wide_.empty()) {
    if (position_ >= 0) {
      return table_.Fail(table_.header_line(),
                         "the measured point is given both as " +
                             Join(PositionForms()[position_].columns) +
                             " and as numbered markers (x1" + unit +
                             ", ...): a file holds one representation of "
                             "each quantity",
                         error);
    }
    if (table_.Has("marker")) {
      return table_.Fail(table_.header_line(),
                         "a 'marker' column and numbered marker columns (x1" +
                             unit +
                             ", ...): the numbers already say which "
                             "marker each column is",
                         error);
    }
  }
  return true;
}

JointUnit MeasurementsReader::UnitOf(const JointColumnPair& cols, int j) const {
  const bool rev = Revolute(model_, j);
  if (table_.Has(cols.si)) return {cols.si, rev ? "rad" : "m", 1.0};
  return {cols.display, rev ? "deg" : "mm", DisplayScale(model_, j)};
}

bool MeasurementsReader::ReadJointsOf(const Row& row,
                                      const std::vector<JointColumnPair>& cols,
                                      bool second, Eigen::VectorXd* q,
                                      std::string* error) {
  q->resize(model_.num_joints());
  for (int j = 0; j < model_.num_joints(); ++j) {
    if (!ReadJoint(table_, row, model_, j, cols[j], &(*q)[j], error)) {
      return false;
    }
  }
  return CheckLimits(row, cols, second, *q, error);
}

bool MeasurementsReader::CheckLimits(const Row& row,
                                     const std::vector<JointColumnPair>& cols,
                                     bool second, const Eigen::VectorXd& q,
                                     std::string* error) {
  for (int j = 0; j < model_.num_joints(); ++j) {
    const Link& l = model_.links[j];
    const double excess = model_.JointRangeExcess(j, q[j]);
    if (excess == 0.0) continue;
    const bool above = q[j] > l.joint_max;
    const JointUnit unit = UnitOf(cols[j], j);
    const double tolerance = Revolute(model_, j) ? options_.limit_tolerance_rad
                                                 : options_.limit_tolerance_m;
    if (options_.strict_limits || excess > tolerance) {
      auto in_unit = [&](double v) {
        return FormatNumber("%.6g", v / unit.scale) + " " + unit.name;
      };
      std::string what =
          unit.column + ": " + in_unit(q[j]) + " is " + in_unit(excess) +
          " beyond " + JointLabel(j) + "'s range [" +
          FormatNumber("%.6g", l.joint_min / unit.scale) + ", " +
          FormatNumber("%.6g", l.joint_max / unit.scale) + "] " + unit.name;
      if (options_.strict_limits) {
        what += " (strict limits: no reading may lie outside the range)";
      } else {
        what += ", more than the tolerance of " + in_unit(tolerance) +
                " for joint readings (wrong units, or a file of another "
                "robot?)";
      }
      return table_.Fail(row.line, (second ? "second pose: " : "") + what,
                         error);
    }
    LimitExcess& e = excess_[j];
    (second ? e.second_pose : e.first_pose) = true;
    LimitExcess::Side& side = e.side[above ? 0 : 1];
    side.max_excess = std::max(side.max_excess, excess);
    if (side.last_counted_line != row.line) {
      ++side.rows;
      side.last_counted_line = row.line;
      if (side.first_line == 0) side.first_line = row.line;
    }
    if (last_beyond_line_ != row.line) {
      ++rows_beyond_;
      last_beyond_line_ = row.line;
    }
  }
  return true;
}

// Reads the chosen form of a quantity into values (scaled to SI). A used
// quantity must be there and filled (`given` null) or may be empty
// (`given` set to whether it was filled); an unused one must be empty.
bool MeasurementsReader::ReadForm(const Row& row,
                                  const std::vector<Form>& forms, int form,
                                  bool used, const std::string& what,
                                  const std::string& type, double* values,
                                  bool* given, std::string* error,
                                  double* raw) {
  if (given) *given = false;
  if (form < 0) {
    if (!used || given) return true;
    std::string list;
    for (const Form& f : forms)
      list += (list.empty() ? "" : "; ") + Join(f.columns);
    return table_.Fail(table_.header_line(),
                       "a " + type + " row needs " + what +
                           ": the header has "
                           "none of " +
                           list,
                       error);
  }
  const Form& f = forms[form];
  int filled = 0;
  for (const std::string& c : f.columns) filled += !table_.Empty(row, c);
  if (!used) {
    for (const std::string& c : f.columns) {
      if (!table_.Empty(row, c)) {
        return table_.Fail(row.line,
                           c + ": a " + type +
                               " measurement has no such value; leave it empty",
                           error);
      }
    }
    return true;
  }
  if (given) {
    if (filled == 0) return true;
    if (filled != static_cast<int>(f.columns.size())) {
      for (const std::string& c : f.columns) {
        if (table_.Empty(row, c)) {
          return table_.Fail(row.line,
                             c + ": empty, but the row gives the rest of " +
                                 Join(f.columns) + "; fill all or none",
                             error);
        }
      }
    }
    *given = true;
  }
  for (size_t k = 0; k < f.columns.size(); ++k) {
    if (!table_.Number(row, f.columns[k], &values[k], error)) return false;
    if (raw) raw[k] = values[k];  // as written, for messages
    const double written = values[k];
    values[k] = values[k] * f.scale / f.divisor;
    if (f.length &&
        !WithinReach(row, f.columns[k], written, values[k], error)) {
      return false;
    }
  }
  return true;
}

bool MeasurementsReader::ReadRow(const Row& row, std::vector<Measurement>* out,
                                 std::vector<int>* lines, std::string* error) {
  Measurement m;
  std::string type;
  if (table_.Has("type")) {
    type = row.fields[table_.Column("type")];
    if (!ParseMeasurementType(type, &m.type)) {
      return table_.Fail(
          row.line,
          "type: expected position, pose, distance, point or plane, got '" +
              type + "'",
          error);
    }
  } else {
    m.type =
        orientation_ >= 0 ? MeasurementType::kPose : MeasurementType::kPosition;
    type = MeasurementTypeName(m.type);
  }
  if (m.type == MeasurementType::kPointDistance) {
    return table_.Fail(row.line,
                       "type: a known distance between fixed points is given "
                       "in the points file (--points), not as a row",
                       error);
  }
  if (!wide_.empty() && m.type != MeasurementType::kPosition) {
    return table_.Fail(row.line,
                       "type: a file of numbered marker columns (x1_m, ...) "
                       "holds position rows only, got '" +
                           type + "'",
                       error);
  }
  if (!ReadJointsOf(row, joints_, false, &m.joints, error)) return false;
  if (table_.Has("marker") && !table_.Empty(row, "marker")) {
    const std::string name = row.fields[table_.Column("marker")];
    m.marker = model_.MarkerIndex(name);
    if (m.marker < 0) {
      std::string list;
      for (int k = 0; k < model_.num_markers(); ++k) {
        list += (k ? ", " : "") + model_.block_name(model_.marker_block(k));
      }
      return table_.Fail(row.line,
                         "marker: '" + name +
                             "' is not a marker of the model (its markers: " +
                             list + ", or their numbers 1.." +
                             std::to_string(model_.num_markers()) + ")",
                         error);
    }
  }
  const bool pose = m.type == MeasurementType::kPose;
  const bool distance = m.type == MeasurementType::kDistance;
  const bool point = m.type == MeasurementType::kPoint;
  // A label column (point, plane): read into *label on a row of the type
  // it belongs to (`wanted`), where it is required (`needs`: what the row
  // needs), and refused on any other row.
  auto read_label = [&](const char* column, bool wanted, const char* needs,
                        std::string* label) {
    const bool labelled = table_.Has(column) && !table_.Empty(row, column);
    if (wanted && !labelled) {
      return table_.Fail(row.line, std::string(column) + ": " + needs, error);
    }
    if (!wanted && labelled) {
      return table_.Fail(row.line,
                         std::string(column) + ": a " + type +
                             " measurement has no such value; leave it empty",
                         error);
    }
    if (wanted) *label = row.fields[table_.Column(column)];
    return true;
  };
  // A fixed point's row: its label, no coordinates (they are unknowns).
  if (!read_label("point", point,
                  "a point row needs the label of its fixed point (column "
                  "'point')",
                  &m.point)) {
    return false;
  }
  // A touch of a plane: its label, no coordinates, optionally the probe
  // ball's radius.
  const bool plane = m.type == MeasurementType::kPlane;
  if (!read_label("plane", plane,
                  "a plane row needs the label of the plane it touched "
                  "(column 'plane')",
                  &m.plane)) {
    return false;
  }
  for (const char* c : {"probe_radius_m", "probe_radius_mm"}) {
    if (!table_.Has(c) || table_.Empty(row, c)) continue;
    if (!plane) {
      return table_.Fail(row.line,
                         std::string(c) + ": a " + type +
                             " measurement has no such value; leave it empty",
                         error);
    }
    double r = 0.0;
    if (!table_.Number(row, c, &r, error)) return false;
    if (!(r >= 0) || !std::isfinite(r)) {
      return table_.Fail(row.line,
                         std::string(c) +
                             ": a probe radius must be >= 0, got " +
                             ShortestText(r),
                         error);
    }
    m.probe_radius_m = std::string(c) == "probe_radius_mm" ? r / 1e3 : r;
  }
  double v[4];
  if (wide_.empty() &&
      !ReadForm(row, PositionForms(), position_, !distance && !point && !plane,
                "a measured point", type, v, nullptr, error)) {
    return false;
  }
  if (wide_.empty() && !distance && !point && !plane)
    m.position = Eigen::Vector3d(v[0], v[1], v[2]);
  if (!ReadForm(row, OrientationForms(), orientation_, pose, "an orientation",
                type, v, nullptr, error)) {
    return false;
  }
  if (pose && !RotationVectorFromForm(table_, row, orientation_, v, &m.rotation,
                                      error)) {
    return false;
  }
  if (!ReadForm(row, DistanceForms(), distance_, distance, "a distance", type,
                &m.distance, nullptr, error)) {
    return false;
  }
  if (distance) {
    if (!ReadJointsOf(row, joints2_, true, &m.joints2, error)) return false;
  } else {
    for (const JointColumnPair& p : joints2_) {
      for (const std::string& c : {p.si, p.display}) {
        if (!table_.Empty(row, c)) {
          return table_.Fail(row.line,
                             c + ": a " + type +
                                 " measurement has no such value; leave it "
                                 "empty",
                             error);
        }
      }
    }
  }
  // Standard deviations: empty cells are "not given".
  bool iso_given = false, axes_given = false, rad_given = false;
  double sigma = 0, axes[3] = {0, 0, 0}, sigma_rad = 0;
  double sigma_raw = 0, axes_raw[3] = {0, 0, 0}, sigma_rad_raw = 0;
  if (!ReadForm(row, SigmaForms(), sigma_, true, "", type, &sigma, &iso_given,
                error, &sigma_raw) ||
      !ReadForm(row, SigmaAxesForms(), sigma_axes_, !distance, "", type, axes,
                &axes_given, error, axes_raw) ||
      !ReadForm(row, SigmaRotationForms(), sigma_rad_, pose, "", type,
                &sigma_rad, &rad_given, error, &sigma_rad_raw)) {
    return false;
  }
  if (iso_given && axes_given) {
    return table_.Fail(row.line,
                       SigmaForms()[sigma_].columns[0] + " and " +
                           Join(SigmaAxesForms()[sigma_axes_].columns) +
                           ": the row gives its standard deviation twice; "
                           "leave one empty",
                       error);
  }
  auto positive = [&](const std::string& column, double value) {
    if (value > 0) return true;
    return table_.Fail(row.line,
                       column + ": a standard deviation must be > 0, got " +
                           ShortestText(value) +
                           " (leave the cell empty when it is not known)",
                       error);
  };
  if (iso_given) {
    if (!positive(SigmaForms()[sigma_].columns[0], sigma_raw)) return false;
    m.sigma_m = distance ? Eigen::Vector3d(sigma, 0, 0)
                         : Eigen::Vector3d::Constant(sigma);
  }
  if (axes_given) {
    for (int k = 0; k < 3; ++k) {
      if (!positive(SigmaAxesForms()[sigma_axes_].columns[k], axes_raw[k])) {
        return false;
      }
    }
    m.sigma_m = Eigen::Vector3d(axes[0], axes[1], axes[2]);
  }
  if (rad_given) {
    if (!positive(SigmaRotationForms()[sigma_rad_].columns[0], sigma_rad_raw)) {
      return false;
    }
    m.sigma_rad = sigma_rad;
  }
  std::vector<Measurement> row_out;
  if (wide_.empty()) {
    row_out.push_back(std::move(m));
  } else {
    for (const auto& [marker, columns] : wide_) {
      int filled = 0;
      for (int c : columns) filled += !row.fields[c].empty();
      if (filled == 0) {
        ++unseen_[marker];
        continue;
      }
      Measurement mk = m;
      mk.marker = marker - 1;
      for (int a = 0; a < 3; ++a) {
        const std::string& column = table_.header()[columns[a]];
        if (filled != 3 && row.fields[columns[a]].empty()) {
          return table_.Fail(row.line,
                             column + ": empty, but marker " +
                                 std::to_string(marker) +
                                 "'s other coordinates are given: fill all "
                                 "three or none (not seen)",
                             error);
        }
        if (!table_.Number(row, column, &mk.position[a], error)) return false;
        const double written = mk.position[a];
        mk.position[a] /= wide_divisor_;
        if (!WithinReach(row, column, written, mk.position[a], error)) {
          return false;
        }
      }
      row_out.push_back(std::move(mk));
    }
  }
  for (Measurement& r : row_out) {
    std::string why;
    if (!CheckMeasurement(model_, r, &why)) {
      return table_.Fail(row.line, why, error);
    }
    out->push_back(std::move(r));
    lines->push_back(row.line);
  }
  return true;
}

std::string MeasurementsReader::Warning(int num_rows) const {
  std::string text =
      source_ + ": " + std::to_string(rows_beyond_) + " of " +
      std::to_string(num_rows) +
      " rows have joint readings beyond the joint limits, "
      "accepted within the tolerance (" +
      FormatNumber("%.6g", options_.limit_tolerance_rad / kDegree) + " deg, " +
      FormatNumber("%.6g", options_.limit_tolerance_m * 1e3) +
      " mm; strict limits refuse them):";
  bool first = true;
  for (int j = 0; j < model_.num_joints(); ++j) {
    const LimitExcess& e = excess_[j];
    if (e.rows() == 0) continue;
    // The column(s) the readings are in: the first pose's, the second's
    // (a distance), or both; the unit of the first named.
    const JointUnit unit = UnitOf(e.first_pose ? joints_[j] : joints2_[j], j);
    std::string columns = unit.column;
    if (e.first_pose && e.second_pose) {
      columns += ", " + UnitOf(joints2_[j], j).column;
    }
    const Link& l = model_.links[j];
    text +=
        std::string(first ? " " : "; ") + columns + " (" + JointLabel(j) + ")";
    // Above and below apart: one reading above and one below are not two
    // readings below.
    bool first_side = true;
    for (int k = 0; k < 2; ++k) {
      const LimitExcess::Side& side = e.side[k];
      if (side.rows == 0) continue;
      const bool above = k == 0;
      text += std::string(first_side ? "" : ",") + " up to " +
              FormatNumber("%.6g", side.max_excess / unit.scale) + " " +
              unit.name +
              (above ? " above its upper limit " : " below its lower limit ") +
              FormatNumber("%.6g",
                           (above ? l.joint_max : l.joint_min) / unit.scale) +
              " " + unit.name + " in " + std::to_string(side.rows) + " row" +
              (side.rows == 1 ? "" : "s") + " (first: line " +
              std::to_string(side.first_line) + ")";
      first_side = false;
    }
    first = false;
  }
  return text;
}

bool MeasurementsReader::Read(std::vector<Measurement>* out,
                              MeasurementsCsvReport* report,
                              std::string* error) {
  if (!ResolveHeader(error)) return false;
  if (!table_.Has("type") && has_second_) {
    return table_.RequireColumn("type", error);
  }
  std::vector<std::string> extra;
  if (!UnreadColumns(
          table_, [this](const std::string& c) { return Known(c); },
          options_.columns_strict, &extra, error)) {
    return false;
  }
  if (table_.rows().empty()) {
    return table_.Fail(table_.header_line(), "no measurements after the header",
                       error);
  }
  std::vector<Measurement> measurements;
  std::vector<int> lines;
  for (const Row& row : table_.rows()) {
    if (!ReadRow(row, &measurements, &lines, error)) return false;
  }
  // Fixed points: each label reached from two configurations at least.
  std::string why;
  if (!CheckPointLabels(measurements, &why)) {
    // "measurement <i>: ...": the row's line instead.
    const size_t colon = why.find(": ");
    const int i = std::stoi(why.substr(std::string("measurement ").size()));
    return table_.Fail(lines[i], why.substr(colon + 2), error);
  }
  // Planes: each touched three times at least.
  if (!CheckPlaneLabels(measurements, &why)) {
    const size_t colon = why.find(": ");
    const int i = std::stoi(why.substr(std::string("measurement ").size()));
    return table_.Fail(lines[i], why.substr(colon + 2), error);
  }
  if (measurements.empty()) {
    return table_.Fail(table_.header_line(),
                       "no measurements: no marker was seen in any row", error);
  }
  MeasurementsCsvReport r;
  if (rows_beyond_ > 0) {
    r.warnings.push_back(Warning(static_cast<int>(table_.rows().size())));
  }
  if (!extra.empty()) r.notes.push_back(UnreadNote(source_, extra));
  if (!unseen_.empty()) {
    int total = 0;
    std::string list;
    for (const auto& [marker, count] : unseen_) {
      total += count;
      list += (list.empty() ? "" : ", ") + std::string("marker ") +
              std::to_string(marker) + " in " + std::to_string(count) + " row" +
              (count > 1 ? "s" : "");
    }
    r.notes.push_back(source_ + ": " + std::to_string(total) +
                      " marker position" + (total > 1 ? "s" : "") +
                      " left empty (not seen) skipped: " + list);
  }
  r.lines = std::move(lines);
  *out = std::move(measurements);
  if (report) *report = std::move(r);
  return true;
}

}  // namespace

std::vector<std::string> MeasurementsCsvFixedColumns() {
  // The forms above, every one (a new quantity's forms go here too).
  std::vector<std::string> names = {"type", "marker", "pose_index", "pose"};
  for (const std::vector<Form>* forms :
       {&PositionForms(), &OrientationForms(), &CommandedPositionForms(),
        &CommandedOrientationForms(), &DistanceForms(), &SigmaForms(),
        &SigmaAxesForms(), &SigmaRotationForms()}) {
    for (const Form& f : *forms) {
      names.insert(names.end(), f.columns.begin(), f.columns.end());
    }
  }
  return names;
}

bool IsMeasurementsCsvColumn(const std::string& name, const RobotModel& model) {
  static const std::set<std::string> kFixed = [] {
    const std::vector<std::string> names = MeasurementsCsvFixedColumns();
    return std::set<std::string>(names.begin(), names.end());
  }();
  if (kFixed.count(name)) return true;
  for (int j = 0; j < model.num_joints(); ++j) {
    const bool rev = Revolute(model, j);
    const std::string joint = model.block_name(j + 1);
    for (const std::string& suffix : {std::string(""), std::string("_2")}) {
      const JointColumnPair q = QColumns(model, j, suffix);
      for (const std::string& c :
           {q.si, q.display, joint + (rev ? "_rad" : "_m") + suffix,
            joint + (rev ? "_deg" : "_mm") + suffix}) {
        if (name == c) return true;
      }
    }
  }
  int axis, marker;
  double scale;
  return WideColumn(name, &axis, &marker, &scale);
}

namespace internal {

bool ParsePointTable(const std::string& text, const std::string& source,
                     const RobotModel& model, bool columns_strict,
                     PointTable* out, std::string* error) {
  Table table;
  if (!table.Parse(text, source, error)) return false;
  if (!CheckNoExtraJoints(table, model, error)) return false;
  int position = -1, orientation = -1;
  if (!ChooseForm(table, "the target point", PositionForms(), &position,
                  error) ||
      !ChooseForm(table, "the orientation", OrientationForms(), &orientation,
                  error)) {
    return false;
  }
  if (position < 0) {
    return table.Fail(table.header_line(),
                      "the header has no column 'x_m' (the target point: "
                      "x_m,y_m,z_m or x_mm,y_mm,z_mm)",
                      error);
  }
  std::vector<JointColumnPair> joints, unused;
  int num_joints = 0;
  if (!ResolveJointColumns(table, model, /*required=*/false, &joints, &unused,
                           &num_joints, error)) {
    return false;
  }
  const int nj = model.num_joints();
  if (num_joints != 0 && num_joints != nj) {
    int have = 0, lack = 0;
    auto present = [&](int j) {
      return table.Has(joints[j].si) || table.Has(joints[j].display);
    };
    while (!present(have)) ++have;
    while (present(lack)) ++lack;
    return table.Fail(table.header_line(),
                      "the header has joint columns for joint " +
                          std::to_string(have + 1) + " but not for joint " +
                          std::to_string(lack + 1) + " ('" + joints[lack].si +
                          "' or '" + joints[lack].display +
                          "'): give every joint or none",
                      error);
  }
  std::set<std::string> known = {"pose_index"};
  for (const std::string& c : PositionForms()[position].columns)
    known.insert(c);
  if (orientation >= 0) {
    for (const std::string& c : OrientationForms()[orientation].columns) {
      known.insert(c);
    }
  }
  for (const JointColumnPair& p : joints) {
    for (const std::string& c : {p.si, p.display}) {
      if (table.Has(c)) known.insert(c);
    }
  }
  PointTable t;
  if (!UnreadColumns(
          table, [&](const std::string& c) { return known.count(c) > 0; },
          columns_strict, &t.unread, error)) {
    return false;
  }
  const int n = static_cast<int>(table.rows().size());
  if (n == 0) {
    return table.Fail(table.header_line(), "no targets after the header",
                      error);
  }
  t.lines.resize(n);
  t.pose_indices.resize(n);
  t.points.resize(n, 3);
  if (orientation >= 0) t.rotation_vectors.resize(n, 3);
  t.rotation_given_as_vector = orientation == kRotvec;
  if (num_joints > 0) t.joints.resize(n, nj);
  const Form& point = PositionForms()[position];
  for (int i = 0; i < n; ++i) {
    const Row& row = table.rows()[i];
    t.lines[i] = row.line;
    t.pose_indices[i] = i;
    if (table.Has("pose_index") &&
        !ReadPoseIndex(table, row, &t.pose_indices[i], error)) {
      return false;
    }
    for (int a = 0; a < 3; ++a) {
      double v;
      if (!table.Number(row, point.columns[a], &v, error)) return false;
      t.points(i, a) = v * point.scale / point.divisor;
      if (!(std::abs(t.points(i, a)) <= kMaxLengthM)) {
        return table.Fail(row.line,
                          point.columns[a] + ": " + FormatNumber("%.6g", v) +
                              (point.divisor == 1.0 ? " m" : " mm") +
                              " is more than " +
                              FormatNumber("%.6g", kMaxLengthM / 1e3) +
                              " km: a corrupt cell or a wrong unit",
                          error);
      }
    }
    if (orientation >= 0) {
      const Form& f = OrientationForms()[orientation];
      double v[4];
      for (size_t k = 0; k < f.columns.size(); ++k) {
        if (!table.Number(row, f.columns[k], &v[k], error)) return false;
        v[k] *= f.scale;
      }
      Eigen::Vector3d r;
      if (!RotationVectorFromForm(table, row, orientation, v, &r, error)) {
        return false;
      }
      t.rotation_vectors.row(i) = r.transpose();
    }
    for (int j = 0; j < nj && num_joints > 0; ++j) {
      if (!ReadJoint(table, row, model, j, joints[j], &t.joints(i, j), error)) {
        return false;
      }
    }
  }
  *out = std::move(t);
  return true;
}

std::string UnreadColumnsNote(const std::string& source,
                              const std::vector<std::string>& unread) {
  return UnreadNote(source, unread);
}

}  // namespace internal

bool MeasurementsCsvOptions::IsValid(std::string* error) const {
  if (!(limit_tolerance_rad >= 0 &&
        limit_tolerance_rad <= kMeasuredJointToleranceRad &&
        limit_tolerance_m >= 0 &&
        limit_tolerance_m <= kMeasuredJointToleranceM)) {
    if (error) {
      *error = "joint limit tolerances must be in [0, " +
               FormatNumber("%.6g", kMeasuredJointToleranceRad) +
               "] rad and [0, " +
               FormatNumber("%.6g", kMeasuredJointToleranceM) + "] m, got " +
               ShortestText(limit_tolerance_rad) + " rad and " +
               ShortestText(limit_tolerance_m) + " m";
    }
    return false;
  }
  return true;
}

std::string MeasurementsCsvText(const RobotModel& model,
                                const std::vector<Measurement>& measurements,
                                const MeasurementsCsvFormat& format) {
  bool any_pose = false, any_distance = false, any_marker = false;
  bool any_iso = false, any_axes = false, any_sigma_rad = false;
  bool any_point = false, any_plane = false;
  for (const Measurement& m : measurements) {
    any_pose |= m.type == MeasurementType::kPose;
    any_plane |= m.type == MeasurementType::kPlane;
    any_point |= m.type == MeasurementType::kPoint;
    any_distance |= m.type == MeasurementType::kDistance;
    any_marker |= m.marker != 0;
    any_sigma_rad |= m.type == MeasurementType::kPose && m.sigma_rad != 0;
    if (m.type == MeasurementType::kDistance) {
      any_iso |= m.sigma_m[0] != 0;
    } else if (m.sigma_m != Eigen::Vector3d::Zero()) {
      const bool iso =
          m.sigma_m[0] == m.sigma_m[1] && m.sigma_m[0] == m.sigma_m[2];
      (iso ? any_iso : any_axes) = true;
    }
  }
  const int nj = model.num_joints();
  const double length = format.millimetres ? 1e3 : 1.0;
  const std::string lu = format.millimetres ? "_mm" : "_m";
  auto joint_column = [&](int j) {
    const bool rev = Revolute(model, j);
    const std::string unit =
        format.joint_degrees ? (rev ? "_deg" : "_mm") : (rev ? "_rad" : "_m");
    return (format.joint_names ? model.block_name(j + 1)
                               : "q" + std::to_string(j + 1)) +
           unit;
  };
  auto joint_value = [&](const Eigen::VectorXd& q, int j) {
    return ShortestText(format.joint_degrees ? q[j] / DisplayScale(model, j)
                                             : q[j]);
  };
  static const char* const kOrientation[][4] = {
      {"rx_rad", "ry_rad", "rz_rad", nullptr},
      {"qw", "qx", "qy", "qz"},
      {"roll_rad", "pitch_rad", "yaw_rad", nullptr},
      {"roll_deg", "pitch_deg", "yaw_deg", nullptr}};
  const int of = static_cast<int>(format.orientation);
  const int num_orientation = of == 1 ? 4 : 3;
  std::ostringstream out;
  out << "type";
  if (any_point) out << ",point";
  if (any_plane) out << ",plane,probe_radius" << lu;
  if (any_marker) out << ",marker";
  for (int j = 0; j < nj; ++j) out << "," << joint_column(j);
  out << ",x" << lu << ",y" << lu << ",z" << lu;
  if (any_pose) {
    for (int k = 0; k < num_orientation; ++k) out << "," << kOrientation[of][k];
  }
  if (any_distance) {
    for (int j = 0; j < nj; ++j) out << "," << joint_column(j) << "_2";
    out << ",distance" << lu;
  }
  if (any_iso) out << ",sigma" << lu;
  if (any_axes) out << ",sigma_x" << lu << ",sigma_y" << lu << ",sigma_z" << lu;
  if (any_sigma_rad) out << ",sigma_rad";
  out << "\n";
  for (const Measurement& m : measurements) {
    out << MeasurementTypeName(m.type);
    if (any_point) out << "," << m.point;
    if (any_plane) {
      const bool plane = m.type == MeasurementType::kPlane;
      out << "," << m.plane << ","
          << (plane ? ShortestText(m.probe_radius_m * length) : "");
    }
    if (any_marker)
      out << "," << model.block_name(model.marker_block(m.marker));
    for (int j = 0; j < nj; ++j) out << "," << joint_value(m.joints, j);
    const bool distance = m.type == MeasurementType::kDistance;
    const bool pose = m.type == MeasurementType::kPose;
    // A fixed point's row has no coordinates (they are unknowns).
    const bool no_point = distance || m.type == MeasurementType::kPoint ||
                          m.type == MeasurementType::kPlane;
    for (int k = 0; k < 3; ++k) {
      out << "," << (no_point ? "" : ShortestText(m.position[k] * length));
    }
    if (any_pose) {
      double v[4] = {0, 0, 0, 0};
      if (pose) {
        // In extended precision, as the reader.
        const Eigen::Matrix<long double, 3, 1> r =
            m.rotation.cast<long double>();
        const long double angle = r.norm();
        const Eigen::AngleAxis<long double> aa(
            angle, angle > 0 ? Eigen::Matrix<long double, 3, 1>(r / angle)
                             : Eigen::Matrix<long double, 3, 1>::UnitX());
        if (format.orientation == OrientationFormat::kRotationVector) {
          for (int k = 0; k < 3; ++k) v[k] = m.rotation[k];
        } else if (format.orientation == OrientationFormat::kQuaternion) {
          Eigen::Quaternion<long double> quat(aa);
          if (quat.w() < 0) quat.coeffs() *= -1;
          v[0] = static_cast<double>(quat.w());
          v[1] = static_cast<double>(quat.x());
          v[2] = static_cast<double>(quat.y());
          v[3] = static_cast<double>(quat.z());
        } else {
          const Eigen::Vector3d rpy =
              RotationToRpy(aa.toRotationMatrix().cast<double>());
          const double scale =
              format.orientation == OrientationFormat::kRpyDeg ? kDegree : 1.0;
          for (int k = 0; k < 3; ++k) v[k] = rpy[k] / scale;
        }
      }
      for (int k = 0; k < num_orientation; ++k) {
        out << "," << (pose ? ShortestText(v[k]) : "");
      }
    }
    if (any_distance) {
      for (int j = 0; j < nj; ++j) {
        out << "," << (distance ? joint_value(m.joints2, j) : "");
      }
      out << "," << (distance ? ShortestText(m.distance * length) : "");
    }
    const bool iso = distance ? m.sigma_m[0] != 0
                              : m.sigma_m != Eigen::Vector3d::Zero() &&
                                    m.sigma_m[0] == m.sigma_m[1] &&
                                    m.sigma_m[0] == m.sigma_m[2];
    const bool axes = !distance && !iso && m.sigma_m != Eigen::Vector3d::Zero();
    if (any_iso) out << "," << (iso ? ShortestText(m.sigma_m[0] * length) : "");
    if (any_axes) {
      for (int k = 0; k < 3; ++k) {
        out << "," << (axes ? ShortestText(m.sigma_m[k] * length) : "");
      }
    }
    if (any_sigma_rad) {
      out << "," << (pose && m.sigma_rad != 0 ? ShortestText(m.sigma_rad) : "");
    }
    out << "\n";
  }
  return out.str();
}

namespace {

// The column map hook: with options.column_map, the text in activecal's
// own form (column_map.h) into *mapped.
bool ApplyColumnMapOption(const MeasurementsCsvOptions& options,
                          const RobotModel& model, const std::string& text,
                          const std::string& source, std::string* mapped,
                          std::vector<std::string>* notes, std::string* error) {
  return !options.column_map || ApplyColumnMap(*options.column_map, model, text,
                                               source, mapped, notes, error);
}

}  // namespace

bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          const MeasurementsCsvOptions& options,
                          std::vector<Measurement>* measurements,
                          MeasurementsCsvReport* report, std::string* error) {
  if (!options.IsValid(error)) return false;
  std::string mapped;
  std::vector<std::string> map_notes;
  if (!ApplyColumnMapOption(options, model, text, source, &mapped, &map_notes,
                            error)) {
    return false;
  }
  Table table;
  if (!table.Parse(options.column_map ? mapped : text, source, error)) {
    return false;
  }
  if (!CheckNoExtraJoints(table, model, error)) return false;
  MeasurementsReader reader(table, source, model, options);
  if (!reader.Read(measurements, report, error)) return false;
  if (report) {
    report->notes.insert(report->notes.begin(), map_notes.begin(),
                         map_notes.end());
  }
  return true;
}

bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         const MeasurementsCsvOptions& options,
                         std::vector<Measurement>* measurements,
                         MeasurementsCsvReport* report, std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseMeasurementsCsv(text, path, model, options, measurements, report,
                              error);
}

bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          std::vector<Measurement>* measurements,
                          std::string* error) {
  return ParseMeasurementsCsv(text, source, model, MeasurementsCsvOptions(),
                              measurements, nullptr, error);
}

bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         std::vector<Measurement>* measurements,
                         std::string* error) {
  return ReadMeasurementsCsv(path, model, MeasurementsCsvOptions(),
                             measurements, nullptr, error);
}

// ---------------------------------------------------------------------------
// The commanded poses of ISO 9283 cycles.

bool ParseCommandedPosesCsv(const std::string& text, const std::string& source,
                            const RobotModel& model,
                            const MeasurementsCsvOptions& options,
                            std::vector<CommandedPose>* poses,
                            std::string* error) {
  std::string mapped;
  std::vector<std::string> notes;
  if (!ApplyColumnMapOption(options, model, text, source, &mapped, &notes,
                            error)) {
    return false;
  }
  Table table;
  if (!table.Parse(options.column_map ? mapped : text, source, error)) {
    return false;
  }
  int position = -1, orientation = -1;
  if (!ChooseForm(table, "the commanded point", CommandedPositionForms(),
                  &position, error) ||
      !ChooseForm(table, "the commanded orientation",
                  CommandedOrientationForms(), &orientation, error)) {
    return false;
  }
  if (!table.Has("pose")) {
    return table.Fail(table.header_line(),
                      "the header has no column 'pose' (the label the cycles "
                      "to one commanded pose share: P1, P2, ...)",
                      error);
  }
  if (position < 0) {
    return table.Fail(table.header_line(),
                      "the header has no column 'commanded_x_m' (the "
                      "commanded point: commanded_x_m,commanded_y_m,"
                      "commanded_z_m or commanded_x_mm,commanded_y_mm,"
                      "commanded_z_mm)",
                      error);
  }
  const Form& pf = CommandedPositionForms()[position];
  std::vector<CommandedPose> out;
  for (const Row& row : table.rows()) {
    CommandedPose c;
    c.line = row.line;
    c.pose = row.fields[table.Column("pose")];
    if (c.pose.empty()) return table.Fail(row.line, "pose: empty", error);
    for (int k = 0; k < 3; ++k) {
      double v;
      if (!table.Number(row, pf.columns[k], &v, error)) return false;
      c.position[k] = v * pf.scale / pf.divisor;
      if (!(std::abs(c.position[k]) <= kMaxLengthM)) {
        return table.Fail(row.line,
                          pf.columns[k] + ": " + FormatNumber("%.6g", v) +
                              " is more than " +
                              FormatNumber("%.6g", kMaxLengthM / 1e3) +
                              " km: a corrupt cell or a wrong unit",
                          error);
      }
    }
    if (orientation >= 0) {
      const Form& of = CommandedOrientationForms()[orientation];
      double v[9];
      for (size_t k = 0; k < of.columns.size(); ++k) {
        if (!table.Number(row, of.columns[k], &v[k], error)) return false;
      }
      c.has_rotation = true;
      if (orientation == kCommandedQuat) {
        const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
        if (!(std::abs(q.norm() - 1.0) <= kQuaternionNormTolerance)) {
          return table.Fail(row.line,
                            "commanded_qw,commanded_qx,commanded_qy,"
                            "commanded_qz: the quaternion's norm is " +
                                FormatNumber("%.6g", q.norm()) +
                                ", not 1 (to " +
                                FormatNumber("%.6g", kQuaternionNormTolerance) +
                                "): not a unit quaternion",
                            error);
        }
        c.rotation = q.normalized().toRotationMatrix();
      } else {
        Eigen::Matrix3d r;
        r << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
        const double off = (r.transpose() * r - Eigen::Matrix3d::Identity())
                               .cwiseAbs()
                               .maxCoeff();
        const double det = r.determinant();
        if (!(off <= kCommandedRotationTolerance) || !(det > 0)) {
          return table.Fail(
              row.line,
              "commanded_r11..commanded_r33: not a rotation matrix (|R^T R - "
              "I| = " +
                  FormatNumber("%.6g", off) +
                  ", det = " + FormatNumber("%.6g", det) + "; to " +
                  FormatNumber("%.6g", kCommandedRotationTolerance) +
                  " a rotation has R^T R = I and det = +1)",
              error);
        }
        // The nearest rotation (the file's digits round it off one).
        const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
            r, Eigen::ComputeFullU | Eigen::ComputeFullV);
        c.rotation = svd.matrixU() * svd.matrixV().transpose();
      }
    }
    out.push_back(std::move(c));
  }
  *poses = std::move(out);
  return true;
}

bool ReadCommandedPosesCsv(const std::string& path, const RobotModel& model,
                           const MeasurementsCsvOptions& options,
                           std::vector<CommandedPose>* poses,
                           std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseCommandedPosesCsv(text, path, model, options, poses, error);
}

bool ParseCommandedPosesIfAny(const std::string& text,
                              const std::string& source,
                              const RobotModel& model,
                              const MeasurementsCsvOptions& options,
                              std::vector<CommandedPose>* poses,
                              std::string* error) {
  poses->clear();
  std::istringstream in(text);
  std::string line;
  bool has_pose = false;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(" \t\r\xEF\xBB\xBF");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream header(line);
    std::string name;
    while (std::getline(header, name, ',')) {
      const size_t b = name.find_first_not_of(" \t\r\"\xEF\xBB\xBF");
      const size_t e = name.find_last_not_of(" \t\r\"");
      if (b != std::string::npos && name.substr(b, e - b + 1) == "pose") {
        has_pose = true;
      }
    }
    break;
  }
  return !has_pose ||
         ParseCommandedPosesCsv(text, source, model, options, poses, error);
}

namespace {

// A CSV field: quoted when it holds a separator or a quote.
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string WithCommandedPoseColumns(
    const std::string& text, const std::vector<CommandedPose>& commanded,
    const std::vector<int>& row_of) {
  bool rotation = false;
  for (const CommandedPose& c : commanded) rotation |= c.has_rotation;
  std::istringstream in(text);
  std::string line, out;
  bool header = true;
  size_t i = 0;
  char number[64];
  auto add = [&](double v) {
    std::snprintf(number, sizeof(number), ",%.17g", v);
    out += number;
  };
  while (std::getline(in, line)) {
    out += line;
    if (!line.empty() && line[0] != '#') {
      if (header) {
        out += ",pose,commanded_x_m,commanded_y_m,commanded_z_m";
        if (rotation) {
          out += ",commanded_qw,commanded_qx,commanded_qy,commanded_qz";
        }
        header = false;
      } else {
        CHECK_LT(i, row_of.size());
        const CommandedPose& c = commanded[row_of[i++]];
        out += "," + CsvField(c.pose);
        for (int k = 0; k < 3; ++k) add(c.position[k]);
        if (rotation) {
          const Eigen::Quaterniond q(c.rotation);
          add(q.w());
          add(q.x());
          add(q.y());
          add(q.z());
        }
      }
    }
    out += "\n";
  }
  CHECK_EQ(i, row_of.size());
  return out;
}

}  // namespace activecal
