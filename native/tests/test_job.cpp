// The asynchronous bake job: progress that never decreases and reaches 1, a report that is
// a JSON object with the documented keys, prompt cancel, the memory budget, and copies of
// the inputs that outlive the caller's handles.
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "capi_test_scene.h"
#include "util/job_context.h"
#include "util/report.h"

namespace bakegi::test {
namespace {

using Clock = std::chrono::steady_clock;

// A small strict JSON parser, enough to check that reports are well-formed.
struct Json {
  enum Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = kNull;
  double number = 0;
  bool boolean = false;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> members;
};

class JsonParser {
  static constexpr const char* kEscapes = "\"\\/bfnrt";
  static constexpr const char* kEscaped = "\"\\/\b\f\n\r\t";

 public:
  explicit JsonParser(const std::string& text) : s_(text) {}
  // Returns false on any syntax error or trailing characters.
  bool parse(Json& out) {
    if (!value(out)) return false;
    skip_space();
    return at_ == s_.size();
  }

 private:
  void skip_space() {
    while (at_ < s_.size() && std::strchr(" \t\r\n", s_[at_])) ++at_;
  }
  bool literal(const char* word) {
    const size_t n = std::strlen(word);
    if (s_.compare(at_, n, word) != 0) return false;
    at_ += n;
    return true;
  }
  bool string(std::string& out) {
    if (at_ >= s_.size() || s_[at_] != '"') return false;
    ++at_;
    while (at_ < s_.size() && s_[at_] != '"') {
      const char c = s_[at_++];
      if (static_cast<unsigned char>(c) < 0x20) return false;  // must be escaped
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_ >= s_.size()) return false;
      const char e = s_[at_++];
      if (e == 'u') {
        if (at_ + 4 > s_.size()) return false;
        for (int i = 0; i < 4; ++i) {
          if (!std::isxdigit(static_cast<unsigned char>(s_[at_ + i]))) return false;
        }
        out += char(std::stoi(s_.substr(at_, 4), nullptr, 16));
        at_ += 4;
      } else if (const char* found = std::strchr(kEscapes, e)) {
        out += kEscaped[found - kEscapes];
      } else {
        return false;
      }
    }
    if (at_ >= s_.size()) return false;
    ++at_;
    return true;
  }
  bool value(Json& out) {
    skip_space();
    if (at_ >= s_.size()) return false;
    const char c = s_[at_];
    if (c == '{') {
      out.kind = Json::kObject;
      ++at_;
      skip_space();
      if (at_ < s_.size() && s_[at_] == '}') return ++at_, true;
      while (true) {
        skip_space();
        std::string key;
        if (!string(key)) return false;
        skip_space();
        if (at_ >= s_.size() || s_[at_++] != ':') return false;
        if (out.members.count(key)) return false;  // duplicate names
        if (!value(out.members[key])) return false;
        skip_space();
        if (at_ >= s_.size()) return false;
        if (s_[at_] == ',') {
          ++at_;
          continue;
        }
        if (s_[at_] == '}') return ++at_, true;
        return false;
      }
    }
    if (c == '[') {
      out.kind = Json::kArray;
      ++at_;
      skip_space();
      if (at_ < s_.size() && s_[at_] == ']') return ++at_, true;
      while (true) {
        out.items.emplace_back();
        if (!value(out.items.back())) return false;
        skip_space();
        if (at_ >= s_.size()) return false;
        if (s_[at_] == ',') {
          ++at_;
          continue;
        }
        if (s_[at_] == ']') return ++at_, true;
        return false;
      }
    }
    if (c == '"') return out.kind = Json::kString, string(out.text);
    if (literal("null")) return out.kind = Json::kNull, true;
    if (literal("true")) return out.kind = Json::kBool, out.boolean = true, true;
    if (literal("false")) return out.kind = Json::kBool, true;
    // Number: -?digits[.digits][e[+-]digits]
    const size_t start = at_;
    if (s_[at_] == '-') ++at_;
    auto digits = [&] {
      const size_t from = at_;
      while (at_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[at_]))) ++at_;
      return at_ > from;
    };
    if (!digits()) return false;
    if (at_ < s_.size() && s_[at_] == '.' && (++at_, !digits())) return false;
    if (at_ < s_.size() && (s_[at_] == 'e' || s_[at_] == 'E')) {
      ++at_;
      if (at_ < s_.size() && (s_[at_] == '+' || s_[at_] == '-')) ++at_;
      if (!digits()) return false;
    }
    out.kind = Json::kNumber;
    out.number = std::stod(s_.substr(start, at_ - start));
    return true;
  }

  const std::string& s_;
  size_t at_ = 0;
};

