#include "activecal/core/csv_files.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "number_text.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

struct Row {
  int line = 0;
  std::vector<std::string> fields;
};

// A CSV table: header names and rows of trimmed fields.
class Table {
 public:
  bool Parse(const std::string& text, const std::string& source,
             std::string* error) {
    source_ = source;
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
      if (!line.empty() && Trim(line).back() == ',') fields.push_back("");
      if (!have_header) {
        for (size_t c = 0; c < fields.size(); ++c) {
          if (fields[c].empty()) {
            return Fail(
                number,
                "header column " + std::to_string(c + 1) + " has no name",
                error);
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
    if (error) *error = source_ + ":" + std::to_string(line) + ": " + what;
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

// Reads joint j of a row from its SI column or its display column (suffix
// appended to both names); checks agreement when both are present.
bool ReadJoint(const Table& table, const Row& row, const RobotModel& model,
               int j, const std::string& suffix, double* q,
               std::string* error) {
  const std::string si = JointColumn(model, j) + suffix;
  const std::string display = DisplayColumn(model, j) + suffix;
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

bool ReadJoints(const Table& table, const Row& row, const RobotModel& model,
                const std::string& suffix, Eigen::VectorXd* q,
                std::string* error) {
  q->resize(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j) {
    if (!ReadJoint(table, row, model, j, suffix, &(*q)[j], error)) return false;
  }
  std::string why;
  if (!model.CheckJointValues(*q, &why)) {
    return table.Fail(row.line, (suffix.empty() ? "" : "second pose: ") + why,
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
  PoseList out;
  out.joints.resize(n, model.num_joints());
  out.pose_indices.resize(n);
  std::map<std::vector<double>, int> seen;
  for (int i = 0; i < n; ++i) {
    const Row& row = table.rows()[i];
    Eigen::VectorXd q;
    if (!ReadJoints(table, row, model, "", &q, error)) return false;
    out.joints.row(i) = q.transpose();
    out.pose_indices[i] = i;
    if (table.Has("pose_index")) {
      double index;
      if (!table.Number(row, "pose_index", &index, error)) return false;
      if (index < 0 || index != std::floor(index) || index > 9e15) {
        return table.Fail(
            row.line,
            "pose_index: expected an integer >= 0, got " + ShortestText(index),
            error);
      }
      out.pose_indices[i] = static_cast<int64_t>(index);
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

std::string MeasurementsCsvText(const RobotModel& model,
                                const std::vector<Measurement>& measurements) {
  bool any_pose = false, any_distance = false;
  for (const Measurement& m : measurements) {
    any_pose |= m.type == MeasurementType::kPose;
    any_distance |= m.type == MeasurementType::kDistance;
  }
  const int nj = model.num_joints();
  bool any_marker = false;
  for (const Measurement& m : measurements) any_marker |= m.marker != 0;
  std::ostringstream out;
  out << "type";
  if (any_marker) out << ",marker";
  for (int j = 0; j < nj; ++j) out << "," << JointColumn(model, j);
  out << ",x_m,y_m,z_m";
  if (any_pose) out << ",rx_rad,ry_rad,rz_rad";
  if (any_distance) {
    for (int j = 0; j < nj; ++j) out << "," << JointColumn(model, j) << "_2";
    out << ",distance_m";
  }
  out << "\n";
  for (const Measurement& m : measurements) {
    out << MeasurementTypeName(m.type);
    if (any_marker)
      out << "," << model.block_name(model.marker_block(m.marker));
    for (int j = 0; j < nj; ++j) out << "," << ShortestText(m.joints[j]);
    const bool distance = m.type == MeasurementType::kDistance;
    for (int k = 0; k < 3; ++k) {
      out << "," << (distance ? "" : ShortestText(m.position[k]));
    }
    if (any_pose) {
      for (int k = 0; k < 3; ++k) {
        out << ","
            << (m.type == MeasurementType::kPose ? ShortestText(m.rotation[k])
                                                 : "");
      }
    }
    if (any_distance) {
      for (int j = 0; j < nj; ++j) {
        out << "," << (distance ? ShortestText(m.joints2[j]) : "");
      }
      out << "," << (distance ? ShortestText(m.distance) : "");
    }
    out << "\n";
  }
  return out.str();
}

bool ParseMeasurementsCsv(const std::string& text, const std::string& source,
                          const RobotModel& model,
                          std::vector<Measurement>* measurements,
                          std::string* error) {
  Table table;
  if (!table.Parse(text, source, error)) return false;
  if (!CheckNoExtraJoints(table, model, error)) return false;
  if (!table.RequireColumn("type", error)) return false;
  if (table.rows().empty()) {
    return table.Fail(table.header_line(), "no measurements after the header",
                      error);
  }
  static const char* const kPosition[] = {"x_m", "y_m", "z_m"};
  static const char* const kRotation[] = {"rx_rad", "ry_rad", "rz_rad"};
  std::vector<std::string> second;
  for (int j = 0; j < model.num_joints(); ++j) {
    second.push_back(JointColumn(model, j) + "_2");
  }
  std::vector<Measurement> out;
  for (const Row& row : table.rows()) {
    Measurement m;
    const std::string type = row.fields[table.Column("type")];
    if (!ParseMeasurementType(type, &m.type)) {
      return table.Fail(
          row.line,
          "type: expected position, pose or distance, got '" + type + "'",
          error);
    }
    if (!ReadJoints(table, row, model, "", &m.joints, error)) return false;
    if (table.Has("marker") && !table.Empty(row, "marker")) {
      const std::string name = row.fields[table.Column("marker")];
      m.marker = model.MarkerIndex(name);
      if (m.marker < 0) {
        std::string list;
        for (int k = 0; k < model.num_markers(); ++k) {
          list += (k ? ", " : "") + model.block_name(model.marker_block(k));
        }
        return table.Fail(row.line,
                          "marker: '" + name +
                              "' is not a marker of the model (its markers: " +
                              list + ", or their numbers 1.." +
                              std::to_string(model.num_markers()) + ")",
                          error);
      }
    }
    const bool has_point = m.type != MeasurementType::kDistance;
    const bool has_rotation = m.type == MeasurementType::kPose;
    const bool has_second = m.type == MeasurementType::kDistance;
    // Columns this type uses must be filled; the others must be empty.
    auto expect = [&](const std::string& column, bool used,
                      double* value) -> bool {
      if (used) {
        return table.RequireColumn(column, error) &&
               table.Number(row, column, value, error);
      }
      if (!table.Empty(row, column)) {
        return table.Fail(row.line,
                          column + ": a " + type +
                              " measurement has no such value; leave it empty",
                          error);
      }
      return true;
    };
    for (int k = 0; k < 3; ++k) {
      if (!expect(kPosition[k], has_point, &m.position[k])) return false;
      if (!expect(kRotation[k], has_rotation, &m.rotation[k])) return false;
    }
    if (!expect("distance_m", has_second, &m.distance)) return false;
    if (has_second) {
      m.joints2.resize(model.num_joints());
      for (int j = 0; j < model.num_joints(); ++j) {
        if (!table.RequireColumn(second[j], error) ||
            !table.Number(row, second[j], &m.joints2[j], error)) {
          return false;
        }
      }
      std::string why;
      if (!model.CheckJointValues(m.joints2, &why)) {
        return table.Fail(row.line, "second pose: " + why, error);
      }
    } else {
      for (const std::string& column : second) {
        double unused;
        if (!expect(column, false, &unused)) return false;
      }
    }
    std::string why;
    if (!CheckMeasurement(model, m, &why)) {
      return table.Fail(row.line, why, error);
    }
    out.push_back(std::move(m));
  }
  *measurements = std::move(out);
  return true;
}

bool ReadMeasurementsCsv(const std::string& path, const RobotModel& model,
                         std::vector<Measurement>* measurements,
                         std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseMeasurementsCsv(text, path, model, measurements, error);
}

}  // namespace activecal
