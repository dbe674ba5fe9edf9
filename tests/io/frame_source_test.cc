// The folder frame source on real image files, and URI parsing.
#include "groundline/io/frame_source.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "groundline/core/dataset_records.h"
#include "test_data.h"

namespace groundline::io {
namespace {

// A 40x30 BGR image whose blue channel is `value` (so grey differs per file).
cv::Mat TestImage(int value) {
  cv::Mat bgr(30, 40, CV_8UC3, cv::Scalar(value, 100, 50));
  bgr.at<cv::Vec3b>(5, 7) = cv::Vec3b(255, 255, 255);
  return bgr;
}

// OpenCV's BT.601 grey of TestImage: 0.114 B + 0.587 G + 0.299 R.
double ExpectedGrey(int value) { return 0.114 * value + 0.587 * 100 + 0.299 * 50; }

TEST(FolderFrameSource, DeliversSortedFilesAsGreyWithRateStampsThenEnds) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("folder");
  ASSERT_TRUE(cv::imwrite((dir / "b.png").string(), TestImage(200)));
  ASSERT_TRUE(cv::imwrite((dir / "a.png").string(), TestImage(10)));
  ASSERT_TRUE(cv::imwrite((dir / "c.jpg").string(), TestImage(120)));
  std::ofstream(dir / "notes.txt") << "not an image";
  core::Result<std::unique_ptr<FrameSource>> source =
      OpenFrameSource("folder:" + dir.string() + "?rate=4");
  ASSERT_TRUE(source.ok()) << source.message();
  EXPECT_FALSE((*source)->IsLive());
  EXPECT_NE((*source)->Describe().find("3 images"), std::string::npos) << (*source)->Describe();
  const char* names[] = {"a.png", "b.png", "c.jpg"};
  const int values[] = {10, 200, 120};
  for (int i = 0; i < 3; ++i) {
    core::Result<std::optional<Frame>> frame = (*source)->Next(1.0);
    ASSERT_TRUE(frame.ok()) << frame.message();
    ASSERT_TRUE(frame->has_value());
    const Frame& f = **frame;
    EXPECT_EQ(f.name, names[i]);
    EXPECT_EQ(f.sequence, static_cast<std::uint64_t>(i));
    EXPECT_DOUBLE_EQ(f.stamp_s, i / 4.0);
    ASSERT_EQ(f.grey.type(), CV_8UC1);
    ASSERT_EQ(f.grey.size(), cv::Size(40, 30));
    // PNG is lossless: exact up to rounding; JPEG within its quantization.
    EXPECT_NEAR(f.grey.at<std::uint8_t>(20, 20), ExpectedGrey(values[i]), i == 2 ? 4.0 : 1.0);
    EXPECT_EQ(f.grey.at<std::uint8_t>(5, 7), 255) << f.name;
  }
  for (int i = 0; i < 2; ++i) {  // the end is sticky
    core::Result<std::optional<Frame>> end = (*source)->Next(1.0);
    ASSERT_TRUE(end.ok());
    EXPECT_FALSE(end->has_value());
  }
  EXPECT_EQ((*source)->stats().delivered, 3u);
  EXPECT_EQ((*source)->stats().skipped, 0u);
}

TEST(FolderFrameSource, CorruptFileIsSkippedAndCountedNotFatal) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("corrupt");
  ASSERT_TRUE(cv::imwrite((dir / "0.png").string(), TestImage(1)));
  std::ofstream(dir / "1.png", std::ios::binary) << "\x89PNG\r\n\x1a\n truncated";
  ASSERT_TRUE(cv::imwrite((dir / "2.png").string(), TestImage(2)));
  std::ofstream(dir / "3.png", std::ios::binary);  // empty
  core::Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(dir.string());
  ASSERT_TRUE(source.ok()) << source.message();
  std::vector<std::string> names;
  for (;;) {
    core::Result<std::optional<Frame>> frame = (*source)->Next(1.0);
    ASSERT_TRUE(frame.ok()) << frame.message();
    if (!frame->has_value()) break;
    names.push_back((*frame)->name);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"0.png", "2.png"}));
  const FrameSourceStats& stats = (*source)->stats();
  EXPECT_EQ(stats.delivered, 2u);
  ASSERT_EQ(stats.skipped, 2u);
  ASSERT_EQ(stats.skipped_reasons.size(), 2u);
  // Each reason names the file and what is wrong with it.
  EXPECT_NE(stats.skipped_reasons[0].find("1.png: cannot be decoded as an image"),
            std::string::npos)
      << stats.skipped_reasons[0];
  EXPECT_NE(stats.skipped_reasons[1].find("3.png: empty file (expected an image)"),
            std::string::npos)
      << stats.skipped_reasons[1];
}

