#include "api/live_handles.h"

#include <mutex>
#include <string>
#include <unordered_map>

#include "api/api_guard.h"
#include "util/error.h"

namespace bakegi {

namespace {

struct Registry {
  std::mutex mutex;
  std::unordered_map<const void*, const char*> kinds;
};

Registry& registry() {
  static Registry* live = new Registry();  // never destroyed: handles may outlive statics
  return *live;
}

}  // namespace

void remember_handle(const void* handle, const char* kind) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  r.kinds[handle] = kind;
}

bool forget_handle(const void* handle, const char* kind) {
  Registry& r = registry();
  {
    const std::lock_guard<std::mutex> lock(r.mutex);
    const auto found = r.kinds.find(handle);
    if (found != r.kinds.end() && std::string(found->second) == kind) {
      r.kinds.erase(found);
      return true;
    }
  }
  fail(BAKEGI_ERROR_INVALID_ARGUMENT, std::string("bakegi_") + kind + "_destroy: not a live " +
                                          kind + " handle (destroyed already?); nothing was done");
  return false;
}

bool is_live_handle(const void* handle, const char* kind) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto found = r.kinds.find(handle);
  return found != r.kinds.end() && std::string(found->second) == kind;
}

void require_live_handle(const void* handle, const char* kind, const char* name) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto found = r.kinds.find(handle);
  if (found == r.kinds.end()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                std::string(name) + " is not a live " + kind +
                    " handle (destroyed already, or not made by this library)");
  }
  if (std::string(found->second) != kind) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, std::string(name) + " is a " + found->second +
                                                   " handle, not a " + kind + " handle");
  }
}

}  // namespace bakegi
