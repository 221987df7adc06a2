// Exit codes of the `bakegi` command, documented in `bakegi --help`.
#pragma once

namespace bakegi::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBakeFailed = 1;   // the core refused the scene or settings, or failed
inline constexpr int kExitUsage = 2;        // bad command line
inline constexpr int kExitIo = 3;           // a file could not be read or written
inline constexpr int kExitCancelled = 130;  // Ctrl-C (128 + SIGINT, as shells report it)

}  // namespace bakegi::cli