std::string report_of(bakegi_job* job) {
  size_t length = 0;
  EXPECT_EQ(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_OK) << bakegi_last_error();
  std::string text(length + 1, '\0');
  EXPECT_EQ(bakegi_job_get_report(job, text.data(), text.size(), &length), BAKEGI_OK);
  text.resize(length);
  return text;
}

Json parse_report(bakegi_job* job) {
  const std::string text = report_of(job);
  Json json;
  EXPECT_TRUE(JsonParser(text).parse(json)) << text;
  EXPECT_EQ(json.kind, Json::kObject) << text;
  return json;
}

std::string stage_of(const bakegi_job* job) {
  char buffer[128];
  bakegi_job_stage(job, buffer, sizeof buffer);
  return buffer;
}

TEST(JsonParserSelfTest, AcceptsValidAndRejectsInvalid) {
  Json json;
  EXPECT_TRUE(JsonParser(R"({"a": [1, -2.5e3, "x\"y\u0001"], "b": {}, "c": null})").parse(json));
  EXPECT_EQ(json.members["a"].items[2].text, "x\"y\x01");
  for (const char* bad : {"{", R"({"a" 1})", R"({"a": 1,})", "[1 2]", R"({"a": nan})",
                          R"({"a": 1, "a": 2})", "{} x", "\"tab\there\""}) {
    Json ignored;
    EXPECT_FALSE(JsonParser(bad).parse(ignored)) << bad;
  }
}

TEST(ReportJson, TextIsEscapedAndNumbersStayFinite) {
  Report report;
  report.set_text("text", "quote\" backslash\\ newline\n control\x01 \xc3\xa9 bad\xff");
  report.set_number("not_a_number", std::nan(""));
  report.set_number("third", 1.0 / 3.0);
  report.warn("tab\there");
  const std::string text = report.to_json();
  Json json;
  ASSERT_TRUE(JsonParser(text).parse(json)) << text;
  EXPECT_EQ(json.members["text"].text.substr(0, 42),
            "quote\" backslash\\ newline\n control\x01 \xc3\xa9 bad");
  EXPECT_NE(text.find("bad\\ufffd"), std::string::npos) << text;  // invalid UTF-8 replaced
  EXPECT_EQ(json.members["not_a_number"].kind, Json::kNull);
  EXPECT_EQ(json.members["third"].number, 1.0 / 3.0);  // 17 digits round-trip exactly
  EXPECT_EQ(json.members["warnings"].items[0].text, "tab\there");
}

