// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/urdf_export.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "activecal/core/kinematics.h"
#include "activecal/io/xml_text.h"
#include "number_text.h"

namespace activecal {
namespace {

using internal::ShortestText;

// How far (largest matrix entry) a written rotation may read back from the
// one meant: RotationToRpy's few ulp and urdfdom's quaternion.
constexpr double kRereadTolerance = 1e-14;

Eigen::Isometry3d Iso(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

// The correction of a URDF block: Trans(x, y, z) Rz(rz) Ry(ry) Rx(rx).
Eigen::Isometry3d Correction(const double* p) {
  return Iso(RpyRotation(p[kUrdfRx], p[kUrdfRy], p[kUrdfRz]),
             Eigen::Vector3d(p[kUrdfX], p[kUrdfY], p[kUrdfZ]));
}

Eigen::Isometry3d LinkAt(const Link& link, const double* p) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  LinkTransform(link, p, 0.0, &R, &t);
  return Iso(R, t);
}

// Text for an XML attribute value.
std::string Escaped(const std::string& text) {
  return EscapeXmlText(text, XmlApostrophe::kNamed);
}

// UTF-8 of a character number (a numeric character reference).
void AppendUtf8(unsigned long c, std::string* out) {
  if (c < 0x80) {
    *out += static_cast<char>(c);
  } else if (c < 0x800) {
    *out += static_cast<char>(0xC0 | (c >> 6));
    *out += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    *out += static_cast<char>(0xE0 | (c >> 12));
    *out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    *out += static_cast<char>(0xF0 | (c >> 18));
    *out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    *out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (c & 0x3F));
  }
}

// The value an XML parser gives for attribute text: the five predefined
// entities and numeric character references replaced (what urdfdom's
// parser does), anything else kept as it is.
std::string Unescaped(const std::string& text) {
  static const std::pair<const char*, char> kEntities[] = {{"&amp;", '&'},
                                                           {"&lt;", '<'},
                                                           {"&gt;", '>'},
                                                           {"&quot;", '"'},
                                                           {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < text.size();) {
    if (text[i] != '&') {
      out += text[i++];
      continue;
    }
    bool replaced = false;
    for (const auto& [entity, c] : kEntities) {
      if (text.compare(i, std::strlen(entity), entity) == 0) {
        out += c;
        i += std::strlen(entity);
        replaced = true;
        break;
      }
    }
    const size_t semicolon = text.find(';', i);
    if (!replaced && text.compare(i, 2, "&#") == 0 &&
        semicolon != std::string::npos) {
      const bool hex = i + 2 < text.size() && text[i + 2] == 'x';
      const std::string digits =
          text.substr(i + (hex ? 3 : 2), semicolon - i - (hex ? 3 : 2));
      char* end = nullptr;
      const unsigned long c = std::strtoul(digits.c_str(), &end, hex ? 16 : 10);
      if (!digits.empty() && *end == 0 && c > 0 && c <= 0x10FFFF) {
        AppendUtf8(c, &out);
        i = semicolon + 1;
        replaced = true;
      }
    }
    if (!replaced) out += text[i++];
  }
  return out;
}

std::string Triple(const Eigen::Vector3d& v) {
  return ShortestText(v[0]) + " " + ShortestText(v[1]) + " " +
         ShortestText(v[2]);
}

// The rpy attribute of a rotation: RotationToRpy's angles, which read back
// to it to rounding also at pitch +-90 deg (where urdfdom's own getRPY
// snaps); CalibratedUrdfText checks the text it writes.
std::string RpyText(const Eigen::Matrix3d& R) {
  return Triple(RotationToRpy(R));
}

// The gain of a link block (1 for the base).
double GainOf(const Link& link, const double* p) {
  if (link.convention == LinkConvention::kUrdf) return p[kUrdfGain];
  if (link.convention == LinkConvention::kFrame) return 1.0;
  return p[kGain];
}

// ---------------------------------------------------------------------------
// Editing the text of a URDF: the start tag of an element, its attributes.

struct Tag {
  size_t begin = std::string::npos;  // '<'
  size_t end = std::string::npos;    // one past '>'
};

// The end of a start tag beginning at `begin` ('<'), quotes respected.
size_t TagEnd(const std::string& s, size_t begin) {
  char quote = 0;
  for (size_t i = begin; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      return i + 1;
    }
  }
  return std::string::npos;
}

// The value of attribute `name` of a start tag, with its position.
bool Attribute(const std::string& s, const Tag& tag, const std::string& name,
               size_t* value_begin, size_t* value_end) {
  size_t i = tag.begin;
  while (true) {
    i = s.find(name, i);
    if (i == std::string::npos || i >= tag.end) return false;
    const bool word_start = std::isspace(static_cast<unsigned char>(s[i - 1]));
    size_t j = i + name.size();
    while (j < tag.end && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (word_start && j < tag.end && s[j] == '=') {
      ++j;
      while (j < tag.end && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j < tag.end && (s[j] == '"' || s[j] == '\'')) {
        const size_t close = s.find(s[j], j + 1);
        if (close == std::string::npos || close >= tag.end) return false;
        *value_begin = j + 1;
        *value_end = close;
        return true;
      }
    }
    i += name.size();
  }
}

// Start tags of element `element` outside comments, in order.
std::vector<Tag> StartTags(const std::string& s, const std::string& element,
                           size_t from, size_t to) {
  std::vector<Tag> tags;
  const std::string open = "<" + element;
  size_t i = from;
  while (i < to) {
    const size_t comment = s.find("<!--", i);
    const size_t next = s.find(open, i);
    if (next == std::string::npos || next >= to) break;
    if (comment != std::string::npos && comment < next) {
      const size_t close = s.find("-->", comment + 4);
      if (close == std::string::npos) break;
      i = close + 3;
      continue;
    }
    const char after =
        next + open.size() < s.size() ? s[next + open.size()] : 0;
    if (std::isspace(static_cast<unsigned char>(after)) || after == '>' ||
        after == '/') {
      Tag tag;
      tag.begin = next;
      tag.end = TagEnd(s, next);
      if (tag.end == std::string::npos) break;
      tags.push_back(tag);
      i = tag.end;
    } else {
      i = next + open.size();
    }
  }
  return tags;
}

// Sets (or adds) attribute `name` of a start tag to `value`; returns the
// change in length.
long SetAttribute(std::string* s, Tag* tag, const std::string& name,
                  const std::string& value) {
  size_t vb, ve;
  if (Attribute(*s, *tag, name, &vb, &ve)) {
    const long delta = static_cast<long>(value.size()) - (ve - vb);
    s->replace(vb, ve - vb, value);
    tag->end += delta;
    return delta;
  }
  // Before "/>" or ">".
  size_t at = tag->end - 1;
  if (at > tag->begin && (*s)[at - 1] == '/') --at;
  const std::string text = " " + name + "=\"" + value + "\"";
  s->insert(at, text);
  tag->end += text.size();
  return static_cast<long>(text.size());
}

}  // namespace

bool CalibratedUrdfText(const std::string& xml, const std::string& source,
                        const UrdfChainOptions& chain, const RobotModel& model,
                        const Eigen::VectorXd& values, std::string* out,
                        std::vector<std::string>* warnings,
                        std::string* error) {
  auto fail = [&](const std::string& what) {
    if (error) *error = source + ": " + what;
    return false;
  };
  std::vector<UrdfChainJoint> joints;
  if (!UrdfChainJoints(xml, source, chain, &joints, error)) return false;
  std::string text = xml;
  const std::vector<const double*> blocks = BlockPointers(model, values.data());
  // The origins written, checked against the text read back.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> written;
  for (int i = 0; i < model.num_joints(); ++i) {
    const Link& link = model.links[i];
    if (link.convention != LinkConvention::kUrdf) {
      return fail("link '" + link.name + "' is not a URDF joint (convention " +
                  LinkConventionName(link.convention) + ")");
    }
    const auto joint = std::find_if(joints.begin(), joints.end(),
                                    [&](const UrdfChainJoint& j) {
                                      return j.moving && j.name == link.name;
                                    });
    if (joint == joints.end()) {
      return fail("joint '" + link.name +
                  "' of the model is not a moving "
                  "joint of the chain in this file");
    }
    const double* p = blocks[i + 1];
    if (p[kUrdfGain] != 1.0 && warnings) {
      warnings->push_back("joint '" + link.name + "' has gain " +
                          ShortestText(p[kUrdfGain]) +
                          ", which a URDF cannot hold: the URDF uses 1");
    }
    // A joint the calibration left at its nominal origin keeps its bytes.
    bool unchanged = p[kUrdfOffset] == 0.0;
    for (int k = kUrdfX; k <= kUrdfRz; ++k) unchanged &= p[k] == 0.0;
    if (unchanged) continue;
    const double s = p[kUrdfOffset];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (link.joint_type == JointType::kRevolute) {
      motion.linear() = AxisRotation(link.axis, s);
    } else {
      motion.translation() = s * link.axis;
    }
    const Eigen::Isometry3d origin =
        Iso(joint->rotation, joint->xyz) * Correction(p) * motion;
    // The joint's start tag: name="..." (compared as the XML parser reads
    // it: "j2 &amp; b" is joint "j2 & b") and a type attribute (joints of
    // transmissions have no type).
    Tag found;
    for (const Tag& tag : StartTags(text, "joint", 0, text.size())) {
      size_t vb, ve, tb, te;
      if (Attribute(text, tag, "name", &vb, &ve) &&
          Unescaped(text.substr(vb, ve - vb)) == link.name &&
          Attribute(text, tag, "type", &tb, &te)) {
        found = tag;
        break;
      }
    }
    if (found.begin == std::string::npos) {
      return fail("cannot find the <joint name=\"" + Escaped(link.name) +
                  "\" type=...> element in the text");
    }
    const size_t close = text.find("</joint>", found.end);
    if (close == std::string::npos) {
      return fail("joint '" + link.name + "' has no </joint>");
    }
    const std::string xyz = Triple(origin.translation());
    const std::string rpy = RpyText(origin.linear());
    written.emplace_back(link.name, origin);
    const std::vector<Tag> origins =
        StartTags(text, "origin", found.end, close);
    if (origins.empty()) {
      text.insert(found.end,
                  "<origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/>");
    } else {
      Tag tag = origins[0];
      SetAttribute(&text, &tag, "xyz", xyz);
      SetAttribute(&text, &tag, "rpy", rpy);
    }
  }
  // Every origin written reads back (through urdfdom) as the rotation and
  // translation meant, to the rounding of urdfdom's quaternion.
  if (!written.empty()) {
    std::vector<UrdfChainJoint> reread;
    std::string why;
    if (!UrdfChainJoints(text, source, chain, &reread, &why)) {
      return fail("the edited text does not parse: " + why);
    }
    for (const auto& [name, origin] : written) {
      for (const UrdfChainJoint& j : reread) {
        if (!j.moving || j.name != name) continue;
        const double rotation =
            (j.rotation - origin.linear()).cwiseAbs().maxCoeff();
        const double translation =
            (j.xyz - origin.translation()).cwiseAbs().maxCoeff();
        if (!(rotation <= kRereadTolerance && translation == 0.0)) {
          return fail("joint '" + name + "': the written origin reads back " +
                      ShortestText(std::max(rotation, translation)) +
                      " away from the calibrated one");
        }
      }
    }
  }
  *out = std::move(text);
  return true;
}

std::string UrdfFromModel(const RobotModel& model,
                          const Eigen::VectorXd& values,
                          std::vector<std::string>* warnings) {
  const std::vector<const double*> blocks = BlockPointers(model, values.data());
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- written by activecal from a kinematic model -->\n"
      << "<robot name=\"" << Escaped(model.name) << "\">\n"
      << "  <link name=\"base_link\"/>\n";
  for (int i = 1; i <= model.num_joints(); ++i) {
    out << "  <link name=\"link" << i << "\"/>\n";
  }
  out << "  <link name=\"tip\"/>\n";
  // A moving joint's URDF type and <limit>: a revolute joint unbounded at
  // both ends is continuous (no limits); revolute and prismatic joints need
  // finite limits.
  auto type_and_limits = [&](const Link& link, const std::string& name,
                             std::string* limits) {
    const bool revolute = link.joint_type == JointType::kRevolute;
    const bool finite =
        std::isfinite(link.joint_min) && std::isfinite(link.joint_max);
    auto range = [&] {
      return "[" + ShortestText(link.joint_min) + ", " +
             ShortestText(link.joint_max) + "] " + (revolute ? "rad" : "m");
    };
    if (revolute && !finite) {
      if (std::isfinite(link.joint_min) || std::isfinite(link.joint_max)) {
        if (warnings) {
          warnings->push_back("joint '" + name + "' has the range " + range() +
                              ", which a URDF cannot hold (a revolute joint "
                              "has two finite limits): written as continuous");
        }
      }
      return std::string("continuous");
    }
    const double big = std::numeric_limits<double>::max();
    if (!finite && warnings) {
      warnings->push_back("joint '" + name + "' has the range " + range() +
                          ", which a URDF cannot hold (a prismatic joint has "
                          "two finite limits): its unbounded end is written "
                          "as " +
                          ShortestText(big) + " m");
    }
    *limits = "    <limit lower=\"" +
              ShortestText(std::max(link.joint_min, -big)) + "\" upper=\"" +
              ShortestText(std::min(link.joint_max, big)) +
              "\" effort=\"0\" velocity=\"0\"/>\n";
    return std::string(revolute ? "revolute" : "prismatic");
  };
  auto joint = [&](const std::string& name, const std::string& parent,
                   const std::string& child, const Eigen::Isometry3d& origin,
                   const Eigen::Vector3d& axis, const Link* link) {
    std::string limits;
    const std::string type =
        link ? type_and_limits(*link, name, &limits) : "fixed";
    out << "  <joint name=\"" << Escaped(name) << "\" type=\"" << type
        << "\">\n"
        << "    <parent link=\"" << parent << "\"/>\n"
        << "    <child link=\"" << child << "\"/>\n"
        << "    <origin xyz=\"" << Triple(origin.translation()) << "\" rpy=\""
        << RpyText(origin.linear()) << "\"/>\n";
    if (link) out << "    <axis xyz=\"" << Triple(axis) << "\"/>\n" << limits;
    out << "  </joint>\n";
  };
  // The fixed transform waiting to be folded into the next joint's origin.
  Eigen::Isometry3d pending = model.base.convention == LinkConvention::kFrame
                                  ? Eigen::Isometry3d::Identity()
                                  : LinkAt(model.base, blocks[0]);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  for (int i = 0; i < model.num_joints(); ++i) {
    const Link& l = model.links[i];
    const double* p = blocks[i + 1];
    const bool revolute = l.joint_type == JointType::kRevolute;
    if (GainOf(l, p) != 1.0 && warnings) {
      warnings->push_back("link '" + model.block_name(i + 1) + "' has gain " +
                          ShortestText(GainOf(l, p)) +
                          ", which a URDF cannot hold: the URDF uses 1");
    }
    double q[kMaxBlockSize];
    std::copy(p, p + model.block_size(i + 1), q);
    Eigen::Isometry3d origin, next = Eigen::Isometry3d::Identity();
    Eigen::Vector3d axis = z;
    switch (l.convention) {
      case LinkConvention::kUrdf: {
        Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
        if (revolute) {
          motion.linear() = AxisRotation(l.axis, p[kUrdfOffset]);
        } else {
          motion.translation() = p[kUrdfOffset] * l.axis;
        }
        origin = pending * Iso(l.origin_rotation, l.origin_xyz) *
                 Correction(p) * motion;
        axis = l.axis;
        break;
      }
      case LinkConvention::kModifiedDH:
        // Rx(alpha) Tx(a) Rz(gamma) [Tz(d)] | motion | [Tz(d)]
        if (revolute) q[kD] = 0.0;
        q[kGain] = 0.0;
        origin = pending * LinkAt(l, q);
        if (revolute) next.translation() = p[kD] * z;
        break;
      default: {
        // Rz(gamma) [Tz(d)] | motion | [Tz(d)] Tx(a) Rx(alpha) [Ry(beta)]
        Eigen::Isometry3d pre = Iso(
            AxisRotation(z, p[kGamma]),
            revolute ? Eigen::Vector3d::Zero() : Eigen::Vector3d(p[kD] * z));
        origin = pending * pre;
        q[kGamma] = 0.0;
        q[kGain] = 0.0;
        if (!revolute) q[kD] = 0.0;
        next = LinkAt(l, q);
        break;
      }
    }
    joint(model.block_name(i + 1),
          i == 0 ? "base_link" : "link" + std::to_string(i),
          "link" + std::to_string(i + 1), origin, axis, &l);
    pending = next;
  }
  // The links are all generated (base_link, link1 .. linkN, tip); the
  // joints are the model's, and the fixed one to the tip gets a name none
  // of them has.
  std::set<std::string> names;
  for (int b = 1; b <= model.num_joints(); ++b)
    names.insert(model.block_name(b));
  std::string tip_joint = "tip_fixed";
  for (int k = 2; names.count(tip_joint); ++k) {
    tip_joint = "tip_fixed_" + std::to_string(k);
  }
  joint(tip_joint, "link" + std::to_string(model.num_joints()), "tip",
        pending * Iso(model.tip.rotation, model.tip.translation), z, nullptr);
  out << "</robot>\n";
  return out.str();
}

bool CheckUrdfAgainstModel(const std::string& urdf, const std::string& source,
                           const UrdfChainOptions& chain,
                           const RobotModel& model,
                           const Eigen::VectorXd& values,
                           const std::vector<Measurement>& measurements,
                           double* max_difference_m, std::string* error) {
  RobotDescription reloaded;
  if (!ParseUrdfRobot(urdf, source, chain, &reloaded, error)) return false;
  RobotModel& r = reloaded.model;
  if (r.num_joints() != model.num_joints()) {
    if (error) {
      *error = source + ": the reloaded chain has " +
               std::to_string(r.num_joints()) + " joints, the model " +
               std::to_string(model.num_joints());
    }
    return false;
  }
  r.markers = model.markers;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(r.num_parameters());
  for (int b = 0; b < r.num_blocks(); ++b) {
    DefaultBlockValues(r, b, p.data() + r.block_offset(b));
  }
  if (model.base.convention == LinkConvention::kFrame)
    p.head(6) = values.head(6);
  const int tail = kMarkerBlockSize * model.num_markers();
  p.tail(tail) = values.tail(tail);
  r.nominal = p;
  double worst = 0.0;
  for (const Measurement& m : measurements) {
    const Measurement a = PredictMeasurement(model, values, m);
    const Measurement b = PredictMeasurement(r, p, m);
    worst = std::max(worst, (a.position - b.position).norm());
    worst = std::max(worst, std::abs(a.distance - b.distance));
    if (m.type == MeasurementType::kPose) {
      Eigen::Matrix3d Ra, Rb;
      Eigen::Vector3d ta, tb;
      TargetFrame(model, values, m.joints, &Ra, &ta, m.marker);
      TargetFrame(r, p, m.joints, &Rb, &tb, m.marker);
      worst = std::max(worst, Eigen::AngleAxisd(Ra.transpose() * Rb).angle());
    }
  }
  *max_difference_m = worst;
  return true;
}

}  // namespace activecal
