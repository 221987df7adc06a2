// Owning C++ handles for the C API's objects (header-only, over bakegi.h): for C++ callers
// such as the CLI, the benchmarks and the tests. Destroying a JobHandle cancels and waits.
#pragma once

#include <memory>

#include "bakegi/bakegi.h"

namespace bakegi {

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

struct GridDeleter {
  void operator()(bakegi_grid* g) const { bakegi_grid_destroy(g); }
};

struct PreviewDeleter {
  void operator()(bakegi_preview* p) const { bakegi_preview_destroy(p); }
};

using SceneHandle = std::unique_ptr<bakegi_scene, SceneDeleter>;
using PointsHandle = std::unique_ptr<bakegi_points, PointsDeleter>;
using SettingsHandle = std::unique_ptr<bakegi_settings, SettingsDeleter>;
using JobHandle = std::unique_ptr<bakegi_job, JobDeleter>;
using GridHandle = std::unique_ptr<bakegi_grid, GridDeleter>;
using PreviewHandle = std::unique_ptr<bakegi_preview, PreviewDeleter>;

}  // namespace bakegi
