// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The end every Options::IsValid shares: the checks write the first failure
// into a stream, and this turns the stream into the answer.
//
//   bool FooOptions::IsValid(std::string* error) const {
//     std::ostringstream msg;
//     if (num_poses <= 0) msg << "num_poses must be > 0, got " << num_poses;
//     return FinishValidation(msg, error);
//   }

#ifndef ACTIVECAL_CORE_VALIDATION_H_
#define ACTIVECAL_CORE_VALIDATION_H_

#include <sstream>
#include <string>
#include <utility>

namespace activecal {

// True if nothing was written to `msg`; otherwise false with what was
// written in *error (when error is not null).
inline bool FinishValidation(const std::ostringstream& msg,
                             std::string* error) {
  std::string text = msg.str();
  if (text.empty()) return true;
  if (error) *error = std::move(text);
  return false;
}

}  // namespace activecal

#endif  // ACTIVECAL_CORE_VALIDATION_H_
