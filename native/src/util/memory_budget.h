// The memory a bake may take (setting memory_budget_mb), made once by the job and handed to
// each stage: what the job already holds (scene, points, ray tracer) is counted as held, so
// a solver sizes its own structures from what remains instead of re-deriving the budget.
#pragma once

#include <cstdint>
#include <string>

namespace bakegi {

class MemoryBudget {
 public:
  static constexpr uint64_t kDefaultBytes = uint64_t(4096) << 20;  // memory_budget_mb 4096

  explicit MemoryBudget(uint64_t total_bytes = kDefaultBytes) : total_(total_bytes) {}

  uint64_t total() const { return total_; }
  uint64_t held() const { return held_; }
  // What is left for the next stage (0 when the held part already exceeds the total).
  uint64_t remaining() const { return held_ < total_ ? total_ - held_ : 0; }
  // What is left once `more` bytes are held too (0 when they do not fit).
  uint64_t remaining_after(uint64_t more) const {
    const uint64_t left = remaining();
    return more < left ? left - more : 0;
  }
  // Counts bytes that live as long as the bake (checked by whoever sized them).
  void hold(uint64_t bytes) { held_ += bytes; }

  // "4096.0 MB (setting memory_budget_mb)": for messages that name the limit.
  std::string describe() const { return megabytes(total_) + " (setting memory_budget_mb)"; }
  // "12.3 MB"
  static std::string megabytes(uint64_t bytes);

 private:
  uint64_t total_;
  uint64_t held_ = 0;
};

}  // namespace bakegi
