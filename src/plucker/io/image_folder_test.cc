#include "plucker/io/image_folder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/imgcodecs.hpp>

#include "plucker/io/io_test_utils.h"

namespace plucker {
namespace io {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

void WriteImage(const fs::path& path, int width, int height, int channels = 1) {
  cv::Mat image(height, width, channels == 1 ? CV_8UC1 : CV_8UC3, cv::Scalar::all(0));
  image(cv::Rect(1, 1, width / 2, height / 2)).setTo(cv::Scalar::all(200));
  ASSERT_TRUE(cv::imwrite(path.string(), image)) << path;
}

std::string ProblemOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ImageFolder, ImagesInNameOrderOthersIgnored) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  WriteImage(dir / "b.png", 8, 6);
  WriteImage(dir / "a.JPG", 8, 6, 3);
  WriteImage(dir / "c.pgm", 8, 6);
  std::ofstream(dir / "K.txt") << "1 0 0\n";
  std::ofstream(dir / "data.csv") << "#t,f\n";
  WriteImage(dir / ".hidden.png", 8, 6);
  fs::create_directories(dir / "sub.png");  // a folder with an image-like name
  const ImageFolder folder = OpenImageFolder(dir.string());
  ASSERT_EQ(folder.files.size(), 3u);
  EXPECT_EQ(fs::path(folder.files[0]).filename(), "a.JPG");
  EXPECT_EQ(fs::path(folder.files[1]).filename(), "b.png");
  EXPECT_EQ(fs::path(folder.files[2]).filename(), "c.pgm");
  EXPECT_EQ(folder.size, (ImageSize{8, 6}));
  const cv::Mat colour_as_gray = ReadGrayImage(folder.files[0]);
  EXPECT_EQ(colour_as_gray.type(), CV_8UC1);
  EXPECT_TRUE(IsImageFile("x/Y.TIFF"));
  EXPECT_FALSE(IsImageFile("x/y.txt"));
  EXPECT_FALSE(IsImageFile("png"));
}

TEST(ImageFolder, BadInput) {
  const ScratchDir scratch;
  const fs::path& dir = scratch.path();
  EXPECT_NE(ProblemOf([&] { ListImageFiles(dir.string()); }).find("no image files"),
            std::string::npos);
  EXPECT_NE(ProblemOf([&] { ListImageFiles((dir / "nope").string()); }).find("not a folder"),
            std::string::npos);
  WriteImage(dir / "0.png", 8, 6);
  WriteImage(dir / "1.png", 9, 6);
  const std::string mixed = ProblemOf([&] { OpenImageFolder(dir.string()); });
  EXPECT_NE(mixed.find("1.png: image size 9x6 differs from 8x6"), std::string::npos) << mixed;
  fs::remove(dir / "1.png");
  std::ofstream(dir / "2.png") << "not a png at all";
  const std::string broken = ProblemOf([&] { OpenImageFolder(dir.string()); });
  EXPECT_NE(broken.find("2.png: not a readable image"), std::string::npos) << broken;
  std::ofstream(dir / "2.png", std::ios::trunc);  // empty file
  EXPECT_NE(ProblemOf([&] { ReadGrayImage((dir / "2.png").string()); }).find("not a readable"),
            std::string::npos);
  EXPECT_NE(ProblemOf([&] { ReadGrayImage((dir / "9.png").string()); }).find("no such image"),
            std::string::npos);
  EXPECT_NE(ProblemOf([&] { ReadGrayImage((dir / "0.png").string(), 3); }).find("reduction 3"),
            std::string::npos);
  EXPECT_NE(ProblemOf([&] { CheckSameImageSize({}); }).find("empty list"), std::string::npos);
}

TEST(ImageFolder, BlankImagesAreNamed) {
  cv::Mat textured(48, 64, CV_8UC1);
  cv::randu(textured, 0, 256);
  EXPECT_EQ(BlankImageProblem(textured), "");
  EXPECT_NE(BlankImageProblem(cv::Mat(48, 64, CV_8UC1, cv::Scalar(0))).find("black image"),
            std::string::npos);
  cv::Mat noisy_black(48, 64, CV_8UC1);
  cv::randu(noisy_black, 0, 6);  // sensor noise on a covered lens
  EXPECT_NE(BlankImageProblem(noisy_black).find("black image"), std::string::npos);
  EXPECT_NE(BlankImageProblem(cv::Mat(48, 64, CV_8UC1, cv::Scalar(255))).find("saturated image"),
            std::string::npos);
  EXPECT_NE(BlankImageProblem(cv::Mat(48, 64, CV_8UC1, cv::Scalar(128))).find("uniform image"),
            std::string::npos);
  // A dark but textured image is not blank.
  cv::Mat dark(48, 64, CV_8UC1);
  cv::randu(dark, 0, 40);
  EXPECT_EQ(BlankImageProblem(dark), "");
  // Half saturated: still something to track.
  cv::Mat half = textured.clone();
  half.rowRange(0, 24).setTo(255);
  EXPECT_EQ(BlankImageProblem(half), "");
}

TEST(ImageFolder, RealKittiClip) {
  const fs::path dir = fs::path(PLUCKER_SHARED_DATA_DIR) / "kitti-mono-clip/image_0";
  if (!fs::exists(dir)) GTEST_SKIP() << "shared data absent: " << dir;
  const ImageFolder folder = OpenImageFolder(dir.string());
  EXPECT_EQ(folder.files.size(), 51u);
  EXPECT_EQ(fs::path(folder.files.front()).filename(), "000000.png");
  EXPECT_EQ(fs::path(folder.files.back()).filename(), "000050.png");
  EXPECT_EQ(folder.size, (ImageSize{1226, 370}));
}

}  // namespace
}  // namespace io
}  // namespace plucker