TEST(BakeJob, ProgressIsMonotoneReachesOneAndTheReportIsComplete) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(100);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 64), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "seed", 3), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "threads", 1), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK)
      << bakegi_last_error();
  JobPtr owned(job);

  double last = 0.0;
  int polls = 0;
  while (!bakegi_job_is_done(job)) {
    const double progress = bakegi_job_progress(job);
    EXPECT_GE(progress, last);
    EXPECT_LE(progress, 1.0);
    last = progress;
    ++polls;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  EXPECT_GE(bakegi_job_progress(job), last);
  EXPECT_EQ(bakegi_job_progress(job), 1.0);
  EXPECT_EQ(stage_of(job), "done");

  std::vector<float> rgb(300);
  ASSERT_EQ(bakegi_job_get_result(job, rgb.data(), 100), BAKEGI_OK);
  for (float v : rgb) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GT(v, 0.0f);  // a closed lit box: indirect light reaches every floor point
  }

  Json report = parse_report(job);
  for (const char* key : {"method", "settings", "bake_points", "triangles", "lights", "seconds",
                          "rays", "memory_bytes", "warnings", "status", "error"}) {
    EXPECT_TRUE(report.members.count(key)) << "report lacks \"" << key << "\"";
  }
  EXPECT_EQ(report.members["method"].text, "pathtrace");
  EXPECT_EQ(report.members["status"].text, "BAKEGI_OK");
  EXPECT_EQ(report.members["error"].text, "");
  EXPECT_EQ(report.members["bake_points"].number, 100);
  EXPECT_EQ(report.members["triangles"].number, 12);
  EXPECT_EQ(report.members["lights"].number, 1);
  EXPECT_EQ(report.members["threads"].number, 1);
  EXPECT_GT(report.members["rays"].number, 100 * 64);  // at least one ray per sample
  EXPECT_GT(report.members["memory_bytes"].number, 0);
  Json& settings_json = report.members["settings"];
  ASSERT_EQ(settings_json.kind, Json::kObject);
  EXPECT_EQ(settings_json.members["samples"].number, 64);
  EXPECT_EQ(settings_json.members["seed"].number, 3);
  EXPECT_EQ(settings_json.members["method"].text, "pathtrace");
  Json& seconds = report.members["seconds"];
  double stages = 0;
  for (const char* stage : {"validate", "bvh", "solve", "evaluate", "total"}) {
    ASSERT_EQ(seconds.members[stage].kind, Json::kNumber) << stage;
    EXPECT_GE(seconds.members[stage].number, 0.0);
    if (std::string(stage) != "total") stages += seconds.members[stage].number;
  }
  EXPECT_LE(stages, seconds.members["total"].number + 1e-9);
  EXPECT_EQ(report.members["warnings"].kind, Json::kArray);
}

TEST(BakeJob, EveryFullBakeEstimatesItsOwnError) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(400);
  // Display probes: halfway between consecutive floor points.
  std::vector<float> positions(3 * 400), normals(3 * 400);
  ASSERT_EQ(bakegi_points_get(points.get(), positions.data(), normals.data(), nullptr), BAKEGI_OK);
  std::vector<float> probe_positions, probe_normals, weights;
  std::vector<uint32_t> indices;
  for (uint32_t i = 0; i + 1 < 400; i += 10) {
    for (int c = 0; c < 3; ++c) {
      probe_positions.push_back(0.5f * (positions[3 * i + c] + positions[3 * i + 3 + c]));
    }
    probe_normals.insert(probe_normals.end(), {0.0f, 0.0f, 1.0f});
    indices.insert(indices.end(), {i, i + 1, 0, 0});
    weights.insert(weights.end(), {0.5f, 0.5f, 0.0f, 0.0f});
  }
  const uint64_t display_count = indices.size() / 4;
  ASSERT_EQ(
      bakegi_points_set_display_probes(points.get(), probe_positions.data(), probe_normals.data(),
                                       nullptr, indices.data(), weights.data(), display_count),
      BAKEGI_OK)
      << bakegi_last_error();
  auto run = [&](const char* method, int64_t probes) {
    SettingsPtr settings = new_settings();
    EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", method), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 16), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "error_probe_samples", 64), BAKEGI_OK);
    if (probes >= 0) {
      EXPECT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", probes), BAKEGI_OK);
    }
    bakegi_job* job = nullptr;
    EXPECT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK)
        << bakegi_last_error();
    JobPtr owned(job);
    EXPECT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
    return parse_report(job);
  };

  Json report = run("pathtrace", -1);  // the default: 256 probes
  ASSERT_EQ(report.members["estimated_error"].kind, Json::kNumber);
  const double estimate = report.members["estimated_error"].number;
  Json& interval = report.members["estimated_error_interval"];
  ASSERT_EQ(interval.items.size(), 2u);
  EXPECT_LE(interval.items[0].number, estimate);
  EXPECT_GE(interval.items[1].number, estimate);
  // 16 paths per point in a box lit from its centre: noise of some percent, not 0, not 100%.
  EXPECT_GT(estimate, 0.01);
  EXPECT_LT(estimate, 0.5);
  Json& detail = report.members["error_estimate"];
  EXPECT_EQ(detail.members["at_points"].members["probes"].number, 256);
  EXPECT_EQ(detail.members["display"].members["probes"].number, double(display_count));
  EXPECT_EQ(detail.members["samples"].number, 64);
  EXPECT_GE(report.members["seconds"].members["error_estimate"].number, 0.0);
  EXPECT_GT(report.members["error_probe_rays"].number, 0);

  EXPECT_EQ(run("pathtrace", 0).members.count("estimated_error"), 0u);  // off
  EXPECT_EQ(run("direct", -1).members.count("estimated_error"), 0u);    // not indirect light

  // Probes that point past the bake points are refused at the door.
  indices[0] = 400;
  EXPECT_EQ(
      bakegi_points_set_display_probes(points.get(), probe_positions.data(), probe_normals.data(),
                                       nullptr, indices.data(), weights.data(), display_count),
      BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("display probe 0: bake point 400 is out of range"), std::string::npos)
      << last_error();
}

