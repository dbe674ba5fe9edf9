// The service's status page pieces (service.h): the HTML page, the atlas as
// JSON for its map, and the BEV picture with the detected lines. Private.
#ifndef GROUNDLINE_SERVICE_SRC_STATUS_PAGE_H_
#define GROUNDLINE_SERVICE_SRC_STATUS_PAGE_H_

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "groundline/localization/atlas.h"
#include "groundline/localization/floor_front_end.h"

namespace groundline::service {

// A self-contained page that polls /health.json and /bev.png and draws the
// pose with its 3-sigma covariance ellipse on the atlas (/atlas.json).
const char* StatusPageHtml();
// {"lines": [[ax, ay, bx, by, kind], ...], "junctions": [[x, y], ...]} (map frame, m).
std::string AtlasJson(const localization::Atlas& atlas);
// The BEV (grey) with the frame's lines drawn (tape green, joints magenta,
// junctions red) and the distance ahead of the axle marked every 0.5 m on
// its left edge, 2x, as PNG bytes.
std::vector<std::uint8_t> DrawBevPng(const cv::Mat& bev, const localization::FloorFrontEnd& camera,
                                     const localization::FloorObservations& seen);

}  // namespace groundline::service

#endif  // GROUNDLINE_SERVICE_SRC_STATUS_PAGE_H_
