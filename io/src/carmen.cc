#include "groundline/io/carmen.h"

#include <cmath>
#include <string>
#include <utility>

#include "carmen_parse.h"
#include "groundline/io/compressed_file.h"

namespace groundline::io {

core::Status CarmenReadOptions::Validate() const {
  if (!std::isfinite(old_format_angle_min_rad)) {
    return core::Status::Error("CarmenReadOptions: old_format_angle_min_rad must be finite");
  }
  if (!std::isfinite(old_format_angle_increment_rad) || old_format_angle_increment_rad < 0.0 ||
      old_format_angle_increment_rad > std::numbers::pi) {
    return core::Status::Error(
        "CarmenReadOptions: old_format_angle_increment_rad must be in [0, pi] (0 = guess from "
        "the number of readings), got " +
        std::to_string(old_format_angle_increment_rad));
  }
  if (!std::isfinite(old_format_max_range_m) || old_format_max_range_m <= 0.0) {
    return core::Status::Error("CarmenReadOptions: old_format_max_range_m must be > 0, got " +
                               std::to_string(old_format_max_range_m));
  }
  if (max_readings <= 0) {
    return core::Status::Error("CarmenReadOptions: max_readings must be > 0, got " +
                               std::to_string(max_readings));
  }
  return core::Status::Ok();
}

double GuessOldFormatAngleIncrementRad(std::size_t num_readings) {
  constexpr double kPi = std::numbers::pi;
  switch (num_readings) {
    case 180:
    case 181:
      return kPi / 180.0;
    case 360:
    case 361:
      return kPi / 360.0;
    case 400:
    case 401:
      return kPi / 720.0;
    default:
      break;
  }
  if (num_readings < 2) return 0.0;
  return kPi / static_cast<double>(num_readings - 1);
}

std::string CarmenLaserMessageName(const CarmenLaserScan& scan) {
  switch (scan.message) {
    case CarmenLaserMessage::kFlaser:
      return "FLASER";
    case CarmenLaserMessage::kRlaser:
      return "RLASER";
    case CarmenLaserMessage::kRawLaser:
      return "RAWLASER" + std::to_string(scan.laser_id);
    case CarmenLaserMessage::kRobotLaser:
      return "ROBOTLASER" + std::to_string(scan.laser_id);
  }
  return "LASER?";
}

int64_t CarmenReadSummary::Count(std::string_view message_name) const {
  const auto it = message_counts.find(std::string(message_name));
  return it == message_counts.end() ? 0 : it->second;
}

core::Result<CarmenReadSummary> StreamCarmenLog(const std::filesystem::path& path,
                                                const CarmenReadOptions& options,
                                                const CarmenCallback& callback) {
  if (core::Status valid = options.Validate(); !valid.ok()) return valid;
  core::Result<LineReader> reader = LineReader::Open(path);
  if (!reader.ok()) return reader.status();

  CarmenReadSummary summary;
  std::string line;
  std::vector<std::string_view> fields;
  internal::ParsedCarmenLine parsed;
  while (reader->ReadLine(&line)) {
    const int64_t line_number = reader->line_number();
    ++summary.lines;
    const core::Status status =
        internal::ParseCarmenLine(line, line_number, options, &fields, &parsed);
    if (!status.ok()) {
      const std::string where = path.string() + ":" + std::to_string(line_number);
      if (options.strict) return status.WithContext(where);
      ++summary.skipped_line_count;
      if (summary.skipped_lines.size() < options.max_recorded_skips) {
        summary.skipped_lines.push_back({line_number, status.message()});
      }
      continue;
    }
    switch (parsed.type) {
      case internal::CarmenLineType::kBlank:
        ++summary.blank_lines;
        continue;
      case internal::CarmenLineType::kComment:
        ++summary.comment_lines;
        continue;
      case internal::CarmenLineType::kUnknown:
        ++summary.unknown_messages;
        break;
      case internal::CarmenLineType::kCountedOnly:
      case internal::CarmenLineType::kMessage:
        break;
    }
    ++summary.message_counts[std::string(parsed.name)];
    if (parsed.message.has_value() && callback) {
      if (core::Status accepted = callback(std::move(*parsed.message)); !accepted.ok()) {
        return accepted.WithContext(path.string() + ":" + std::to_string(line_number));
      }
    }
  }
  if (!reader->status().ok()) return reader->status();
  return summary;
}

namespace {

// Moves each message into its vector of the CarmenLog.
struct LogCollector {
  CarmenLog* log;
  void operator()(CarmenParam& param) const { log->params[param.name] = std::move(param.value); }
  void operator()(CarmenOdometry& odom) const { log->odometry.push_back(odom); }
  void operator()(CarmenLaserScan& scan) const { log->scans.push_back(std::move(scan)); }
  void operator()(CarmenTruePose& pose) const { log->true_poses.push_back(pose); }
};

}  // namespace

core::Result<CarmenLog> ReadCarmenLog(const std::filesystem::path& path,
                                      const CarmenReadOptions& options) {
  CarmenLog log;
  core::Result<CarmenReadSummary> summary =
      StreamCarmenLog(path, options, [&log](CarmenMessage message) {
        std::visit(LogCollector{&log}, message);
        return core::Status::Ok();
      });
  if (!summary.ok()) return summary.status();
  log.summary = std::move(summary).value();
  return log;
}

}  // namespace groundline::io
