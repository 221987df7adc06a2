#include "file_error.h"

#include <filesystem>

#include "atomic_file.h"

namespace bakegi::cli {

void check_output_folder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!folder.empty() && !std::filesystem::is_directory(folder, error)) {
    throw FileError(path + ": folder " + folder.string() + " does not exist");
  }
}

void write_output_file(const std::string& path, std::span<const unsigned char> bytes) {
  const std::string reason = write_file_atomically_or_reason(std::filesystem::u8path(path), bytes);
  if (!reason.empty()) throw FileError(path + ": " + reason);
}

void write_output_file(const std::string& path, const std::string& text) {
  write_output_file(path, std::span<const unsigned char>(
                              reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

}  // namespace bakegi::cli
