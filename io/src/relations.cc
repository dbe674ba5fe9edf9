#include "groundline/io/relations.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "groundline/io/compressed_file.h"
#include "text_fields.h"

namespace groundline::io {
namespace {

constexpr std::array<std::string_view, 8> kFieldNames = {"t1", "t2",   "x",     "y",
                                                         "z",  "roll", "pitch", "yaw"};

std::string FormatTolerance(double value) {
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "%g", value);
  return text.data();
}

core::Status ParseRelationLine(const std::vector<std::string_view>& fields,
                               const RelationsReadOptions& options, core::Relation* relation) {
  if (fields.size() != kFieldNames.size()) {
    return core::Status::Error("expected 8 fields 't1 t2 x y z roll pitch yaw', got " +
                               std::to_string(fields.size()) +
                               (fields.size() < kFieldNames.size() ? " (truncated line?)" : ""));
  }
  std::array<double, 8> v{};
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!internal::ParseFiniteDouble(fields[i], &v[i])) {
      return core::Status::Error("field '" + std::string(kFieldNames[i]) + "' (field " +
                                 std::to_string(i + 1) + "): expected a finite number, got " +
                                 internal::QuoteField(fields[i]));
    }
  }
  for (std::size_t i = 4; i <= 6; ++i) {
    if (std::abs(v[i]) > options.max_out_of_plane) {
      return core::Status::Error("field '" + std::string(kFieldNames[i]) + "' (field " +
                                 std::to_string(i + 1) + "): expected 0 for a planar relation " +
                                 "(|value| <= " + FormatTolerance(options.max_out_of_plane) +
                                 "), got " + std::string(fields[i]));
    }
  }
  relation->t1_s = v[0];
  relation->t2_s = v[1];
  relation->delta = core::SE2(v[2], v[3], v[7]);
  return core::Status::Ok();
}

}  // namespace

core::Status RelationsReadOptions::Validate() const {
  if (!(max_out_of_plane >= 0.0) || !std::isfinite(max_out_of_plane)) {
    return core::Status::Error("RelationsReadOptions: max_out_of_plane must be finite and >= 0");
  }
  return core::Status::Ok();
}

core::Result<std::vector<core::Relation>> ReadRelations(const std::filesystem::path& path,
                                                        const RelationsReadOptions& options) {
  if (core::Status valid = options.Validate(); !valid.ok()) return valid;
  core::Result<LineReader> reader = LineReader::Open(path);
  if (!reader.ok()) return reader.status();
  std::vector<core::Relation> relations;
  std::string line;
  std::vector<std::string_view> fields;
  while (reader->ReadLine(&line)) {
    internal::SplitFields(line, &fields);
    if (fields.empty() || fields.front().front() == '#') continue;
    core::Relation relation;
    if (core::Status s = ParseRelationLine(fields, options, &relation); !s.ok()) {
      return s.WithContext(path.string() + ":" + std::to_string(reader->line_number()));
    }
    relations.push_back(relation);
  }
  if (!reader->status().ok()) return reader->status();
  return relations;
}

}  // namespace groundline::io
