// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/robot_file.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <vector>

#include "activecal/core/kinematics.h"
#include "activecal/io/csv_files.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;

class Parser : public internal::YamlReader {
 public:
  using YamlReader::YamlReader;

  bool Parse(const std::string& text, RobotDescription* robot) {
    YAML::Node root;
    if (!LoadMap(text, "of robot fields at the top", &root)) return false;
    if (!CheckKeys(
            root, "",
            {"name", "angle_unit", "base", "links", "tip", "tool", "markers",
             "collision", "learned_residual"})) {  // collision: read by cell/
      return false;
    }
    RobotModel& m = robot->model;
    m = RobotModel();
    if (!String(root, "name", "name", &m.name)) return false;
    std::string unit;
    if (!String(root, "angle_unit", "angle_unit", &unit)) return false;
    if (unit == "rad") {
      robot->angle_unit = AngleUnit::kRadian;
      angle_scale_ = 1.0;
    } else if (unit == "deg") {
      robot->angle_unit = AngleUnit::kDegree;
      angle_scale_ = kDegree;
    } else {
      return Fail(root["angle_unit"].Mark(), "angle_unit",
                  "expected 'rad' or 'deg', got '" + unit + "'");
    }
    const YAML::Node links = root["links"];
    if (!links) return Fail(root.Mark(), "links", "missing");
    if (!links.IsSequence() || links.size() == 0) {
      return Fail(links.Mark(), "links", "expected a non-empty list of links");
    }
    const int n = static_cast<int>(links.size());
    m.links.resize(n);
    // Markers: a single "tool" block, or a list of named markers.
    std::vector<YAML::Node> marker_nodes;
    std::vector<std::string> marker_fields;
    if (root["tool"] && root["markers"]) {
      return Fail(root["markers"].Mark(), "markers",
                  "give either 'tool' (one marker) or 'markers', not both");
    }
    if (const YAML::Node markers = root["markers"]) {
      if (!markers.IsSequence() || markers.size() == 0) {
        return Fail(markers.Mark(), "markers",
                    "expected a non-empty list of markers");
      }
      for (size_t k = 0; k < markers.size(); ++k) {
        marker_nodes.push_back(markers[k]);
        marker_fields.push_back("markers[" + std::to_string(k) + "]");
      }
    } else if (const YAML::Node tool = root["tool"]) {
      marker_nodes.push_back(tool);
      marker_fields.push_back("tool");
    }
    m.markers.assign(std::max<size_t>(1, marker_nodes.size()), Marker());
    for (size_t k = 1; k < m.markers.size(); ++k) {
      m.markers[k].name = "marker" + std::to_string(k + 1);
    }

    // The structure first (conventions decide the block sizes), then the
    // values. Base: optional, default the identity frame, nothing free.
    m.base.name = "B";
    m.base.joint_type = JointType::kFixed;
    m.base.convention = LinkConvention::kStandardDH;
    const YAML::Node base = root["base"];
    if (base && !Convention(base, "base", &m.base)) return false;
    for (int i = 0; i < n; ++i) {
      if (!Convention(links[i], "links[" + std::to_string(i) + "]",
                      &m.links[i])) {
        return false;
      }
    }
    m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
    for (int b = 0; b < m.num_blocks(); ++b) {
      DefaultBlockValues(m, b, m.nominal.data() + m.block_offset(b));
    }
    truth_ = m.nominal;
    if (base && !ParseBlock(base, "base", 0, robot)) return false;
    for (int i = 0; i < n; ++i) {
      if (!ParseBlock(links[i], "links[" + std::to_string(i) + "]", i + 1,
                      robot)) {
        return false;
      }
    }
    for (size_t k = 0; k < marker_nodes.size(); ++k) {
      if (!ParseBlock(marker_nodes[k], marker_fields[k],
                      m.marker_block(static_cast<int>(k)), robot)) {
        return false;
      }
    }
    if (const YAML::Node tip = root["tip"]) {
      if (!Origin(tip, "tip", &m.tip.translation, &m.tip.rotation)) {
        return false;
      }
    }
    std::string why;
    if (!m.Validate(&why)) return Fail(root.Mark(), "", why);
    robot->true_parameters =
        has_truth_ ? truth_ : Eigen::VectorXd(Eigen::VectorXd());
    if (const YAML::Node learned = root["learned_residual"]) {
      if (!LearnedResidual(learned, m, &robot->learned_correction)) {
        return false;
      }
    }
    return true;
  }

