// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/controller_programs.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "activecal/core/enum_name_list.h"
#include "activecal/core/validation.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {

namespace {

using internal::kDegree;

bool Prismatic(const RobotModel& model, int j) {
  return model.links[j].joint_type == JointType::kPrismatic;
}

class ConventionParser : public internal::YamlReader {
 public:
  using YamlReader::YamlReader;

  bool Parse(const std::string& text, const RobotModel& model,
             ControllerConvention* out) {
    YAML::Node root;
    if (!LoadMap(text, "with controller and joints", &root)) return false;
    if (!CheckKeys(root, "", {"controller", "joints"})) return false;
    *out = ControllerConvention();
    if (root["controller"] &&
        !String(root, "controller", "controller", &out->controller)) {
      return false;
    }
    const YAML::Node joints = root["joints"];
    if (!joints) return Fail(root.Mark(), "joints", "missing");
    if (!joints.IsSequence()) {
      return Fail(joints.Mark(), "joints",
                  "expected a list, one entry per joint");
    }
    if (static_cast<int>(joints.size()) != model.num_joints()) {
      return Fail(joints.Mark(), "joints",
                  "has " + std::to_string(joints.size()) +
                      " entries, the robot '" + model.name + "' " +
                      std::to_string(model.num_joints()) + " joints");
    }
    for (int j = 0; j < model.num_joints(); ++j) {
      const YAML::Node e = joints[j];
      const std::string field = "joints[" + std::to_string(j) + "]";
      if (!e.IsMap()) {
        return Fail(e.Mark(), field, "expected {name: A1, sign: 1, ...}");
      }
      if (!CheckKeys(e, field,
                     {"name", "sign", "offset_deg", "offset_rad", "offset_mm",
                      "offset_m", "joint"})) {
        return false;
      }
      ControllerJoint c;
      if (!String(e, "name", field + ".name", &c.name)) return false;
      if (e["sign"]) {
        if (!Number(e["sign"], field + ".sign", &c.sign)) return false;
        if (c.sign != 1 && c.sign != -1) {
          return Fail(e["sign"].Mark(), field + ".sign",
                      "expected 1 or -1, got " + e["sign"].Scalar());
        }
      }
      const bool prismatic = Prismatic(model, j);
      const char* const keys[] = {"offset_deg", "offset_rad", "offset_mm",
                                  "offset_m"};
      const double scales[] = {kDegree, 1.0, 1e-3, 1.0};
      const bool for_prismatic[] = {false, false, true, true};
      int given = 0;
      for (int k = 0; k < 4; ++k) {
        const YAML::Node v = e[keys[k]];
        if (!v) continue;
        if (++given > 1) {
          return Fail(v.Mark(), field + "." + keys[k],
                      "one offset per joint (offset_deg, offset_rad, "
                      "offset_mm or offset_m)");
        }
        if (for_prismatic[k] != prismatic) {
          return Fail(v.Mark(), field + "." + keys[k],
                      std::string("joint ") + std::to_string(j + 1) + " is " +
                          (prismatic ? "prismatic: use offset_mm or offset_m"
                                     : "revolute: use offset_deg or "
                                       "offset_rad"));
        }
        double value;
        if (!Number(v, field + "." + keys[k], &value)) return false;
        c.offset = value * scales[k];
      }
      if (const YAML::Node name = e["joint"]) {
        if (!name.IsScalar() || name.Scalar() != model.links[j].name) {
          return Fail(name.Mark(), field + ".joint",
                      "is for joint '" + name.Scalar() +
                          "', the robot's joint " + std::to_string(j + 1) +
                          " is '" + model.links[j].name + "'");
        }
      }
      out->joints.push_back(c);
    }
    return true;
  }
};

// A value for the program: fixed-point text to `digits` decimals, without
// a minus sign on zero.
std::string Fixed(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  std::string s = text;
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') {
    s.erase(0, 1);
  }
  return s;
}

