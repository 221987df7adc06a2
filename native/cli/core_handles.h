// Owning handles for the C API's objects, and the exception the CLI raises when a C API
// call fails (its status and the core's message).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "bakegi/bakegi.h"

namespace bakegi::cli {

struct SceneDeleter {
  void operator()(bakegi_scene* s) const { bakegi_scene_destroy(s); }
};
struct PointsDeleter {
  void operator()(bakegi_points* p) const { bakegi_points_destroy(p); }
};
struct SettingsDeleter {
  void operator()(bakegi_settings* s) const { bakegi_settings_destroy(s); }
};
struct JobDeleter {
  void operator()(bakegi_job* j) const { bakegi_job_destroy(j); }
};
using SceneHandle = std::unique_ptr<bakegi_scene, SceneDeleter>;
using PointsHandle = std::unique_ptr<bakegi_points, PointsDeleter>;
using SettingsHandle = std::unique_ptr<bakegi_settings, SettingsDeleter>;
using JobHandle = std::unique_ptr<bakegi_job, JobDeleter>;

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