 private:
  // Reads a link's convention (the structure that decides its block size).
  bool Convention(const YAML::Node& node, const std::string& field,
                  Link* link) {
    if (!node.IsMap()) return Fail(node.Mark(), field, "expected a mapping");
    std::string convention;
    if (!String(node, "convention", field + ".convention", &convention)) {
      return false;
    }
    for (LinkConvention c :
         {LinkConvention::kStandardDH, LinkConvention::kModifiedDH,
          LinkConvention::kHayati, LinkConvention::kUrdf,
          LinkConvention::kFrame}) {
      if (convention == LinkConventionName(c)) {
        link->convention = c;
        return true;
      }
    }
    return Fail(node["convention"].Mark(), field + ".convention",
                "expected standard_dh, modified_dh, hayati, urdf or frame, "
                "got '" +
                    convention + "'");
  }

  // {xyz: [..], rpy: [..]} (rpy in the file's angle unit) or {xyz: [..],
  // rotation: [9 entries, row by row]} (what the writer uses when no rpy
  // angles read back to exactly the rotation); all optional.
  bool Origin(const YAML::Node& node, const std::string& field,
              Eigen::Vector3d* xyz, Eigen::Matrix3d* rotation) {
    Eigen::Vector3d rpy;
    if (!Pose(node, field, angle_scale_, xyz, &rpy) ||
        !CheckKeys(node, field, {"xyz", "rpy", "rotation"})) {
      return false;
    }
    *rotation = RpyRotation(rpy[0], rpy[1], rpy[2]);
    const YAML::Node matrix = node["rotation"];
    if (!matrix) return true;
    const std::string where = field + ".rotation";
    if (node["rpy"]) {
      return Fail(matrix.Mark(), where, "give rpy or rotation, not both");
    }
    if (!matrix.IsSequence() || matrix.size() != 9) {
      return Fail(matrix.Mark(), where,
                  "expected the 9 entries of a rotation matrix, row by row");
    }
    for (int k = 0; k < 9; ++k) {
      if (!Number(matrix[k], where + "[" + std::to_string(k) + "]",
                  &(*rotation)(k / 3, k % 3))) {
        return false;
      }
    }
    const double off =
        (rotation->transpose() * *rotation - Eigen::Matrix3d::Identity())
            .cwiseAbs()
            .maxCoeff();
    if (!(off <= 1e-9) || !(rotation->determinant() > 0.0)) {
      return Fail(matrix.Mark(), where,
                  "not a rotation matrix (orthonormal to 1e-9, determinant "
                  "+1)");
    }
    return true;
  }

