// The EXR writer and reader: sizes and values survive a round trip (full floats exactly,
// half floats within half precision), rows are stored top-down as EXR expects (row 0 of
// the image, v = 0, is the file's last scanline), every compression reads back, no
// temporary file is left behind, and failures name the path.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>

#include "util/error.h"
#include "lightmap/exr_writer.h"

namespace bakegi::test {
namespace {

namespace fs = std::filesystem;

class LightmapExr : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::path(::testing::TempDir()) /
                 ("bakegi_lightmap_exr_" +
                  std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }
  std::string path(const std::string& name) const { return (directory_ / name).string(); }
  fs::path directory_;
};

// A 5 x 3 image whose every channel differs, with values that are not exact in half.
RgbImage test_image() {
  RgbImage image;
  image.width = 5;
  image.height = 3;
  for (uint32_t y = 0; y < image.height; ++y) {
    for (uint32_t x = 0; x < image.width; ++x) {
      image.pixels.push_back(
          {0.1f + 0.37f * x + 3.1f * y, 1e-3f * (x + 1) * (y + 2), 100.0f / float(1 + x + 7 * y)});
    }
  }
  return image;
}

TEST_F(LightmapExr, FullFloatRoundTripIsExact) {
  const RgbImage image = test_image();
  for (ExrCompression compression :
       {ExrCompression::kZip, ExrCompression::kPiz, ExrCompression::kNone}) {
    write_exr(path("full.exr"), image, {ExrPixelType::kFloat, compression});
    const RgbImage back = read_exr(path("full.exr"));
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    ASSERT_EQ(back.pixels.size(), image.pixels.size());
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      EXPECT_EQ(back.pixels[i], image.pixels[i]) << "pixel " << i;  // lossless codecs
    }
  }
}

TEST_F(LightmapExr, HalfRoundTripIsWithinHalfPrecision) {
  const RgbImage image = test_image();
  write_exr(path("half.exr"), image);  // defaults: half, ZIP
  const RgbImage back = read_exr(path("half.exr"));
  ASSERT_EQ(back.width, image.width);
  ASSERT_EQ(back.height, image.height);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      // Half has an 11-bit significand: rounding error <= 2^-11 relative (all values here
      // are normal halves, >= 2^-14).
      EXPECT_NEAR(back.pixels[i][c], image.pixels[i][c], std::abs(image.pixels[i][c]) * 0x1p-11f)
          << "pixel " << i << " channel " << c;
    }
  }
}

TEST_F(LightmapExr, HalfSaturatesInsteadOfInfinity) {
  RgbImage image;
  image.width = 2;
  image.height = 1;
  image.pixels = {glm::vec3(1e6f, -1e6f, 65504.0f), glm::vec3(0.5f)};
  write_exr(path("big.exr"), image);
  const RgbImage back = read_exr(path("big.exr"));
  EXPECT_EQ(back.pixels[0], glm::vec3(65504.0f, -65504.0f, 65504.0f));  // half's largest
  EXPECT_EQ(back.pixels[1], glm::vec3(0.5f));
}

TEST_F(LightmapExr, RowZeroIsTheBottomScanline) {
  const RgbImage image = test_image();
  write_exr(path("rows.exr"), image, {ExrPixelType::kFloat, ExrCompression::kZip});
  // Read the file's first scanline (the top of the picture) with OpenEXR directly.
  Imf::InputFile file(path("rows.exr").c_str());
  const Imath::Box2i window = file.header().dataWindow();
  ASSERT_EQ(window.min.y, 0);
  std::vector<float> red(image.width);
  Imf::FrameBuffer frame;
  frame.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(red.data()), sizeof(float), 0));
  file.setFrameBuffer(frame);
  file.readPixels(0, 0);
  for (uint32_t x = 0; x < image.width; ++x) {
    EXPECT_EQ(red[x], image.pixels[(image.height - 1) * image.width + x].x) << "x " << x;
  }
}

TEST_F(LightmapExr, LeavesNoTemporaryFileAndReplacesTheOld) {
  RgbImage image = test_image();
  write_exr(path("a.exr"), image);
  image.pixels[0] = glm::vec3(42.0f);
  write_exr(path("a.exr"), image);
  EXPECT_EQ(read_exr(path("a.exr")).pixels[0], glm::vec3(42.0f));
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(directory_)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "a.exr");
  }
  EXPECT_EQ(files, 1u);
}

TEST_F(LightmapExr, ErrorsNameThePath) {
  const RgbImage image = test_image();
  const std::string missing_directory = path("no/such/dir/x.exr");
  try {
    write_exr(missing_directory, image);
    FAIL() << "wrote into a missing directory";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_IO);
    EXPECT_NE(std::string(e.what()).find(missing_directory), std::string::npos) << e.what();
  }
  try {
    read_exr(path("missing.exr"));
    FAIL() << "read a missing file";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_IO);
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
  }
  std::ofstream(path("garbage.exr")) << "not an EXR file at all";
  try {
    read_exr(path("garbage.exr"));
    FAIL() << "read a garbage file";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    EXPECT_NE(std::string(e.what()).find("garbage.exr"), std::string::npos) << e.what();
  }
  RgbImage wrong = image;
  wrong.pixels.pop_back();
  EXPECT_THROW(write_exr(path("wrong.exr"), wrong), Error);
  EXPECT_FALSE(fs::exists(path("wrong.exr")));
}

}  // namespace
}  // namespace bakegi::test
