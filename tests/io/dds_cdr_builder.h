// The plain CDR (XCDR1, little endian) layout of ROS 2 Humble messages as
// rmw_cyclonedds puts them on the wire, written out by hand so that the
// golden tests compare CycloneDDS's bytes with the rules, not with itself:
//   - 4-byte encapsulation header 00 01 00 00 (CDR_LE, options 0);
//   - every primitive aligned to its size relative to the first byte after
//     the header, float64 to 8 (XCDR2 would align it to 4), padding zero;
//   - string: uint32 length including the NUL, the bytes, the NUL;
//   - sequence: uint32 element count, then the elements; arrays: elements only.
// Values are encoded with shifts, independent of the host's byte order.
#ifndef GROUNDLINE_TESTS_IO_DDS_CDR_BUILDER_H_
#define GROUNDLINE_TESTS_IO_DDS_CDR_BUILDER_H_

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

namespace groundline::io::testing {

class CdrBuilder {
 public:
  CdrBuilder() : bytes_{0x00, 0x01, 0x00, 0x00} {}

  CdrBuilder& Align(std::size_t a) {
    while ((bytes_.size() - 4) % a != 0) bytes_.push_back(0);
    return *this;
  }
  CdrBuilder& U8(std::uint8_t v) {
    bytes_.push_back(v);
    return *this;
  }
  CdrBuilder& U32(std::uint32_t v) {
    Align(4);
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    return *this;
  }
  CdrBuilder& I32(std::int32_t v) { return U32(static_cast<std::uint32_t>(v)); }
  CdrBuilder& F32(float v) { return U32(std::bit_cast<std::uint32_t>(v)); }
  CdrBuilder& F64(double v) {
    Align(8);
    const auto u = std::bit_cast<std::uint64_t>(v);
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
    return *this;
  }
  CdrBuilder& Str(const std::string& s) {
    U32(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  CdrBuilder& Count(std::size_t n) { return U32(static_cast<std::uint32_t>(n)); }
  // builtin_interfaces/Time then the frame id: std_msgs/Header.
  CdrBuilder& Header(std::int32_t sec, std::uint32_t nanosec, const std::string& frame) {
    return I32(sec).U32(nanosec).Str(frame);
  }

  // The bytes so far. Trailing padding to a multiple of 4 is the writer's
  // choice (XTypes 7.6.3.1.2: the options' two low bits give its length), so
  // the golden tests compare the header and the payload, then check any tail.
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace groundline::io::testing

#endif  // GROUNDLINE_TESTS_IO_DDS_CDR_BUILDER_H_
