// images/index.csv, wheel_encoders.csv and ground_truth_extrinsics.csv.
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "groundline/core/atomic_file.h"
#include "groundline/core/dataset_records.h"
#include "groundline/core/text_parse.h"
#include "text_lines.h"

namespace groundline::core {
namespace {

constexpr char kImageIndexHeader[] = "stamp_s,file";
constexpr char kWheelEncodersHeader[] = "stamp_s,left_delta_rad,right_delta_rad";
constexpr char kExtrinsicsHeader[] =
    "stamp_s,height_m,pitch_rad,roll_rad,yaw_rad,forward_m,lateral_m";
constexpr const char* kExtrinsicsFields[] = {"stamp_s", "height_m",  "pitch_rad", "roll_rad",
                                             "yaw_rad", "forward_m", "lateral_m"};
constexpr int kExtrinsicsFieldCount = 7;

// Splits a CSV record and checks its field count against the header's.
Status SplitRecord(std::string_view text, std::size_t expected_fields, const std::string& file,
                   std::size_t line, std::string_view header,
                   std::vector<std::string_view>* fields) {
  *fields = SplitDelimited(text, ',');
  if (fields->size() == expected_fields) return Status::Ok();
  return Status::Error(FieldError(
      file, line, "line", std::to_string(expected_fields) + " fields '" + std::string(header) + "'",
      std::to_string(fields->size()) + " fields in '" + internal::Abbreviate(text) + "'"));
}

Status CheckImageRecord(const ImageRecord& image, const std::filesystem::path& directory,
                        bool check_file, const std::string& file, std::size_t line) {
  if (!std::isfinite(image.stamp_s)) {
    return Status::Error(FieldError(file, line, "stamp_s", "a finite number", "non-finite"));
  }
  if (const std::string problem = internal::RelativePathProblem(image.file); !problem.empty()) {
    return Status::Error(FieldError(file, line, "file", problem, image.file));
  }
  if (image.file.find_first_of(",\n\r") != std::string::npos || Trim(image.file) != image.file) {
    return Status::Error(FieldError(file, line, "file",
                                    "a name without commas, line breaks or surrounding spaces",
                                    image.file));
  }
  if (!image.file.ends_with(".png")) {
    return Status::Error(
        FieldError(file, line, "file", "a PNG file name ending in '.png'", image.file));
  }
  if (check_file && !std::filesystem::is_regular_file(directory / image.file)) {
    return Status::Error(
        FieldError(file, line, "file",
                   "an existing image file (relative to " + directory.string() + ")", image.file));
  }
  return Status::Ok();
}

Status CheckWheelReading(const WheelEncoderReading& r, const std::string& file, std::size_t line) {
  const std::pair<const char*, double> fields[] = {{"stamp_s", r.stamp_s},
                                                   {"left_delta_rad", r.left_delta_rad},
                                                   {"right_delta_rad", r.right_delta_rad}};
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value)) {
      return Status::Error(FieldError(file, line, name, "a finite number", "non-finite"));
    }
  }
  return Status::Ok();
}

std::array<double, kExtrinsicsFieldCount> Values(const CameraExtrinsicsRecord& r) {
  return {r.stamp_s, r.height_m, r.pitch_rad, r.roll_rad, r.yaw_rad, r.forward_m, r.lateral_m};
}

Status CheckExtrinsicsRecord(const CameraExtrinsicsRecord& r, const std::string& file,
                             std::size_t line) {
  const std::array<double, kExtrinsicsFieldCount> values = Values(r);
  for (int k = 0; k < kExtrinsicsFieldCount; ++k) {
    if (!std::isfinite(values[k])) {
      return Status::Error(
          FieldError(file, line, kExtrinsicsFields[k], "a finite number", "non-finite"));
    }
  }
  const auto fail = [&](const char* field, const char* expected, double got) {
    return Status::Error(FieldError(file, line, field, expected, internal::FormatShortest(got)));
  };
  constexpr double kPi = std::numbers::pi;
  if (!(r.height_m > 0.0)) return fail("height_m", "a height above the floor, > 0", r.height_m);
  if (!(std::abs(r.pitch_rad) < 0.5 * kPi)) {
    return fail("pitch_rad", "a pitch in (-pi/2, pi/2)", r.pitch_rad);
  }
  if (!(std::abs(r.roll_rad) <= kPi)) return fail("roll_rad", "a roll in [-pi, pi]", r.roll_rad);
  if (!(std::abs(r.yaw_rad) <= kPi)) return fail("yaw_rad", "a yaw in [-pi, pi]", r.yaw_rad);
  return Status::Ok();
}

}  // namespace

