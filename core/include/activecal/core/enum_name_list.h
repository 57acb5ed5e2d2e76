// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// EnumToString and StringToEnum (core/enum_names.h) on the names of an
// enum's values listed in the enum's order, for an enum numbered as
// `enum class X { kA, kB, ... }` numbers it (0, 1, ...): the list is the
// table, ACTIVECAL_ENUM_STRING_FUNCTIONS takes it as it takes an EnumName
// table.
//
//   enum class MeasureStatus { kOk, kNotVisible, kUnreachable, kError };
//
//   constexpr const char* kMeasureStatusNames[] = {"ok", "not_visible",
//                                                  "unreachable", "error"};
//   ACTIVECAL_ENUM_STRING_FUNCTIONS(MeasureStatus, kMeasureStatusNames)

#ifndef ACTIVECAL_CORE_ENUM_NAME_LIST_H_
#define ACTIVECAL_CORE_ENUM_NAME_LIST_H_

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <string>

#include "activecal/core/enum_names.h"

namespace activecal {

// names[value]; `unknown` for a value past the list.
template <typename Enum, std::size_t N>
const char* EnumToString(const char* const (&names)[N], Enum value,
                         const char* unknown = "unknown") {
  const auto index = static_cast<std::size_t>(value);
  return index < N ? names[index] : unknown;
}

// The value whose name is `text` (compared exactly), into *value; false
// (and *value untouched) for a name the list lacks.
template <typename Enum, std::size_t N>
bool StringToEnum(const char* const (&names)[N], const std::string& text,
                  Enum* value) {
  const auto found = std::find(std::begin(names), std::end(names), text);
  if (found == std::end(names)) return false;
  *value = static_cast<Enum>(found - std::begin(names));
  return true;
}

}  // namespace activecal

#endif  // ACTIVECAL_CORE_ENUM_NAME_LIST_H_
