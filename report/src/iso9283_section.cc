// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/report/iso9283_section.h"

#include <cmath>

#include "activecal/core/text_table.h"
#include "activecal/report/svg_figures.h"

namespace activecal {
namespace {

std::string Table(const Iso9283CyclesSummary& s, bool with) {
  const std::string which = with ? "with" : "without";
  std::string h = "<table class=\"iso9283\" data-key=\"iso9283." + which +
                  "\"><caption>" +
                  (with ? std::string("with the model: predicted after "
                                      "compensation (first order)")
                        : std::string("without the model: attained, as "
                                      "measured")) +
                  "</caption>\n<tr><th>pose</th><th>cycles</th><th>AP_p "
                  "(mm)</th><th>AP_x</th><th>AP_y</th><th>AP_z</th><th>RP_l "
                  "(mm)</th><th>AP_a (mrad)</th><th>AP_b</th><th>AP_c</th>"
                  "<th>RP_a (&plusmn;mrad)</th><th>RP_b</th><th>RP_c</th>"
                  "</tr>\n";
  for (const Iso9283PoseReport& p : s.poses) {
    const Iso9283PoseResult& r = with ? p.with : p.without;
    const std::string k = "iso9283." + p.pose + "." + which + ".";
    h += "<tr><th>" + HtmlEscape(p.pose) + "</th><td class=\"num\">" +
         std::to_string(r.num_cycles) + "</td>" +
         HtmlNumberCell(k + "ap_p", r.ap_p_m, r.ap_p_m * 1e3);
    static const char* kAxis[] = {"x", "y", "z"};
    static const char* kAngle[] = {"a", "b", "c"};
    for (int i = 0; i < 3; ++i) {
      h += HtmlNumberCell(k + "ap_" + kAxis[i], r.ap_xyz_m[i],
                          r.ap_xyz_m[i] * 1e3);
    }
    h += HtmlNumberCell(k + "rp_l", r.rp_l_m, r.rp_l_m * 1e3);
    for (int i = 0; i < 3; ++i) {
      h += p.has_orientation ? HtmlNumberCell(k + "ap_" + kAngle[i],
                                              r.ap_rad[i], r.ap_rad[i] * 1e3)
                             : std::string("<td>-</td>");
    }
    for (int i = 0; i < 3; ++i) {
      h += p.has_orientation ? HtmlNumberCell(k + "rp_" + kAngle[i],
                                              r.rp_rad[i], r.rp_rad[i] * 1e3)
                             : std::string("<td>-</td>");
    }
    h += "</tr>\n";
  }
  return h + "</table>\n";
}

}  // namespace

std::string Iso9283Section(const Iso9283CyclesSummary& s) {
  return "<h2 id=\"iso9283\">ISO 9283 pose accuracy and repeatability</h2>\n"
         "<p>ISO 9283:1998 7.2, in the robot's base frame: AP the distance "
         "of the cycles' barycentre from the commanded pose, RP_l = l_bar + "
         "3 S_l; orientation deviations as rotation vectors about the base's "
         "x, y, z (docs/iso9283.md).</p>\n" +
         Table(s, false) + Table(s, true);
}

}  // namespace activecal
