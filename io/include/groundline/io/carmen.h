// Reader for CARMEN log files (.clf, plain, gzip or bzip2), the format of the
// Freiburg / Radish SLAM data sets (Kuemmerle et al. 2009).
//
// A log is text, one message per line, fields separated by whitespace; lines
// starting with '#' are comments. Every message ends with
// `ipc_timestamp ipc_hostname logger_timestamp`. Messages understood here
// (variable-length parts are read BY THE COUNT in the line, never by column):
//
//   PARAM name value [ipc_timestamp] hostname logger_timestamp
//   SYNC tagname ipc_timestamp hostname logger_timestamp     (counted only)
//   ODOM x y theta tv rv accel ...
//   TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta ...
//   FLASER | RLASER  num_readings r_1..r_n  x y theta  odom_x odom_y odom_theta ...
//   RAWLASERk  laser_type start_angle field_of_view angular_resolution
//              maximum_range accuracy remission_mode
//              num_readings r_1..r_n  num_remissions e_1..e_m ...
//   ROBOTLASERk  (as RAWLASERk)  laser_x laser_y laser_theta
//              robot_x robot_y robot_theta  tv rv forward_safety_dist
//              side_safety_dist turn_axis ...
//
// where "..." is the ipc_timestamp / hostname / logger_timestamp tail. A line
// must have exactly the fields its counts imply: fewer, more, a count that
// runs past the end of the line, or a field that is not a finite number is a
// malformed line. (Old PARAM lines, e.g. in aces.clf, have no ipc_timestamp:
// `PARAM robot_use_laser on nohost 0`.)
//
// Conventions of the logs (CARMEN, SI units): poses are (x [m], y [m],
// theta [rad]) in the odometry frame of the robot, x forward, y left, theta
// counter-clockwise, as ROS REP-103. In FLASER / RLASER / ROBOTLASER lines the
// first pose is the laser's pose T_odom_laser (the robot pose composed with
// the mounting offset, e.g. PARAM robot_frontlaser_offset) and the second is
// the robot's odometry pose T_odom_base; in aces.clf and mit-csail.clf both
// are equal (offset 0), in fr-clinic_robotlaser.clf the laser is 0.22 m ahead.
// Beam i of a scan points at angle_min_rad + i * angle_increment_rad in the
// laser frame, i.e. counter-clockwise from the right. A range at or above
// max_range_m means "no return" (SICK LMS logs write 81.91 m for it).
// ipc_timestamp is the message's own stamp, set by the module that sent it
// (Unix time in mit-csail and fr-clinic; a relative clock starting at 70 s
// in aces); the Kuemmerle .relations files use it. logger_timestamp is the
// time at which the logger received the message, since the logger started.
// Laser stamps strictly increase in all three shared logs; in aces ODOM and
// FLASER lines interleave with occasional out-of-order stamps between them.
//
// Old-format lasers (FLASER/RLASER) carry no geometry. Like CARMEN's own
// log reader (readlog.c, carmen_laser_guess_angle_increment), they start at
// -90 deg and the increment is guessed from the count: 180 or 181 readings ->
// 1 deg, 360 or 361 -> 0.5 deg, 400 or 401 -> 0.25 deg, otherwise
// pi / (n - 1). For aces.clf (180 readings) this puts beam i at -90 + i deg:
// CARMEN takes 180 readings to be a 181-beam SICK scan at 1 deg with the
// last beam dropped, and pi / (n - 1) would instead stretch the scan by
// 1/179 (1 deg, 17 cm at 10 m, on the last beam). For mit-csail.clf (361
// readings) both rules give 0.5 deg. PARAM lines are not consulted (none of
// the shared logs has laser geometry parameters); the options override the
// guess when a log's PARAM lines or a data sheet say otherwise.
//
// Thread-safety: the functions are reentrant; results are plain values.
#ifndef GROUNDLINE_IO_CARMEN_H_
#define GROUNDLINE_IO_CARMEN_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "groundline/core/se2.h"
#include "groundline/core/status.h"

namespace groundline::io {

struct CarmenReadOptions {
  // false (default): a malformed line of a known message type is skipped and
  // recorded in CarmenReadSummary, because real logs contain junk (truncated
  // last lines, interleaved writes). true: it is an error naming
  // file:line:field (for tests and for checking a converted log).
  bool strict = false;
  // Keep the reasons of at most this many skipped lines (all are counted).
  std::size_t max_recorded_skips = 1000;

  // Geometry of old-format lasers (FLASER / RLASER), see the file comment.
  double old_format_angle_min_rad = -std::numbers::pi / 2.0;
  // 0: guess from the number of readings as CARMEN does.
  double old_format_angle_increment_rad = 0.0;
  // CARMEN's readlog default for old-format lasers.
  double old_format_max_range_m = 80.0;

  // A count above this is treated as malformed (guards against garbage).
  int64_t max_readings = 100000;