TEST(BakeJob, CancelStopsALongJobPromptly) {
  // Hours of work at full speed: only cancel can end it within the test.
  bakegi_job* job = start_endless_job(256);
  ASSERT_NE(job, nullptr);
  JobPtr owned(job);
  // Let it get into the long stage.
  const auto started = Clock::now();
  while (stage_of(job) == "queued" || stage_of(job) == "validating" ||
         stage_of(job) == "building BVH") {
    ASSERT_LT(Clock::now() - started, std::chrono::seconds(30));
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(bakegi_job_is_done(job));
  const auto cancelled_at = Clock::now();
  bakegi_job_cancel(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_ERROR_CANCELLED);
  const double seconds = std::chrono::duration<double>(Clock::now() - cancelled_at).count();
  // Prompt means well under a second; the bound allows for a slow sanitizer build.
  EXPECT_LT(seconds, 2.0);
  EXPECT_NE(std::string(bakegi_last_error()).find("cancelled"), std::string::npos);
  EXPECT_EQ(stage_of(job), "cancelled");
  EXPECT_LT(bakegi_job_progress(job), 1.0);
  Json report = parse_report(job);
  EXPECT_EQ(report.members["status"].text, "BAKEGI_ERROR_CANCELLED");
}

// A cancel that comes after the job ended changes nothing: it stays a success, its results
// readable. (One that comes before the end, even after its last stage polled, ends it
// cancelled: BakeJob::cancel and finish agree under one lock.)
TEST(BakeJob, ACancelAfterTheEndChangesNothing) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(16);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 4), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK)
      << bakegi_last_error();
  JobPtr owned(job);
  ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  bakegi_job_cancel(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_OK);
  std::vector<float> rgb(3 * 16);
  EXPECT_EQ(bakegi_job_get_result(job, rgb.data(), 16), BAKEGI_OK) << bakegi_last_error();
  EXPECT_EQ(stage_of(job), "done");
}

TEST(BakeJob, DestroyingARunningJobCancelsIt) {
  bakegi_job* job = start_endless_job(64);
  ASSERT_NE(job, nullptr);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto start = Clock::now();
  bakegi_job_destroy(job);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 2.0);
}

TEST(BakeJob, MemoryBudgetRefusesBeforeAllocating) {
  ScenePtr scene = new_box_scene();
  // 100,000 points x (28 bytes held + 12 of result) = 4 MB > 1 MB.
  PointsPtr points = new_floor_points(100000);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "memory_budget_mb", 1), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
  JobPtr owned(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_ERROR_OUT_OF_MEMORY);
  const std::string message = bakegi_last_error();
  EXPECT_NE(message.find("the bake needs an estimated 3.8 MB"), std::string::npos) << message;
  EXPECT_NE(message.find("memory_budget_mb"), std::string::npos) << message;
  Json report = parse_report(job);
  EXPECT_EQ(report.members["status"].text, "BAKEGI_ERROR_OUT_OF_MEMORY");
  EXPECT_GT(report.members["memory_estimate_bytes"].number, 1 << 20);
  EXPECT_EQ(report.members["seconds"].members["bvh"].number, 0.0);  // never got there
}

