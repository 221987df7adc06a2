// One bake setting's value as the C API receives it.
#pragma once

#include <cstdint>
#include <string>
#include <variant>

namespace bakegi {

using SettingValue = std::variant<int64_t, double, std::string>;

// JSON text of a setting value ("pathtrace" quoted and escaped, numbers as numbers).
std::string setting_to_json(const SettingValue& value);

}  // namespace bakegi
