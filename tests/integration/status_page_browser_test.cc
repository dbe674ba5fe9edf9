// The service's live status page in a real browser: `groundline serve`
// replays a short simulated zone B drive (LiDAR, wheels and a 1 Hz camera)
// at 0.3 x real time, and headless Chromium loads http://127.0.0.1:<port>/ (the port
// the service chose and printed). Everything checked is what the page's own
// scripts fill in from /health.json and /atlas.json, so a page whose script
// breaks, or a field the script reads that the service renamed, fails here:
// the mode and state in the title, the health table (the pose agrees with the
// odometry-rate trajectory the service wrote for the data time the page
// shows, to the printed digits), input rates from two successive polls, the
// map drawn with atlas lines and the covariance ellipse, the BEV picture
// loaded by the browser, and a screenshot that shows the drawn heading and
// ellipse.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../service/simulated_drive.h"
#include "child_process.h"
#include "headless_chromium.h"
#include "test_data.h"
#include "tools_under_test.h"

// Last: <resolv.h>, which it includes, defines the macro _res that Eigen uses as a name.
#include <httplib.h>

namespace groundline {
namespace {

// The text of the health table's value cell in the row labelled label, as
// the page's row() writes it; nullopt when the row is absent.
std::optional<std::string> HealthCell(const std::string& dom, const std::string& label) {
  const std::string head = "<tr><td>" + label + "</td><td class=\"v";
  const std::size_t row = dom.find(head);
  if (row == std::string::npos) return std::nullopt;
  const std::size_t open = dom.find('>', row + head.size());
  const std::size_t close = dom.find("</td>", open);
  if (open == std::string::npos || close == std::string::npos) return std::nullopt;
  return dom.substr(open + 1, close - open - 1);
}

std::string InnerHtmlOf(const std::string& dom, const std::string& open_tag,
                        const std::string& close_tag) {
  const std::size_t a = dom.find(open_tag);
  if (a == std::string::npos) return {};
  const std::size_t b = dom.find(close_tag, a);
  return b == std::string::npos ? std::string()
                                : dom.substr(a + open_tag.size(), b - a - open_tag.size());
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Pixels within tol (per channel) of the colour rgb.
int PixelsNear(const cv::Mat& bgr, int r, int g, int b, int tol) {
  int n = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      if (std::abs(p[2] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[0] - b) <= tol) ++n;
    }
  }
  return n;
}

// Share of the pixels whose colour differs from the most common one (the
// page background): 0 for a blank screenshot.
double ShareNotBackground(const cv::Mat& bgr) {
  std::map<std::uint32_t, int> histogram;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      ++histogram[(p[0] << 16) | (p[1] << 8) | p[2]];
    }
  }
  int most = 0;
  for (const auto& [colour, n] : histogram) most = std::max(most, n);
  return 1.0 - static_cast<double>(most) / static_cast<double>(bgr.total());
}

