// The C API's calls that return text (a report, a settings schema, a grid's info) share one
// contract: the caller passes a buffer of `capacity` bytes (NUL included), or capacity 0 and
// out_length to learn the size first; the text is cut to fit and its full length returned.
#pragma once

#include <algorithm>
#include <cstring>
#include <string>

#include "api/api_guard.h"

namespace bakegi {

// Refuses a buffer missing for a non-zero capacity, or a call that asks for nothing.
inline void check_text_output(const char* buffer, size_t capacity, const size_t* out_length) {
  if (capacity > 0) require(buffer, "buffer");
  if (capacity == 0 && !out_length) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "capacity is 0 and out_length is NULL");
  }
}

inline void write_text_output(const std::string& text, char* buffer, size_t capacity,
                              size_t* out_length) {
  if (out_length) *out_length = text.size();
  if (capacity > 0) {
    const size_t n = std::min(text.size(), capacity - 1);
    std::memcpy(buffer, text.data(), n);
    buffer[n] = '\0';
  }
}

}  // namespace bakegi
