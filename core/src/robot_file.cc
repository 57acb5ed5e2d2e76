#include "activecal/core/robot_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <vector>

#include "activecal/core/csv_files.h"
#include "number_text.h"

namespace activecal {
namespace {

using internal::kDegree;
using internal::ShortestText;

bool IsAngle(bool tool, int index) {
  if (tool) return index >= 3;
  return index == kGamma || index == kAlpha || index == kBeta;
}

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  const std::string& error() const { return error_; }

  bool Parse(const std::string& text, RobotDescription* robot) {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      return Fail(e.mark, "", "not valid YAML: " + e.msg);
    }
    if (!root.IsMap()) {
      return Fail(root.Mark(), "",
                  "expected a mapping of robot fields at the top");
    }
    if (!CheckKeys(root, "", {"name", "angle_unit", "base", "links", "tool"})) {
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
    m.nominal = Eigen::VectorXd::Zero(m.num_parameters());
    truth_ = Eigen::VectorXd::Zero(m.num_parameters());

    // Base: optional, default the identity frame with nothing free.
    m.base.name = "B";
    m.base.joint_type = JointType::kFixed;
    m.base.convention = LinkConvention::kStandardDH;
    m.nominal[kGain] = 1.0;
    truth_[kGain] = 1.0;
    if (const YAML::Node base = root["base"]) {
      if (!ParseBlock(base, "base", 0, robot)) return false;
    }
    for (int i = 0; i < n; ++i) {
      if (!ParseBlock(links[i], "links[" + std::to_string(i) + "]", i + 1,
                      robot)) {
        return false;
      }
    }
    if (const YAML::Node tool = root["tool"]) {
      if (!ParseBlock(tool, "tool", n + 1, robot)) return false;
    }
    std::string why;
    if (!m.Validate(&why)) return Fail(root.Mark(), "", why);
    robot->true_parameters =
        has_truth_ ? truth_ : Eigen::VectorXd(Eigen::VectorXd());
    return true;
  }

 private:
  bool Fail(const YAML::Mark& mark, const std::string& field,
            const std::string& what) {
    std::ostringstream msg;
    msg << source_;
    if (!mark.is_null()) msg << ":" << mark.line + 1 << ":" << mark.column + 1;
    msg << ": ";
    if (!field.empty()) msg << field << ": ";
    msg << what;
    error_ = msg.str();
    return false;
  }

  bool CheckKeys(const YAML::Node& map, const std::string& field,
                 std::set<std::string> allowed) {
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (!allowed.count(key)) {
        std::string list;
        for (const std::string& a : allowed) {
          list += (list.empty() ? "" : ", ") + a;
        }
        return Fail(kv.first.Mark(), field.empty() ? key : field + "." + key,
                    "unknown field (expected one of: " + list + ")");
      }
    }
    return true;
  }

  bool String(const YAML::Node& map, const char* key, const std::string& field,
              std::string* out) {
    const YAML::Node node = map[key];
    if (!node) return Fail(map.Mark(), field, "missing");
    if (!node.IsScalar()) return Fail(node.Mark(), field, "expected a text");
    *out = node.Scalar();
    return true;
  }

  bool Number(const YAML::Node& node, const std::string& field, double* out) {
    if (!node.IsScalar()) return Fail(node.Mark(), field, "expected a number");
    std::string why;
    return internal::ParseFiniteNumber(node.Scalar(), out, &why) ||
           Fail(node.Mark(), field, why);
  }

