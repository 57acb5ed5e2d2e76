// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// The ISO 9283 section of the HTML report: per pose the cycles, AP_p,
// AP_x,y,z and RP_l (mm), AP_a,b,c and RP_a,b,c (mrad), without the model
// and with it (iso9283_cycles.h). Each number is a cell with
// data-key="iso9283.<pose>.<without|with>.<figure>" and its SI value in
// data-value (m, rad), as the report's other tables.

#ifndef ACTIVECAL_REPORT_ISO9283_SECTION_H_
#define ACTIVECAL_REPORT_ISO9283_SECTION_H_

#include <string>

#include "activecal/calibration/iso9283_cycles.h"

namespace activecal {

std::string Iso9283Section(const Iso9283CyclesSummary& summary);

}  // namespace activecal

#endif  // ACTIVECAL_REPORT_ISO9283_SECTION_H_
