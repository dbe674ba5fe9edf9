// An 8-bit grey raster as a data: URI (PNG, base64) to embed in a report page.
#ifndef GROUNDLINE_CALIBRATION_SRC_PNG_DATA_URI_H_
#define GROUNDLINE_CALIBRATION_SRC_PNG_DATA_URI_H_

#include <cstdint>
#include <string>
#include <vector>

namespace groundline::calibration::internal {

// RFC 4648 base64 with padding.
std::string Base64(const std::vector<std::uint8_t>& bytes);

// "data:image/png;base64,..." of a row-major width x height grey raster
// (asserted to hold width * height bytes); empty when encoding fails.
std::string GreyPngDataUri(const std::vector<std::uint8_t>& grey, int width_px, int height_px);

}  // namespace groundline::calibration::internal

#endif  // GROUNDLINE_CALIBRATION_SRC_PNG_DATA_URI_H_
