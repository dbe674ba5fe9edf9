// lidar_scans.txt: one planar scan per line, counts before their values.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/text_parse.h"
#include "text_lines.h"

namespace groundline::core {
namespace {

constexpr const char* kHeadNames[] = {"stamp_s",     "angle_min_rad", "angle_increment_rad",
                                      "range_min_m", "range_max_m",   "n"};
constexpr std::size_t kHeadSize = 6;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string Indexed(const char* name, std::size_t i) {
  return std::string(name) + "[" + std::to_string(i) + "]";
}

std::string Fixed4(double value) {
  std::string text;
  internal::AppendFixed(value, 4, &text);
  return text;
}

Status Fail(const std::string& file, std::size_t line, std::string_view field,
            std::string_view expected, std::string_view got) {
  return Status::Error(FieldError(file, line, field, expected, got));
}

// Checks the values of a parsed scan (counts and finiteness are checked by
// the parser).
Status CheckScanValues(const LaserScan& scan, const std::string& file, std::size_t line) {
  if (std::abs(scan.angle_min_rad) > kTwoPi) {
    return Fail(file, line, "angle_min_rad", "an angle in [-2 pi, 2 pi]",
                internal::FormatShortest(scan.angle_min_rad));
  }
  const double sweep_rad =
      std::abs(scan.angle_increment_rad) * static_cast<double>(scan.ranges_m.size() - 1);
  if (scan.angle_increment_rad == 0.0 || sweep_rad > kTwoPi * (1.0 + 1e-6)) {
    return Fail(file, line, "angle_increment_rad",
                "a non-zero increment with |increment| * (n - 1) <= 2 pi",
                internal::FormatShortest(scan.angle_increment_rad));
  }
  if (!(scan.range_min_m >= kMinRangeLimit_m)) {
    return Fail(file, line, "range_min_m", "a limit >= 0.001 m (0 encodes 'no return')",
                internal::FormatShortest(scan.range_min_m));
  }
  if (!(scan.range_max_m > scan.range_min_m)) {
    return Fail(file, line, "range_max_m", "a limit > range_min_m",
                internal::FormatShortest(scan.range_max_m));
  }
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double r = scan.ranges_m[i];
    if (r != kNoReturnRange_m && (r < scan.range_min_m || r > scan.range_max_m)) {
      return Fail(file, line, Indexed("ranges_m", i),
                  "0 (no return) or a range in [" + Fixed4(scan.range_min_m) + ", " +
                      Fixed4(scan.range_max_m) + "] m",
                  internal::FormatShortest(r));
    }
  }
  for (std::size_t i = 0; i < scan.intensities.size(); ++i) {
    if (scan.intensities[i] < 0.0) {
      return Fail(file, line, Indexed("intensities", i), "an intensity >= 0",
                  internal::FormatShortest(scan.intensities[i]));
    }
  }
  return Status::Ok();
}

// Parses one scan line (already trimmed, not a comment).
Status ParseScanLine(std::string_view text, const std::string& file, std::size_t line,
                     LaserScan* scan) {
  const std::vector<std::string_view> tokens = SplitWhitespace(text);
  if (tokens.size() < kHeadSize) {
    return Fail(file, line, kHeadNames[tokens.size()],
                "a value (a scan line starts 'stamp_s angle_min_rad angle_increment_rad "
                "range_min_m range_max_m n')",
                "end of line");
  }
  double head[kHeadSize - 1];
  for (std::size_t k = 0; k + 1 < kHeadSize; ++k) {
    if (Status s = internal::ParseFinite(tokens[k], file, line, kHeadNames[k], &head[k]); !s.ok()) {
      return s;
    }
  }
  const std::optional<std::int64_t> n = ParseInt(tokens[5]);
  if (!n || *n < 1) return Fail(file, line, "n", "a beam count >= 1", tokens[5]);
  const std::size_t count = static_cast<std::size_t>(*n);
  const std::size_t after_head = tokens.size() - kHeadSize;
  if (after_head < count) {
    return Fail(file, line, "ranges_m",
                std::to_string(count) + " ranges (n = " + std::to_string(count) + ") followed by m",
                std::to_string(after_head) + " values before the end of the line");
  }
  if (after_head == count) {
    return Fail(file, line, "m", "the intensity count (0 or n) after the ranges", "end of line");
  }
  const std::string_view m_token = tokens[kHeadSize + count];
  const std::optional<std::int64_t> m = ParseInt(m_token);
  if (!m || (*m != 0 && *m != *n)) {
    return Fail(file, line, "m", "0 or n = " + std::to_string(count), m_token);
  }
  const std::size_t intensity_count = static_cast<std::size_t>(*m);
  const std::size_t given = tokens.size() - kHeadSize - count - 1;
  if (given != intensity_count) {
    return Fail(file, line, "intensities", std::to_string(intensity_count) + " values (m)",
                std::to_string(given) + " values");
  }
  scan->stamp_s = head[0];
  scan->angle_min_rad = head[1];
  scan->angle_increment_rad = head[2];
  scan->range_min_m = head[3];
  scan->range_max_m = head[4];
  scan->ranges_m.resize(count);
  scan->intensities.resize(intensity_count);
  for (std::size_t i = 0; i < count; ++i) {
    if (Status s = internal::ParseFinite(tokens[kHeadSize + i], file, line, Indexed("ranges_m", i),
                                         &scan->ranges_m[i]);
        !s.ok()) {
      return s;
    }
  }
  for (std::size_t i = 0; i < intensity_count; ++i) {
    if (Status s = internal::ParseFinite(tokens[kHeadSize + count + 1 + i], file, line,
                                         Indexed("intensities", i), &scan->intensities[i]);
        !s.ok()) {
      return s;
    }
  }
  return CheckScanValues(*scan, file, line);
}

void AppendScanLine(const LaserScan& scan, std::string* out) {
  internal::AppendFixed(scan.stamp_s, 9, out);
  // Angles exactly (shortest round trip): beam i's angle multiplies the
  // increment by i, so rounding it would grow along the scan.
  for (double value : {scan.angle_min_rad, scan.angle_increment_rad}) {
    *out += ' ' + internal::FormatShortest(value);
  }
  for (double value : {scan.range_min_m, scan.range_max_m}) {
    *out += ' ';
    internal::AppendFixed(value, 4, out);
  }
  *out += ' ' + std::to_string(scan.ranges_m.size());
  for (double r : scan.ranges_m) {
    *out += ' ';
    internal::AppendFixed(r, 4, out);
  }
  *out += ' ' + std::to_string(scan.intensities.size());
  for (double intensity : scan.intensities) {
    *out += ' ';
    internal::AppendGeneral(intensity, 6, out);
  }
  *out += '\n';
}

}  // namespace

