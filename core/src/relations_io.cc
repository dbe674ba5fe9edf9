#include "groundline/core/relations_io.h"

#include <array>
#include <cmath>
#include <fstream>
#include <string>

#include "groundline/core/text_parse.h"

namespace groundline::core {
namespace {

constexpr double kMaxTiltRad = 1e-3;
constexpr std::array<const char*, 8> kFieldNames = {"t1", "t2",   "x",     "y",
                                                    "z",  "roll", "pitch", "yaw"};

}  // namespace

Result<std::vector<Relation>> ReadRelations(const std::filesystem::path& path) {
  std::ifstream in(path);
  const std::string file = path.string();
  if (!in) return Status::Error("cannot open relations file " + file);
  std::vector<Relation> relations;
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::vector<std::string_view> tokens = SplitWhitespace(text);
    if (tokens.empty() || tokens.front().front() == '#') continue;
    if (tokens.size() != kFieldNames.size()) {
      return Status::Error(FieldError(file, line, "line", "8 fields 't1 t2 x y z roll pitch yaw'",
                                      std::to_string(tokens.size()) + " fields"));
    }
    std::array<double, 8> f{};
    for (std::size_t i = 0; i < f.size(); ++i) {
      const std::optional<double> value = ParseDouble(tokens[i]);
      if (!value || !std::isfinite(*value)) {
        return Status::Error(FieldError(file, line, kFieldNames[i], "a finite number", tokens[i]));
      }
      f[i] = *value;
    }
    for (std::size_t i : {5u, 6u}) {
      if (std::abs(f[i]) > kMaxTiltRad) {
        return Status::Error(FieldError(file, line, kFieldNames[i],
                                        "a planar relation (|angle| <= 1e-3 rad)", tokens[i]));
      }
    }
    relations.push_back({f[0], f[1], SE2(f[2], f[3], f[7])});
  }
  if (in.bad()) return Status::Error("read error in " + file);
  return relations;
}

}  // namespace groundline::core
