#include "text_lines.h"

#include <charconv>
#include <cmath>
#include <vector>

#include "groundline/core/text_parse.h"

namespace groundline::core::internal {

LineReader::LineReader(const std::filesystem::path& path)
    : in_(path, std::ios::binary), file_(path.string()) {
  if (!in_.is_open()) status_ = Status::Error("cannot open " + file_);
}

bool LineReader::Next(std::string_view* text) {
  if (!status_.ok()) return false;
  while (std::getline(in_, buffer_)) {
    ++line_;
    // getline sets eof only when the line was not terminated by '\n'.
    if (in_.eof()) {
      status_ = Status::Error(FieldError(file_, line_, "line",
                                         "a line ending in a newline (the file looks cut mid-way)",
                                         Abbreviate(Trim(buffer_))));
      return false;
    }
    const std::string_view trimmed = Trim(buffer_);
    if (trimmed.empty()) continue;
    *text = trimmed;
    return true;
  }
  if (in_.bad()) status_ = Status::Error("read error in " + file_);
  return false;
}

Status ExpectHeader(LineReader* reader, std::string_view header, bool csv) {
  if (!reader->status().ok()) return reader->status();
  std::string_view line;
  if (!reader->Next(&line)) {
    if (!reader->status().ok()) return reader->status();
    return Status::Error(FieldError(reader->file(), reader->line() + 1, "header",
                                    "the line '" + std::string(header) + "'", "end of file"));
  }
  bool same = line == header;
  if (csv) {
    const std::vector<std::string_view> got = SplitDelimited(line, ',');
    const std::vector<std::string_view> want = SplitDelimited(header, ',');
    same = got == want;
  }
  if (!same) {
    return Status::Error(FieldError(reader->file(), reader->line(), "header",
                                    "the line '" + std::string(header) + "'",
                                    Abbreviate(line, 200)));
  }
  return Status::Ok();
}

Status CheckIncreasing(const std::string& file, std::size_t line, double previous_s,
                       double stamp_s) {
  if (stamp_s > previous_s) return Status::Ok();
  std::string expected = "a stamp > ";
  AppendFixed(previous_s, 9, &expected);
  expected += " (strictly increasing within the file)";
  std::string got;
  AppendFixed(stamp_s, 9, &got);
  return Status::Error(FieldError(file, line, "stamp_s", expected, got));
}

Status CheckIncreasingWritten(const std::string& file, std::size_t line, double previous_s,
                              double stamp_s) {
  if (!std::isfinite(previous_s) || !std::isfinite(stamp_s)) {
    return Status::Error(FieldError(file, line, "stamp_s", "a finite number", "non-finite"));
  }
  return CheckIncreasing(file, line, Quantize(previous_s, 9), Quantize(stamp_s, 9));
}

double Quantize(double value, int decimals) {
  std::string text;
  AppendFixed(value, decimals, &text);
  return ParseDouble(text).value_or(value);
}

std::string Abbreviate(std::string_view text, std::size_t max_chars) {
  if (text.size() <= max_chars) return std::string(text);
  return std::string(text.substr(0, max_chars)) + "...";
}

Status ParseFinite(std::string_view token, const std::string& file, std::size_t line,
                   std::string_view field, double* value) {
  const std::optional<double> parsed = ParseDouble(token);
  if (!parsed || !std::isfinite(*parsed)) {
    return Status::Error(FieldError(file, line, field, "a finite number", token));
  }
  *value = *parsed;
  return Status::Ok();
}

void AppendFixed(double value, int decimals, std::string* out) {
  if (value == 0.0) {
    out->push_back('0');
    return;
  }
  char buffer[64];
  const auto [end, ec] =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, decimals);
  // Values beyond 1e40 do not fit; they never occur in a dataset, fall back.
  if (ec != std::errc()) {
    *out += FormatShortest(value);
    return;
  }
  out->append(buffer, end);
}

void AppendGeneral(double value, int digits, std::string* out) {
  char buffer[64];
  const auto [end, ec] =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, digits);
  out->append(buffer, ec == std::errc() ? end : buffer);
}

std::string FormatShortest(double value) { return FormatShortestDouble(value); }

Status CheckEndsWithNewline(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return Status::Error("cannot open " + path.string());
  const std::streamoff size = in.tellg();
  if (size <= 0) return Status::Ok();
  in.seekg(size - 1);
  char last_char = '\0';
  in.get(last_char);
  if (last_char == '\n') return Status::Ok();
  std::size_t lines = 1;
  in.seekg(0);
  std::string text, last;
  while (std::getline(in, text)) {
    if (!in.eof()) ++lines;
    last.swap(text);
  }
  return Status::Error(FieldError(path.string(), lines, "line",
                                  "a line ending in a newline (the file looks cut mid-way)",
                                  Abbreviate(Trim(last))));
}

std::string RelativePathProblem(std::string_view path) {
  if (path.empty()) return "a non-empty path";
  if (path.front() == '/') return "a path relative to the dataset directory";
  if (path.find('\\') != std::string_view::npos) return "a '/'-separated path";
  for (std::string_view part : SplitDelimited(path, '/')) {
    if (part == ".." || part.empty()) return "a path without '..' or empty components";
  }
  return {};
}

}  // namespace groundline::core::internal
