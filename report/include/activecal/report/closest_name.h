// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The name a mistyped option most likely meant ("--num_pose" for
// "--num_poses"), for the programs' "did you mean" messages.

#ifndef ACTIVECAL_REPORT_CLOSEST_NAME_H_
#define ACTIVECAL_REPORT_CLOSEST_NAME_H_

#include <string>
#include <vector>

namespace activecal {

// The Levenshtein distance of a and b (insertions, deletions and
// substitutions of one character).
int EditDistance(const std::string& a, const std::string& b);

// The first of `names` at the least EditDistance from `name`, when that
// distance is at most max(2, name.size() / 3); empty otherwise (and for no
// names).
std::string ClosestName(const std::string& name,
                        const std::vector<std::string>& names);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_CLOSEST_NAME_H_
