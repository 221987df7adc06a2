// A cancel request that another thread raises while work runs outside a bake job (the
// lightmaps' texel rasterization, seam search and inside-geometry rejection, which the
// add-on runs on a worker before the job starts). The work checks it between small steps
// (a triangle row, a block of samples) and stops by throwing Error(CANCELLED); a null flag
// is never raised.
#pragma once

#include <atomic>
#include <string>

#include "util/error.h"

namespace bakegi {

using CancelFlag = std::atomic<bool>;

inline void throw_if_cancelled(const CancelFlag* flag, const char* work) {
  if (flag && flag->load(std::memory_order_relaxed)) {
    throw Error(BAKEGI_ERROR_CANCELLED, std::string(work) + " was cancelled");
  }
}

}  // namespace bakegi
