// Errors inside the core are exceptions of this one type; the C API (api/) turns them
// into a bakegi_status and a message, so nothing ever escapes into Blender.
#pragma once

#include <stdexcept>
#include <string>

#include "bakegi/bakegi.h"

namespace bakegi {

class Error : public std::runtime_error {
 public:
  Error(bakegi_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  bakegi_status status() const { return status_; }

 private:
  bakegi_status status_;
};

}  // namespace bakegi
