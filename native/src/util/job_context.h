// What long-running work needs from the job that runs it: progress, a stage name, the
// cancel flag (checked often; work stops by throwing Cancelled) and the report.
#pragma once

#include <atomic>
#include <mutex>
#include <string>

#include "util/report.h"

namespace bakegi {

class JobContext {
 public:
  // A stage covers [begin, end] of the current range (the whole job, or the part a
  // ProgressRange handed out: a solver counts its own work from 0 to 1, whichever part of
  // the job it runs in). Overall progress never decreases. Thread-safe.
  void set_stage(const std::string& name, double begin, double end);
  void set_stage_progress(double fraction);
  // Changes only the stage text (e.g. "tracing 32/256 samples"), not the progress range.
  void set_stage_text(const std::string& name);
  double progress() const { return progress_.load(std::memory_order_relaxed); }
  std::string stage() const;

  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  bool is_cancelled() const { return cancelled_.load(std::memory_order_relaxed); }
  // Throws bakegi::Error(BAKEGI_ERROR_CANCELLED) if cancel was asked for.
  void throw_if_cancelled() const;

  Report& report() { return report_; }
  const Report& report() const { return report_; }

 private:
  friend class ProgressRange;
  void raise_progress(double value);

  std::atomic<double> range_begin_{0.0}, range_end_{1.0};
  std::atomic<double> progress_{0.0};
  std::atomic<bool> cancelled_{false};
  std::atomic<double> stage_begin_{0.0}, stage_end_{1.0};
  mutable std::mutex stage_mutex_;
  std::string stage_;
  Report report_;
};

// While alive, stages set on `context` cover [begin, end] of the range that was current (the
// job hands each stage its part: the solver gets [0.1, 0.6] of the bake). Restores the
// previous range when destroyed. Only the thread that runs the job makes ranges.
class ProgressRange {
 public:
  ProgressRange(JobContext& context, double begin, double end);
  ~ProgressRange();
  ProgressRange(const ProgressRange&) = delete;
  ProgressRange& operator=(const ProgressRange&) = delete;

 private:
  JobContext& context_;
  double previous_begin_, previous_end_;
};

}  // namespace bakegi
