// The checks a bake's settings get before any work, in one place for the job
// (BakeJob::start) and for callers that want the answer before they export a scene
// (bakegi_settings_check: the add-on asks before exporting, rasterizing or uploading).
#pragma once

#include <string>

namespace bakegi {

class Settings;

// Adds the default method's settings when `settings` name no method, checks that "method"
// is text naming a registered method and that every key, type and value fits that method's
// schema. Returns the method. Throws Error(INVALID_ARGUMENT) naming the first bad setting.
std::string validated_method(Settings& settings);

// validated_method, then the solver reads every setting it uses (Solver::check_settings:
// what a schema cannot say, e.g. a "viewpoint" that is not "x,y,z").
std::string check_bake_settings(Settings& settings);

}  // namespace bakegi