// Joint j at activecal's q as the program writes it, to `digits` decimals.
// Rounding to nearest could put a pose at a limit a step beyond it, where
// the controller stops at its software limit: such a value is rounded
// toward the range instead. (Beyond by a millionth of a step is the limit
// itself: -120.000000 deg for a URDF's -2.0943951023931953 rad.)
std::string JointText(const RobotModel& model,
                      const ControllerConvention& convention,
                      ProgramLanguage language, int j, double q, int digits) {
  const double v = ControllerJointValue(model, convention, language, j, q);
  std::string text = Fixed(v, digits);
  const Link& link = model.links[j];
  if (!(q >= link.joint_min && q <= link.joint_max)) return text;
  double lo =
      ControllerJointValue(model, convention, language, j, link.joint_min);
  double hi =
      ControllerJointValue(model, convention, language, j, link.joint_max);
  if (lo > hi) std::swap(lo, hi);
  const double written = std::strtod(text.c_str(), nullptr);
  const double step = std::pow(10.0, -digits);
  if (written > hi + 1e-6 * step) text = Fixed(v - 0.5 * step, digits);
  if (written < lo - 1e-6 * step) text = Fixed(v + 0.5 * step, digits);
  return text;
}

bool ValidName(const std::string& name) {
  if (name.empty() || name.size() > 24 || !std::isalpha(name[0])) return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

}  // namespace

constexpr const char* kProgramLanguageNames[] = {"urscript", "krl", "rapid"};
ACTIVECAL_ENUM_STRING_FUNCTIONS(ProgramLanguage, kProgramLanguageNames)

ControllerConvention IdentityConvention(const RobotModel& model) {
  ControllerConvention c;
  c.controller = "activecal's own joint convention";
  for (int j = 0; j < model.num_joints(); ++j) {
    ControllerJoint joint;
    joint.name = "J" + std::to_string(j + 1);
    c.joints.push_back(joint);
  }
  return c;
}

bool ParseControllerConvention(const std::string& text,
                               const std::string& source,
                               const RobotModel& model,
                               ControllerConvention* convention,
                               std::string* error) {
  ConventionParser parser(source);
  if (parser.Parse(text, model, convention)) return true;
  *error = parser.error();
  return false;
}

bool ReadControllerConvention(const std::string& path, const RobotModel& model,
                              ControllerConvention* convention,
                              std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseControllerConvention(text, path, model, convention, error);
}

double ControllerJointValue(const RobotModel& model,
                            const ControllerConvention& convention,
                            ProgramLanguage language, int j, double q) {
  const ControllerJoint& c = convention.joints[j];
  const double value = c.sign * q + c.offset;
  if (language == ProgramLanguage::kUrScript) return value;
  return Prismatic(model, j) ? value * 1e3 : value / kDegree;
}

bool ControllerProgramOptions::IsValid(std::string* error) const {
  std::ostringstream msg;
  if (!ValidName(name)) {
    msg << "program name '" << name
        << "' must be a letter, then letters, digits or '_', at most 24";
  } else if (!(wait_s >= 0) || !std::isfinite(wait_s)) {
    msg << "the wait must be >= 0 s, got " << wait_s;
  } else if (!(speed_fraction >= 0.01 && speed_fraction <= 1)) {
    msg << "the speed fraction must be in [0.01, 1], got " << speed_fraction;
  } else if (comment.find('\n') != std::string::npos) {
    msg << "the comment must be one line";
  }
  return FinishValidation(msg, error);
}

