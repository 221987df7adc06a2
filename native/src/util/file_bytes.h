// Whole-file reads with a size limit, and writes that never leave a half-written file under
// the final name (a temporary file in the same folder, then a rename): what a cache needs
// when a bake may be cancelled, crash or run beside another bake writing the same file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace bakegi {

// A path from UTF-8 text (what Blender and the C API pass), also on Windows where a plain
// std::string would be read in the ANSI code page.
std::filesystem::path utf8_path(const std::string& text);
// The path as UTF-8 text, for messages and reports.
std::string utf8_text(const std::filesystem::path& path);

// Throws Error(IO) when the file cannot be read, Error(BAD_FILE) when it is larger than
// `max_bytes` (checked before anything is allocated).
std::vector<uint8_t> read_file_bytes(const std::filesystem::path& path, uint64_t max_bytes);

// Writes `bytes` to a temporary file next to `path` and renames it to `path`, replacing any
// file there; on failure removes the temporary file and throws Error(IO) with the reason.
void write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes);

}  // namespace bakegi
