#include "npy_file.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <numeric>

namespace bakegi::cli {
namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;

uint64_t element_count(const std::vector<uint64_t>& shape) {
  return std::accumulate(shape.begin(), shape.end(), uint64_t{1},
                         [](uint64_t a, uint64_t b) { return a * b; });
}

// The value of `key` in the header's Python dict literal, e.g. "'<f4'" or "(10, 3)".
std::string header_field(const std::string& header, const std::string& key,
                         const std::string& path) {
  const size_t at = header.find("'" + key + "'");
  if (at == std::string::npos) throw FileError(path + ": .npy header has no '" + key + "'");
  size_t begin = header.find(':', at);
  if (begin == std::string::npos) throw FileError(path + ": malformed .npy header");
  ++begin;
  while (begin < header.size() && header[begin] == ' ') ++begin;
  size_t end = begin;
  if (header[begin] == '(') {
    end = header.find(')', begin);
    if (end == std::string::npos) throw FileError(path + ": malformed .npy shape");
    ++end;
  } else {
    while (end < header.size() && header[end] != ',' && header[end] != '}') ++end;
  }
  return header.substr(begin, end - begin);
}

std::vector<uint64_t> parse_shape(const std::string& text, const std::string& path) {
  std::vector<uint64_t> shape;
  std::string number;
  for (const char c : text.substr(1)) {
    if (c >= '0' && c <= '9') {
      number += c;
    } else if (c == ',' || c == ')') {
      if (!number.empty()) shape.push_back(std::stoull(number));
      number.clear();
    } else if (c != ' ') {
      throw FileError(path + ": malformed .npy shape " + text);
    }
  }
  return shape;
}

}  // namespace

void write_npy_float32(const std::string& path, const float* data,
                       const std::vector<uint64_t>& shape) {
  static_assert(std::endian::native == std::endian::little, "writes little-endian data as is");
  std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (";
  for (size_t i = 0; i < shape.size(); ++i) {
    dict += std::to_string(shape[i]);
    if (shape.size() == 1 || i + 1 < shape.size()) dict += ",";
    if (i + 1 < shape.size()) dict += " ";
  }
  dict += "), }";
  // Version 1.0: magic, 2 version bytes, 2 length bytes, then the header padded with spaces
  // and ended by '\n' so that the data starts at a multiple of 64 bytes.
  const size_t unpadded = kMagicSize + 4 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  if (dict.size() > 0xFFFF) throw FileError(path + ": shape too long for a .npy header");

  std::string bytes(kMagic, kMagicSize);
  const uint16_t header_length = static_cast<uint16_t>(dict.size());
  bytes += char(1);
  bytes += char(0);
  bytes.append(reinterpret_cast<const char*>(&header_length), 2);
  bytes += dict;
  bytes.append(reinterpret_cast<const char*>(data), element_count(shape) * sizeof(float));
  write_output_file(path, bytes);  // atomically: a kill leaves the previous file whole
}

NpyArray read_npy_float32(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw FileError(path + ": cannot open: " + std::strerror(errno));
  char magic[kMagicSize];
  uint8_t version[2];
  if (!file.read(magic, kMagicSize) || std::memcmp(magic, kMagic, kMagicSize) != 0 ||
      !file.read(reinterpret_cast<char*>(version), 2)) {
    throw FileError(path + ": not a .npy file");
  }
  uint32_t header_length = 0;
  if (version[0] == 1) {
    uint16_t length16 = 0;
    file.read(reinterpret_cast<char*>(&length16), 2);
    header_length = length16;
  } else if (version[0] == 2 || version[0] == 3) {
    file.read(reinterpret_cast<char*>(&header_length), 4);
  } else {
    throw FileError(path + ": unsupported .npy version " + std::to_string(version[0]));
  }
  std::string header(header_length, '\0');
  if (!file || !file.read(header.data(), header_length)) {
    throw FileError(path + ": truncated .npy header");
  }

  const std::string descr = header_field(header, "descr", path);
  if (header_field(header, "fortran_order", path) != "False") {
    throw FileError(path + ": Fortran-ordered arrays are not supported");
  }
  NpyArray array;
  array.shape = parse_shape(header_field(header, "shape", path), path);
  const uint64_t count = element_count(array.shape);
  array.data.resize(count);
  if (descr == "'<f4'") {
    file.read(reinterpret_cast<char*>(array.data.data()),
              static_cast<std::streamsize>(count * sizeof(float)));
  } else if (descr == "'<f8'") {
    std::vector<double> wide(count);
    file.read(reinterpret_cast<char*>(wide.data()),
              static_cast<std::streamsize>(count * sizeof(double)));
    for (uint64_t i = 0; i < count; ++i) array.data[i] = static_cast<float>(wide[i]);
  } else {
    throw FileError(path + ": dtype " + descr + " is not supported (need float32 or float64)");
  }
  if (!file) throw FileError(path + ": file ends before its " + std::to_string(count) + " values");
  return array;
}

}  // namespace bakegi::cli
