// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/points_file.h"

#include <map>
#include <set>
#include <utility>

#include "activecal/io/csv_files.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

class PointsFileReader : public internal::YamlReader {
 public:
  explicit PointsFileReader(const std::string& source) : YamlReader(source) {}

  bool Read(const std::string& text, std::vector<Measurement>* distances,
            std::vector<int>* lines) {
    YAML::Node root;
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
      return Fail(YAML::Mark::null_mark(), "",
                  "empty: expected 'distances:' (a list of {from, to, "
                  "distance_m})");
    }
    if (!LoadMap(text, "(a points file: distances)", &root) ||
        !CheckKeys(root, "", {"distances"})) {
      return false;
    }
    const YAML::Node list = root["distances"];
    if (!list || !list.IsSequence() || list.size() == 0) {
      return Fail(list ? list.Mark() : root.Mark(), "distances",
                  "expected a list of {from, to, distance_m}");
    }
    std::set<std::pair<std::string, std::string>> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node e = list[i];
      const std::string field = "distances[" + std::to_string(i) + "]";
      if (!e.IsMap()) {
        return Fail(e.Mark(), field, "expected {from, to, distance_m}");
      }
      if (!CheckKeys(e, field,
                     {"from", "to", "distance_m", "distance_mm", "sigma_m",
                      "sigma_mm"})) {
        return false;
      }
      Measurement m;
      m.type = MeasurementType::kPointDistance;
      if (!String(e, "from", field + ".from", &m.point) ||
          !String(e, "to", field + ".to", &m.point2)) {
        return false;
      }
      if (m.point.empty() || m.point2.empty()) {
        return Fail(e.Mark(), field, "empty point label");
      }
      if (m.point == m.point2) {
        return Fail(e.Mark(), field,
                    "a distance between point '" + m.point +
                        "' and itself measures nothing");
      }
      const auto key = std::minmax(m.point, m.point2);
      if (!seen.insert(key).second) {
        return Fail(e.Mark(), field,
                    "the distance between '" + m.point + "' and '" + m.point2 +
                        "' is given twice");
      }
      if (!Length(e, "distance", field, true, &m.distance)) return false;
      if (!(m.distance > 0)) {
        return Fail(e.Mark(),
                    field + (e["distance_m"] ? ".distance_m" : ".distance_mm"),
                    "must be > 0 (two fixed points apart), got " +
                        std::to_string(m.distance) + " m");
      }
      double sigma = 0.0;
      if (!Length(e, "sigma", field, false, &sigma)) return false;
      if (e["sigma_m"] || e["sigma_mm"]) {
        if (!(sigma > 0)) {
          return Fail(e.Mark(), field + ".sigma",
                      "must be > 0 (leave it out for the default)");
        }
      }
      m.sigma_m[0] = sigma;
      distances->push_back(m);
      if (lines) lines->push_back(e.Mark().line + 1);
    }
    return true;
  }

 private:
  // <name>_m or <name>_mm of entry `e` (one of the two) in metres.
  bool Length(const YAML::Node& e, const std::string& name,
              const std::string& field, bool required, double* out) {
    const YAML::Node m = e[name + "_m"], mm = e[name + "_mm"];
    if (m && mm) {
      return Fail(e.Mark(), field,
                  name + "_m and " + name + "_mm: give one of the two");
    }
    if (!m && !mm) {
      if (required) {
        return Fail(e.Mark(), field, name + "_m (or " + name + "_mm) missing");
      }
      *out = 0.0;
      return true;
    }
    double v = 0.0;
    if (!Number(m ? m : mm, field + "." + name + (m ? "_m" : "_mm"), &v)) {
      return false;
    }
    *out = m ? v : 1e-3 * v;
    return true;
  }
};

}  // namespace

bool ParsePointsFile(const std::string& text, const std::string& source,
                     std::vector<Measurement>* distances,
                     std::vector<int>* lines, std::string* error) {
  distances->clear();
  if (lines) lines->clear();
  PointsFileReader reader(source);
  if (!reader.Read(text, distances, lines)) {
    if (error) *error = reader.error();
    return false;
  }
  return true;
}

bool ReadPointsFile(const std::string& path,
                    std::vector<Measurement>* distances,
                    std::vector<int>* lines, std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParsePointsFile(text, path, distances, lines, error);
}

bool CheckPointDistanceLabels(const std::vector<Measurement>& measurements,
                              const std::vector<Measurement>& distances,
                              const std::vector<int>& lines,
                              const std::string& source, std::string* error) {
  std::map<std::string, int> rows;
  for (const Measurement& m : measurements) {
    if (m.type == MeasurementType::kPoint) ++rows[m.point];
  }
  for (size_t i = 0; i < distances.size(); ++i) {
    for (const std::string* label :
         {&distances[i].point, &distances[i].point2}) {
      if (rows.count(*label) == 0) {
        if (error) {
          *error = source + ":" +
                   std::to_string(i < lines.size() ? lines[i] : 0) +
                   ": distances[" + std::to_string(i) + "]." +
                   (label == &distances[i].point ? "from" : "to") +
                   ": a known distance to point '" + *label +
                   "', which no type=point row of the measurements names";
        }
        return false;
      }
    }
  }
  return true;
}

}  // namespace activecal
