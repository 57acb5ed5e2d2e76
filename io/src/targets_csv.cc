#include "activecal/io/targets_csv.h"

#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

#include "activecal/io/csv_files.h"
#include "number_text.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;
using internal::Trim;

bool Revolute(const RobotModel& model, int j) {
  return model.links[j].joint_type == JointType::kRevolute;
}

std::string DisplayColumn(const RobotModel& model, int j) {
  return "q" + std::to_string(j + 1) + (Revolute(model, j) ? "_deg" : "_mm");
}

// Reads the file: a header and rows of trimmed fields, with the messages
// of every other activecal CSV reader.
class Reader {
 public:
  Reader(const std::string& source, std::string* error)
      : source_(source), error_(error) {}

  bool Fail(int line, const std::string& what) {
    if (error_) *error_ = source_ + ":" + std::to_string(line) + ": " + what;
    return false;
  }

  bool Parse(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    int number = 0;
    bool have_header = false;
    while (std::getline(in, line)) {
      ++number;
      const std::string trimmed = Trim(line);
      if (trimmed.empty() || trimmed[0] == '#') continue;
      std::vector<std::string> fields;
      std::string field;
      std::istringstream split(line);
      while (std::getline(split, field, ',')) fields.push_back(Trim(field));
      if (trimmed.back() == ',') fields.push_back("");
      if (!have_header) {
        for (size_t c = 0; c < fields.size(); ++c) {
          if (fields[c].empty()) {
            return Fail(number, "header column " + std::to_string(c + 1) +
                                    " has no name");
          }
          if (!columns_.emplace(fields[c], static_cast<int>(c)).second) {
            return Fail(number,
                        "header names column '" + fields[c] + "' twice");
          }
        }
        num_columns_ = fields.size();
        header_line_ = number;
        have_header = true;
        continue;
      }
      if (fields.size() != num_columns_) {
        return Fail(number, "expected " + std::to_string(num_columns_) +
                                " fields as in the header, got " +
                                std::to_string(fields.size()));
      }
      lines_.push_back(number);
      rows_.push_back(std::move(fields));
    }
    if (!have_header) {
      if (error_) *error_ = source_ + ": empty file: no header line";
      return false;
    }
    return true;
  }

  bool Has(const std::string& column) const { return columns_.count(column); }

  bool Number(int row, const std::string& column, double* value) {
    const std::string& text = rows_[row][columns_.at(column)];
    if (text.empty()) return Fail(lines_[row], column + ": empty");
    std::string why;
    if (!internal::ParseFiniteNumber(text, value, &why)) {
      return Fail(lines_[row], column + ": " + why);
    }
    return true;
  }

  const std::map<std::string, int>& columns() const { return columns_; }
  int header_line() const { return header_line_; }
  int num_rows() const { return static_cast<int>(rows_.size()); }
  int line(int row) const { return lines_[row]; }

 private:
  std::string source_;
  std::string* error_;
  std::map<std::string, int> columns_;
  size_t num_columns_ = 0;
  int header_line_ = 0;
  std::vector<int> lines_;
  std::vector<std::vector<std::string>> rows_;
};

// A joint column (q<k>_rad, _deg, _m, _mm) for a joint the robot lacks.
bool CheckNoExtraJoints(Reader* reader, const RobotModel& model) {
  for (const auto& [name, column] : reader->columns()) {
    (void)column;
    if (name.size() < 3 || name[0] != 'q' || !std::isdigit(name[1])) continue;
    size_t end = 1;
    while (end < name.size() && std::isdigit(name[end])) ++end;
    const std::string unit = name.substr(end);
    if (unit != "_rad" && unit != "_deg" && unit != "_m" && unit != "_mm") {
      continue;
    }
    const int k = std::stoi(name.substr(1, std::min<size_t>(end - 1, 6)));
    if (k > model.num_joints() || k < 1) {
      return reader->Fail(reader->header_line(),
                          "column '" + name + "' is for joint " +
                              std::to_string(k) + ", but robot '" + model.name +
                              "' has " + std::to_string(model.num_joints()) +
                              " joints (a file for another robot?)");
    }
  }
  return true;
}

}  // namespace

