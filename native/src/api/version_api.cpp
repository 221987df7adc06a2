#if BAKEGI_EMBREE_MAJOR >= 4
#include <embree4/rtcore_config.h>
#else
#include <embree3/rtcore_config.h>
#endif
#if __has_include(<tbb/version.h>)
#include <tbb/version.h>  // oneTBB
#else
#include <tbb/tbb_stddef.h>  // TBB 2020 (the portable build's Debian 11)
#endif

#include <string_view>

#include "bakegi/bakegi.h"

extern "C" {

uint32_t bakegi_abi_version(void) { return BAKEGI_ABI_VERSION; }

size_t bakegi_struct_size(const char* name) {
  if (!name) return 0;
  const std::string_view n(name);
  if (n == "bakegi_material_desc") return sizeof(bakegi_material_desc);
  if (n == "bakegi_mesh_desc") return sizeof(bakegi_mesh_desc);
  if (n == "bakegi_light_desc") return sizeof(bakegi_light_desc);
  if (n == "bakegi_lightmap_info") return sizeof(bakegi_lightmap_info);
  if (n == "bakegi_grid_info") return sizeof(bakegi_grid_info);
  return 0;
}

uint32_t bakegi_version(void) {
  return BAKEGI_VERSION_MAJOR * 10000 + BAKEGI_VERSION_MINOR * 100 + BAKEGI_VERSION_PATCH;
}

#define BAKEGI_STRINGIFY_(x) #x
#define BAKEGI_STRINGIFY(x) BAKEGI_STRINGIFY_(x)
#define BAKEGI_VERSION_TEXT              \
  BAKEGI_STRINGIFY(BAKEGI_VERSION_MAJOR) \
  "." BAKEGI_STRINGIFY(BAKEGI_VERSION_MINOR) "." BAKEGI_STRINGIFY(BAKEGI_VERSION_PATCH)
#define BAKEGI_TBB_TEXT BAKEGI_STRINGIFY(TBB_VERSION_MAJOR) "." BAKEGI_STRINGIFY(TBB_VERSION_MINOR)

// A literal built by the preprocessor: static storage, nothing to fail at run time.
const char* bakegi_version_string(void) {
  return BAKEGI_VERSION_TEXT " (embree " RTC_VERSION_STRING ", tbb " BAKEGI_TBB_TEXT ")";
}

const char* bakegi_status_string(bakegi_status status) {
  switch (status) {
    case BAKEGI_OK:
      return "BAKEGI_OK";
    case BAKEGI_ERROR_INVALID_ARGUMENT:
      return "BAKEGI_ERROR_INVALID_ARGUMENT";
    case BAKEGI_ERROR_INVALID_SCENE:
      return "BAKEGI_ERROR_INVALID_SCENE";
    case BAKEGI_ERROR_OUT_OF_MEMORY:
      return "BAKEGI_ERROR_OUT_OF_MEMORY";
    case BAKEGI_ERROR_CANCELLED:
      return "BAKEGI_ERROR_CANCELLED";
    case BAKEGI_ERROR_IO:
      return "BAKEGI_ERROR_IO";
    case BAKEGI_ERROR_BAD_FILE:
      return "BAKEGI_ERROR_BAD_FILE";
    case BAKEGI_ERROR_NOT_READY:
      return "BAKEGI_ERROR_NOT_READY";
    case BAKEGI_ERROR_RAY_TRACER:
      return "BAKEGI_ERROR_RAY_TRACER";
    case BAKEGI_ERROR_INTERNAL:
      return "BAKEGI_ERROR_INTERNAL";
  }
  return "BAKEGI_UNKNOWN_STATUS";
}

}  // extern "C"
