// Every handle the C API has given out and not yet destroyed. A call with a handle that is
// not live (destroyed already, never made by this library, or a handle of another kind) is
// refused with INVALID_ARGUMENT instead of touching freed memory, and destroying one twice
// does nothing: inside Blender a use after free is a crash that loses the user's work.
// Best effort by nature: a new handle that reuses a destroyed one's address reads as live.
#pragma once

#include <memory>

#include "bakegi/bakegi.h"

namespace bakegi {

// The kind a handle type is checked as; only the C API's opaque handles have one.
template <typename T>
struct HandleKind {
  static constexpr const char* name = nullptr;
};
#define BAKEGI_HANDLE_KIND(type, text)        \
  template <>                                 \
  struct HandleKind<type> {                   \
    static constexpr const char* name = text; \
  }
BAKEGI_HANDLE_KIND(bakegi_scene, "scene");
BAKEGI_HANDLE_KIND(bakegi_points, "points");
BAKEGI_HANDLE_KIND(bakegi_settings, "settings");
BAKEGI_HANDLE_KIND(bakegi_job, "job");
BAKEGI_HANDLE_KIND(bakegi_lightmaps, "lightmaps");
BAKEGI_HANDLE_KIND(bakegi_grid, "grid");
BAKEGI_HANDLE_KIND(bakegi_preview, "preview");
#undef BAKEGI_HANDLE_KIND

void remember_handle(const void* handle, const char* kind);
// False when `handle` is not a live handle of `kind` (then nothing is forgotten).
bool forget_handle(const void* handle, const char* kind);
bool is_live_handle(const void* handle, const char* kind);
// For the calls that return a value, not a status (progress, counts): a dead handle reads
// as empty instead of being touched.
template <typename Handle>
bool live(const Handle* handle) {
  return handle && is_live_handle(handle, HandleKind<Handle>::name);
}
// Throws Error(INVALID_ARGUMENT) "<name> is not a live <kind> handle (destroyed already?)".
void require_live_handle(const void* handle, const char* kind, const char* name);

// Hands a new handle to the caller, remembered as live (null stays null).
template <typename Handle>
Handle* give_out(std::unique_ptr<Handle> handle) {
  if (handle) remember_handle(handle.get(), HandleKind<Handle>::name);
  return handle.release();
}

// The body of every bakegi_*_destroy: deletes a live handle once; null, a destroyed or a
// foreign pointer is left alone (the error is recorded for bakegi_last_error).
template <typename Handle>
void destroy_handle(Handle* handle) {
  if (handle && forget_handle(handle, HandleKind<Handle>::name)) delete handle;
}

}  // namespace bakegi
