// Escaping text for the SVG and HTML groundline writes (target sheets, the
// calibration report).
#ifndef GROUNDLINE_CALIBRATION_SRC_XML_TEXT_H_
#define GROUNDLINE_CALIBRATION_SRC_XML_TEXT_H_

#include <string>

namespace groundline::calibration::internal {

// & < > " escaped; safe in element text and in quoted attribute values.
inline std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_XML_TEXT_H_
