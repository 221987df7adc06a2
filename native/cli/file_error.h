// A file the CLI reads or writes itself (.npy arrays, JSON outputs) could not be used.
// main() prints the message and exits with kExitIo. And how the CLI writes its outputs.
#pragma once

#include <span>
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

// Writes `bytes` (or `text`) to `path` atomically (native/common/atomic_file.h): a kill or a
// full disk mid-write leaves the previous file whole. Throws FileError with the reason.
void write_output_file(const std::string& path, std::span<const unsigned char> bytes);
void write_output_file(const std::string& path, const std::string& text);

}  // namespace bakegi::cli
