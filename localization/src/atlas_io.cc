#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "groundline/core/atomic_file.h"
#include "groundline/core/json_fields.h"
#include "groundline/localization/atlas.h"

namespace groundline::localization {
namespace {

using nlohmann::json;

Eigen::Matrix2d Matrix2(const std::vector<double>& v) {
  Eigen::Matrix2d m;
  m << v[0], v[1], v[2], v[3];
  return m;
}

json ToJson(const Eigen::Matrix2d& m) { return json::array({m(0, 0), m(0, 1), m(1, 0), m(1, 1)}); }
json ToJson(const Eigen::Vector2d& v) { return json::array({v.x(), v.y()}); }

json ToJson(const LandmarkSightings& seen) {
  return {{"keyframes", seen.keyframes}, {"first_s", seen.first_s}, {"last_s", seen.last_s}};
}

// The optional "seen" member of a line or junction entry.
std::optional<LandmarkSightings> ReadSightings(const json& entry, const std::string& p,
                                               core::JsonFieldReader* reader) {
  const auto found = entry.find("seen");
  if (found == entry.end()) return std::nullopt;
  LandmarkSightings seen;
  const std::string q = p + "seen.";
  const std::int64_t keyframes = reader->Id(*found, q, "keyframes");
  seen.first_s = reader->Finite(*found, q, "first_s");
  seen.last_s = reader->Finite(*found, q, "last_s");
  if (!reader->ok()) return std::nullopt;
  if (keyframes < 1 || keyframes > std::numeric_limits<int>::max()) {
    reader->Fail(q + "keyframes", "an integer >= 1", std::to_string(keyframes));
    return std::nullopt;
  }
  seen.keyframes = static_cast<int>(keyframes);
  if (seen.last_s < seen.first_s) {
    reader->Fail(q + "last_s", "a stamp >= first_s (" + std::to_string(seen.first_s) + ")",
                 std::to_string(seen.last_s));
  }
  return seen;
}

// The optional "missed" member: an integer >= 0.
int ReadMissed(const json& entry, const std::string& p, core::JsonFieldReader* reader) {
  if (entry.find("missed") == entry.end()) return 0;
  const std::int64_t missed = reader->Id(entry, p, "missed");
  if (!reader->ok()) return 0;
  if (missed < 0 || missed > std::numeric_limits<int>::max()) {
    reader->Fail(p + "missed", "an integer >= 0", std::to_string(missed));
    return 0;
  }
  return static_cast<int>(missed);
}

core::Status CheckSightings(const std::optional<LandmarkSightings>& seen,
                            const std::string& field) {
  if (!seen || (seen->keyframes >= 1 && std::isfinite(seen->first_s) &&
                std::isfinite(seen->last_s) && seen->last_s >= seen->first_s)) {
    return core::Status::Ok();
  }
  return core::Status::Error("field '" + field +
                             ".seen': expected keyframes >= 1 and finite first_s <= last_s");
}

core::Status CheckCovariance(const Eigen::Matrix2d& c, const std::string& field) {
  const bool ok = c.allFinite() && std::abs(c(0, 1) - c(1, 0)) <= 1e-12 * c.cwiseAbs().maxCoeff() &&
                  c(0, 0) > 0.0 && c.determinant() > 0.0;
  if (ok) return core::Status::Ok();
  return core::Status::Error("field '" + field +
                             "': expected a symmetric positive definite 2x2 matrix");
}

}  // namespace

core::Status Atlas::Validate() const {
  std::set<std::int64_t> ids;
  for (size_t i = 0; i < lines.size(); ++i) {
    const AtlasLine& line = lines[i];
    const std::string field = "lines[" + std::to_string(i) + "]";
    if (!ids.insert(line.id).second) {
      return core::Status::Error("field '" + field + ".id': duplicate id " +
                                 std::to_string(line.id));
    }
    if (!std::isfinite(line.line_map.rho_m) || !std::isfinite(line.line_map.alpha_rad) ||
        !perception::IsNormalized(line.line_map)) {
      return core::Status::Error("field '" + field +
                                 "': expected a normalized line (rho_m >= 0, alpha_rad in "
                                 "(-pi, pi])");
    }
    if (!line.endpoint_a_m.allFinite() || !line.endpoint_b_m.allFinite()) {
      return core::Status::Error("field '" + field + ".endpoints_m': expected finite numbers");
    }
    core::Status status = CheckCovariance(line.covariance, field + ".covariance");
    if (!status.ok()) return status;
    if (status = CheckSightings(line.seen, field); !status.ok()) return status;
    if (line.missed < 0) return core::Status::Error("field '" + field + ".missed': expected >= 0");
  }
  ids.clear();
  for (size_t i = 0; i < junctions.size(); ++i) {
    const std::string field = "junctions[" + std::to_string(i) + "]";
    if (!ids.insert(junctions[i].id).second) {
      return core::Status::Error("field '" + field + ".id': duplicate id");
    }
    if (!junctions[i].point_m.allFinite()) {
      return core::Status::Error("field '" + field + ".point_m': expected finite numbers");
    }
    core::Status status = CheckCovariance(junctions[i].covariance, field + ".covariance");
    if (!status.ok()) return status;
    if (status = CheckSightings(junctions[i].seen, field); !status.ok()) return status;
    if (junctions[i].missed < 0) {
      return core::Status::Error("field '" + field + ".missed': expected >= 0");
    }
  }
  return core::Status::Ok();
}

core::Result<Atlas> ReadAtlas(const std::filesystem::path& path) {
  json root;
  if (core::Status s = core::ReadJsonFile(path, "atlas file", &root); !s.ok()) return s;
  const std::string file = path.filename().string();
  core::JsonFieldReader reader(file);
  const std::string format = reader.String(root, "", "format");
  if (reader.status().ok() && format != kAtlasFormatName) {
    reader.Fail("format", std::string("\"") + kAtlasFormatName + "\"", "\"" + format + "\"");
  }
  const double major = reader.Number(root, "", "version_major");
  if (reader.status().ok() && major != kAtlasFormatMajor) {
    reader.Fail("version_major", std::to_string(kAtlasFormatMajor), std::to_string(major));
  }
  Atlas atlas;
  atlas.frame = reader.String(root, "", "frame");
  // Optional: absent in files written before it, which read as not stated.
  if (const auto stated = root.find("covariances_stated"); stated != root.end()) {
    if (stated->is_boolean()) {
      atlas.covariances_stated = stated->get<bool>();
    } else {
      reader.Fail("covariances_stated", "true or false", stated->dump());
    }
  }
  const json* lines = reader.Get(root, "", "lines");
  const json* junctions = reader.Get(root, "", "junctions");
  if (!reader.status().ok()) return reader.status();
  if (!lines->is_array()) reader.Fail("lines", "an array", lines->dump().substr(0, 40));
  if (!junctions->is_array()) reader.Fail("junctions", "an array", junctions->dump().substr(0, 40));
  if (!reader.status().ok()) return reader.status();
  for (size_t i = 0; i < lines->size(); ++i) {
    const json& entry = (*lines)[i];
    const std::string p = "lines[" + std::to_string(i) + "].";
    AtlasLine line;
    line.id = reader.Id(entry, p, "id");
    line.line_map.rho_m = reader.Number(entry, p, "rho_m");
    line.line_map.alpha_rad = reader.Number(entry, p, "alpha_rad");
    line.covariance = Matrix2(reader.Numbers(entry, p, "covariance", 4));
    const std::string kind = reader.String(entry, p, "kind");
    const auto parsed_kind = core::MarkingKindFromName(kind);
    if (reader.status().ok() && !parsed_kind) reader.Fail(p + "kind", "a marking kind", kind);
    if (parsed_kind) line.kind = *parsed_kind;
    const std::vector<double> ends = reader.Numbers(entry, p, "endpoints_m", 4);
    line.endpoint_a_m = {ends[0], ends[1]};
    line.endpoint_b_m = {ends[2], ends[3]};
    line.seen = ReadSightings(entry, p, &reader);
    line.missed = ReadMissed(entry, p, &reader);
    atlas.lines.push_back(line);
  }
  for (size_t i = 0; i < junctions->size(); ++i) {
    const json& entry = (*junctions)[i];
    const std::string p = "junctions[" + std::to_string(i) + "].";
    AtlasJunction junction;
    junction.id = reader.Id(entry, p, "id");
    const std::vector<double> point = reader.Numbers(entry, p, "point_m", 2);
    junction.point_m = {point[0], point[1]};
    junction.covariance = Matrix2(reader.Numbers(entry, p, "covariance", 4));
    junction.seen = ReadSightings(entry, p, &reader);
    junction.missed = ReadMissed(entry, p, &reader);
    atlas.junctions.push_back(junction);
  }
  if (!reader.status().ok()) return reader.status();
  const core::Status valid = atlas.Validate();
  if (!valid.ok()) return valid.WithContext(file);
  return atlas;
}

core::Status WriteAtlas(const std::filesystem::path& path, const Atlas& atlas) {
  const core::Status valid = atlas.Validate();
  if (!valid.ok()) return valid.WithContext("atlas not written to " + path.string());
  json root;
  root["format"] = kAtlasFormatName;
  root["version_major"] = kAtlasFormatMajor;
  root["frame"] = atlas.frame;
  root["covariances_stated"] = atlas.covariances_stated;
  root["lines"] = json::array();
  for (const AtlasLine& line : atlas.lines) {
    root["lines"].push_back(
        {{"id", line.id},
         {"rho_m", line.line_map.rho_m},
         {"alpha_rad", line.line_map.alpha_rad},
         {"covariance", ToJson(line.covariance)},
         {"kind", std::string(core::MarkingKindName(line.kind))},
         {"endpoints_m", json::array({line.endpoint_a_m.x(), line.endpoint_a_m.y(),
                                      line.endpoint_b_m.x(), line.endpoint_b_m.y()})}});
    if (line.seen) root["lines"].back()["seen"] = ToJson(*line.seen);
    if (line.missed > 0) root["lines"].back()["missed"] = line.missed;
  }
  root["junctions"] = json::array();
  for (const AtlasJunction& junction : atlas.junctions) {
    root["junctions"].push_back({{"id", junction.id},
                                 {"point_m", ToJson(junction.point_m)},
                                 {"covariance", ToJson(junction.covariance)}});
    if (junction.seen) root["junctions"].back()["seen"] = ToJson(*junction.seen);
    if (junction.missed > 0) root["junctions"].back()["missed"] = junction.missed;
  }
  return core::WriteFileAtomically(path, root.dump(1) + "\n");
}

}  // namespace groundline::localization
