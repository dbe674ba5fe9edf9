#include "status_page.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace groundline::service {

const char* StatusPageHtml() {
  return R"HTML(<!doctype html>
<html><head><meta charset="utf-8"><title>groundline</title>
<style>
body { font-family: sans-serif; margin: 16px; background: #f4f4f4; color: #222; }
.row { display: flex; gap: 16px; flex-wrap: wrap; }
.card { background: #fff; border-radius: 6px; padding: 12px; box-shadow: 0 1px 3px #0002; }
h1 { font-size: 20px; margin: 0 0 12px 0; }
h2 { font-size: 15px; margin: 0 0 8px 0; }
table { border-collapse: collapse; font-size: 13px; }
td { padding: 2px 8px 2px 0; }
td.v { font-family: monospace; text-align: right; }
.ok { color: #178017; font-weight: bold; } .bad { color: #b31d1d; font-weight: bold; }
.legend { font-size: 12px; margin-top: 4px; }
.legend span.item { white-space: nowrap; }
.swatch { display: inline-block; width: 14px; height: 3px; vertical-align: middle; margin: 0 3px 0 8px; }
#bevmsg { width: 360px; padding: 40px 0; text-align: center; color: #777; background: #fafafa; }
</style></head><body>
<h1>groundline &mdash; <span id="mode">?</span> <span id="state"></span></h1>
<div class="row">
<div class="card"><h2>Pose on the atlas (3&sigma; ellipse, 20 m around)</h2>
<svg id="map" width="420" height="420" style="background:#fafafa"></svg>
<div class="legend" style="width:420px">map frame, x right, y up;
<span class="item"><span class="swatch" style="background:#c90"></span>floor tape</span>
<span class="item"><span class="swatch" style="background:#a0a"></span>joints</span>
<span class="item"><span class="swatch" style="background:#777"></span>walls, rack faces</span>
<span class="item"><span class="swatch" style="background:#1565c0"></span>vehicle, heading, 3&sigma; ellipse</span></div></div>
<div class="card"><h2>Camera: bird's-eye view and detected lines</h2>
<img id="bev" width="360" alt="bird's-eye view" hidden><div id="bevmsg">no camera frame yet</div>
<div class="legend" style="width:360px">seen from above, vehicle forward up, distances ahead of the axle in m;
green: tape, magenta: joints, red: junctions</div></div>
<div class="card"><h2>Health</h2><table id="health"></table></div>
</div>
<script>
let atlas = null;
fetch('/atlas.json').then(r => r.json()).then(a => atlas = a);
function row(k, v, cls) { return '<tr><td>' + k + '</td><td class="v ' + (cls || '') + '">' + v + '</td></tr>'; }
function draw(h) {
  const svg = document.getElementById('map'), W = 420, R = 20, s = W / (2 * R);
  const px = h.pose.x_m, py = h.pose.y_m;
  const X = x => (x - px) * s + W / 2, Y = y => W / 2 - (y - py) * s;
  let g = '';
  if (atlas) for (const l of atlas.lines) {
    if (Math.min(Math.hypot(l[0] - px, l[1] - py), Math.hypot(l[2] - px, l[3] - py)) > 3 * R) continue;
    const face = l[4] === 'wall' || l[4] === 'rack_face';
    g += '<line x1="' + X(l[0]) + '" y1="' + Y(l[1]) + '" x2="' + X(l[2]) + '" y2="' + Y(l[3]) +
         '" stroke="' + (face ? '#777' : (l[4] === 'joint' ? '#a0a' : '#c90')) + '" stroke-width="' + (face ? 2 : 1.5) + '"/>';
  }
  // 3-sigma ellipse of the position covariance (drawn at least 3 px wide).
  const a = h.cov[0], b = h.cov[1], d = h.cov[4];
  const t = 0.5 * Math.atan2(2 * b, a - d), m = 0.5 * (a + d), q = Math.sqrt(0.25 * (a - d) * (a - d) + b * b);
  const r1 = Math.max(3, 3 * Math.sqrt(Math.max(m + q, 0)) * s), r2 = Math.max(3, 3 * Math.sqrt(Math.max(m - q, 0)) * s);
  g += '<ellipse cx="' + X(px) + '" cy="' + Y(py) + '" rx="' + r1 + '" ry="' + r2 + '" transform="rotate(' +
       (-t * 180 / Math.PI) + ' ' + X(px) + ' ' + Y(py) + ')" fill="#1565c055" stroke="#1565c0"/>';
  const yaw = h.pose.yaw_deg * Math.PI / 180;
  g += '<line x1="' + X(px) + '" y1="' + Y(py) + '" x2="' + X(px + 1.5 * Math.cos(yaw)) + '" y2="' +
       Y(py + 1.5 * Math.sin(yaw)) + '" stroke="#1565c0" stroke-width="3"/>';
  g += '<rect x="8" y="' + (W - 30) + '" width="' + (5 * s + 16) + '" height="24" fill="#fafafa" fill-opacity="0.85"/>' +
       '<line x1="16" y1="' + (W - 12) + '" x2="' + (16 + 5 * s) + '" y2="' + (W - 12) + '" stroke="#222" stroke-width="2"/>' +
       '<text x="' + (16 + 2.5 * s) + '" y="' + (W - 17) + '" font-size="12" text-anchor="middle">5 m</text>';
  svg.innerHTML = g;
}
async function tick() {
  try {
    const h = await (await fetch('/health.json')).json();
    const c = h.counters, k = h.last_keyframe || {};
    // The service's rates, per second of data time.
    const rate = f => h.rates_hz ? h.rates_hz[f].toFixed(1) + ' /s' : '-';
    document.getElementById('mode').textContent = h.mode;
    const sensors = k.sensors || {};
    const mode = sensors.degraded_mode;
    document.getElementById('state').innerHTML = !h.started ? '<span class="bad">waiting for a start pose</span>' :
      (!mode || mode === 'full') ? '<span class="ok">running' + (mode ? ', all sensors in use' : '') + '</span>' :
      '<span class="bad">degraded: the estimate rests on ' + mode + '</span>';
    let t = row('data time [s]', h.stamp_s.toFixed(2)) +
      row('x, y [m]', h.pose.x_m.toFixed(3) + ', ' + h.pose.y_m.toFixed(3)) +
      row('yaw [deg]', h.pose.yaw_deg.toFixed(2)) +
      row('sigma x, y [mm]', (1e3 * Math.sqrt(h.cov[0])).toFixed(1) + ', ' + (1e3 * Math.sqrt(h.cov[4])).toFixed(1)) +
      row('odometry in', rate('wheel_readings')) + row('frames in', rate('frames')) + row('scans in', rate('scans')) +
      row('frames dropped (queue full)', h.camera_stage.dropped_queue_full, h.camera_stage.dropped_queue_full ? 'bad' : '') +
      row('frames unreadable', c.frames_unreadable + h.camera_stage.unreadable) +
      row('frames without odometry', h.camera_stage.without_odometry, h.camera_stage.without_odometry ? 'bad' : '') +
      row('readings dropped', c.wheel_dropped_non_finite + c.wheel_dropped_out_of_order + c.wheel_dropped_duplicate + c.wheel_dropped_frozen + c.wheel_dropped_slip) +
      row('readings late (merged)', c.wheel_late_merged) +
      row('clock jumps', c.clock_jumps, c.clock_jumps ? 'bad' : '') +
      row('scans dropped', c.scans_dropped_bad + c.scans_dropped_out_of_order + c.scans_dropped_ahead) +
      row('lines used / rejected (last)', (k.lines_used ?? '-') + ' / ' + (k.lines_rejected ?? '-')) +
      row('LiDAR degenerate (last)', k.lidar_degenerate === undefined ? '-' : (k.lidar_degenerate ? 'yes' : 'no'), k.lidar_degenerate ? 'bad' : 'ok') +
      row('walls used (last)', k.walls_used ?? '-') +
      row('solve [ms] (last)', k.solve_ms === undefined ? '-' : k.solve_ms.toFixed(2)) +
      row('latency median / p99 [ms]', h.latency_ms.median.toFixed(2) + ' / ' + h.latency_ms.p99.toFixed(2)) +
      row('keyframes', c.keyframes) +
      row('re-initializations', c.reinitializations);
    const dds = h.dds || {};
    for (const [name, d] of Object.entries(dds.inputs || {})) {
      if (d.received || d.matched_writers) {
        t += row('DDS ' + name + ' received / dropped', d.received + ' / ' + d.dropped + (d.dropped ? ' (' + d.last_drop_reason.replace(/</g, '&lt;') + ')' : ''), d.dropped ? 'bad' : '');
      }
    }
    if (dds.initial_poses) t += row('DDS initial poses applied / refused', dds.initial_poses.applied + ' / ' + dds.initial_poses.refused);
    if (dds.outputs) t += row('DDS out poses / tf / diagnostics', dds.outputs.poses + ' / ' + dds.outputs.tf + ' / ' + dds.outputs.diagnostics, dds.outputs.write_errors ? 'bad' : '');
    document.getElementById('health').innerHTML = t;
    draw(h);
  } catch (e) { document.getElementById('state').innerHTML = '<span class="bad">service not answering</span>'; }
}
setInterval(tick, 500); tick();
// The BEV replaces its placeholder once a picture loads (a 404 before the
// first frame, or without a camera, keeps the placeholder, not a broken image).
const bev = document.getElementById('bev'), bevMsg = document.getElementById('bevmsg');
bev.onload = () => { bev.hidden = false; bevMsg.hidden = true; };
bev.onerror = () => { bev.hidden = true; bevMsg.hidden = false; };
function pollBev() { bev.src = '/bev.png?t=' + Date.now(); }
setInterval(pollBev, 1000); pollBev();
</script></body></html>
)HTML";
}

std::string AtlasJson(const localization::Atlas& atlas) {
  nlohmann::json j;
  j["lines"] = nlohmann::json::array();
  for (const localization::AtlasLine& l : atlas.lines) {
    j["lines"].push_back({l.endpoint_a_m.x(), l.endpoint_a_m.y(), l.endpoint_b_m.x(),
                          l.endpoint_b_m.y(), std::string(core::MarkingKindName(l.kind))});
  }
  j["junctions"] = nlohmann::json::array();
  for (const localization::AtlasJunction& p : atlas.junctions) {
    j["junctions"].push_back({p.point_m.x(), p.point_m.y()});
  }
  return j.dump();
}

std::vector<std::uint8_t> DrawBevPng(const cv::Mat& bev, const localization::FloorFrontEnd& camera,
                                     const localization::FloorObservations& seen) {
  constexpr int kScale = 2;
  cv::Mat colour;
  cv::cvtColor(bev, colour, cv::COLOR_GRAY2BGR);
  cv::resize(colour, colour, cv::Size(), kScale, kScale, cv::INTER_NEAREST);
  const perception::BevGrid& grid = camera.remap().grid();
  auto pixel = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d c = grid.CellOfFloorPoint(p) * kScale;
    return cv::Point(static_cast<int>(c.x() + 0.5 * kScale),
                     static_cast<int>(c.y() + 0.5 * kScale));
  };
  for (const localization::LineObservation& l : seen.lines) {
    const cv::Scalar colour_bgr =
        l.kind == core::MarkingKind::kJoint ? cv::Scalar(255, 0, 255) : cv::Scalar(0, 200, 0);
    cv::line(colour, pixel(l.endpoint_a_base_m), pixel(l.endpoint_b_base_m), colour_bgr, 2);
  }
  for (const localization::JunctionObservation& j : seen.junctions) {
    cv::circle(colour, pixel(j.point_base_m), 6, cv::Scalar(0, 0, 255), 2);
  }
  // The scale: distance ahead of the axle (base_link x) every 0.5 m along
  // the left edge, white on a dark outline to read on any floor.
  const double x_max_m = grid.options().x_max_m;
  const double x_min_m = x_max_m - grid.rows() * grid.cell_m();
  for (double x_m = std::ceil(x_min_m / 0.5) * 0.5; x_m <= x_max_m + 1e-9; x_m += 0.5) {
    const int row = pixel({x_m, grid.options().y_max_m}).y;
    char label[16];
    std::snprintf(label, sizeof(label), "%.1f m", x_m);
    for (const auto& [bgr, thickness] :
         {std::pair{cv::Scalar(0, 0, 0), 3}, std::pair{cv::Scalar(255, 255, 255), 1}}) {
      cv::line(colour, {0, row}, {12, row}, bgr, thickness);
      cv::putText(colour, label, {16, row + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, bgr, thickness,
                  cv::LINE_AA);
    }
  }
  std::vector<std::uint8_t> png;
  cv::imencode(".png", colour, png);
  return png;
}

}  // namespace groundline::service
