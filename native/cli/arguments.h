// A tiny command-line parser: positional arguments plus `--name value` and `--flag`
// options, each declared up front so that a typo is an error, not a silent default.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace bakegi::cli {

struct OptionSpec {
  std::string name;  // without the leading "--"
  bool takes_value = true;
  bool repeatable = false;  // e.g. --set key=value, given several times
};

class Arguments {
 public:
  // Parses args (the words after the command name). Throws UsageError.
  Arguments(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs);

  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // The (last) value of an option, or nullopt.
  std::optional<std::string> value(const std::string& name) const;
  // Every value of a repeatable option, in order.
  std::vector<std::string> values(const std::string& name) const;

  std::string require(const std::string& name) const;  // throws UsageError if absent
  int64_t int_value(const std::string& name, int64_t fallback, int64_t lo, int64_t hi) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::vector<std::string>> values_;
};

// Parses a whole decimal integer in [lo, hi]; `what` names it in the error.
int64_t parse_int(const std::string& text, const std::string& what, int64_t lo, int64_t hi);
// Parses "1,2,4,8" into integers in [lo, hi].
std::vector<int64_t> parse_int_list(const std::string& text, const std::string& what, int64_t lo,
                                    int64_t hi);
// One finite number ("--cell: 'x' is not a finite number").
float parse_float(const std::string& text, const std::string& what);
// A comma-separated list of exactly `count` finite numbers ("--camera: 'x' is not a number").
std::vector<float> parse_float_list(const std::string& text, const std::string& what,
                                    size_t count);

}  // namespace bakegi::cli
