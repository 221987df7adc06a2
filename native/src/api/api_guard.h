// The wall between the core and its callers: every C entry point runs its body through
// guarded(), which turns any exception into a status and a thread-local message, so that
// nothing is ever thrown into Blender.
#pragma once

#include <new>
#include <string>

#include "api/live_handles.h"
#include "bakegi/bakegi.h"
#include "util/error.h"

namespace bakegi {

// Records the message for bakegi_last_error() on this thread and returns status.
bakegi_status fail(bakegi_status status, const std::string& message) noexcept;

// Throws Error(INVALID_ARGUMENT, "<name> is NULL") when pointer is null, and for one of the
// C API's handles when it is not live (api/live_handles.h: destroyed, foreign, other kind).
template <typename T>
void require(const T* pointer, const char* name) {
  if (!pointer) throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, std::string(name) + " is NULL");
  if constexpr (HandleKind<T>::name != nullptr) {
    require_live_handle(pointer, HandleKind<T>::name, name);
  }
}

template <typename Body>
bakegi_status guarded(const char* function, Body&& body) noexcept {
  try {
    body();
    return BAKEGI_OK;
  } catch (const Error& e) {
    // Messages about the scene, files and jobs are for users and stand alone; misuse of
    // the API names the function.
    if (e.status() == BAKEGI_ERROR_INVALID_ARGUMENT || e.status() == BAKEGI_ERROR_INTERNAL) {
      return fail(e.status(), std::string(function) + ": " + e.what());
    }
    return fail(e.status(), e.what());
  } catch (const std::bad_alloc&) {
    return fail(BAKEGI_ERROR_OUT_OF_MEMORY, std::string(function) + ": out of memory");
  } catch (const std::exception& e) {
    return fail(BAKEGI_ERROR_INTERNAL, std::string(function) + ": internal error: " + e.what());
  } catch (...) {
    return fail(BAKEGI_ERROR_INTERNAL, std::string(function) + ": internal error");
  }
}

}  // namespace bakegi
