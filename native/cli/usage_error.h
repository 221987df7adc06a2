// A mistake on the command line (unknown option, missing value, bad number). main()
// prints it with a hint and exits with kExitUsage.
#pragma once

#include <stdexcept>
#include <string>

namespace bakegi::cli {

class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace bakegi::cli