bool ControllerProgramText(const RobotModel& model,
                           const ControllerConvention& convention,
                           const PoseList& poses,
                           const ControllerProgramOptions& options,
                           std::string* text, std::string* error) {
  if (!options.IsValid(error)) return false;
  const int nj = model.num_joints();
  if (static_cast<int>(convention.joints.size()) != nj) {
    *error = "the controller convention has " +
             std::to_string(convention.joints.size()) + " joints, the robot " +
             std::to_string(nj);
    return false;
  }
  const ProgramLanguage lang = options.language;
  if (lang != ProgramLanguage::kUrScript && nj > 12) {
    *error = std::string(ProgramLanguageToString(lang)) +
             " programs hold 6 robot and 6 external axes, the robot has " +
             std::to_string(nj) + " joints";
    return false;
  }
  if (poses.joints.cols() != nj) {
    *error = "the poses have " + std::to_string(poses.joints.cols()) +
             " joints, the robot " + std::to_string(nj);
    return false;
  }
  const int n = static_cast<int>(poses.joints.rows());
  const bool ur = lang == ProgramLanguage::kUrScript;
  const std::string c = ur ? "#" : lang == ProgramLanguage::kKrl ? ";" : "!";
  const std::string indent = lang == ProgramLanguage::kRapid ? "    " : "  ";
  std::ostringstream out;
  auto header = [&](const std::string& in) {
    out << in << c << " activecal: " << n << " poses of robot '" << model.name
        << "', a wait of " << options.wait_s
        << " s at each for the measurement\n";
    if (!options.comment.empty())
      out << in << c << " " << options.comment << "\n";
    out << in << c << " joint values in the controller's convention ("
        << (convention.controller.empty() ? "as stated" : convention.controller)
        << "): ";
    for (int j = 0; j < nj; ++j) {
      const ControllerJoint& cj = convention.joints[j];
      out << (j ? ", " : "") << cj.name << " = " << (cj.sign < 0 ? "-" : "")
          << "q" << j + 1;
      if (cj.offset != 0) {
        out << " + "
            << internal::ShortestText(Prismatic(model, j) ? cj.offset * 1e3
                                                          : cj.offset / kDegree)
            << (Prismatic(model, j) ? " mm" : " deg");
      }
    }
    out << "\n";
  };
  auto pose_comment = [&](const std::string& in, int i) {
    out << in << c << " pose " << i + 1 << " of " << n << ": pose_index "
        << (i < static_cast<int>(poses.pose_indices.size())
                ? poses.pose_indices[i]
                : i)
        << "\n";
  };
  auto value = [&](int i, int j) {
    return JointText(model, convention, lang, j, poses.joints(i, j),
                     ur ? 9 : 6);
  };
  const double pct = 100.0 * options.speed_fraction;
  if (ur) {
    out << "def " << options.name << "():\n";
    header("  ");
    const std::string av = "a=" + Fixed(1.4 * options.speed_fraction, 4) +
                           ", v=" + Fixed(1.05 * options.speed_fraction, 4);
    for (int i = 0; i < n; ++i) {
      pose_comment("  ", i);
      out << "  textmsg(\"activecal: pose " << i + 1 << " of " << n << "\")\n";
      out << "  movej([";
      for (int j = 0; j < nj; ++j) out << (j ? ", " : "") << value(i, j);
      out << "], " << av << ")\n";
      out << "  sleep(" << Fixed(options.wait_s, 3) << ")\n";
    }
    out << "end\n";
  } else if (lang == ProgramLanguage::kKrl) {
    out << "DEF " << options.name << "( )\n";
    header("  ");
    // KUKA's own way to set the PTP speed of A1..A6 (no loop variable: KRL
    // names are case-insensitive, and AXIS is one of its types); the
    // external axes' $VEL_EXTAX and $ACC_EXTAX (INT percent) explicitly.
    const std::string percent = std::to_string(std::lround(pct));
    out << "  BAS(#INITMOV, 0)\n";
    out << "  BAS(#VEL_PTP, " << percent << ")\n";
    out << "  BAS(#ACC_PTP, " << percent << ")\n";
    for (int e = 1; e <= nj - 6; ++e) {
      out << "  $VEL_EXTAX[" << e << "] = " << percent << "\n";
      out << "  $ACC_EXTAX[" << e << "] = " << percent << "\n";
    }
    for (int i = 0; i < n; ++i) {
      pose_comment("  ", i);
      out << "  PTP {";
      for (int j = 0; j < nj; ++j) {
        out << (j ? ", " : "")
            << (j < 6 ? "A" + std::to_string(j + 1)
                      : "E" + std::to_string(j - 5))
            << " " << value(i, j);
      }
      out << "}\n";
      out << "  WAIT SEC " << Fixed(options.wait_s, 3) << "\n";
    }
    out << "END\n";
  } else {
    out << "MODULE " << options.name << "\n";
    header("  ");
    out << "  PROC main()\n";
    out << "    VelSet " << Fixed(pct, 1) << ", 5000;\n";
    for (int i = 0; i < n; ++i) {
      pose_comment("    ", i);
      out << "    MoveAbsJ [[";
      for (int j = 0; j < 6; ++j) {
        out << (j ? ", " : "") << (j < nj ? value(i, j) : "9E9");
      }
      out << "], [";
      for (int j = 6; j < 12; ++j) {
        out << (j > 6 ? ", " : "") << (j < nj ? value(i, j) : "9E9");
      }
      out << "]], v1000, fine, tool0;\n";
      out << "    WaitTime " << Fixed(options.wait_s, 3) << ";\n";
    }
    out << "  ENDPROC\n";
    out << "ENDMODULE\n";
  }
  *text = out.str();
  return true;
}

}  // namespace activecal
