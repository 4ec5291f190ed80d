#pragma once
// Text placed in XML and HTML (VTK files, SVG maps, the run report): the
// five characters markup reserves, escaped, so a recipe's names and titles
// cannot break the document.

#include <string>

namespace bliskrun {

inline std::string xml_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace bliskrun