// The irradiance cache's work counts in the estimate: 30,000 points fit 2 MB for the plain
// path tracer (28 + 12 bytes each and the box: about 1.2 MB) and not with the cache
// (kIrradianceCacheBytesPerPoint more each: 30,000 x ~390 bytes), which is refused before
// any of it is allocated.
TEST(BakeJob, MemoryBudgetCountsTheIrradianceCache) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(30000);
  const auto start = [&](bool cache) {
    SettingsPtr settings = new_settings();
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "memory_budget_mb", 2), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", 0), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", cache ? 256 : 1), BAKEGI_OK);
    if (cache) {
      EXPECT_EQ(bakegi_settings_set_float(settings.get(), "irradiance_cache", 0.2), BAKEGI_OK);
    }
    bakegi_job* job = nullptr;
    EXPECT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
    return JobPtr(job);
  };
  JobPtr plain = start(false);
  EXPECT_EQ(bakegi_job_wait(plain.get()), BAKEGI_OK) << bakegi_last_error();
  JobPtr cached = start(true);
  EXPECT_EQ(bakegi_job_wait(cached.get()), BAKEGI_ERROR_OUT_OF_MEMORY);
  const std::string message = bakegi_last_error();
  EXPECT_NE(message.find("memory_budget_mb"), std::string::npos) << message;
  Json report = parse_report(cached.get());
  EXPECT_EQ(report.members["seconds"].members["bvh"].number, 0.0);  // never got there
}

// Settings that name no method bake with the core's default, and the report says which.
// No method named: the default recipe (the path tracer to 5% through the denoiser), with
// what the caller did set kept.
TEST(BakeJob, SettingsWithoutAMethodBakeWithTheDefault) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(16);
  SettingsPtr settings = new_settings(nullptr);
  ASSERT_EQ(bakegi_settings_set_float(settings.get(), "target_error", 0.1), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", 0), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK)
      << bakegi_last_error();
  JobPtr owned(job);
  ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  Json report = parse_report(job);
  EXPECT_EQ(report.members["method"].text, "pathtrace");
  EXPECT_DOUBLE_EQ(report.members["target_error"].number, 0.1);
  EXPECT_GT(report.members["denoise_noise_after"].number, 0.0);
  EXPECT_LE(report.members["sampling_predicted_error"].number, 0.1);
  // The noise as the filter's residuals show it: never more than the variances say.
  const double scale = report.members["denoise_variance_scale"].number;
  EXPECT_GT(scale, 0.0);
  EXPECT_LE(scale, 1.0);
  EXPECT_GE(report.members["denoise_local_bias"].number, 0.0);
}

TEST(BakeJob, KeepsItsOwnCopiesAndReportsWarnings) {
  ScenePtr scene = new_box_scene();
  // A second mesh with one degenerate triangle: dropped, with a warning in the report.
  const float positions[] = {0.2f, 0.2f, 0.5f, 0.4f, 0.2f, 0.5f,
                             0.3f, 0.2f, 0.5f, 0.2f, 0.4f, 0.5f};
  const uint32_t indices[] = {0, 1, 2, 0, 1, 3};
  bakegi_mesh_desc mesh{};
  mesh.positions = positions;
  mesh.vertex_count = 4;
  mesh.indices = indices;
  mesh.triangle_count = 2;
  mesh.object_id = 5;
  ASSERT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  PointsPtr points = new_floor_points(9);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 4), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
  JobPtr owned(job);
  scene.reset();
  points.reset();
  settings.reset();
  ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  Json report = parse_report(job);
  EXPECT_EQ(report.members["triangles"].number, 13);
  ASSERT_EQ(report.members["warnings"].items.size(), 1u);
  EXPECT_EQ(report.members["warnings"].items[0].text,
            "mesh 1 (object 5): 1 of 2 triangles dropped as degenerate (zero area)");
  EXPECT_EQ(report.members["settings"].members["samples"].number, 4);
}

