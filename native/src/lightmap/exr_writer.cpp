#include "lightmap/exr_writer.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <system_error>

#if __has_include(<Imath/half.h>)
#include <Imath/half.h>  // OpenEXR 3
#else
#include <half.h>  // OpenEXR 2 (the portable build's Debian 11)
#endif
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include "atomic_file.h"
#include "util/error.h"

namespace bakegi {

namespace {

namespace fs = std::filesystem;

Imf::Compression to_imf(ExrCompression compression) {
  switch (compression) {
    case ExrCompression::kNone:
      return Imf::NO_COMPRESSION;
    case ExrCompression::kZip:
      return Imf::ZIP_COMPRESSION;
    case ExrCompression::kPiz:
      return Imf::PIZ_COMPRESSION;
  }
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "unknown EXR compression");
}

// Top-down copy of a bottom-up image: the scanline order EXR stores.
std::vector<float> top_down_rgb(const RgbImage& image) {
  std::vector<float> rgb(size_t(image.width) * image.height * 3);
  for (uint32_t y = 0; y < image.height; ++y) {
    const glm::vec3* source = image.pixels.data() + size_t(image.height - 1 - y) * image.width;
    float* target = rgb.data() + size_t(y) * image.width * 3;
    for (uint32_t x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) target[3 * x + c] = source[x][c];
    }
  }
  return rgb;
}

// OpenEXR takes UTF-8 file names on every platform (it widens them itself on Windows).
std::string utf8_name(const fs::path& path) {
  const std::u8string name = path.u8string();
  return std::string(name.begin(), name.end());
}

}  // namespace

void write_exr(const std::string& path, const RgbImage& image, const ExrWriteOptions& options) {
  if (image.width == 0 || image.height == 0 ||
      image.width > uint32_t(std::numeric_limits<int>::max()) ||
      image.height > uint32_t(std::numeric_limits<int>::max())) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                path + ": image size " + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + " cannot be written");
  }
  if (image.pixels.size() != size_t(image.width) * image.height) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, path + ": image holds " +
                                                   std::to_string(image.pixels.size()) +
                                                   " pixels, not width x height");
  }
  const std::vector<float> rgb = top_down_rgb(image);
  const fs::path target = fs::u8path(path);
  remove_stale_temporaries(target);  // of writers killed mid-write
  const fs::path temporary = temporary_path_beside(target);
  try {
    const int width = int(image.width), height = int(image.height);
    Imf::Header header(width, height, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y,
                       to_imf(options.compression));
    const Imf::PixelType type = options.pixel_type == ExrPixelType::kHalf ? Imf::HALF : Imf::FLOAT;
    // OpenEXR converts pixel types only when reading: the frame buffer must hold the
    // file's type.
    std::vector<half> halves;
    const char* data = reinterpret_cast<const char*>(rgb.data());
    size_t component = sizeof(float);
    if (type == Imf::HALF) {
      // Rounded to nearest; light beyond half's range is kept as +-65504, not infinity.
      halves.assign(rgb.begin(), rgb.end());
      for (half& h : halves) {
        if (h.isInfinity()) h = h.isNegative() ? -HALF_MAX : HALF_MAX;
      }
      data = reinterpret_cast<const char*>(halves.data());
      component = sizeof(half);
    }
    Imf::FrameBuffer frame;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
      header.channels().insert(names[c], Imf::Channel(type));
      frame.insert(names[c], Imf::Slice(type, const_cast<char*>(data + c * component),
                                        3 * component, size_t(width) * 3 * component));
    }
    {
      Imf::OutputFile file(utf8_name(temporary).c_str(), header);
      file.setFrameBuffer(frame);
      // Blocks of scanlines (multiples of ZIP's 16-line blocks), with a cancel check between.
      constexpr int kRowsPerBlock = 128;
      for (int written = 0; written < height; written += kRowsPerBlock) {
        throw_if_cancelled(options.cancel, "writing the lightmap");
        file.writePixels(std::min(kRowsPerBlock, height - written));
      }
    }  // closed (and flushed) before the rename
    fs::rename(temporary, target);
  } catch (const Error&) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw Error(BAKEGI_ERROR_IO, path + ": cannot write EXR file: " + e.what());
  }
}

RgbImage read_exr(const std::string& path) {
  const fs::path source = fs::u8path(path);
  std::error_code error;
  if (!fs::is_regular_file(source, error)) {
    throw Error(BAKEGI_ERROR_IO, path + ": no such file");
  }
  try {
    Imf::InputFile file(utf8_name(source).c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1;
    const int64_t height = int64_t(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > (int64_t(1) << 31)) {
      throw Error(BAKEGI_ERROR_BAD_FILE, path + ": EXR data window has an unusable size");
    }
    std::vector<float> rgb(size_t(width * height * 3), 0.0f);
    Imf::FrameBuffer frame;
    const char* names[3] = {"R", "G", "B"};
    // Slices are addressed by absolute pixel coordinates: shift the base by the window.
    char* base =
        reinterpret_cast<char*>(rgb.data()) -
        (int64_t(window.min.x) + int64_t(window.min.y) * width) * 3 * int64_t(sizeof(float));
    for (int c = 0; c < 3; ++c) {
      frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float),
                                        size_t(width) * 3 * sizeof(float), 1, 1, 0.0));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    RgbImage image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.pixels.resize(size_t(width * height));
    for (int64_t y = 0; y < height; ++y) {
      const float* row = rgb.data() + size_t((height - 1 - y) * width * 3);
      for (int64_t x = 0; x < width; ++x) {
        image.pixels[size_t(y * width + x)] = {row[3 * x], row[3 * x + 1], row[3 * x + 2]};
      }
    }
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(BAKEGI_ERROR_BAD_FILE, path + ": cannot read EXR file: " + e.what());
  }
}

}  // namespace bakegi