Result<std::vector<ImageRecord>> ReadImageIndex(const std::filesystem::path& path,
                                                bool check_files) {
  internal::LineReader reader(path);
  if (Status s = internal::ExpectHeader(&reader, kImageIndexHeader, /*csv=*/true); !s.ok()) {
    return s;
  }
  const std::filesystem::path directory = path.parent_path();
  std::vector<ImageRecord> images;
  std::vector<std::string_view> fields;
  std::string_view text;
  while (reader.Next(&text)) {
    const std::size_t line = reader.line();
    if (Status s = SplitRecord(text, 2, reader.file(), line, kImageIndexHeader, &fields); !s.ok()) {
      return s;
    }
    ImageRecord image;
    if (Status s = internal::ParseFinite(fields[0], reader.file(), line, "stamp_s", &image.stamp_s);
        !s.ok()) {
      return s;
    }
    image.file = std::string(fields[1]);
    if (Status s = CheckImageRecord(image, directory, check_files, reader.file(), line); !s.ok()) {
      return s;
    }
    if (!images.empty()) {
      if (Status s =
              internal::CheckIncreasing(reader.file(), line, images.back().stamp_s, image.stamp_s);
          !s.ok()) {
        return s;
      }
    }
    images.push_back(std::move(image));
  }
  if (!reader.status().ok()) return reader.status();
  return images;
}

Status WriteImageIndex(const std::filesystem::path& path, const std::vector<ImageRecord>& images) {
  const std::string file = path.string();
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::size_t line = i + 2;  // after the header
    if (Status s = CheckImageRecord(images[i], path.parent_path(), true, file, line); !s.ok()) {
      return s;
    }
    if (i > 0) {
      if (Status s = internal::CheckIncreasingWritten(file, line, images[i - 1].stamp_s,
                                                      images[i].stamp_s);
          !s.ok()) {
        return s;
      }
    }
  }
  return WriteFileAtomically(path, [&images](std::ostream& out) {
    std::string text = std::string(kImageIndexHeader) + "\n";
    for (const ImageRecord& image : images) {
      internal::AppendFixed(image.stamp_s, 9, &text);
      text += ',' + image.file + '\n';
    }
    out << text;
    return Status::Ok();
  });
}

Result<std::vector<WheelEncoderReading>> ReadWheelEncoders(const std::filesystem::path& path) {
  internal::LineReader reader(path);
  if (Status s = internal::ExpectHeader(&reader, kWheelEncodersHeader, /*csv=*/true); !s.ok()) {
    return s;
  }
  constexpr const char* kNames[] = {"stamp_s", "left_delta_rad", "right_delta_rad"};
  std::vector<WheelEncoderReading> readings;
  std::vector<std::string_view> fields;
  std::string_view text;
  while (reader.Next(&text)) {
    const std::size_t line = reader.line();
    if (Status s = SplitRecord(text, 3, reader.file(), line, kWheelEncodersHeader, &fields);
        !s.ok()) {
      return s;
    }
    double values[3];
    for (int k = 0; k < 3; ++k) {
      if (Status s = internal::ParseFinite(fields[k], reader.file(), line, kNames[k], &values[k]);
          !s.ok()) {
        return s;
      }
    }
    if (!readings.empty()) {
      if (Status s =
              internal::CheckIncreasing(reader.file(), line, readings.back().stamp_s, values[0]);
          !s.ok()) {
        return s;
      }
    }
    readings.push_back({values[0], values[1], values[2]});
  }
  if (!reader.status().ok()) return reader.status();
  return readings;
}