  // One block: base (0), link (1..n) or marker (n+1..).
  bool ParseBlock(const YAML::Node& node, const std::string& field, int block,
                  RobotDescription* robot) {
    RobotModel& m = robot->model;
    const bool marker = m.is_marker_block(block);
    const bool base = block == 0;
    if (!node.IsMap()) return Fail(node.Mark(), field, "expected a mapping");
    std::vector<std::string> names;
    for (int j = 0; j < m.block_size(block); ++j) {
      names.push_back(m.BlockParameterName(block, j));
    }
    Link* link = marker ? nullptr : (base ? &m.base : &m.links[block - 1]);
    const LinkConvention convention =
        link ? link->convention : LinkConvention::kFrame;
    const bool dh = link && convention != LinkConvention::kUrdf &&
                    convention != LinkConvention::kFrame;
    std::set<std::string> allowed(names.begin(), names.end());
    allowed.insert({"free", "true", "name"});
    if (link) allowed.insert("convention");
    if (base && dh) allowed.erase("gain");
    if (link && !base) allowed.insert({"joint", "limits"});
    if (convention == LinkConvention::kUrdf) allowed.insert({"origin", "axis"});
    if (!CheckKeys(node, field, allowed)) return false;

    if (const YAML::Node name = node["name"]) {
      if (!name.IsScalar())
        return Fail(name.Mark(), field + ".name", "expected a text");
      if (link) {
        link->name = name.Scalar();
      } else {
        m.markers[block - m.num_joints() - 1].name = name.Scalar();
      }
    } else if (link && !base) {
      link->name = "L" + std::to_string(block);
    }
    if (link && !base) {
      std::string joint;
      if (!String(node, "joint", field + ".joint", &joint)) return false;
      if (joint == "revolute") {
        link->joint_type = JointType::kRevolute;
      } else if (joint == "prismatic") {
        link->joint_type = JointType::kPrismatic;
      } else {
        return Fail(node["joint"].Mark(), field + ".joint",
                    "expected revolute or prismatic, got '" + joint + "'");
      }
      const YAML::Node limits = node["limits"];
      if (!limits) return Fail(node.Mark(), field + ".limits", "missing");
      if (!limits.IsSequence() || limits.size() != 2) {
        return Fail(limits.Mark(), field + ".limits", "expected [min, max]");
      }
      // An end may be unbounded (a continuous joint): -.inf / .inf.
      auto end = [&](int k, double sign, double* value) {
        const YAML::Node& n = limits[k];
        if (n.IsScalar()) {
          const std::string t = n.Scalar();
          const bool inf = t == ".inf" || t == ".Inf" || t == ".INF";
          const bool minus_inf = t == "-.inf" || t == "-.Inf" || t == "-.INF";
          if ((sign > 0 && inf) || (sign < 0 && minus_inf)) {
            *value = sign * std::numeric_limits<double>::infinity();
            return true;
          }
        }
        return Number(n, field + ".limits[" + std::to_string(k) + "]", value);
      };
      double lo, hi;
      if (!end(0, -1.0, &lo) || !end(1, 1.0, &hi)) return false;
      if (!(lo <= hi)) {
        return Fail(
            limits.Mark(), field + ".limits",
            "min " + ShortestText(lo) + " is above max " + ShortestText(hi));
      }
      const double scale =
          link->joint_type == JointType::kRevolute ? angle_scale_ : 1.0;
      link->joint_min = lo * scale;
      link->joint_max = hi * scale;
    }
    if (convention == LinkConvention::kUrdf) {
      if (const YAML::Node origin = node["origin"]) {
        if (!Origin(origin, field + ".origin", &link->origin_xyz,
                    &link->origin_rotation)) {
          return false;
        }
      }
      if (const YAML::Node axis = node["axis"]) {
        Eigen::Vector3d a;
        if (!Vector(axis, field + ".axis", &a)) return false;
        if (!(a.norm() > 1e-12)) {
          return Fail(axis.Mark(), field + ".axis", "the axis is zero");
        }
        link->axis = a.normalized();
      }
    }

    // Values: the DH geometry (gamma, alpha, a, d) and a marker's point are
    // required; beta (Hayati only), gains, URDF corrections, frame values
    // and marker angles default to their DefaultBlockValues.
    const int offset = m.block_offset(block);
    for (int j = 0; j < m.block_size(block); ++j) {
      const YAML::Node value = node[names[j]];
      if (!value) {
        const bool required = marker ? j < 3 : dh && j <= kD;
        if (required) {
          return Fail(node.Mark(), field + "." + names[j], "missing");
        }
        continue;
      }
      double v;
      if (!Number(value, field + "." + names[j], &v)) return false;
      if (m.Kind(offset + j) == ParameterKind::kAngle) v *= angle_scale_;
      m.nominal[offset + j] = v;
      truth_[offset + j] = v;
    }
    if (const YAML::Node free = node["free"]) {
      if (!free.IsSequence()) {
        return Fail(free.Mark(), field + ".free",
                    "expected a list of parameter names, e.g. [a, d]");
      }
      for (size_t k = 0; k < free.size(); ++k) {
        const std::string name = free[k].IsScalar() ? free[k].Scalar() : "";
        const auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end() || (base && dh && name == "gain")) {
          return Fail(free[k].Mark(), field + ".free",
                      "'" + name + "' is not a parameter of this block");
        }
        m.SetFree(offset + static_cast<int>(it - names.begin()), true);
      }
    }
    if (const YAML::Node truth = node["true"]) {
      if (!truth.IsMap()) {
        return Fail(truth.Mark(), field + ".true",
                    "expected a mapping of parameter: true value");
      }
      for (const auto& kv : truth) {
        const std::string name = kv.first.Scalar();
        const auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) {
          return Fail(kv.first.Mark(), field + ".true." + name,
                      "not a parameter of this block");
        }
        const int j = static_cast<int>(it - names.begin());
        double v;
        if (!Number(kv.second, field + ".true." + name, &v)) return false;
        truth_[offset + j] =
            m.Kind(offset + j) == ParameterKind::kAngle ? v * angle_scale_ : v;
      }
      has_truth_ = true;
    }
    return true;
  }

  // A list of `size` numbers (size < 0: any) into *out.
  bool Numbers(const YAML::Node& node, const std::string& field, int size,
               const std::string& what, Eigen::VectorXd* out) {
    if (!node || !node.IsSequence() ||
        (size >= 0 && static_cast<int>(node.size()) != size)) {
      const std::string got =
          node && node.IsSequence() ? std::to_string(node.size()) : "none";
      return Fail(node ? node.Mark() : YAML::Mark::null_mark(), field,
                  size >= 0 ? "expected a list of " + std::to_string(size) +
                                  " numbers (" + what + "), got " + got
                            : "expected a list of numbers (" + what + ")");
    }
    out->resize(node.size());
    for (size_t k = 0; k < node.size(); ++k) {
      if (!Number(node[k], field + "[" + std::to_string(k) + "]", &(*out)[k])) {
        return false;
      }
    }
    return true;
  }

  // `rows` lists of `cols` numbers into *out (rows x cols).
  bool NumberRows(const YAML::Node& node, const std::string& field, int rows,
                  int cols, const std::string& what, Eigen::MatrixXd* out) {
    if (!node || !node.IsSequence() || static_cast<int>(node.size()) != rows) {
      const std::string got =
          node && node.IsSequence() ? std::to_string(node.size()) : "none";
      return Fail(node ? node.Mark() : YAML::Mark::null_mark(), field,
                  "expected " + std::to_string(rows) +
                      " rows (one per feature), got " + got);
    }
    out->resize(rows, cols);
    Eigen::VectorXd row;
    for (int r = 0; r < rows; ++r) {
      if (!Numbers(node[r], field + "[" + std::to_string(r) + "]", cols, what,
                   &row)) {
        return false;
      }
      out->row(r) = row.transpose();
    }
    return true;
  }

  // The "learned_residual:" block (core/learned_correction.h).
  bool LearnedResidual(const YAML::Node& node, const RobotModel& m,
                       LearnedCorrection* c) {
    const std::string f = "learned_residual";
    if (!node.IsMap()) return Fail(node.Mark(), f, "expected a mapping");
    if (!CheckKeys(node, f,
                   {"features", "inputs", "scale", "length_scale", "ridge",
                    "seed", "num_training", "held_out_rms_parametric_m",
                    "held_out_rms_hybrid_m", "frequencies", "phases", "weights",
                    "bias"})) {
      return false;
    }
    *c = LearnedCorrection();
    double v = 0;
    auto required = [&](const char* key, double* out) {
      const YAML::Node n = node[key];
      if (!n) return Fail(node.Mark(), f + "." + key, "missing");
      return Number(n, f + "." + key, out);
    };
    auto optional = [&](const char* key, double* out) {
      const YAML::Node n = node[key];
      return !n || Number(n, f + "." + key, out);
    };
    if (!required("features", &v)) return false;
    if (!(v >= 1 && v <= 5000 && v == std::floor(v))) {
      return Fail(node["features"].Mark(), f + ".features",
                  "expected a whole number in [1, 5000]");
    }
    const int d = static_cast<int>(v);
    const YAML::Node inputs = node["inputs"];
    if (!inputs || !inputs.IsSequence() ||
        static_cast<int>(inputs.size()) != m.num_joints()) {
      return Fail(inputs ? inputs.Mark() : node.Mark(), f + ".inputs",
                  "expected a list of " + std::to_string(m.num_joints()) +
                      " entries (periodic or linear, one per joint)");
    }
    for (size_t j = 0; j < inputs.size(); ++j) {
      const std::string t = inputs[j].IsScalar() ? inputs[j].Scalar() : "";
      if (t != "periodic" && t != "linear") {
        return Fail(inputs[j].Mark(), f + ".inputs[" + std::to_string(j) + "]",
                    "expected periodic or linear, got '" + t + "'");
      }
      c->periodic.push_back(t == "periodic");
    }
    if (!Numbers(node["scale"], f + ".scale", m.num_joints(), "one per joint",
                 &c->scale)) {
      return false;
    }
    if (!required("length_scale", &c->length_scale) ||
        !required("ridge", &c->ridge) ||
        !optional("held_out_rms_parametric_m", &c->held_out_rms_parametric_m) ||
        !optional("held_out_rms_hybrid_m", &c->held_out_rms_hybrid_m)) {
      return false;
    }
    double count = 0;
    if (!optional("num_training", &count)) return false;
    c->num_training = static_cast<int>(std::max(0.0, count));
    if (const YAML::Node seed = node["seed"]) {
      try {
        c->seed = seed.as<uint64_t>();
      } catch (const YAML::Exception&) {
        return Fail(seed.Mark(), f + ".seed", "expected a whole number >= 0");
      }
    }
    const int outputs = 3 * m.num_markers();
    if (!NumberRows(node["frequencies"], f + ".frequencies", d, c->num_inputs(),
                    "inputs: 2 per periodic joint, 1 per linear one",
                    &c->frequencies) ||
        !Numbers(node["phases"], f + ".phases", d, "one per feature",
                 &c->phases) ||
        !NumberRows(node["weights"], f + ".weights", d, outputs, "3 per marker",
                    &c->weights) ||
        !Numbers(node["bias"], f + ".bias", outputs, "3 per marker",
                 &c->bias)) {
      return false;
    }
    std::string why;
    if (!c->Validate(&m, &why)) return Fail(node.Mark(), f, why);
    return true;
  }

  double angle_scale_ = 1.0;
  Eigen::VectorXd truth_;
  bool has_truth_ = false;
};

}  // namespace

