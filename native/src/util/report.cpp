#include "util/report.h"

#include <cmath>
#include <cstdio>

namespace bakegi {

void Report::add_seconds(const std::string& stage, double seconds) {
  std::lock_guard lock(mutex_);
  seconds_[stage] += seconds;
}

void Report::set_number(const std::string& key, double value) {
  std::lock_guard lock(mutex_);
  numbers_[key] = value;
}

void Report::add_count(const std::string& key, uint64_t value) {
  std::lock_guard lock(mutex_);
  counts_[key] += value;
}

void Report::set_text(const std::string& key, const std::string& value) {
  std::lock_guard lock(mutex_);
  texts_[key] = value;
}

void Report::set_json(const std::string& key, const std::string& json_value) {
  std::lock_guard lock(mutex_);
  json_values_[key] = json_value;
}

void Report::warn(const std::string& message) {
  std::lock_guard lock(mutex_);
  warnings_.push_back(message);
}

std::vector<std::string> Report::warnings() const {
  std::lock_guard lock(mutex_);
  return warnings_;
}

uint64_t Report::count(const std::string& key) const {
  std::lock_guard lock(mutex_);
  auto it = counts_.find(key);
  return it == counts_.end() ? 0 : it->second;
}

std::string Report::to_json() const {
  std::lock_guard lock(mutex_);
  // One member per key: later kinds win if a key was used twice, so the output stays a
  // valid object with unique names.
  std::map<std::string, std::string> members;
  for (const auto& [key, value] : numbers_) members[key] = json_number(value);
  for (const auto& [key, value] : counts_) members[key] = std::to_string(value);
  for (const auto& [key, value] : texts_) members[key] = json_quote(value);
  for (const auto& [key, value] : json_values_) members[key] = value;
  std::string seconds = "{";
  for (const auto& [stage, value] : seconds_) {
    if (seconds.size() > 1) seconds += ", ";
    seconds += json_quote(stage) + ": " + json_number(value);
  }
  members["seconds"] = seconds + "}";
  std::string warnings = "[";
  for (const std::string& warning : warnings_) {
    if (warnings.size() > 1) warnings += ", ";
    warnings += json_quote(warning);
  }
  members["warnings"] = warnings + "]";

  std::string json = "{";
  for (const auto& [key, value] : members) {
    if (json.size() > 1) json += ", ";
    json += json_quote(key) + ": " + value;
  }
  return json + "}";
}

namespace {

// Length of the valid UTF-8 sequence starting at text[i], or 0 if it is not valid.
size_t utf8_sequence_length(const std::string& text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  size_t length = 0;
  uint32_t min = 0;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2, min = 0x80;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3, min = 0x800;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4, min = 0x10000;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  uint32_t code = lead & (0x7F >> length);
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  // Overlong forms, surrogates and code points beyond Unicode are not valid.
  if (code < min || (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF) return 0;
  return length;
}

}  // namespace

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (static_cast<unsigned char>(c) >= 0x80) {
      // Paths and messages may hold bytes that are not UTF-8; JSON must not.
      const size_t length = utf8_sequence_length(text, i);
      if (length == 0) {
        out += "\\ufffd";
        ++i;
      } else {
        out.append(text, i, length);
        i += length;
      }
      continue;
    }
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
          out += buffer;
        } else {
          out += c;
        }
    }
    ++i;
  }
  return out + "\"";
}

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[32];
  // 17 significant digits round-trip a double exactly.
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

}  // namespace bakegi
