// What the C API's opaque handles hold: the core's own types, copied in at the door.
#pragma once

#include <memory>
#include <string>

#include "api/api_guard.h"
#include "bake/bake_job.h"
#include "bake/error_probes.h"
#include "grid/irradiance_vector_grid.h"
#include "scene/bake_points.h"
#include "scene/scene.h"
#include "settings/settings.h"

struct bakegi_scene {
  bakegi::SceneDescription description;
};

struct bakegi_points {
  bakegi::BakePoints points;
  bakegi::ErrorProbes display_probes;  // bakegi_points_set_display_probes; checked there
};

struct bakegi_settings {
  bakegi::Settings settings;
};

struct bakegi_job {
  std::unique_ptr<bakegi::BakeJob> job;
};

struct bakegi_grid {
  std::shared_ptr<const bakegi::IrradianceVectorGrid> grid;
  std::string info_json = "{}";  // stored with the grid in its file
};

// The grid a handle holds; Error(INVALID_ARGUMENT) naming "grid" for a null one.
inline const bakegi::IrradianceVectorGrid& grid_of(const bakegi_grid* grid) {
  bakegi::require(grid, "grid");
  bakegi::require(grid->grid.get(), "grid");
  return *grid->grid;
}
