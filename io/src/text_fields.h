// Whitespace-separated text fields and the number parsing shared by the text
// log readers (CARMEN, relations). Private to the io module.
#ifndef GROUNDLINE_IO_SRC_TEXT_FIELDS_H_
#define GROUNDLINE_IO_SRC_TEXT_FIELDS_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace groundline::io::internal {

// Splits `line` at runs of ASCII whitespace (space, tab, CR, VT, FF) into
// non-empty fields that view `line`. `fields` is cleared first.
void SplitFields(std::string_view line, std::vector<std::string_view>* fields);

// Parses a whole field as a finite double in decimal or exponent notation
// (an optional leading '+' or '-'). Rejects "nan", "inf", hex floats, empty
// fields and trailing characters. Locale-independent.
bool ParseFiniteDouble(std::string_view field, double* value);

// Parses a whole field as a decimal integer (optional sign).
bool ParseInt64(std::string_view field, int64_t* value);

// The field quoted for an error message, shortened to at most 40 characters.
std::string QuoteField(std::string_view field);

}  // namespace groundline::io::internal

#endif  // GROUNDLINE_IO_SRC_TEXT_FIELDS_H_
