// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

#include "activecal/io/xml_text.h"

namespace activecal {

std::string EscapeXmlText(const std::string& text, XmlApostrophe apostrophe) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += apostrophe == XmlApostrophe::kNamed ? "&apos;" : "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace activecal
