// Owning handles for the C API's objects, and the exception the CLI raises when a C API
// call fails (its status and the core's message).
#pragma once

#include <stdexcept>
#include <string>

#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"

namespace bakegi::cli {

using bakegi::GridHandle;
using bakegi::JobHandle;
using bakegi::PointsHandle;
using bakegi::PreviewHandle;
using bakegi::SceneHandle;
using bakegi::SettingsHandle;

class CoreError : public std::runtime_error {
 public:
  CoreError(bakegi_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  bakegi_status status() const { return status_; }

 private:
  bakegi_status status_;
};

// Throws CoreError with the thread's last error if status is not BAKEGI_OK; `what` says
// which step failed (e.g. "reading scene.bgs").
inline void check(bakegi_status status, const std::string& what) {
  if (status != BAKEGI_OK) {
    throw CoreError(status,
                    what + ": " + bakegi_last_error() + " (" + bakegi_status_string(status) + ")");
  }
}

}  // namespace bakegi::cli
