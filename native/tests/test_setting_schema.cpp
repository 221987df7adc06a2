// The settings schemas (settings/setting_schema.h, solvers/method_registry.cpp): each is
// consistent with itself, the C API hands them out, and the roles keep what relights and the
// meshless cache did before the schemas existed.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bakegi/bakegi.h"
#include "settings/setting_schema.h"
#include "settings/settings.h"
#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {
namespace {

std::vector<std::string> sorted(std::vector<std::string> keys) {
  std::sort(keys.begin(), keys.end());
  return keys;
}

TEST(SettingSchema, EveryMethodsDefaultsLieInTheirOwnRanges) {
  for (const std::string& method : method_names()) {
    const SettingSchema& schema = method_schema(method);
    std::set<std::string> seen;
    for (const SettingSpec& spec : schema.specs()) {
      SCOPED_TRACE(method + "." + spec.key);
      EXPECT_TRUE(seen.insert(spec.key).second) << "key twice";
      EXPECT_FALSE(spec.doc.empty());
      // Reading an absent key gives the default, which must pass the spec's own checks.
      Settings given;
      given.set(spec.key, spec.fallback);
      EXPECT_NO_THROW(given.validate(schema, setting_keys_of_any_method()));
      const Settings none;
      const SettingReader read(none, schema);
      switch (spec.type) {
        case SettingType::kInteger:
          EXPECT_EQ(read.get_int(spec.key), std::get<int64_t>(spec.fallback));
          break;
        case SettingType::kNumber:
          EXPECT_EQ(read.get_float(spec.key), std::get<double>(spec.fallback));
          break;
        case SettingType::kText:
          EXPECT_EQ(read.get_string(spec.key), std::get<std::string>(spec.fallback));
          break;
      }
    }
  }
}

TEST(SettingSchema, ReadingAKeyOutsideTheSchemaIsABug) {
  Settings settings;
  const SettingReader read(settings, method_schema("pathtrace"));
  try {
    read.get_int("bins");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_INTERNAL);
  }
}

TEST(SettingSchema, ReadsRememberDefaultsForTheReport) {
  Settings settings;
  settings.set("levels", int64_t(3));
  const SettingReader read(settings, method_schema("meshless"));
  EXPECT_EQ(read.get_int("levels"), 3);
  EXPECT_EQ(read.get_float("epsilon"), 0.01);
  const auto used = settings.used_values();
  EXPECT_EQ(std::get<int64_t>(used.at("levels")), 3);
  EXPECT_EQ(std::get<double>(used.at("epsilon")), 0.01);
}

// What a relight may change, per method: the lists the solvers stated before the schemas,
// plus "samples" (only the path tracer a method hands a bake to reads it) and the execution
// keys ("threads", and "cache_dir" of the methods with a precomputation cache).
TEST(SettingSchema, RolesGiveTheKeysARelightMayChange) {
  auto changeable = [](const std::string& method) {
    const SettingSchema& schema = method_schema(method);
    std::vector<std::string> keys = schema.keys_with_role(SettingRole::kLighting);
    for (const std::string& k : schema.keys_with_role(SettingRole::kExecution)) keys.push_back(k);
    return sorted(keys);
  };
  EXPECT_EQ(changeable("antiradiance"),
            sorted({"iterations", "tolerance", "scheme", "direct_samples", "seed", "samples",
                    "target_error", "threads", "cache_dir", "residual", "residual_fraction",
                    "denoise", "cache_max_mb", "irradiance_cache", "shadow_cache"}));
  EXPECT_EQ(
      changeable("meshless"),
      sorted({"direct_samples", "sender_cutoff", "bounces", "cache_dir", "samples", "target_error",
              "threads", "denoise", "cache_max_mb", "irradiance_cache", "shadow_cache"}));
}

TEST(SettingSchema, MethodsThatHandBakesToThePathTracerReadItsSettings) {
  EXPECT_NE(method_schema("antiradiance").find("max_bounces"), nullptr);
  EXPECT_NE(method_schema("meshless").find("max_bounces"), nullptr);
  EXPECT_EQ(method_schema("direct").find("max_bounces"), nullptr);
  // A method's own default wins over the common one (antiradiance relights with a new seed).
  EXPECT_EQ(method_schema("antiradiance").find("seed")->role, SettingRole::kLighting);
  EXPECT_EQ(method_schema("meshless").find("seed")->role, SettingRole::kShapes);
  EXPECT_EQ(std::get<int64_t>(method_schema("antiradiance").find("direct_samples")->fallback), 64);
  EXPECT_EQ(std::get<int64_t>(method_schema("meshless").find("direct_samples")->fallback), 4);
}

// Each solver folder registers its method while the library loads (no central list): all six
// are there, in listing order, and the default method is one of them and the "method"
// setting's default in every schema.
TEST(SettingSchema, EverySolverFolderRegistersItsMethod) {
  EXPECT_EQ(method_names(), (std::vector<std::string>{"pathtrace", "direct", "antiradiance",
                                                      "meshless", "splatting", "grid"}));
  EXPECT_NE(std::find(method_names().begin(), method_names().end(), kDefaultMethod),
            method_names().end());
  for (const std::string& method : method_names()) {
    SCOPED_TRACE(method);
    EXPECT_EQ(std::get<std::string>(method_schema(method).find("method")->fallback),
              kDefaultMethod);
    EXPECT_NE(make_solver(method), nullptr);
  }
}

TEST(SettingSchema, TheCApiDescribesEachMethod) {
  size_t length = 0;
  ASSERT_EQ(bakegi_settings_describe(nullptr, nullptr, 0, &length), BAKEGI_OK);
  std::string all(length + 1, '\0');
  ASSERT_EQ(bakegi_settings_describe("", all.data(), all.size(), nullptr), BAKEGI_OK);
  all.resize(length);
  EXPECT_EQ(all,
            "{\"methods\": [\"pathtrace\", \"direct\", \"antiradiance\", \"meshless\", "
            "\"splatting\", \"grid\"], "
            "\"default\": \"pathtrace\", \"default_settings\": {\"denoise\": 1, "
            "\"samples\": 65536, \"target_error\": 0.050000000000000003}}");

  ASSERT_EQ(bakegi_settings_describe("meshless", nullptr, 0, &length), BAKEGI_OK);
  std::string meshless(length + 1, '\0');
  ASSERT_EQ(bakegi_settings_describe("meshless", meshless.data(), meshless.size(), nullptr),
            BAKEGI_OK);
  EXPECT_NE(meshless.find("{\"key\": \"cache_dir\", \"type\": \"text\", \"default\": \"\", "
                          "\"choices\": [], \"role\": \"execution\""),
            std::string::npos)
      << meshless;
  // A short buffer gets a NUL-terminated prefix.
  char small[8];
  ASSERT_EQ(bakegi_settings_describe("meshless", small, sizeof small, nullptr), BAKEGI_OK);
  EXPECT_EQ(std::string(small), meshless.substr(0, 7));

  EXPECT_EQ(bakegi_settings_describe("radiosity", nullptr, 0, &length),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("unknown method 'radiosity'"), std::string::npos);
  EXPECT_EQ(bakegi_settings_describe("meshless", nullptr, 0, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
}

}  // namespace
}  // namespace bakegi
