// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The names of an enum's values as one table, for the XToString/StringToX
// pairs of the public headers (Ceres' types.h style). Each enum keeps its
// two public functions, declared (and documented) in its header; its source
// file defines them from its table:
//
//   constexpr EnumName<RobustLoss> kRobustLossNames[] = {
//       {RobustLoss::kNone, "none"}, {RobustLoss::kHuber, "huber"}};
//   ACTIVECAL_ENUM_STRING_FUNCTIONS(RobustLoss, kRobustLossNames)
//
// which defines `const char* RobustLossToString(RobustLoss)` (EnumToString)
// and `bool StringToRobustLoss(const std::string&, RobustLoss*)`
// (StringToEnum).

#ifndef ACTIVECAL_CORE_ENUM_NAMES_H_
#define ACTIVECAL_CORE_ENUM_NAMES_H_

#include <cstddef>
#include <string>

namespace activecal {

// One value of an enum and its name.
template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value` in `table`; `unknown` for a value the table lacks.
template <typename Enum, std::size_t N>
const char* EnumToString(const EnumName<Enum> (&table)[N], Enum value,
                         const char* unknown = "unknown") {
  for (const EnumName<Enum>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return unknown;
}

// The value named `text` in `table` (the names compared exactly), into
// *value; false (and *value untouched) for a name the table lacks.
template <typename Enum, std::size_t N>
bool StringToEnum(const EnumName<Enum> (&table)[N], const std::string& text,
                  Enum* value) {
  for (const EnumName<Enum>& entry : table) {
    if (text == entry.name) {
      *value = entry.value;
      return true;
    }
  }
  return false;
}

}  // namespace activecal

// Defines Enum##ToString and StringTo##Enum (declared in Enum's header) on
// `table`, an array of EnumName<Enum>; in namespace activecal.
#define ACTIVECAL_ENUM_STRING_FUNCTIONS(Enum, table)          \
  const char* Enum##ToString(Enum value) {                    \
    return ::activecal::EnumToString(table, value);           \
  }                                                           \
  bool StringTo##Enum(const std::string& text, Enum* value) { \
    return ::activecal::StringToEnum(table, text, value);     \
  }

#endif  // ACTIVECAL_CORE_ENUM_NAMES_H_
