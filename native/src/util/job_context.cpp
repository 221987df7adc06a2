#include "util/job_context.h"

#include <algorithm>

#include "util/error.h"

namespace bakegi {

void JobContext::raise_progress(double value) {
  value = std::clamp(value, 0.0, 1.0);
  double current = progress_.load(std::memory_order_relaxed);
  // Several threads report at once; only ever move forward.
  while (value > current &&
         !progress_.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}

void JobContext::set_stage(const std::string& name, double begin, double end) {
  begin = std::clamp(begin, 0.0, 1.0);
  end = std::clamp(end, begin, 1.0);
  const double range_begin = range_begin_.load(std::memory_order_relaxed);
  const double range_size = range_end_.load(std::memory_order_relaxed) - range_begin;
  begin = range_begin + begin * range_size;
  end = range_begin + end * range_size;
  stage_begin_.store(begin, std::memory_order_relaxed);
  stage_end_.store(end, std::memory_order_relaxed);
  raise_progress(begin);
  set_stage_text(name);
}

void JobContext::set_stage_progress(double fraction) {
  if (!(fraction >= 0.0)) fraction = 0.0;  // also catches NaN
  fraction = std::min(fraction, 1.0);
  const double begin = stage_begin_.load(std::memory_order_relaxed);
  const double end = stage_end_.load(std::memory_order_relaxed);
  raise_progress(begin + fraction * (end - begin));
}

void JobContext::set_stage_text(const std::string& name) {
  std::lock_guard lock(stage_mutex_);
  stage_ = name;
}

std::string JobContext::stage() const {
  std::lock_guard lock(stage_mutex_);
  return stage_;
}

void JobContext::throw_if_cancelled() const {
  if (is_cancelled()) throw Error(BAKEGI_ERROR_CANCELLED, "the bake was cancelled");
}

ProgressRange::ProgressRange(JobContext& context, double begin, double end)
    : context_(context),
      previous_begin_(context.range_begin_.load(std::memory_order_relaxed)),
      previous_end_(context.range_end_.load(std::memory_order_relaxed)) {
  begin = std::clamp(begin, 0.0, 1.0);
  end = std::clamp(end, begin, 1.0);
  const double size = previous_end_ - previous_begin_;
  context.range_begin_.store(previous_begin_ + begin * size, std::memory_order_relaxed);
  context.range_end_.store(previous_begin_ + end * size, std::memory_order_relaxed);
}

ProgressRange::~ProgressRange() {
  context_.range_begin_.store(previous_begin_, std::memory_order_relaxed);
  context_.range_end_.store(previous_end_, std::memory_order_relaxed);
}

}  // namespace bakegi