struct LaserScanReader::Impl {
  explicit Impl(const std::filesystem::path& path) : lines(path) {}
  internal::LineReader lines;
  bool has_previous = false;
  double previous_stamp_s = 0.0;
  bool failed = false;
};

LaserScanReader::LaserScanReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
LaserScanReader::LaserScanReader(LaserScanReader&&) noexcept = default;
LaserScanReader& LaserScanReader::operator=(LaserScanReader&&) noexcept = default;
LaserScanReader::~LaserScanReader() = default;

Result<LaserScanReader> LaserScanReader::Open(const std::filesystem::path& path) {
  auto impl = std::make_unique<Impl>(path);
  if (Status s = internal::ExpectHeader(&impl->lines, kLaserScanFileHeader, /*csv=*/false);
      !s.ok()) {
    return s;
  }
  return LaserScanReader(std::move(impl));
}

Result<bool> LaserScanReader::Next(LaserScan* scan) {
  if (impl_->failed) return false;
  internal::LineReader& lines = impl_->lines;
  std::string_view text;
  if (!lines.Next(&text)) {
    if (lines.status().ok()) return false;  // end of file
    impl_->failed = true;
    return lines.status();
  }
  Status status = ParseScanLine(text, lines.file(), lines.line(), scan);
  if (status.ok() && impl_->has_previous) {
    status = internal::CheckIncreasing(lines.file(), lines.line(), impl_->previous_stamp_s,
                                       scan->stamp_s);
  }
  if (!status.ok()) {
    impl_->failed = true;
    return status;
  }
  impl_->has_previous = true;
  impl_->previous_stamp_s = scan->stamp_s;
  return true;
}

const std::string& LaserScanReader::file() const { return impl_->lines.file(); }
std::size_t LaserScanReader::line() const { return impl_->lines.line(); }

Result<std::vector<LaserScan>> ReadLaserScans(const std::filesystem::path& path) {
  Result<LaserScanReader> reader = LaserScanReader::Open(path);
  if (!reader.ok()) return reader.status();
  std::vector<LaserScan> scans;
  LaserScan scan;
  while (true) {
    const Result<bool> more = reader->Next(&scan);
    if (!more.ok()) return more.status();
    if (!*more) break;
    scans.push_back(scan);
  }
  return scans;
}

Status WriteLaserScans(const std::filesystem::path& path, const std::vector<LaserScan>& scans) {
  // Each line is formatted, then parsed back with the reader's parser before
  // it is written: the writer rejects exactly what the reader would (NaN,
  // counts, limits, and values that only go wrong after rounding to the
  // written precision). On an error the temporary file is discarded.
  const std::string file = path.string();
  return WriteFileAtomically(path, [&scans, &file](std::ostream& out) {
    out << kLaserScanFileHeader << '\n';
    std::string text;
    LaserScan parsed;
    double previous_stamp_s = 0.0;
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const std::size_t line = i + 2;  // after the header
      const LaserScan& scan = scans[i];
      if (!scan.intensities.empty() && scan.intensities.size() != scan.ranges_m.size()) {
        return Fail(file, line, "m", "0 or n = " + std::to_string(scan.ranges_m.size()),
                    std::to_string(scan.intensities.size()));
      }
      text.clear();
      AppendScanLine(scan, &text);
      if (Status s = ParseScanLine(Trim(text), file, line, &parsed); !s.ok()) return s;
      if (i > 0) {
        if (Status s = internal::CheckIncreasing(file, line, previous_stamp_s, parsed.stamp_s);
            !s.ok()) {
          return s;
        }
      }
      previous_stamp_s = parsed.stamp_s;
      out << text;
    }
    return Status::Ok();
  });
}

}  // namespace groundline::core
