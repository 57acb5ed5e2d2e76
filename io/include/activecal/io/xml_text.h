// Copyright (c) 2026, the activecal authors.
// SPDX-License-Identifier: BSD-3-Clause

// Text made safe inside XML and HTML elements and attribute values: the
// five characters & < > " ' written as entities, everything else as is
// (UTF-8 passes through). The apostrophe is the one difference between the
// writers: XML (the URDF) has `&apos;`, HTML 4 readers know only the
// numeric `&#39;` (the report).
//
//   EscapeXmlText("a<b", XmlApostrophe::kNumeric)  // "a&lt;b"

#ifndef ACTIVECAL_IO_XML_TEXT_H_
#define ACTIVECAL_IO_XML_TEXT_H_

#include <string>

namespace activecal {

enum class XmlApostrophe {
  kNamed,    // &apos; (XML)
  kNumeric,  // &#39;  (HTML and SVG read by any browser)
};

std::string EscapeXmlText(const std::string& text, XmlApostrophe apostrophe);

}  // namespace activecal

#endif  // ACTIVECAL_IO_XML_TEXT_H_
