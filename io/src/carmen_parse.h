// Parsing of one CARMEN log line into a message. Private to the io module;
// the file format is described in groundline/io/carmen.h.
#ifndef GROUNDLINE_IO_SRC_CARMEN_PARSE_H_
#define GROUNDLINE_IO_SRC_CARMEN_PARSE_H_

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "groundline/core/status.h"
#include "groundline/io/carmen.h"

namespace groundline::io::internal {

enum class CarmenLineType {
  kBlank,
  kComment,
  kMessage,      // `message` holds the parsed message
  kCountedOnly,  // a well-formed known message that is not delivered (SYNC)
  kUnknown,      // a message type this reader does not know
};

struct ParsedCarmenLine {
  CarmenLineType type = CarmenLineType::kBlank;
  std::string_view name;  // message name; views the parsed line
  std::optional<CarmenMessage> message;
};

// Parses `line` (number `line_number`, stored in the message). A malformed
// line of a known type returns an error "NAME field 'f' (field k): ..." that
// the caller prefixes with file:line. `fields` is scratch space, reused
// across calls to avoid allocations.
core::Status ParseCarmenLine(std::string_view line, int64_t line_number,
                             const CarmenReadOptions& options,
                             std::vector<std::string_view>* fields, ParsedCarmenLine* out);

}  // namespace groundline::io::internal

#endif  // GROUNDLINE_IO_SRC_CARMEN_PARSE_H_
