#include "api/api_guard.h"

namespace bakegi {

namespace {

// The message of the last failed call on this thread. If even storing it fails (no
// memory), last_error_text points at a fixed text instead.
thread_local std::string last_error_message;
thread_local const char* last_error_text = "";

}  // namespace

bakegi_status fail(bakegi_status status, const std::string& message) noexcept {
  try {
    last_error_message = message;
    last_error_text = last_error_message.c_str();
  } catch (...) {
    last_error_text = "out of memory while reporting an error";
  }
  return status;
}

}  // namespace bakegi

extern "C" const char* bakegi_last_error(void) {
  return bakegi::last_error_text;
}
