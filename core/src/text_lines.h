// Private helpers shared by the dataset's line-oriented files: a numbered line
// reader that detects a file cut mid-line, the CSV header check, stamp order
// checks and locale-independent number formatting.
#ifndef GROUNDLINE_CORE_SRC_TEXT_LINES_H_
#define GROUNDLINE_CORE_SRC_TEXT_LINES_H_

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "groundline/core/status.h"

namespace groundline::core::internal {

// Reads a text file line by line, numbering lines from 1 and skipping blank
// ones. Every line must end with '\n': a last line without one is the sign of
// a file cut mid-way and is reported as an error.
class LineReader {
 public:
  explicit LineReader(const std::filesystem::path& path);

  bool is_open() const { return in_.is_open(); }
  const std::string& file() const { return file_; }
  // Number of the line last returned by Next().
  std::size_t line() const { return line_; }

  // Stores the next non-blank line in *text (valid until the next call).
  // Returns false at the end of the file or on an error; status() tells which.
  bool Next(std::string_view* text);
  const Status& status() const { return status_; }

 private:
  std::ifstream in_;
  std::string file_;
  std::string buffer_;
  std::size_t line_ = 0;
  Status status_ = Status::Ok();
};

// Opens `reader`'s file and checks that its first non-blank line is `header`
// (CSV: the comma-separated column names, spaces around names ignored; other
// files: the exact line).
Status ExpectHeader(LineReader* reader, std::string_view header, bool csv);

// "file:line: field 'stamp_s': expected a stamp > <previous> (strictly
// increasing), got '<stamp>'" if stamp_s <= previous_s.
Status CheckIncreasing(const std::string& file, std::size_t line, double previous_s,
                       double stamp_s);

// For writers: CheckIncreasing on the stamps as written with 9 decimals, so
// that two stamps closer than the written precision are caught before writing.
Status CheckIncreasingWritten(const std::string& file, std::size_t line, double previous_s,
                              double stamp_s);
// `value` as it reads back after AppendFixed(value, decimals).
double Quantize(double value, int decimals);

// `text` cut to at most `max_chars` characters, with "..." when cut: keeps
// messages about long lines readable.
std::string Abbreviate(std::string_view text, std::size_t max_chars = 80);

// Parses a finite double; the error names file, line and field.
Status ParseFinite(std::string_view token, const std::string& file, std::size_t line,
                   std::string_view field, double* value);

// Appends `value` with `decimals` digits after the point ("%.*f" without the
// locale); integral zero is written as "0".
void AppendFixed(double value, int decimals, std::string* out);
// Appends `value` with `digits` significant digits ("%.*g" without the locale).
void AppendGeneral(double value, int digits, std::string* out);
// The shortest text that reads back to exactly `value`.
std::string FormatShortest(double value);

// An error if the non-empty file `path` does not end with '\n' (cut mid-line);
// for formats read by other readers (the TUM ground truth).
Status CheckEndsWithNewline(const std::filesystem::path& path);

// Checks a dataset-relative path: non-empty, relative, '/'-separated, no ".."
// component. Returns what is wrong, or an empty string.
std::string RelativePathProblem(std::string_view path);

}  // namespace groundline::core::internal

#endif  // GROUNDLINE_CORE_SRC_TEXT_LINES_H_
