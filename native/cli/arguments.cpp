#include "arguments.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "usage_error.h"

namespace bakegi::cli {

Arguments::Arguments(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word.size() < 3 || word.rfind("--", 0) != 0) {
      if (word.size() > 1 && word[0] == '-') throw UsageError("unknown option '" + word + "'");
      positional_.push_back(word);
      continue;
    }
    std::string name = word.substr(2);
    std::optional<std::string> inline_value;
    if (const size_t eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    const auto spec = std::find_if(specs.begin(), specs.end(),
                                   [&](const OptionSpec& s) { return s.name == name; });
    if (spec == specs.end()) throw UsageError("unknown option '--" + name + "'");
    if (values_.count(name) && !spec->repeatable) {
      throw UsageError("option '--" + name + "' given twice");
    }
    if (!spec->takes_value) {
      if (inline_value) throw UsageError("option '--" + name + "' takes no value");
      values_[name].push_back("");
      continue;
    }
    if (inline_value) {
      values_[name].push_back(*inline_value);
    } else {
      if (i + 1 >= args.size()) throw UsageError("option '--" + name + "' needs a value");
      values_[name].push_back(args[++i]);
    }
  }
}

std::optional<std::string> Arguments::value(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second.back();
}

std::vector<std::string> Arguments::values(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

std::string Arguments::require(const std::string& name) const {
  const auto v = value(name);
  if (!v) throw UsageError("option '--" + name + "' is required");
  return *v;
}

int64_t Arguments::int_value(const std::string& name, int64_t fallback, int64_t lo,
                             int64_t hi) const {
  const auto v = value(name);
  return v ? parse_int(*v, "--" + name, lo, hi) : fallback;
}

int64_t parse_int(const std::string& text, const std::string& what, int64_t lo, int64_t hi) {
  errno = 0;
  char* end = nullptr;
  const long long parsed = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    throw UsageError(what + ": '" + text + "' is not a whole number");
  }
  if (parsed < lo || parsed > hi) {
    throw UsageError(what + ": " + text + " is outside [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  }
  return parsed;
}

std::vector<int64_t> parse_int_list(const std::string& text, const std::string& what, int64_t lo,
                                    int64_t hi) {
  std::vector<int64_t> list;
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t comma = std::min(text.find(',', begin), text.size());
    list.push_back(parse_int(text.substr(begin, comma - begin), what, lo, hi));
    begin = comma + 1;
  }
  return list;
}

float parse_float(const std::string& text, const std::string& what) {
  size_t used = 0;
  float value = 0.0f;
  try {
    value = std::stof(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(value)) {
    throw UsageError(what + ": '" + text + "' is not a finite number");
  }
  return value;
}

std::vector<float> parse_float_list(const std::string& text, const std::string& what,
                                    size_t count) {
  std::vector<float> values;
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t comma = std::min(text.find(',', begin), text.size());
    values.push_back(parse_float(text.substr(begin, comma - begin), what));
    begin = comma + 1;
  }
  if (values.size() != count) {
    throw UsageError(what + " expects " + std::to_string(count) + " numbers, got " +
                     std::to_string(values.size()));
  }
  return values;
}

}  // namespace bakegi::cli
