// A file the CLI reads or writes itself (.npy arrays, JSON outputs) could not be used.
// main() prints the message and exits with kExitIo.
#pragma once

#include <stdexcept>
#include <string>

namespace bakegi::cli {

class FileError : public std::runtime_error {
 public:
  explicit FileError(const std::string& message) : std::runtime_error(message) {}
};

// Throws FileError if the folder `path` would be written into does not exist, so that a
// long bake does not end in an output it cannot write.
void check_output_folder(const std::string& path);

}  // namespace bakegi::cli
