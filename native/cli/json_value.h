// A minimal JSON reader, enough to pull numbers out of the core's bake report
// (bakegi_job_get_report), plus the two helpers the CLI needs to write JSON.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "json_text.h"

namespace bakegi::cli {

class JsonError : public std::runtime_error {
 public:
  explicit JsonError(const std::string& message) : std::runtime_error(message) {}
};

struct JsonValue {
  using Array = std::vector<JsonValue>;
  using Object = std::map<std::string, JsonValue>;
  std::variant<std::nullptr_t, bool, double, std::string, Array, Object> value;

  static JsonValue parse(const std::string& text);  // throws JsonError

  const JsonValue* find(const std::string& key) const;  // nullptr if not an object or absent
  // Follows a path of object keys, e.g. {"seconds", "total"}.
  const JsonValue* find_path(const std::vector<std::string>& path) const;
  std::optional<double> number() const;
  std::optional<std::string> string() const;
};

// Writing JSON: the core's own helpers (util/report.h), so that escaping lives in one place.
using bakegi::json_number;
using bakegi::json_quote;

}  // namespace bakegi::cli
