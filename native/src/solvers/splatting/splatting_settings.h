// The settings of the splatting method (bake and preview alike), read once from a Settings.
#pragma once

#include <cstdint>
#include <vector>

#include "settings/setting_schema.h"
#include "solvers/splatting/min_max_mipmap.h"
#include "solvers/splatting/multiresolution_buffer.h"
#include "solvers/splatting/reflective_shadow_map.h"
#include "solvers/splatting/virtual_point_lights.h"

namespace bakegi {

class Settings;

enum class SubsplatRefinement { kShared, kIllumination, kNone };

struct SplattingSettings {
  RsmOptions rsm;
  uint32_t vpl_count = 1024;
  VplSampling vpl_sampling = VplSampling::kRegular;
  // Coarsest level: cells per side of the points' extent (the bake), texels along the image's
  // larger side (a preview; the C API gives frames 16, the paper's, unless set).
  uint32_t base_resolution = 32;
  uint32_t max_resolution = 0;  // finest level's texels along the larger side, 0: pixels
  DiscontinuityTest discontinuity;
  // kShared: §3.3 (one set for all VPLs); kIllumination: §3.3.1 (per VPL); kNone: every
  // pixel a subsplat (full-resolution splatting).
  SubsplatRefinement refinement = SubsplatRefinement::kShared;
  float illumination_threshold = 0.25f;
  // Shared refinement: split also where the summed light curves more than this fraction of
  // itself between neighbouring subsplats (0: the paper's geometric tests only).
  float light_threshold = 0.05f;
  Upsampling upsampling = Upsampling::kInterpolated;
  float detail_alpha = 0.0f;  // §4.3, equation 3
  uint32_t direct_samples = 1;
  // Preview: glossy lobes wider than this exponent reflect as diffuse (glossy_receivers.h).
  float glossy_fold_exponent = 16.0f;
  // Shadow rays per receiver towards clustered VPLs (0: none, the paper's approximation).
  uint32_t visibility_clusters = 64;
  // A VPL closer than this many radii of its surface sends its texels' light (0: never).
  float near_field_split = 2.0f;
  // Bake: cosine rays per point that add the near field the clamped VPLs leave out
  // (near_field_gather.h); 0: VPLs bounded by their surface and near_field_split instead.
  uint32_t gather_rays = 32;
  float gather_radii = 4.0f;  // the clamp's distance in radii of a VPL's mean surface
  uint64_t seed = 0;
  // Not a setting: whether SplatStatistics::pixel_levels is filled (the pictures want it).
  bool record_pixel_levels = false;

  static SplattingSettings from(const Settings& settings);
  static const std::vector<SettingSpec>& specs();
};

}  // namespace bakegi