TEST(StatusPageBrowser, ShowsTheLivePoseRatesCountersAndMapOfARunningService) {
  GROUNDLINE_REQUIRE_CHROMIUM();
  if (::groundline::testing::Sanitized()) {
    GTEST_SKIP() << "the service's scan matching under AddressSanitizer is too slow to keep a "
                    "paced replay alive while the browser loads; runs in the release build";
  }
  const auto dir = ::groundline::testing::ScratchDir("status_page");
  // 12 m at 1-2 m/s paced at 0.3 x real time: about 25 s of service for the
  // browser's two runs of a few seconds each; the test stops it when done.
  // The camera at 1 Hz: each simulated frame takes 0.25 s to render. Port 0:
  // the system's choice, so no clash with a parallel test or a running service.
  ASSERT_TRUE(testing::SimulatedZoneBDrive(12.0, 7, dir / "drive", 1.0).has_value());
  std::ofstream(dir / "serve.yaml") << "inputs:\n  replay: {dataset: drive, speed: 0.3}\n"
                                    << "localizer: {preset: fusion}\n"
                                    << "start: {resume: false}\n"
                                    << "output: {dir: out}\n"
                                    << "http: {address: 127.0.0.1, port: 0}\n";
  testing::ChildProcess serve(
      {::groundline::testing::GroundlineCli(), "serve", "--config", (dir / "serve.yaml").string()},
      dir / "serve.log");
  ASSERT_TRUE(serve.started());
  ASSERT_TRUE(serve.WaitForOutput("/ (health: /health.json)", std::chrono::seconds(60)))
      << serve.output();
  std::smatch m;
  const std::string announced = serve.output();
  ASSERT_TRUE(
      std::regex_search(announced, m, std::regex(R"(status page http://127\.0\.0\.1:(\d+)/)")))
      << announced;
  const int port = std::stoi(m[1].str());
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";

  // Wait until the service has keyframes and a BEV picture to show.
  httplib::Client client("127.0.0.1", port);
  nlohmann::json health;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  bool ready = false;
  while (!ready && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const httplib::Result h = client.Get("/health.json");
    const httplib::Result bev = client.Get("/bev.png");
    if (!h || h->status != 200) continue;
    health = nlohmann::json::parse(h->body);
    ready = health["started"].get<bool>() && health["counters"]["keyframes"].get<int>() >= 2 &&
            bev && bev->status == 200;
  }
  ASSERT_TRUE(ready) << "no keyframe and BEV after 30 s: " << health.dump() << "\n"
                     << serve.output();
  // The picture the page polls decodes (the browser's own load of it shows in
  // the screenshot below only as pixels).
  const httplib::Result bev = client.Get("/bev.png");
  ASSERT_TRUE(bev && bev->status == 200);
  const cv::Mat bev_image = cv::imdecode(
      cv::Mat(1, static_cast<int>(bev->body.size()), CV_8UC1, const_cast<char*>(bev->body.data())),
      cv::IMREAD_COLOR);
  ASSERT_FALSE(bev_image.empty());
  EXPECT_GT(bev_image.cols, 100);

  // 3 s of the page's virtual time: six polls of /health.json, three of the BEV.
  const testing::BrowserRun dom_run = testing::DumpDom(url, 1280, 1000, 3000, dir);
  ASSERT_TRUE(dom_run.ok) << dom_run.error;
  const testing::BrowserRun shot_run =
      testing::Screenshot(url, dir / "status_page.png", 1280, 1000, 3000, dir);
  ASSERT_TRUE(shot_run.ok) << shot_run.error;
  ASSERT_EQ(serve.Wait(std::chrono::milliseconds(0)), -1)
      << "the replay ended while the browser ran (a machine slower than the test allows for): "
      << serve.output();
  serve.Terminate();
  ASSERT_EQ(serve.Wait(std::chrono::seconds(30)), 0) << serve.output();

  const std::string& dom = dom_run.stdout_text;
  std::ofstream(dir / "status_page.dom.html") << dom;
  EXPECT_NE(dom.find("<span id=\"mode\">" + health["mode"].get<std::string>() + "</span>"),
            std::string::npos)
      << dom;
  // The state: running, with all sensors or (a frame late at the 1 Hz
  // camera) degraded; not "waiting for a start pose" nor "service not
  // answering" (the script's catch, also what a script error shows).
  const std::string title = InnerHtmlOf(dom, "<h1>", "</h1>");
  EXPECT_TRUE(std::regex_search(
      title, std::regex("<span id=\"state\"><span class=\"(ok\">running, all sensors in use|"
                        "bad\">degraded: the estimate rests on [a-z+]+)</span>")))
      << title;

  // The pose the page shows is the service's pose at the data time it shows.
  const std::optional<std::string> stamp = HealthCell(dom, "data time [s]");
  const std::optional<std::string> xy = HealthCell(dom, "x, y [m]");
  const std::optional<std::string> yaw = HealthCell(dom, "yaw [deg]");
  ASSERT_TRUE(stamp && xy && yaw) << dom;
  double x_m = 0.0, y_m = 0.0;
  ASSERT_EQ(std::sscanf(xy->c_str(), "%lf, %lf", &x_m, &y_m), 2) << *xy;
  const double stamp_s = std::stod(*stamp), yaw_deg = std::stod(*yaw);
  std::ifstream tum(dir / "out" / "trajectory_odometry_rate.tum");
  bool found = false;
  int lines = 0;
  for (std::string line; std::getline(tum, line); ++lines) {
    double t = 0, x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
    std::istringstream(line) >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    const double tum_yaw_deg = 2.0 * std::atan2(qz, qw) * 180.0 / std::numbers::pi;
    // The page prints 2 decimals of the stamp and of the yaw, 3 of x and y.
    found = found || (std::abs(t - stamp_s) <= 0.0051 && std::abs(x - x_m) <= 0.00051 &&
                      std::abs(y - y_m) <= 0.00051 &&
                      std::abs(std::remainder(tum_yaw_deg - yaw_deg, 360.0)) <= 0.0051);
  }
  EXPECT_GT(lines, 100);
  EXPECT_TRUE(found) << "no pose at " << *stamp << " s with x, y " << *xy << " m, yaw " << *yaw
                     << " deg in trajectory_odometry_rate.tum";
  const std::optional<std::string> sigma = HealthCell(dom, "sigma x, y [mm]");
  ASSERT_TRUE(sigma);
  double sigma_x_mm = 0.0, sigma_y_mm = 0.0;
  ASSERT_EQ(std::sscanf(sigma->c_str(), "%lf, %lf", &sigma_x_mm, &sigma_y_mm), 2) << *sigma;
  EXPECT_GT(sigma_x_mm, 0.0);
  EXPECT_LT(sigma_x_mm, 200.0);

  // The service's rates per second of data (the page shows '-' for the first
  // second of data): the drive's 100 Hz odometry, 15 Hz LiDAR, 1 Hz camera.
  const struct {
    const char* row;
    double hz;
  } rates[] = {{"odometry in", 100.0}, {"frames in", 1.0}, {"scans in", 15.0}};
  for (const auto& rate : rates) {
    const std::optional<std::string> cell = HealthCell(dom, rate.row);
    ASSERT_TRUE(cell) << rate.row;
    ASSERT_TRUE(std::regex_match(*cell, std::regex(R"(\d+\.\d /s)"))) << rate.row << ": " << *cell;
    EXPECT_NEAR(std::stod(*cell), rate.hz, 0.1 * rate.hz + 0.5) << rate.row << ": " << *cell;
  }
  const std::optional<std::string> keyframes = HealthCell(dom, "keyframes");
  ASSERT_TRUE(keyframes);
  EXPECT_GE(std::stoi(*keyframes), 2);
  const std::optional<std::string> lines_cell = HealthCell(dom, "lines used / rejected (last)");
  ASSERT_TRUE(lines_cell);
  EXPECT_TRUE(std::regex_match(*lines_cell, std::regex(R"(\d+ / \d+)"))) << *lines_cell;
  const std::optional<std::string> latency = HealthCell(dom, "latency median / p99 [ms]");
  ASSERT_TRUE(latency);
  EXPECT_TRUE(std::regex_match(*latency, std::regex(R"(\d+\.\d\d / \d+\.\d\d)"))) << *latency;
  for (const char* counter :
       {"frames dropped (queue full)", "readings dropped", "scans dropped", "clock jumps"}) {
    const std::optional<std::string> cell = HealthCell(dom, counter);
    ASSERT_TRUE(cell) << counter;
    EXPECT_TRUE(std::regex_match(*cell, std::regex(R"(\d+)"))) << counter << ": " << *cell;
  }

  // The map: atlas lines around the pose, the ellipse and the heading.
  const std::string map = InnerHtmlOf(dom, "<svg id=\"map\"", "</svg>");
  EXPECT_EQ(Count(map, "<ellipse"), 1u) << map;
  EXPECT_GE(Count(map, "<line"), 5u) << map;
  EXPECT_EQ(map.find("NaN"), std::string::npos) << map;
  // The BEV as the browser loaded it: its onload shows the picture and hides
  // the placeholder (a broken or missing picture keeps them the other way).
  std::smatch bev_tag;
  ASSERT_TRUE(std::regex_search(dom, bev_tag, std::regex(R"(<img id="bev"[^>]*>)"))) << dom;
  EXPECT_TRUE(std::regex_search(bev_tag.str(), std::regex(R"( src="/bev\.png\?t=\d+")")))
      << bev_tag.str();
  EXPECT_EQ(bev_tag.str().find(" hidden"), std::string::npos) << bev_tag.str();
  EXPECT_NE(dom.find("<div id=\"bevmsg\" hidden=\"\">"), std::string::npos) << dom;

  // The screenshot: a rendered page, not a blank one, with the heading line
  // and the ellipse (#1565c0) the script drew.
  const cv::Mat shot = cv::imread((dir / "status_page.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty());
  EXPECT_EQ(shot.cols, 1280);
  EXPECT_GT(ShareNotBackground(shot), 0.2);
  EXPECT_GT(PixelsNear(shot, 0x15, 0x65, 0xc0, 24), 20);
}

}  // namespace
}  // namespace groundline
