// bakegi_job_*: the asynchronous bake (BakeJob) behind the C API.
#include <algorithm>
#include <cstring>

#include "api/api_guard.h"
#include "api/handles.h"
#include "api/text_output.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

bakegi::BakeJob& job_of(const bakegi_job* job) {
  require(job, "job");
  require(job->job.get(), "job");
  return *job->job;
}

}  // namespace

extern "C" {

bakegi_status bakegi_job_start(const bakegi_scene* scene, const bakegi_points* points,
                               const bakegi_settings* settings, bakegi_job** out_job) {
  return guarded(__func__, [&] {
    require(out_job, "out_job");
    *out_job = nullptr;
    require(scene, "scene");
    require(points, "points");
    auto handle = std::make_unique<bakegi_job>();
    handle->job = std::make_unique<bakegi::BakeJob>(
        scene->description, points->points, settings ? settings->settings : bakegi::Settings(),
        points->display_probes);
    *out_job = bakegi::give_out(std::move(handle));
  });
}

double bakegi_job_progress(const bakegi_job* job) {
  return bakegi::live(job) && job->job ? job->job->progress() : 0.0;
}

void bakegi_job_stage(const bakegi_job* job, char* buffer, size_t capacity) {
  if (!buffer || capacity == 0) return;
  buffer[0] = '\0';
  try {
    if (!bakegi::live(job) || !job->job) return;
    const std::string stage = job->job->stage();
    const size_t n = std::min(stage.size(), capacity - 1);
    std::memcpy(buffer, stage.data(), n);
    buffer[n] = '\0';
  } catch (...) {
    // Out of memory copying a short text: leave the buffer empty.
  }
}

void bakegi_job_cancel(bakegi_job* job) {
  if (bakegi::live(job) && job->job) job->job->cancel();
}

int bakegi_job_is_done(const bakegi_job* job) {
  // A missing job has nothing left to do; 1 keeps polling loops from spinning forever.
  if (!bakegi::live(job) || !job->job) return 1;
  try {
    return job->job->is_done() ? 1 : 0;
  } catch (...) {
    return 1;
  }
}

bakegi_status bakegi_job_wait(bakegi_job* job) {
  return guarded(__func__, [&] {
    std::string message;
    const bakegi_status status = job_of(job).wait(message);
    if (status != BAKEGI_OK) throw Error(status, message);
  });
}

bakegi_status bakegi_job_get_result(const bakegi_job* job, float* out_rgb, uint64_t count) {
  return guarded(__func__, [&] {
    const bakegi::BakeJob& j = job_of(job);
    require(out_rgb, "out_rgb");
    if (!j.is_done()) {
      throw Error(BAKEGI_ERROR_NOT_READY, "the job has not finished yet");
    }
    if (j.status() != BAKEGI_OK) {
      throw Error(j.status(), "the job failed, there is no result: " + j.error());
    }
    if (count != j.point_count()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "count " + std::to_string(count) + " does not match the " +
                      std::to_string(j.point_count()) + " bake points");
    }
    const std::vector<glm::vec3>& results = j.results();
    for (size_t i = 0; i < results.size(); ++i) {
      out_rgb[3 * i] = results[i].x;
      out_rgb[3 * i + 1] = results[i].y;
      out_rgb[3 * i + 2] = results[i].z;
    }
  });
}

bakegi_status bakegi_job_get_report(const bakegi_job* job, char* buffer, size_t capacity,
                                    size_t* out_length) {
  return guarded(__func__, [&] {
    const bakegi::BakeJob& j = job_of(job);
    bakegi::check_text_output(buffer, capacity, out_length);
    if (!j.is_done()) throw Error(BAKEGI_ERROR_NOT_READY, "the job has not finished yet");
    bakegi::write_text_output(j.report_json(), buffer, capacity, out_length);
  });
}

int bakegi_job_can_relight(const bakegi_job* job) {
  try {
    return bakegi::live(job) && job->job && job->job->is_done() && job->job->precomputation() ? 1
                                                                                              : 0;
  } catch (...) {
    return 0;
  }
}

bakegi_status bakegi_job_start_relight(const bakegi_job* previous, const bakegi_scene* scene,
                                       const bakegi_points* points, const bakegi_settings* settings,
                                       bakegi_job** out_job) {
  return guarded(__func__, [&] {
    require(out_job, "out_job");
    *out_job = nullptr;
    const bakegi::BakeJob& before = job_of(previous);
    require(scene, "scene");
    if (!before.is_done()) {
      throw Error(BAKEGI_ERROR_NOT_READY, "the previous job has not finished yet");
    }
    if (before.status() != BAKEGI_OK) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "the previous job failed, there is nothing to relight from: " + before.error());
    }
    auto handle = std::make_unique<bakegi_job>();
    handle->job = std::make_unique<bakegi::BakeJob>(
        scene->description, points ? points->points : before.points(), before.precomputation(),
        settings ? settings->settings : bakegi::Settings());
    *out_job = bakegi::give_out(std::move(handle));
  });
}

void bakegi_job_destroy(bakegi_job* job) {
  try {
    bakegi::destroy_handle(job);
  } catch (...) {
    // ~BakeJob only cancels and joins; nothing is expected to throw here.
  }
}

}  // extern "C"