bool ParseTargetsCsv(const std::string& text, const std::string& source,
                     const RobotModel& model, TargetList* targets,
                     std::string* error) {
  Reader reader(source, error);
  if (!reader.Parse(text)) return false;
  if (!CheckNoExtraJoints(&reader, model)) return false;
  for (const char* column : {"x_m", "y_m", "z_m"}) {
    if (!reader.Has(column)) {
      return reader.Fail(
          reader.header_line(),
          std::string("the header has no column '") + column + "'");
    }
  }
  const char* rotation[3] = {"rx_rad", "ry_rad", "rz_rad"};
  const int num_rotation = reader.Has(rotation[0]) + reader.Has(rotation[1]) +
                           reader.Has(rotation[2]);
  if (num_rotation != 0 && num_rotation != 3) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        if (reader.Has(rotation[a]) && !reader.Has(rotation[b])) {
          return reader.Fail(reader.header_line(),
                             std::string("the header has ") + rotation[a] +
                                 " but not " + rotation[b] +
                                 ": give all three or none");
        }
      }
    }
  }
  // Per joint: the SI column, the pendant column, or neither.
  const int n_joints = model.num_joints();
  std::vector<int> joint_source(n_joints, 0);  // 0 none, 1 SI, 2 display
  int num_with_joint = 0;
  for (int j = 0; j < n_joints; ++j) {
    if (reader.Has(JointColumn(model, j))) {
      joint_source[j] = 1;
    } else if (reader.Has(DisplayColumn(model, j))) {
      joint_source[j] = 2;
    }
    num_with_joint += joint_source[j] != 0;
  }
  if (num_with_joint != 0 && num_with_joint != n_joints) {
    int have = 0, lack = 0;
    while (joint_source[have] == 0) ++have;
    while (joint_source[lack] != 0) ++lack;
    return reader.Fail(
        reader.header_line(),
        "the header has start joints for joint " + std::to_string(have + 1) +
            " but not for joint " + std::to_string(lack + 1) + " ('" +
            JointColumn(model, lack) + "' or '" + DisplayColumn(model, lack) +
            "'): give every joint or none");
  }
  const int n = reader.num_rows();
  if (n == 0)
    return reader.Fail(reader.header_line(), "no targets after the header");
  TargetList out;
  out.pose_indices.resize(n);
  out.points.resize(n, 3);
  if (num_rotation == 3) out.rotation_vectors.resize(n, 3);
  if (num_with_joint > 0) out.start_joints.resize(n, n_joints);
  const char* point[3] = {"x_m", "y_m", "z_m"};
  for (int i = 0; i < n; ++i) {
    out.pose_indices[i] = i;
    if (reader.Has("pose_index")) {
      double index;
      if (!reader.Number(i, "pose_index", &index)) return false;
      if (index < 0 || index != std::floor(index) || index > 9e15) {
        return reader.Fail(
            reader.line(i),
            "pose_index: expected an integer >= 0, got " + ShortestText(index));
      }
      out.pose_indices[i] = static_cast<int64_t>(index);
    }
    for (int a = 0; a < 3; ++a) {
      if (!reader.Number(i, point[a], &out.points(i, a))) return false;
    }
    if (num_rotation == 3) {
      for (int a = 0; a < 3; ++a) {
        if (!reader.Number(i, rotation[a], &out.rotation_vectors(i, a))) {
          return false;
        }
      }
      const double angle = out.rotation_vectors.row(i).norm();
      if (angle > M_PI + 1e-12) {
        return reader.Fail(reader.line(i),
                           "the rotation vector has angle " +
                               ShortestText(angle) +
                               " rad > pi: write the same rotation with an "
                               "angle in [0, pi]");
      }
    }
    if (num_with_joint > 0) {
      Eigen::VectorXd q(n_joints);
      for (int j = 0; j < n_joints; ++j) {
        const bool si = joint_source[j] == 1;
        const std::string column =
            si ? JointColumn(model, j) : DisplayColumn(model, j);
        if (!reader.Number(i, column, &q[j])) return false;
        if (!si) q[j] *= Revolute(model, j) ? kDegree : 1e-3;
      }
      std::string why;
      if (!model.CheckJointValues(q, &why)) {
        return reader.Fail(reader.line(i), "start joints: " + why);
      }
      out.start_joints.row(i) = q.transpose();
    }
  }
  *targets = std::move(out);
  return true;
}

bool ReadTargetsCsv(const std::string& path, const RobotModel& model,
                    TargetList* targets, std::string* error) {
  std::string text;
  if (!ReadTextFile(path, &text, error)) return false;
  return ParseTargetsCsv(text, path, model, targets, error);
}

std::string TargetsCsvText(const RobotModel& model, const TargetList& targets) {
  const int n = static_cast<int>(targets.points.rows());
  const bool rotation = targets.rotation_vectors.rows() == n && n > 0;
  const bool joints = targets.start_joints.rows() == n && n > 0;
  std::ostringstream out;
  out << "pose_index,x_m,y_m,z_m";
  if (rotation) out << ",rx_rad,ry_rad,rz_rad";
  if (joints) {
    for (int j = 0; j < model.num_joints(); ++j) {
      out << "," << JointColumn(model, j);
    }
  }
  out << "\n";
  for (int i = 0; i < n; ++i) {
    out << (i < static_cast<int>(targets.pose_indices.size())
                ? targets.pose_indices[i]
                : i);
    for (int a = 0; a < 3; ++a)
      out << "," << ShortestText(targets.points(i, a));
    if (rotation) {
      for (int a = 0; a < 3; ++a) {
        out << "," << ShortestText(targets.rotation_vectors(i, a));
      }
    }
    if (joints) {
      for (int j = 0; j < model.num_joints(); ++j) {
        out << "," << ShortestText(targets.start_joints(i, j));
      }
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace activecal
