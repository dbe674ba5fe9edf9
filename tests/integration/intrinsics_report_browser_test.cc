// The intrinsics report as a technician sees it: `groundline calibrate
// intrinsics` on OpenCV's 13 chessboard views (a FAIL: too few views, empty
// image corners), then report.html rendered by headless Chromium. A probe
// script appended to a copy of the page reports what the browser laid out:
// the page's rendered text (innerText: what is visible, not what the markup
// holds), every figure (<img> and top-level <svg>) with its rendered size and
// whether an image loaded, and the horizontal overflow of the layout at
// 1280 px. Checked: the verdict, the failures and the coverage advice, the
// projection-uncertainty table and sentence with the figures of report.json,
// four figures all drawn and none broken, and a screenshot whose top shows
// the red FAIL badge.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../tools/cli_runner.h"
#include "headless_chromium.h"
#include "test_data.h"

namespace groundline {
namespace {

std::string Fmt(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

using ::groundline::testing::ReadText;

// Appended before </body>: on load, a <pre id="probe"> with the JSON
// {text, figures: [{tag, width, height, loaded, src}], overflow_px}.
constexpr char kProbe[] = R"JS(<script>
window.addEventListener('load', () => {
  const text = document.body.innerText;
  const figures = [...document.querySelectorAll('img, svg')]
    .filter(e => !(e.parentElement && e.parentElement.closest('svg')))
    .map(e => { const b = e.getBoundingClientRect();
      return {tag: e.tagName.toLowerCase(), width: b.width, height: b.height,
              loaded: e.tagName !== 'IMG' || (e.complete && e.naturalWidth > 0),
              src: (e.getAttribute('src') || '').slice(0, 80)}; });
  const pre = document.createElement('pre');
  pre.id = 'probe';
  pre.textContent = JSON.stringify({text, figures,
    overflow_px: document.documentElement.scrollWidth - window.innerWidth});
  document.body.appendChild(pre);
});
</script>)JS";

std::string HtmlUnescape(std::string s) {
  const std::pair<const char*, const char*> entities[] = {
      {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&#39;", "'"}, {"&amp;", "&"}};
  for (const auto& [from, to] : entities) {
    for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + 1)) {
      s.replace(at, std::string(from).size(), to);
    }
  }
  return s;
}

TEST(IntrinsicsReportBrowser, ShowsTheVerdictUncertaintyAndCoverageAdviceForTheOpenCvViews) {
  GROUNDLINE_REQUIRE_CHROMIUM();
  GROUNDLINE_REQUIRE_DATA("calib/opencv_chessboard/left01.jpg");
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("intrinsics_report");
  std::string output;
  const std::string images =
      (::groundline::testing::SharedDataDir() / "calib/opencv_chessboard/left*.jpg").string();
  ASSERT_EQ(testing::RunGroundline("calibrate intrinsics --images '" + images +
                                       "' --target opencv_chessboard_9x6_25mm --out " +
                                       testing::Quoted(dir / "cal"),
                                   dir, &output),
            1)
      << output;
  const nlohmann::json report = nlohmann::json::parse(ReadText(dir / "cal/report.json"));
  ASSERT_EQ(report["verdict"], "FAIL");

  std::string page = ReadText(dir / "cal/report.html");
  const std::size_t body_end = page.rfind("</body>");
  ASSERT_NE(body_end, std::string::npos);
  page.insert(body_end, kProbe);
  // Beside the original, so that relative references resolve the same way.
  const std::filesystem::path probe_page = dir / "cal/report_probe.html";
  std::ofstream(probe_page) << page;
  const std::string url = "file://" + probe_page.string();

  const testing::BrowserRun dom_run = testing::DumpDom(url, 1280, 2000, 1000, dir);
  ASSERT_TRUE(dom_run.ok) << dom_run.error;
  const std::string& dom = dom_run.stdout_text;
  const std::size_t a = dom.find("<pre id=\"probe\">");
  ASSERT_NE(a, std::string::npos) << "the probe did not run; the DOM:\n" << dom;
  const std::size_t b = dom.find("</pre>", a);
  ASSERT_NE(b, std::string::npos);
  const nlohmann::json probe = nlohmann::json::parse(HtmlUnescape(dom.substr(a + 16, b - a - 16)));
  const std::string text = probe["text"].get<std::string>();
  std::ofstream(dir / "report.rendered.txt") << text;

  // The verdict, why, and what to capture next.
  EXPECT_NE(text.find("Intrinsic calibration FAIL"), std::string::npos) << text;
  EXPECT_NE(text.find("What failed and what to do"), std::string::npos) << text;
  for (const nlohmann::json& f : report["failures"]) {
    EXPECT_NE(text.find(f.get<std::string>()), std::string::npos) << f;
  }
  ASSERT_FALSE(report["advice"].empty());
  for (const nlohmann::json& advice : report["advice"]) {
    EXPECT_NE(text.find(advice.get<std::string>()), std::string::npos) << advice;
  }
  EXPECT_NE(text.find("capture views with the board pushed into the image's top-left corner"),
            std::string::npos)
      << text;

  // The intrinsics by name and unit, with the solved values and their sigma.
  const char* names[12] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
  ASSERT_EQ(report["intrinsics"].size(), 12u);
  ASSERT_EQ(report["intrinsics_sigma"].size(), 12u);
  for (int k = 0; k < 12; ++k) {
    const std::string row = std::string(names[k]) + "\t" + (k < 4 ? "px" : "-") + "\t" +
                            Fmt("%.6g", report["intrinsics"][k].get<double>()) + "\t" +
                            Fmt("%.3g", report["intrinsics_sigma"][k].get<double>()) + "\n";
    EXPECT_NE(text.find(row), std::string::npos) << row << text;
  }

  // The projection uncertainty: the table at 1, 2, 4 m (cells tab-separated
  // in innerText) and the judged figure against its limit.
  const nlohmann::json& worst = report["projection_uncertainty"]["worst"];
  ASSERT_EQ(worst.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const std::string row = Fmt("%.0f m", worst[i]["range_m"].get<double>()) + "\t" +
                            Fmt("%.3f", worst[i]["worst_px"].get<double>()) + "\t" +
                            Fmt("%.2f", worst[i]["worst_mm"].get<double>()) + "\t" +
                            Fmt("%.0f", worst[i]["where_px"][0].get<double>()) + ", " +
                            Fmt("%.0f", worst[i]["where_px"][1].get<double>());
    EXPECT_NE(text.find(row), std::string::npos) << "row '" << row << "' not shown:\n" << text;
  }
  EXPECT_NE(text.find("Judged at 2.0 m: worst " +
                      Fmt("%.3f px", worst[3]["worst_px"].get<double>()) + ", limit 0.250 px"),
            std::string::npos)
      << text;
  EXPECT_GT(worst[3]["worst_px"].get<double>(), 0.25);  // this set FAILs the rule too
  // The failure names the pixel the table shows.
  EXPECT_NE(
      text.find("worst direction, at pixel " + Fmt("%.0f", worst[3]["where_px"][0].get<double>()) +
                ", " + Fmt("%.0f", worst[3]["where_px"][1].get<double>()) + ")"),
      std::string::npos)
      << text;

  // Every figure drawn at a readable size, no broken image, no sideways scroll.
  const nlohmann::json& figures = probe["figures"];
  EXPECT_EQ(figures.size(), 4u) << figures.dump(1);
  for (const nlohmann::json& f : figures) {
    EXPECT_TRUE(f["loaded"].get<bool>()) << "broken image: " << f.dump();
    EXPECT_GE(f["width"].get<double>(), 400.0) << f.dump();
    EXPECT_GE(f["height"].get<double>(), 200.0) << f.dump();
  }
  EXPECT_LE(probe["overflow_px"].get<double>(), 0.0);

  // The screenshot: not blank, and the FAIL badge (#c62828) at the top.
  const std::filesystem::path png = dir / "report.png";
  const testing::BrowserRun shot_run = testing::Screenshot(
      "file://" + (dir / "cal/report.html").string(), png, 1280, 2000, 500, dir);
  ASSERT_TRUE(shot_run.ok) << shot_run.error;
  const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty());
  cv::Scalar mean, stddev;
  cv::meanStdDev(shot, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 30.0) << "a blank screenshot";
  cv::Mat badge;
  cv::inRange(shot.rowRange(0, 120), cv::Scalar(0x28 - 20, 0x28 - 20, 0xc6 - 20),
              cv::Scalar(0x28 + 20, 0x28 + 20, 0xc6 + 20), badge);
  EXPECT_GT(cv::countNonZero(badge), 500) << "no red FAIL badge at the top of " << png;
}

}  // namespace
}  // namespace groundline