  core::Status Validate() const;
};

// The angle increment CARMEN guesses for an old-format laser with
// `num_readings` readings (see the file comment); 0 for fewer than 2.
double GuessOldFormatAngleIncrementRad(std::size_t num_readings);

struct CarmenParam {
  int64_t line = 0;
  std::string name;
  std::string value;  // fields between the name and the stamps, joined by ' '
};

// ODOM: the robot's odometry pose and velocities.
struct CarmenOdometry {
  int64_t line = 0;      // 1-based line in the file
  double stamp_s = 0.0;  // ipc_timestamp
  double logger_stamp_s = 0.0;
  core::SE2 pose;         // T_odom_base
  double tv_mps = 0.0;    // translational velocity
  double rv_radps = 0.0;  // rotational velocity
  double accel_mps2 = 0.0;
};

enum class CarmenLaserMessage { kFlaser, kRlaser, kRawLaser, kRobotLaser };

// One laser scan from FLASER, RLASER, RAWLASERk or ROBOTLASERk.
struct CarmenLaserScan {
  int64_t line = 0;
  double stamp_s = 0.0;  // ipc_timestamp
  double logger_stamp_s = 0.0;
  CarmenLaserMessage message = CarmenLaserMessage::kFlaser;
  // CARMEN's laser number: 1 = front (FLASER), 2 = rear (RLASER), k for
  // RAWLASERk / ROBOTLASERk.
  int laser_id = 1;
  int laser_type = -1;  // as logged (RAWLASER/ROBOTLASER); -1 for old format
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double max_range_m = 0.0;
  std::vector<double> ranges_m;
  std::vector<double> remissions;  // empty unless logged (unit as logged)
  // Absent for RAWLASER, which logs no pose.
  std::optional<core::SE2> laser_pose;  // T_odom_laser, as logged
  std::optional<core::SE2> robot_pose;  // T_odom_base, the odometry pose
  double tv_mps = 0.0;                  // ROBOTLASER only, else 0
  double rv_radps = 0.0;                // ROBOTLASER only, else 0

  double BeamAngleRad(std::size_t i) const {
    return angle_min_rad + static_cast<double>(i) * angle_increment_rad;
  }
};

// "FLASER", "RLASER", "RAWLASER<k>" or "ROBOTLASER<k>".
std::string CarmenLaserMessageName(const CarmenLaserScan& scan);

// TRUEPOS: a simulator's true pose and the odometry pose.
struct CarmenTruePose {
  int64_t line = 0;
  double stamp_s = 0.0;
  double logger_stamp_s = 0.0;
  core::SE2 true_pose;  // T_world_base
  core::SE2 odom_pose;  // T_odom_base
};

using CarmenMessage = std::variant<CarmenParam, CarmenOdometry, CarmenLaserScan, CarmenTruePose>;

struct CarmenSkippedLine {
  int64_t line = 0;
  std::string reason;  // "FLASER field 'range[17]' (field 19): expected ..."
};

struct CarmenReadSummary {
  int64_t lines = 0;  // every line read, including comments and blanks
  int64_t comment_lines = 0;
  int64_t blank_lines = 0;
  // Well-formed messages by name as written ("FLASER", "ROBOTLASER1", ...),
  // including message types this reader does not know (which are skipped).
  std::map<std::string, int64_t> message_counts;
  int64_t unknown_messages = 0;  // lines of unknown types (also in message_counts)
  // Malformed lines skipped in lenient mode: how many, and the first
  // max_recorded_skips of them with their reasons.
  int64_t skipped_line_count = 0;
  std::vector<CarmenSkippedLine> skipped_lines;

  int64_t Count(std::string_view message_name) const;
};

// Called once per parsed message, in file order; the callback owns the
// message (it may move from it). Returning an error stops the reading;
// StreamCarmenLog then returns that error prefixed with file:line.
using CarmenCallback = std::function<core::Status(CarmenMessage message)>;

// Streams the messages of a CARMEN log to `callback` (PARAM, ODOM, TRUEPOS,
// lasers; SYNC and unknown types are only counted); an empty callback only
// counts. Errors: the file cannot be read, options are invalid, or (strict
// mode) a malformed line, named "path:line: MESSAGE field 'name' (field k):
// ...".
core::Result<CarmenReadSummary> StreamCarmenLog(const std::filesystem::path& path,
                                                const CarmenReadOptions& options,
                                                const CarmenCallback& callback);

// A whole log in memory.
struct CarmenLog {
  std::vector<CarmenOdometry> odometry;       // file order
  std::vector<CarmenLaserScan> scans;         // file order, all laser kinds
  std::vector<CarmenTruePose> true_poses;     // file order
  std::map<std::string, std::string> params;  // a repeated name keeps the last value
  CarmenReadSummary summary;
};

core::Result<CarmenLog> ReadCarmenLog(const std::filesystem::path& path,
                                      const CarmenReadOptions& options = {});

}  // namespace groundline::io

#endif  // GROUNDLINE_IO_CARMEN_H_
