// bakegi compare values.npy reference.npy: prints the error of values against reference
// (native/common/error_metric.h) as one line of JSON: the project's two metrics ("nrmse",
// "weighted_relative_rmse") and the older one of the sweeps ("relative_rmse"), so that
// scripts (the Cycles side of the sweep) use the same code as `bakegi sweep`.
#include <cstdio>

#include "arguments.h"
#include "commands.h"
#include "exit_codes.h"
#include "file_error.h"
#include "npy_file.h"
#include "usage_error.h"
#include "error_metric.h"

namespace bakegi::cli {

int run_compare_command(const std::vector<std::string>& words) {
  const Arguments args(words, {});
  if (args.positional().size() != 2) {
    throw UsageError("compare expects two .npy files: values and reference");
  }
  const NpyArray reference = read_npy_float32(args.positional()[1]);
  if (reference.shape.size() != 2 || reference.shape[1] != 3) {
    throw FileError(args.positional()[1] + ": expected shape (n, 3)");
  }
  const std::vector<float> values = load_rgb_array(args.positional()[0], reference.shape[0]);
  const auto error = error_metrics(values.data(), reference.data.data(), reference.shape[0]);
  if (!error) {
    std::fprintf(stderr,
                 "bakegi: the error is undefined (no points, a non-finite value, or a "
                 "reference that is zero everywhere)\n");
    return kExitBakeFailed;
  }
  std::printf("{\"nrmse\": %.9g, \"weighted_relative_rmse\": %.9g, \"relative_rmse\": %.9g}\n",
              error->nrmse, error->weighted_relative_rmse, error->relative_rmse);
  return kExitOk;
}

}  // namespace bakegi::cli