TEST(BakeJob, AMethodThatCannotModelTheSceneHandsTheBakeToThePathTracer) {
  // Antiradiance at 3072 bins cannot hold even the unsplit box's tables in 2 MB, which the
  // bake itself (a 12-triangle box, 100 points) fits easily.
  auto start = [](int64_t fallback, bakegi_status expected) {
    ScenePtr scene = new_box_scene();
    PointsPtr points = new_floor_points(100);
    SettingsPtr settings = new_settings();
    EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", "antiradiance"), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "bins", 3072), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "memory_budget_mb", 2), BAKEGI_OK);
    EXPECT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", 0), BAKEGI_OK);
    if (fallback >= 0) {
      EXPECT_EQ(bakegi_settings_set_int(settings.get(), "fallback", fallback), BAKEGI_OK);
    }
    bakegi_job* job = nullptr;
    EXPECT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
    JobPtr owned(job);
    EXPECT_EQ(bakegi_job_wait(job), expected) << bakegi_last_error();
    Json report = parse_report(job);
    std::vector<float> values(300, -1.0f);
    if (expected == BAKEGI_OK) {
      EXPECT_EQ(bakegi_job_get_result(job, values.data(), 100), BAKEGI_OK);
    }
    return std::make_pair(report, values);
  };
  auto [report, values] = start(-1, BAKEGI_OK);
  EXPECT_EQ(report.members["method"].text, "antiradiance");
  EXPECT_EQ(report.members["method_used"].text, "pathtrace");
  ASSERT_FALSE(report.members["warnings"].items.empty());
  const std::string warning = report.members["warnings"].items[0].text;
  EXPECT_NE(warning.find("memory_budget_mb"), std::string::npos) << warning;
  EXPECT_NE(warning.find("Baked with the path tracer instead (128 samples"), std::string::npos)
      << warning;
  double sum = 0.0;
  for (float v : values) {
    EXPECT_TRUE(std::isfinite(v));
    sum += v;
  }
  EXPECT_GT(sum, 0.0);
  // fallback=0: refused as before.
  auto refused = start(0, BAKEGI_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(std::string(bakegi_last_error()).find("memory_budget_mb"), std::string::npos);
  EXPECT_EQ(refused.first.members["status"].text, "BAKEGI_ERROR_OUT_OF_MEMORY");
}

}  // namespace
}  // namespace bakegi::test

// Each stage covers its part of the range the job handed out: a solver counts from 0 to 1
// in [0.1, 0.6] of the bake, and overall progress never goes back.
TEST(JobContext, ProgressRangesMapStagesIntoTheirPart) {
  bakegi::JobContext context;
  context.set_stage("building", 0.0, 0.1);
  context.set_stage_progress(1.0);
  EXPECT_DOUBLE_EQ(context.progress(), 0.1);
  {
    const bakegi::ProgressRange solving(context, 0.1, 0.6);
    context.set_stage("solver: first half", 0.0, 0.5);
    context.set_stage_progress(0.5);
    EXPECT_DOUBLE_EQ(context.progress(), 0.1 + 0.25 * 0.5);
    {
      const bakegi::ProgressRange inner(context, 0.5, 1.0);  // ranges nest
      context.set_stage("solver: second half", 0.0, 1.0);
      context.set_stage_progress(1.0);
      EXPECT_DOUBLE_EQ(context.progress(), 0.6);
    }
    context.set_stage("solver: an earlier stage again", 0.0, 0.1);
    EXPECT_DOUBLE_EQ(context.progress(), 0.6);  // never backwards
  }
  context.set_stage("evaluating", 0.6, 1.0);  // the whole job's range again
  context.set_stage_progress(0.5);
  EXPECT_DOUBLE_EQ(context.progress(), 0.8);
  EXPECT_EQ(context.stage(), "evaluating");
}
