// The core's methods and their settings as the core describes them (bakegi_settings_describe):
// the CLI keeps no list of its own.
#pragma once

#include <string>
#include <vector>

namespace bakegi::cli {

// The JSON the core gives for one method's schema, or for the method list (method = nullptr).
std::string describe_settings(const char* method);
// The method names, in the core's listing order.
std::vector<std::string> method_names();
// The method a bake uses when none is named (the same as the core's and the add-on's).
std::string default_method();

}  // namespace bakegi::cli
