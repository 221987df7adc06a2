// Writing JSON text, shared by the core (its report, the settings schemas) and the command-line
// program, which sees only bakegi.h and native/common/.
#pragma once

#include <string>

namespace bakegi {

// A JSON string literal for any UTF-8 text: quotes, backslashes and control characters
// escaped; bytes that are not UTF-8 become U+FFFD.
std::string json_quote(const std::string& text);
// A JSON number (17 significant digits: a double round-trips); NaN and infinities (not
// representable in JSON) become null.
std::string json_number(double value);

}  // namespace bakegi
