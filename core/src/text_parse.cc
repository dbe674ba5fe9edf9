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
