// Float RGB images as OpenEXR files: the lightmap writer (and the reader that tests and the
// CLI use to check what was written). Images are held bottom-up like Blender's (row 0 at
// v = 0); EXR scanlines run top-down, so rows are flipped on the way in and out.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "util/cancel_flag.h"

namespace bakegi {

enum class ExrPixelType { kHalf, kFloat };
enum class ExrCompression { kNone, kZip, kPiz };

struct ExrWriteOptions {
  ExrPixelType pixel_type = ExrPixelType::kHalf;
  // ZIP: lossless, good on smooth lightmaps, fast to decode (what Blender writes by default).
  ExrCompression compression = ExrCompression::kZip;
  // Checked between blocks of scanlines (a 2048² map encodes in ~0.15 s): raised, the write
  // stops with Error(CANCELLED) and leaves the target as it was.
  const CancelFlag* cancel = nullptr;
};

struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> pixels;  // width * height, row-major, row 0 at the bottom (v = 0)
};

// Writes image to path (UTF-8) atomically: into a temporary file beside it, then renamed
// over path, so a reader (Blender) never sees a half-written file and a failed write leaves
// an existing file untouched. Throws Error(INVALID_ARGUMENT) for a bad image, Error(IO)
// naming the path when the file cannot be written and Error(CANCELLED) when options.cancel
// is raised. Half pixels saturate at +-65504.
void write_exr(const std::string& path, const RgbImage& image, const ExrWriteOptions& options = {});

// Reads the R, G, B channels (missing ones read 0) of an EXR file as float, bottom-up.
// Throws Error(IO) when the file cannot be opened and Error(BAD_FILE) when it is not a
// readable EXR image, naming the path.
RgbImage read_exr(const std::string& path);

}  // namespace bakegi
