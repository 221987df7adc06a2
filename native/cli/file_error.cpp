#include "file_error.h"

#include <filesystem>

namespace bakegi::cli {

void check_output_folder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!folder.empty() && !std::filesystem::is_directory(folder, error)) {
    throw FileError(path + ": folder " + folder.string() + " does not exist");
  }
}

}  // namespace bakegi::cli
