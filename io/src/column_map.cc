// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/column_map.h"

#include <Eigen/Geometry>
#include <cstdio>
#include <map>
#include <set>

#include "activecal/io/csv_files.h"
#include "line_error.h"
#include "number_text.h"
#include "yaml_reader.h"

namespace activecal {
namespace {

using internal::ParseFiniteNumber;
using internal::Trim;

std::string DelimiterName(char c) {
  if (c == '\t') return "tab";
  return std::string("'") + c + "'";
}

class ColumnMapReader : public internal::YamlReader {
 public:
  explicit ColumnMapReader(const std::string& source) : YamlReader(source) {}

  bool Read(const std::string& text, ColumnMap* map) {
    YAML::Node root;
    if (!LoadMap(text,
                 "(a column map: delimiter, decimal, columns, "
                 "orientation)",
                 &root) ||
        !CheckKeys(root, "",
                   {"delimiter", "decimal", "columns", "orientation"})) {
      return false;
    }
    if (const YAML::Node d = root["delimiter"]) {
      map->delimiter_line = d.Mark().line + 1;
      const std::string s = d.IsScalar() ? d.Scalar() : "";
      if (s == "," || s == ";") {
        map->delimiter = s[0];
      } else if (s == "\t" || s == "tab") {
        map->delimiter = '\t';
      } else {
        return Fail(d.Mark(), "delimiter",
                    "expected \",\", \";\" or \"\\t\" (tab), got '" + s +
                        "' (leave it out to detect it from the header)");
      }
    }
    if (const YAML::Node d = root["decimal"]) {
      map->decimal_line = d.Mark().line + 1;
      const std::string s = d.IsScalar() ? d.Scalar() : "";
      if (s != "." && s != ",") {
        return Fail(d.Mark(), "decimal",
                    "expected \".\" or \",\", got '" + s + "'");
      }
      map->decimal = s[0];
      if (map->decimal == ',' && map->delimiter == ',') {
        return Fail(d.Mark(), "decimal",
                    "',' with ',' as the delimiter cannot be read (1,5 "
                    "would be two fields): the file's delimiter is another "
                    "(\";\" or \"\\t\")");
      }
    }
    if (const YAML::Node c = root["columns"]) {
      if (!c.IsMap()) {
        return Fail(c.Mark(), "columns",
                    "expected a mapping of activecal column: the file's "
                    "column");
      }
      if (!CheckUnique(c)) return false;
      for (const auto& kv : c) {
        const std::string field = "columns." + kv.first.Scalar();
        if (!kv.second.IsScalar() || Trim(kv.second.Scalar()).empty()) {
          return Fail(kv.second.Mark(), field,
                      "expected the file's column name");
        }
        map->columns.push_back({kv.first.Scalar(), Trim(kv.second.Scalar()),
                                kv.first.Mark().line + 1});
      }
    }
    if (const YAML::Node o = root["orientation"]) {
      if (!ReadOrientation(o, map)) return false;
    }
    return true;
  }

 private:
  bool CheckUnique(const YAML::Node& c) {
    std::set<std::string> keys;
    for (const auto& kv : c) {
      if (!keys.insert(kv.first.Scalar()).second) {
        return Fail(kv.first.Mark(), "columns." + kv.first.Scalar(),
                    "given twice");
      }
    }
    return true;
  }

