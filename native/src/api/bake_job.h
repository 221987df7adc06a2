// A bake running on its own thread: validate the scene, build the BVH, solve, evaluate at
// the bake points. Holds its own copies of scene, points and settings; progress, stage and
// cancel are safe to use from any thread while it runs.
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "bake_points/bake_points.h"
#include "scene/scene.h"
#include "util/job_context.h"
#include "util/settings.h"

namespace bakegi {

class Solver;

class BakeJob {
 public:
  // Checks the settings (unknown keys, types and ranges of the common ones, the method
  // name) and throws Error(INVALID_ARGUMENT) before anything starts; then starts the thread.
  BakeJob(SceneDescription description, BakePoints points, Settings settings);
  // Cancels if still running and waits for the thread.
  ~BakeJob();
  BakeJob(const BakeJob&) = delete;
  BakeJob& operator=(const BakeJob&) = delete;

  double progress() const { return context_.progress(); }
  std::string stage() const { return context_.stage(); }
  void cancel() { context_.cancel(); }
  bool is_done() const;
  // Blocks until the job ends; returns its status and (if failed) its message.
  bakegi_status wait(std::string& message);
  // After the job ended.
  bakegi_status status() const;
  std::string error() const;
  const std::vector<glm::vec3>& results() const { return results_; }
  size_t point_count() const { return points_.size(); }
  std::string report_json() const;

  // Bytes a bake is expected to need (flattened scene, BVH, points and results), before
  // any of it is allocated.
  static size_t estimate_memory(const SceneDescription& description, size_t point_count);

 private:
  void run() noexcept;
  void execute();
  void finish(bakegi_status status, const std::string& message) noexcept;

  SceneDescription description_;
  BakePoints points_;
  Settings settings_;
  std::unique_ptr<Solver> solver_;
  std::string method_;
  int threads_ = 0;
  size_t memory_budget_bytes_ = 0;

  JobContext context_;
  std::vector<glm::vec3> results_;

  mutable std::mutex mutex_;
  std::condition_variable done_changed_;
  bool done_ = false;
  bakegi_status status_ = BAKEGI_OK;
  std::string error_;
  std::thread thread_;
};

}  // namespace bakegi