TEST(FolderFrameSource, GlobSelectsFilesAndDatasetIndexGivesStamps) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("index");
  std::filesystem::create_directories(dir / "images");
  for (const char* name : {"000000.png", "000001.png", "other.png"}) {
    ASSERT_TRUE(cv::imwrite((dir / "images" / name).string(), TestImage(5)));
  }
  core::Result<std::unique_ptr<FrameSource>> glob =
      OpenFrameSource((dir / "images" / "0*.png").string());
  ASSERT_TRUE(glob.ok()) << glob.message();
  EXPECT_NE((*glob)->Describe().find("2 images"), std::string::npos) << (*glob)->Describe();

  ASSERT_TRUE(core::WriteImageIndex(dir / "images" / "index.csv",
                                    {{1700000000.25, "000000.png"}, {1700000000.5, "000001.png"}})
                  .ok());
  core::Result<std::unique_ptr<FrameSource>> dataset = OpenFrameSource("folder:" + dir.string());
  ASSERT_TRUE(dataset.ok()) << dataset.message();
  core::Result<std::optional<Frame>> first = (*dataset)->Next(1.0);
  core::Result<std::optional<Frame>> second = (*dataset)->Next(1.0);
  core::Result<std::optional<Frame>> end = (*dataset)->Next(1.0);
  ASSERT_TRUE(first.ok() && first->has_value() && second.ok() && second->has_value() && end.ok());
  EXPECT_DOUBLE_EQ((*first)->stamp_s, 1700000000.25);
  EXPECT_DOUBLE_EQ((*second)->stamp_s, 1700000000.5);
  EXPECT_EQ((*second)->name, "000001.png");
  EXPECT_FALSE(end->has_value());  // other.png is not in the index
}

TEST(FrameSourceUri, ParsesSchemesAndQueries) {
  core::Result<FrameSourceUri> v4l2 =
      ParseFrameSourceUri("v4l2:/dev/video2?width=1280&height=800&format=YUYV&fps=30");
  ASSERT_TRUE(v4l2.ok()) << v4l2.message();
  EXPECT_EQ(v4l2->kind, FrameSourceKind::kV4l2);
  EXPECT_EQ(v4l2->location, "/dev/video2");
  EXPECT_EQ(v4l2->options.width_px, 1280);
  EXPECT_EQ(v4l2->options.height_px, 800);
  EXPECT_EQ(v4l2->options.pixel_format, "YUYV");
  EXPECT_DOUBLE_EQ(v4l2->options.fps, 30.0);
  core::Result<FrameSourceUri> cam = ParseFrameSourceUri("libcamera:0?buffers=6");
  ASSERT_TRUE(cam.ok()) << cam.message();
  EXPECT_EQ(cam->kind, FrameSourceKind::kLibcamera);
  EXPECT_EQ(cam->location, "0");
  EXPECT_EQ(cam->options.buffer_count, 6);
  core::Result<FrameSourceUri> folder = ParseFrameSourceUri("views/left*.png");
  ASSERT_TRUE(folder.ok()) << folder.message();
  EXPECT_EQ(folder->kind, FrameSourceKind::kFolder);
  EXPECT_EQ(folder->location, "views/left*.png");
  core::Result<FrameSourceUri> wildcard = ParseFrameSourceUri("folder:views/left?.png?rate=5");
  ASSERT_TRUE(wildcard.ok()) << wildcard.message();
  EXPECT_EQ(wildcard->location, "views/left?.png");
  EXPECT_DOUBLE_EQ(wildcard->options.folder_rate_hz, 5.0);
  EXPECT_EQ(ParseFrameSourceUri("views/left?.png")->location, "views/left?.png");
}

TEST(FrameSourceUri, ErrorsNameTheUriAndWhatWasExpected) {
  const struct {
    const char* uri;
    const char* expected;
  } cases[] = {
      {"rtsp://cam/stream", "unknown source scheme 'rtsp:'"},
      {"v4l2:video0", "absolute device path"},
      {"v4l2:", "no device path"},
      {"v4l2:/dev/video0?format=RGB3", "expected format=GREY, YUYV or MJPG"},
      {"v4l2:/dev/video0?width=abc&height=10", "expected an integer > 0"},
      {"v4l2:/dev/video0?width=640", "give both width and height"},
      {"libcamera:0?format=YUYV", "unknown key 'format'"},
      {"folder:x?fps=3", "unknown key 'fps' for a folder"},
      {"", "empty frame source URI"},
  };
  for (const auto& c : cases) {
    core::Result<FrameSourceUri> parsed = ParseFrameSourceUri(c.uri);
    ASSERT_FALSE(parsed.ok()) << c.uri;
    EXPECT_NE(parsed.message().find(c.expected), std::string::npos) << parsed.message();
    if (*c.uri != '\0') {
      EXPECT_NE(parsed.message().find(c.uri), std::string::npos) << parsed.message();
    }
  }
  core::Result<std::unique_ptr<FrameSource>> missing = OpenFrameSource("folder:/no/such/dir");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("no such directory '/no/such/dir'"), std::string::npos)
      << missing.message();
  const std::filesystem::path empty = ::groundline::testing::ScratchDir("empty");
  core::Result<std::unique_ptr<FrameSource>> none = OpenFrameSource(empty.string());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no image file"), std::string::npos) << none.message();
}

}  // namespace
}  // namespace groundline::io
