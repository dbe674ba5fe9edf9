#include "text_fields.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace groundline::io::internal {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Removes one leading '+' (which std::from_chars does not accept). False if
// the field is empty or the '+' is followed by nothing or by another sign.
bool StripPlus(std::string_view* field) {
  if (field->empty()) return false;
  if (field->front() != '+') return true;
  field->remove_prefix(1);
  return !field->empty() && field->front() != '+' && field->front() != '-';
}

}  // namespace

void SplitFields(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && IsSpace(line[i])) ++i;
    if (i == n) break;
    const std::size_t begin = i;
    while (i < n && !IsSpace(line[i])) ++i;
    fields->push_back(line.substr(begin, i - begin));
  }
}

bool ParseFiniteDouble(std::string_view field, double* value) {
  // std::from_chars accepts neither a leading '+' nor (in general format)
  // hex, but it does accept "nan"/"inf", which the isfinite check rejects.
  if (!StripPlus(&field)) return false;
  double parsed = 0.0;
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, parsed, std::chars_format::general);
  if (ec != std::errc() || ptr != end || !std::isfinite(parsed)) return false;
  *value = parsed;
  return true;
}

bool ParseInt64(std::string_view field, int64_t* value) {
  if (!StripPlus(&field)) return false;
  int64_t parsed = 0;
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, parsed);
  if (ec != std::errc() || ptr != end) return false;
  *value = parsed;
  return true;
}

std::string QuoteField(std::string_view field) {
  // Built with append: GCC 12 warns (-Wrestrict, a false positive) on the
  // equivalent chain of operator+ at -O3.
  constexpr std::size_t kMaxChars = 40;
  std::string quoted;
  quoted.reserve(kMaxChars + 2);
  quoted.push_back('\'');
  if (field.size() <= kMaxChars) {
    quoted.append(field);
  } else {
    quoted.append(field.substr(0, kMaxChars - 3));
    quoted.append("...");
  }
  quoted.push_back('\'');
  return quoted;
}

}  // namespace groundline::io::internal
