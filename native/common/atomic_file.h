// Files that are replaced whole or not at all, shared by the core (caches, scene files,
// layouts, grids, EXRs) and the command-line program (.npy values, reports, sweeps): the
// bytes go to a temporary file beside the target, which is then renamed over it. A reader,
// another process or a kill mid-write sees the old file or the new one, never a torn one.
// A writer that was killed leaves its temporary behind; the next write to the same target
// removes such leftovers once they are older than any live write could be.
#pragma once

#include <chrono>
#include <filesystem>
#include <span>
#include <string>

namespace bakegi {

// "<target>.<16 hex digits>.tmp": unique across threads and processes.
std::filesystem::path temporary_path_beside(const std::filesystem::path& target);

// Leftover temporaries of `target` (its name, a dot, 16 hex digits, ".tmp", or the older
// EXR writer's ".tmp<pid>-<n>") last written more than `age` ago are removed; errors are
// ignored (a leftover is clutter, not damage). Returns how many were removed.
inline constexpr std::chrono::minutes kStaleTemporaryAge{10};
size_t remove_stale_temporaries(const std::filesystem::path& target,
                                std::chrono::seconds age = kStaleTemporaryAge);

// Writes `bytes` atomically as above. Returns an empty string, or why it failed (the
// temporary is then removed and the target untouched).
std::string write_file_atomically_or_reason(const std::filesystem::path& target,
                                            std::span<const unsigned char> bytes);

}  // namespace bakegi
