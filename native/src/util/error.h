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

// A solver's model of this scene is unusable (antiradiance's iteration diverging from its first
// bounce on): with the setting "fallback" on (the default) the bake job hands the bake to the
// path tracer, as it does when a method does not fit the memory budget. A solver throws it
// only when "fallback" is on; otherwise it returns what it has, with a warning.
class CannotModel : public Error {
 public:
  explicit CannotModel(const std::string& message)
      : Error(BAKEGI_ERROR_INVALID_SCENE, message) {}
};

}  // namespace bakegi
