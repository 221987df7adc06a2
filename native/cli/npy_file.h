// Reading and writing NumPy .npy files (format version 1.0/2.0), enough for bake results:
// little-endian float32 or float64 arrays in C order. Results are written as float32 of
// shape (n, 3), which numpy.load reads directly.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "file_error.h"

namespace bakegi::cli {

struct NpyArray {
  std::vector<uint64_t> shape;
  std::vector<float> data;  // row-major; float64 files are converted
};

// Throw FileError naming the path.
void write_npy_float32(const std::string& path, const float* data,
                       const std::vector<uint64_t>& shape);
NpyArray read_npy_float32(const std::string& path);

}  // namespace bakegi::cli