Status WriteWheelEncoders(const std::filesystem::path& path,
                          const std::vector<WheelEncoderReading>& readings) {
  const std::string file = path.string();
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const std::size_t line = i + 2;
    if (Status s = CheckWheelReading(readings[i], file, line); !s.ok()) return s;
    if (i > 0) {
      if (Status s = internal::CheckIncreasingWritten(file, line, readings[i - 1].stamp_s,
                                                      readings[i].stamp_s);
          !s.ok()) {
        return s;
      }
    }
  }
  return WriteFileAtomically(path, [&readings](std::ostream& out) {
    std::string text = std::string(kWheelEncodersHeader) + "\n";
    for (const WheelEncoderReading& r : readings) {
      internal::AppendFixed(r.stamp_s, 9, &text);
      text += ',';
      internal::AppendFixed(r.left_delta_rad, 9, &text);
      text += ',';
      internal::AppendFixed(r.right_delta_rad, 9, &text);
      text += '\n';
    }
    out << text;
    return Status::Ok();
  });
}

Result<std::vector<CameraExtrinsicsRecord>> ReadGroundTruthExtrinsics(
    const std::filesystem::path& path) {
  internal::LineReader reader(path);
  if (Status s = internal::ExpectHeader(&reader, kExtrinsicsHeader, /*csv=*/true); !s.ok()) {
    return s;
  }
  std::vector<CameraExtrinsicsRecord> records;
  std::vector<std::string_view> fields;
  std::string_view text;
  while (reader.Next(&text)) {
    const std::size_t line = reader.line();
    if (Status s = SplitRecord(text, kExtrinsicsFieldCount, reader.file(), line, kExtrinsicsHeader,
                               &fields);
        !s.ok()) {
      return s;
    }
    std::array<double, kExtrinsicsFieldCount> v{};
    for (int k = 0; k < kExtrinsicsFieldCount; ++k) {
      if (Status s =
              internal::ParseFinite(fields[k], reader.file(), line, kExtrinsicsFields[k], &v[k]);
          !s.ok()) {
        return s;
      }
    }
    const CameraExtrinsicsRecord r{v[0], v[1], v[2], v[3], v[4], v[5], v[6]};
    if (Status s = CheckExtrinsicsRecord(r, reader.file(), line); !s.ok()) return s;
    if (!records.empty()) {
      if (Status s =
              internal::CheckIncreasing(reader.file(), line, records.back().stamp_s, r.stamp_s);
          !s.ok()) {
        return s;
      }
    }
    records.push_back(r);
  }
  if (!reader.status().ok()) return reader.status();
  return records;
}

Status WriteGroundTruthExtrinsics(const std::filesystem::path& path,
                                  const std::vector<CameraExtrinsicsRecord>& records) {
  const std::string file = path.string();
  for (std::size_t i = 0; i < records.size(); ++i) {
    const std::size_t line = i + 2;
    if (Status s = CheckExtrinsicsRecord(records[i], file, line); !s.ok()) return s;
    if (i > 0) {
      if (Status s = internal::CheckIncreasingWritten(file, line, records[i - 1].stamp_s,
                                                      records[i].stamp_s);
          !s.ok()) {
        return s;
      }
    }
  }
  return WriteFileAtomically(path, [&records](std::ostream& out) {
    std::string text = std::string(kExtrinsicsHeader) + "\n";
    for (const CameraExtrinsicsRecord& r : records) {
      const std::array<double, kExtrinsicsFieldCount> values = Values(r);
      for (int k = 0; k < kExtrinsicsFieldCount; ++k) {
        if (k > 0) text += ',';
        internal::AppendFixed(values[k], 9, &text);
      }
      text += '\n';
    }
    out << text;
    return Status::Ok();
  });
}

}  // namespace groundline::core
