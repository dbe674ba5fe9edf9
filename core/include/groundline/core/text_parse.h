// Small helpers for the text formats groundline reads (TUM, CSV, relations,
// logs): tokenizing, strict number parsing, and error messages that name the
// file, line and field.
#ifndef GROUNDLINE_CORE_TEXT_PARSE_H_
#define GROUNDLINE_CORE_TEXT_PARSE_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace groundline::core {

// Splits on runs of spaces, tabs and CR; no empty tokens.
std::vector<std::string_view> SplitWhitespace(std::string_view line);
// Splits on `delimiter`, trimming spaces around each field; keeps empty fields.
std::vector<std::string_view> SplitDelimited(std::string_view line, char delimiter);
std::string_view Trim(std::string_view text);

// The whole token must be a number ("1e-3", "-0.5"; no trailing junk). NaN and
// infinities parse (as std::from_chars does); callers that need finite values
// check std::isfinite and report it as such.
std::optional<double> ParseDouble(std::string_view token);
std::optional<std::int64_t> ParseInt(std::string_view token);

// True if `text` is well-formed UTF-8 (no overlong forms, surrogates or code
// points above U+10FFFF). YAML text must be; yaml-cpp does not check, and its
// emitter cannot write back what is not.
bool IsValidUtf8(std::string_view text);

// The shortest text that parses back to exactly `value` ("0.1", "1e-05").
std::string FormatShortestDouble(double value);
// The same, written so that YAML 1.1 readers (PyYAML, and through it mrcal's
// and ROS's tools) take it as a float: a mantissa with a '.' before any
// exponent ("1.0e-05", not "1e-05"). yaml-cpp reads both.
std::string FormatYamlDouble(double value);

// "<file>:<line>: field '<field>': expected <expected>, got '<got>'".
std::string FieldError(const std::string& file, std::size_t line, std::string_view field,
                       std::string_view expected, std::string_view got);

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_TEXT_PARSE_H_
