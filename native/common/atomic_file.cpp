#include "atomic_file.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <thread>

namespace bakegi {

namespace fs = std::filesystem;

namespace {

uint64_t mix(uint64_t x) {  // splitmix64's finalizer
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

bool all_hex(const std::string& text) {
  if (text.empty()) return false;
  for (char c : text) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// Whether `name` is a temporary of `target_name`: "<target>.<16 hex>.tmp", or the EXR
// writer's former "<target>.tmp<digits>-<digits>".
bool is_temporary_of(const std::string& name, const std::string& target_name) {
  if (name.size() <= target_name.size() || name.compare(0, target_name.size(), target_name)) {
    return false;
  }
  const std::string rest = name.substr(target_name.size());
  if (rest.size() == 1 + 16 + 4 && rest[0] == '.' && rest.compare(17, 4, ".tmp") == 0) {
    return all_hex(rest.substr(1, 16));
  }
  if (rest.rfind(".tmp", 0) == 0) {
    const size_t dash = rest.find('-');
    if (dash == std::string::npos) return false;
    const std::string pid = rest.substr(4, dash - 4), count = rest.substr(dash + 1);
    auto digits = [](const std::string& t) {
      if (t.empty()) return false;
      for (char c : t) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
      }
      return true;
    };
    return digits(pid) && digits(count);
  }
  return false;
}

}  // namespace

fs::path temporary_path_beside(const fs::path& target) {
  static std::atomic<uint64_t> counter{0};
  const uint64_t unique =
      mix(counter.fetch_add(1) ^ mix(std::hash<std::thread::id>{}(std::this_thread::get_id())) ^
          mix(uint64_t(std::chrono::steady_clock::now().time_since_epoch().count())) ^
          mix(uint64_t(std::chrono::system_clock::now().time_since_epoch().count())));
  char suffix[24];
  std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(unique));
  fs::path temporary = target;
  temporary += suffix;
  return temporary;
}

size_t remove_stale_temporaries(const fs::path& target, std::chrono::seconds age) {
  std::error_code error;
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::u8string target_name = target.filename().u8string();
  const std::string name(target_name.begin(), target_name.end());
  fs::directory_iterator it(folder, error);
  if (error) return 0;
  size_t removed = 0;
  const auto now = fs::file_time_type::clock::now();
  for (; it != fs::directory_iterator(); it.increment(error)) {
    if (error) break;
    const std::u8string entry_name = it->path().filename().u8string();
    if (!is_temporary_of(std::string(entry_name.begin(), entry_name.end()), name)) continue;
    std::error_code entry_error;
    if (!it->is_regular_file(entry_error) || entry_error) continue;
    const auto written = fs::last_write_time(it->path(), entry_error);
    if (entry_error || now - written < age) continue;
    if (fs::remove(it->path(), entry_error)) ++removed;
  }
  return removed;
}

std::string write_file_atomically_or_reason(const fs::path& target,
                                            std::span<const unsigned char> bytes) {
  remove_stale_temporaries(target);
  const fs::path temporary = temporary_path_beside(target);
  const std::u8string temporary_name = temporary.u8string();
  const std::string temporary_text(temporary_name.begin(), temporary_name.end());
  std::error_code ignored;
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return "cannot write " + temporary_text + ": " + std::strerror(errno);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) {
      const std::string reason = "writing " + temporary_text + " failed: " + std::strerror(errno);
      fs::remove(temporary, ignored);
      return reason;
    }
  }
  std::error_code error;
  fs::rename(temporary, target, error);
  if (error) {
    fs::remove(temporary, ignored);
    const std::u8string target_name = target.u8string();
    return "cannot rename " + temporary_text + " to " +
           std::string(target_name.begin(), target_name.end()) + ": " + error.message();
  }
  return "";
}

}  // namespace bakegi
