#include "groundline/core/text_parse.h"

#include <charconv>
#include <cmath>

namespace groundline::core {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// from_chars rejects a leading '+', which printf-style writers may emit; strip
// one, but not one followed by another sign ("+-1" is not a number).
bool StripPlus(std::string_view* token) {
  if (token->empty() || token->front() != '+') return true;
  token->remove_prefix(1);
  return token->empty() || (token->front() != '-' && token->front() != '+');
}

}  // namespace

std::vector<std::string_view> SplitWhitespace(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (i > begin) tokens.push_back(line.substr(begin, i - begin));
  }
  return tokens;
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> SplitDelimited(std::string_view line, char delimiter) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = line.find(delimiter, begin);
    fields.push_back(Trim(line.substr(begin, end == std::string_view::npos ? end : end - begin)));
    if (end == std::string_view::npos) break;
    begin = end + 1;
  }
  return fields;
}

std::optional<double> ParseDouble(std::string_view token) {
  if (!StripPlus(&token)) return std::nullopt;
  double value = 0.0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec != std::errc() || ptr != end || token.empty()) return std::nullopt;
  return value;
}

bool IsValidUtf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    // The sequence length from the lead byte (0x80-0xC1 and 0xF5-0xFF lead none).
    int n = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 3;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 4;
    }
    if (n == 0 || i + static_cast<std::size_t>(n) > text.size()) return false;
    std::uint32_t cp = c & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
    for (int k = 1; k < n; ++k) {
      const unsigned char cc = static_cast<unsigned char>(text[i + k]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3F);
    }
    const std::uint32_t smallest = n == 2 ? 0x80 : n == 3 ? 0x800 : 0x10000;
    if (cp < smallest || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += static_cast<std::size_t>(n);
  }
  return true;
}

std::optional<std::int64_t> ParseInt(std::string_view token) {
  if (!StripPlus(&token)) return std::nullopt;
  std::int64_t value = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec != std::errc() || ptr != end || token.empty()) return std::nullopt;
  return value;
}

std::string FormatShortestDouble(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return ec == std::errc() ? std::string(buffer, end) : std::string();
}

std::string FormatYamlDouble(double value) {
  std::string text = FormatShortestDouble(value);
  if (!std::isfinite(value)) return text;
  const std::size_t exponent = text.find('e');
  const std::string_view mantissa = std::string_view(text).substr(0, exponent);
  if (exponent != std::string::npos && mantissa.find('.') == std::string_view::npos) {
    text.insert(exponent, ".0");
  }
  return text;
}

std::string FieldError(const std::string& file, std::size_t line, std::string_view field,
                       std::string_view expected, std::string_view got) {
  std::string message = file + ":" + std::to_string(line) + ": field '" + std::string(field) +
                        "': expected " + std::string(expected) + ", got '" + std::string(got) + "'";
  return message;
}

}  // namespace groundline::core