  bool ReadOrientation(const YAML::Node& o, ColumnMap* map) {
    if (!o.IsMap()) {
      return Fail(o.Mark(), "orientation",
                  "expected {convention: XYZ, intrinsic: true, unit: deg, "
                  "columns: [a, b, c]}");
    }
    if (!CheckKeys(o, "orientation",
                   {"convention", "intrinsic", "unit", "columns"})) {
      return false;
    }
    map->has_orientation = true;
    map->orientation_line = o.Mark().line + 1;
    std::string text;
    if (!String(o, "convention", "orientation.convention", &text)) {
      return false;
    }
    if (!StringToEulerAxes(text, &map->convention.axes)) {
      return Fail(o["convention"].Mark(), "orientation.convention",
                  "unknown convention '" + text +
                      "' (expected one of XYZ, XZY, YXZ, YZX, ZXY, ZYX, XYX, "
                      "XZX, YXY, YZY, ZXZ, ZYZ)");
    }
    const YAML::Node intrinsic = o["intrinsic"];
    if (!intrinsic) {
      return Fail(o.Mark(), "orientation.intrinsic",
                  "missing (true: about the moving axes, false: about the "
                  "fixed axes)");
    }
    bool is_intrinsic = false;
    if (!intrinsic.IsScalar() ||
        !YAML::convert<bool>::decode(intrinsic, is_intrinsic)) {
      return Fail(intrinsic.Mark(), "orientation.intrinsic",
                  "expected true or false");
    }
    map->convention.frame =
        is_intrinsic ? EulerFrame::kIntrinsic : EulerFrame::kExtrinsic;
    if (!String(o, "unit", "orientation.unit", &text)) return false;
    if (text != "deg" && text != "rad") {
      return Fail(o["unit"].Mark(), "orientation.unit",
                  "expected deg or rad, got '" + text + "'");
    }
    map->convention.degrees = text == "deg";
    const YAML::Node columns = o["columns"];
    if (!columns) return Fail(o.Mark(), "orientation.columns", "missing");
    if (!columns.IsSequence() || columns.size() != 3) {
      return Fail(
          columns.Mark(), "orientation.columns",
          "expected 3 columns (the angles a, b, c in the "
          "convention's order), got " +
              std::to_string(columns.IsSequence() ? columns.size() : 1));
    }
    for (const auto& c : columns) {
      if (!c.IsScalar() || Trim(c.Scalar()).empty()) {
        return Fail(c.Mark(), "orientation.columns",
                    "expected the file's column name");
      }
      map->orientation_columns.push_back(Trim(c.Scalar()));
    }
    return true;
  }
};

// Splits `line` at `delimiter` outside double quotes; the quotes stay, so
// that a field is passed on as written. False if a quote is not closed.
bool SplitAt(const std::string& line, char delimiter,
             std::vector<std::string>* fields) {
  fields->assign(1, "");
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;  // "" inside a quote toggles twice
    if (c == delimiter && !quoted) {
      fields->emplace_back();
    } else {
      fields->back() += c;
    }
  }
  return !quoted;
}

// A field as the ',' separated form holds it: quoted when it holds a
// comma (a text field of a ';' file).
std::string CommaField(const std::string& field) {
  const std::string t = Trim(field);
  if (t.find(',') == std::string::npos || (!t.empty() && t[0] == '"')) {
    return field;
  }
  std::string quoted = "\"";
  for (char c : t) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// "1,5" -> "1.5" for a number written with a decimal comma; other text
// (a label, a number with a point) as is.
std::string DecimalPoint(const std::string& field) {
  const std::string t = Trim(field);
  const size_t comma = t.find(',');
  if (comma == std::string::npos ||
      t.find(',', comma + 1) != std::string::npos ||
      t.find('.') != std::string::npos || t.empty() || t[0] == '"') {
    return field;
  }
  std::string point = t;
  point[comma] = '.';
  double value;
  std::string why;
  return ParseFiniteNumber(point, &value, &why) ? point : field;
}

int CountOutsideQuotes(const std::string& line, char c) {
  int n = 0;
  bool quoted = false;
  for (char x : line) {
    if (x == '"') quoted = !quoted;
    if (x == c && !quoted) ++n;
  }
  return n;
}

std::string Shortest17(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

}  // namespace

bool ParseColumnMap(const std::string& text, const std::string& source,
                    ColumnMap* map, std::string* error) {
  *map = ColumnMap();
  map->source = source;
  ColumnMapReader reader(source);
  if (!reader.Read(text, map)) {
    *error = reader.error();
    return false;
  }
  return true;
}

bool ReadColumnMap(const std::string& path, ColumnMap* map,
                   std::string* error) {
  std::string text;
  return ReadTextFile(path, &text, error) &&
         ParseColumnMap(text, path, map, error);
}

std::string ColumnMapOrientationText(const ColumnMap& map) {
  if (!map.has_orientation) return "";
  std::string out;
  for (const std::string& c : map.orientation_columns) {
    out += (out.empty() ? "" : ", ") + c;
  }
  return out + " as " + EulerConventionToString(map.convention) + " (" +
         map.source + ")";
}

bool ApplyColumnMap(const ColumnMap& map, const RobotModel& model,
                    const std::string& text, const std::string& source,
                    std::string* out, std::vector<std::string>* notes,
                    std::string* error) {
  const auto fail = [&](int line, const std::string& what,
                        const char* field = "header") {
    *error = internal::LineError(source, line, field, what);
    return false;
  };
  for (const ColumnMap::Column& c : map.columns) {
    if (!IsMeasurementsCsvColumn(c.activecal, model)) {
      *error = map.source + ":" + std::to_string(c.line) +
               ": columns: " + c.activecal +
               ": not an activecal column (docs/formats.md lists them; "
               "joints are q<j>_rad/_deg/_m/_mm or <joint name>_rad/...)";
      return false;
    }
  }
  // Lines, without their ends; a UTF-8 byte order mark dropped.
  std::vector<std::string> lines;
  size_t begin = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
    begin = end + 1;
  }
  const auto skipped = [](const std::string& line) {
    const std::string t = Trim(line);
    return t.empty() || t[0] == '#';
  };
  size_t header = 0;
  while (header < lines.size() && skipped(lines[header])) ++header;
  if (header == lines.size()) {
    *out = text;  // the reader names an empty file
    return true;
  }
  const int header_line = static_cast<int>(header) + 1;

  char delimiter = map.delimiter;
  if (delimiter == '\0') {
    const int commas = CountOutsideQuotes(lines[header], ',');
    const int semicolons = CountOutsideQuotes(lines[header], ';');
    const int tabs = CountOutsideQuotes(lines[header], '\t');
    delimiter = ',';
    if (semicolons > commas && semicolons >= tabs) delimiter = ';';
    if (tabs > commas && tabs > semicolons) delimiter = '\t';
    if (notes) {
      notes->push_back(source + ": column map " + map.source + ": delimiter " +
                       DelimiterName(delimiter) + " detected (the header has " +
                       std::to_string(commas) + " ',', " +
                       std::to_string(semicolons) + " ';', " +
                       std::to_string(tabs) + " tabs)");
    }
    if (map.decimal == ',' && delimiter == ',') {
      return fail(header_line,
                  "the column map " + map.source +
                      " has decimal ',' and the header's delimiter is ',' "
                      "(detected): a decimal comma needs another delimiter");
    }
  }

  // The header: mapped names replaced, the orientation's three angle
  // columns become rx_rad, ry_rad, rz_rad.
  std::vector<std::string> names;
  if (!SplitAt(lines[header], delimiter, &names)) {
    return fail(header_line, "a quote is not closed on the header line");
  }
  std::map<std::string, int> index;
  for (size_t k = 0; k < names.size(); ++k) {
    std::string n = Trim(names[k]);
    if (n.size() >= 2 && n.front() == '"' && n.back() == '"') {
      n = n.substr(1, n.size() - 2);
    }
    index.emplace(n, static_cast<int>(k));
  }
  std::vector<std::string> out_names = names;
  std::set<std::string> used;
  for (const ColumnMap::Column& c : map.columns) {
    const auto it = index.find(c.file);
    if (it == index.end()) {
      return fail(header_line, c.file + ": not in the header (column map " +
                                   map.source + ":" + std::to_string(c.line) +
                                   ": columns: " + c.activecal + ")");
    }
    if (!used.insert(c.file).second) {
      return fail(header_line,
                  c.file + ": mapped twice (column map " + map.source + ")");
    }
    out_names[it->second] = c.activecal;
  }
  std::vector<int> angle_column;
  if (map.has_orientation) {
    static const char* kRotationVector[3] = {"rx_rad", "ry_rad", "rz_rad"};
    for (const char* r : kRotationVector) {
      if (index.count(r)) {
        return fail(header_line,
                    std::string(r) +
                        ": the file has a rotation vector besides the "
                        "column map's orientation (" +
                        map.source + "): one representation per file");
      }
    }
    for (int k = 0; k < 3; ++k) {
      const std::string& c = map.orientation_columns[k];
      const auto it = index.find(c);
      if (it == index.end()) {
        return fail(header_line, c + ": not in the header (column map " +
                                     map.source + ":" +
                                     std::to_string(map.orientation_line) +
                                     ": orientation.columns)");
      }
      if (!used.insert(c).second) {
        return fail(header_line,
                    c + ": mapped twice (column map " + map.source + ")");
      }
      angle_column.push_back(it->second);
      out_names[it->second] = kRotationVector[k];
    }
  }

  std::string result;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (i < header || (i > header && skipped(lines[i]))) {
      result += lines[i] + "\n";
      continue;
    }
    std::vector<std::string> fields;
    if (i == header) {
      fields = out_names;
    } else {
      if (!SplitAt(lines[i], delimiter, &fields)) {
        return fail(static_cast<int>(i) + 1,
                    "a quote is not closed on the line", "row");
      }
      if (map.decimal == ',') {
        for (std::string& f : fields) f = DecimalPoint(f);
      }
      if (!angle_column.empty()) {
        Eigen::Vector3d angles;
        int given = 0;
        for (int k = 0; k < 3; ++k) {
          const size_t c = angle_column[k];
          const std::string value = c < fields.size() ? Trim(fields[c]) : "";
          if (value.empty()) continue;
          std::string why;
          if (!ParseFiniteNumber(value, &angles[k], &why)) {
            return fail(static_cast<int>(i) + 1,
                        map.orientation_columns[k] + ": " + why);
          }
          ++given;
        }
        if (given != 0 && given != 3) {
          return fail(static_cast<int>(i) + 1,
                      ColumnMapOrientationText(map) +
                          ": some angles empty, some given (all three or "
                          "none)",
                      "row");
        }
        if (given == 3) {
          const Eigen::Matrix3d R =
              EulerAnglesToRotationMatrix(angles, map.convention);
          const Eigen::AngleAxis<long double> aa(
              Eigen::Quaternion<long double>(R.cast<long double>()));
          const Eigen::Vector3d v = (aa.angle() * aa.axis()).cast<double>();
          for (int k = 0; k < 3; ++k) {
            if (static_cast<size_t>(angle_column[k]) < fields.size()) {
              fields[angle_column[k]] = Shortest17(v[k]);
            }
          }
        }
      }
    }
    std::string row;
    for (size_t k = 0; k < fields.size(); ++k) {
      row += (k ? "," : "") +
             (delimiter == ',' ? fields[k] : CommaField(fields[k]));
    }
    result += row + "\n";
  }
  *out = result;
  return true;
}

}  // namespace activecal