bool ParseRobotDescription(const std::string& text, const std::string& source,
                           RobotDescription* robot, std::string* error) {
  Parser parser(source);
  RobotDescription parsed;
  if (!parser.Parse(text, &parsed)) {
    if (error) *error = parser.error();
    return false;
  }
  *robot = std::move(parsed);
  return true;
}

bool LoadRobotFile(const std::string& path, RobotDescription* robot,
                   std::string* error) {
  std::string text;
  if (!ReadTextFile(path, &text, nullptr)) {
    if (error) *error = path + ": cannot open the robot file";
    return false;
  }
  return ParseRobotDescription(text, path, robot, error);
}

std::string RobotFileText(const RobotModel& model,
                          const Eigen::VectorXd& values,
                          const RobotFileOptions& options) {
  const double scale =
      options.angle_unit == AngleUnit::kDegree ? 1.0 / kDegree : 1.0;
  const bool with_truth = options.true_parameters.size() == values.size() &&
                          options.true_parameters != values;
  YAML::Emitter out;
  if (!options.comment.empty()) {
    std::istringstream lines(options.comment);
    std::string line, joined;
    while (std::getline(lines, line))
      joined += (joined.empty() ? "" : "\n") + line;
    out << YAML::Comment(joined) << YAML::Newline;
  }
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << model.name;
  out << YAML::Key << "angle_unit" << YAML::Value
      << (options.angle_unit == AngleUnit::kDegree ? "deg" : "rad");
  auto triple = [&](const Eigen::Vector3d& v, double s) {
    out << YAML::Flow << YAML::BeginSeq;
    for (int k = 0; k < 3; ++k) out << ShortestText(v[k] * s);
    out << YAML::EndSeq;
  };
  // A rotation as the angles that read back to exactly it in the file's
  // unit, or else as its matrix (a rotation read from a URDF's quaternion is
  // seldom exactly Rz Ry Rx of any angles): the file holds the model
  // exactly.
  const double unit = options.angle_unit == AngleUnit::kDegree ? kDegree : 1.0;
  auto origin = [&](const Eigen::Vector3d& xyz, const Eigen::Matrix3d& R) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "xyz" << YAML::Value;
    triple(xyz, 1.0);
    const Eigen::Vector3d rpy = RotationToShortRpy(R, unit);
    const Eigen::Vector3d rad = rpy * unit;
    if (RpyRotation(rad[0], rad[1], rad[2]) == R) {
      out << YAML::Key << "rpy" << YAML::Value;
      triple(rpy, 1.0);
    } else {
      out << YAML::Key << "rotation" << YAML::Value << YAML::Flow
          << YAML::BeginSeq;
      for (int k = 0; k < 9; ++k) out << ShortestText(R(k / 3, k % 3));
      out << YAML::EndSeq;
    }
    out << YAML::EndMap;
  };
  auto block = [&](int b) {
    const bool marker = model.is_marker_block(b);
    const int offset = model.block_offset(b);
    const LinkConvention convention =
        marker ? LinkConvention::kFrame : model.link(b).convention;
    const bool dh = !marker && convention != LinkConvention::kUrdf &&
                    convention != LinkConvention::kFrame;
    out << YAML::BeginMap;
    if (marker) {
      if (model.num_markers() > 1) {
        out << YAML::Key << "name" << YAML::Value << model.block_name(b);
      }
    } else {
      const Link& l = model.link(b);
      out << YAML::Key << "name" << YAML::Value << model.block_name(b);
      out << YAML::Key << "convention" << YAML::Value
          << LinkConventionName(l.convention);
      if (b > 0) {
        out << YAML::Key << "joint" << YAML::Value
            << JointTypeName(l.joint_type);
        const double s = l.joint_type == JointType::kRevolute ? scale : 1.0;
        // Unbounded ends (a continuous joint) as YAML's -.inf / .inf.
        auto end = [&](double v) {
          if (std::isinf(v)) return std::string(v < 0 ? "-.inf" : ".inf");
          return ShortestText(v * s);
        };
        out << YAML::Key << "limits" << YAML::Value << YAML::Flow
            << YAML::BeginSeq << end(l.joint_min) << end(l.joint_max)
            << YAML::EndSeq;
      }
      if (convention == LinkConvention::kUrdf) {
        out << YAML::Key << "origin" << YAML::Value;
        origin(l.origin_xyz, l.origin_rotation);
        out << YAML::Key << "axis" << YAML::Value;
        triple(l.axis, 1.0);
      }
    }
    std::vector<std::string> free;
    std::vector<int> differs;
    for (int j = 0; j < model.block_size(b); ++j) {
      const std::string name = model.BlockParameterName(b, j);
      const bool skip =
          dh && ((b == 0 && j == kGain) ||
                 (j == kBeta && convention != LinkConvention::kHayati));
      const double s =
          model.Kind(offset + j) == ParameterKind::kAngle ? scale : 1.0;
      if (!skip) {
        out << YAML::Key << name << YAML::Value
            << ShortestText(values[offset + j] * s);
      }
      if (model.IsFree(offset + j)) free.push_back(name);
      if (with_truth &&
          options.true_parameters[offset + j] != values[offset + j]) {
        differs.push_back(j);
      }
    }
    out << YAML::Key << "free" << YAML::Value << YAML::Flow << free;
    if (!differs.empty()) {
      out << YAML::Key << "true" << YAML::Value << YAML::Flow << YAML::BeginMap;
      for (int j : differs) {
        const double s =
            model.Kind(offset + j) == ParameterKind::kAngle ? scale : 1.0;
        out << YAML::Key << model.BlockParameterName(b, j) << YAML::Value
            << ShortestText(options.true_parameters[offset + j] * s);
      }
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  };
  out << YAML::Key << "base" << YAML::Value;
  block(0);
  out << YAML::Key << "links" << YAML::Value << YAML::BeginSeq;
  for (int b = 1; b <= model.num_joints(); ++b) block(b);
  out << YAML::EndSeq;
  if (!model.tip.IsIdentity()) {
    out << YAML::Key << "tip" << YAML::Value;
    origin(model.tip.translation, model.tip.rotation);
  }
  const bool single = model.num_markers() == 1 &&
                      model.block_name(model.marker_block(0)) == "tool";
  if (single) {
    out << YAML::Key << "tool" << YAML::Value;
    block(model.marker_block(0));
  } else {
    out << YAML::Key << "markers" << YAML::Value << YAML::BeginSeq;
    for (int k = 0; k < model.num_markers(); ++k) block(model.marker_block(k));
    out << YAML::EndSeq;
  }
  if (options.learned_correction && !options.learned_correction->empty()) {
    const LearnedCorrection& c = *options.learned_correction;
    auto list = [&](const auto& v) {
      out << YAML::Flow << YAML::BeginSeq;
      for (int k = 0; k < v.size(); ++k) out << ShortestText(v[k]);
      out << YAML::EndSeq;
    };
    auto rows = [&](const Eigen::MatrixXd& a) {
      out << YAML::BeginSeq;
      for (int r = 0; r < a.rows(); ++r) {
        const Eigen::VectorXd row = a.row(r).transpose();
        list(row);
      }
      out << YAML::EndSeq;
    };
    out << YAML::Key << "learned_residual" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "features" << YAML::Value << c.num_features();
    out << YAML::Key << "inputs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (bool p : c.periodic) out << (p ? "periodic" : "linear");
    out << YAML::EndSeq;
    out << YAML::Key << "scale" << YAML::Value;
    list(c.scale);
    out << YAML::Key << "length_scale" << YAML::Value
        << ShortestText(c.length_scale);
    out << YAML::Key << "ridge" << YAML::Value << ShortestText(c.ridge);
    out << YAML::Key << "seed" << YAML::Value << c.seed;
    out << YAML::Key << "num_training" << YAML::Value << c.num_training;
    out << YAML::Key << "held_out_rms_parametric_m" << YAML::Value
        << ShortestText(c.held_out_rms_parametric_m);
    out << YAML::Key << "held_out_rms_hybrid_m" << YAML::Value
        << ShortestText(c.held_out_rms_hybrid_m);
    out << YAML::Key << "frequencies" << YAML::Value;
    rows(c.frequencies);
    out << YAML::Key << "phases" << YAML::Value;
    list(c.phases);
    out << YAML::Key << "weights" << YAML::Value;
    rows(c.weights);
    out << YAML::Key << "bias" << YAML::Value;
    list(c.bias);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace activecal
