// GreyImageFileReader on real image files: the pixels cv::imread gives, the
// decoded buffer reused across files of one size, and errors that name the file.
#include "groundline/io/image_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "test_data.h"

namespace groundline::io {
namespace {

// A BGR image with a gradient and a pattern seeded by `value`, so that
// every file differs and the grey conversion is exercised.
cv::Mat ColourImage(int rows, int cols, int value) {
  cv::Mat bgr(rows, cols, CV_8UC3);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      bgr.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<std::uint8_t>((value + 3 * r) % 256),
                                          static_cast<std::uint8_t>((value * c + r) % 256),
                                          static_cast<std::uint8_t>((r * c) % 256));
    }
  }
  return bgr;
}

TEST(GreyImageFileReader, GivesImreadsPixelsAndReusesTheBufferForOneSize) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("image_file");
  const std::filesystem::path a = dir / "a.png", b = dir / "b.png", c = dir / "c.jpg";
  ASSERT_TRUE(cv::imwrite(a.string(), ColourImage(48, 64, 10)));
  ASSERT_TRUE(cv::imwrite(b.string(), ColourImage(48, 64, 200)));
  ASSERT_TRUE(cv::imwrite(c.string(), ColourImage(30, 40, 77)));
  GreyImageFileReader reader;
  cv::Mat grey;
  ASSERT_TRUE(reader.Read(a, &grey).ok());
  EXPECT_EQ(cv::norm(grey, cv::imread(a.string(), cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
  const std::uint8_t* buffer = grey.data;
  const cv::Mat view = grey;  // shares the buffer
  ASSERT_TRUE(reader.Read(b, &grey).ok());
  EXPECT_EQ(grey.data, buffer);
  EXPECT_EQ(cv::norm(grey, cv::imread(b.string(), cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(view, grey, cv::NORM_INF), 0.0);  // the view sees the new frame
  ASSERT_TRUE(reader.Read(c, &grey).ok());
  EXPECT_EQ(grey.type(), CV_8UC1);
  EXPECT_EQ(grey.size(), cv::Size(40, 30));
  EXPECT_EQ(cv::norm(grey, cv::imread(c.string(), cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
}

TEST(GreyImageFileReader, ErrorsNameTheFileAndWhatWasWrong) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("image_file_bad");
  GreyImageFileReader reader;
  cv::Mat grey;
  const std::filesystem::path missing = dir / "missing.png";
  core::Status s = reader.Read(missing, &grey);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(missing.string()), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("cannot be opened"), std::string::npos) << s.message();
  EXPECT_TRUE(grey.empty());

  const std::filesystem::path empty = dir / "empty.png";
  std::ofstream(empty).close();
  s = reader.Read(empty, &grey);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("empty.png: empty file"), std::string::npos) << s.message();

  const std::filesystem::path text = dir / "notes.png";
  std::ofstream(text) << "not an image at all";
  ASSERT_TRUE(cv::imwrite((dir / "good.png").string(), ColourImage(8, 8, 1)));
  ASSERT_TRUE(reader.Read(dir / "good.png", &grey).ok());
  s = reader.Read(text, &grey);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("notes.png: cannot be decoded as an image"), std::string::npos)
      << s.message();
  EXPECT_TRUE(grey.empty());  // not the previous file's pixels

  // A PNG signature with a broken header, read into a buffer of a good frame.
  const std::string good_bytes = ::groundline::testing::ReadText(dir / "good.png");
  const std::filesystem::path truncated = dir / "truncated.png";
  std::ofstream(truncated, std::ios::binary) << good_bytes.substr(0, 20);
  ASSERT_TRUE(reader.Read(dir / "good.png", &grey).ok());
  s = reader.Read(truncated, &grey);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("truncated.png: cannot be decoded"), std::string::npos) << s.message();
  EXPECT_TRUE(grey.empty());
}

// An all-black image is a valid frame, also read into a buffer of its size.
TEST(GreyImageFileReader, ReadsABlackFrameAsBlack) {
  const std::filesystem::path dir = ::groundline::testing::ScratchDir("image_file_black");
  ASSERT_TRUE(cv::imwrite((dir / "frame.png").string(), ColourImage(48, 64, 5)));
  ASSERT_TRUE(cv::imwrite((dir / "black.png").string(), cv::Mat(48, 64, CV_8UC1, cv::Scalar(0))));
  GreyImageFileReader reader;
  cv::Mat grey;
  ASSERT_TRUE(reader.Read(dir / "frame.png", &grey).ok());
  const core::Status s = reader.Read(dir / "black.png", &grey);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(grey.size(), cv::Size(64, 48));
  EXPECT_EQ(cv::countNonZero(grey), 0);
}

}  // namespace
}  // namespace groundline::io