  // One block: base (0), link (1..n) or tool (n+1).
  bool ParseBlock(const YAML::Node& node, const std::string& field, int block,
                  RobotDescription* robot) {
    RobotModel& m = robot->model;
    const bool tool = block == m.num_joints() + 1;
    const bool base = block == 0;
    if (!node.IsMap()) return Fail(node.Mark(), field, "expected a mapping");
    std::vector<std::string> names;
    for (int j = 0; j < m.block_size(block); ++j) {
      names.push_back(tool ? ToolParameterName(j) : LinkParameterName(j));
    }
    std::set<std::string> allowed(names.begin(), names.end());
    allowed.insert({"free", "true"});
    if (!tool) allowed.insert({"name", "convention"});
    if (base) allowed.erase("gain");
    if (!tool && !base) allowed.insert({"joint", "limits"});
    if (!CheckKeys(node, field, allowed)) return false;

    Link* link = tool ? nullptr : (base ? &m.base : &m.links[block - 1]);
    if (link) {
      if (const YAML::Node name = node["name"]) {
        if (!name.IsScalar())
          return Fail(name.Mark(), field + ".name", "expected a text");
        link->name = name.Scalar();
      } else if (!base) {
        link->name = "L" + std::to_string(block);
      }
      std::string convention;
      if (!String(node, "convention", field + ".convention", &convention)) {
        return false;
      }
      if (convention == "standard_dh") {
        link->convention = LinkConvention::kStandardDH;
      } else if (convention == "modified_dh") {
        link->convention = LinkConvention::kModifiedDH;
      } else if (convention == "hayati") {
        link->convention = LinkConvention::kHayati;
      } else {
        return Fail(node["convention"].Mark(), field + ".convention",
                    "expected standard_dh, modified_dh or hayati, got '" +
                        convention + "'");
      }
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
      double lo, hi;
      if (!Number(limits[0], field + ".limits[0]", &lo) ||
          !Number(limits[1], field + ".limits[1]", &hi)) {
        return false;
      }
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

    // Values: the geometric ones are required (beta for Hayati links only),
    // gain and tool angles default to 1 and 0.
    const int offset = m.block_offset(block);
    for (int j = 0; j < m.block_size(block); ++j) {
      const YAML::Node value = node[names[j]];
      double v;
      if (!value) {
        const bool optional =
            tool
                ? j >= 3
                : (j == kGain ||
                   (j == kBeta && link->convention != LinkConvention::kHayati));
        if (!optional) {
          return Fail(node.Mark(), field + "." + names[j], "missing");
        }
        v = (!tool && j == kGain) ? 1.0 : 0.0;
      } else {
        if (!Number(value, field + "." + names[j], &v)) return false;
        if (IsAngle(tool, j)) v *= angle_scale_;
      }
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
        if (it == names.end() || (base && name == "gain")) {
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
        truth_[offset + j] = IsAngle(tool, j) ? v * angle_scale_ : v;
      }
      has_truth_ = true;
    }
    return true;
  }

  std::string source_;
  std::string error_;
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
  auto block = [&](int b) {
    const bool tool = b == model.num_joints() + 1;
    const int offset = model.block_offset(b);
    out << YAML::BeginMap;
    if (!tool) {
      const Link& l = model.link(b);
      out << YAML::Key << "name" << YAML::Value << model.block_name(b);
      out << YAML::Key << "convention" << YAML::Value
          << LinkConventionName(l.convention);
      if (b > 0) {
        out << YAML::Key << "joint" << YAML::Value
            << JointTypeName(l.joint_type);
        const double s = l.joint_type == JointType::kRevolute ? scale : 1.0;
        out << YAML::Key << "limits" << YAML::Value << YAML::Flow
            << YAML::BeginSeq << ShortestText(l.joint_min * s)
            << ShortestText(l.joint_max * s) << YAML::EndSeq;
      }
    }
    std::vector<std::string> free;
    std::vector<int> differs;
    for (int j = 0; j < model.block_size(b); ++j) {
      const std::string name =
          tool ? ToolParameterName(j) : LinkParameterName(j);
      const bool skip =
          !tool &&
          ((b == 0 && j == kGain) ||
           (j == kBeta && model.link(b).convention != LinkConvention::kHayati));
      if (!skip) {
        const double s = IsAngle(tool, j) ? scale : 1.0;
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
        const double s = IsAngle(tool, j) ? scale : 1.0;
        out << YAML::Key << (tool ? ToolParameterName(j) : LinkParameterName(j))
            << YAML::Value
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
  out << YAML::Key << "tool" << YAML::Value;
  block(model.num_joints() + 1);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace activecal
