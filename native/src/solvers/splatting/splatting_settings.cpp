#include "solvers/splatting/splatting_settings.h"

#include "settings/settings.h"
#include "solvers/method_registry.h"

namespace bakegi {

namespace {

using R = SettingRole;

template <typename Enum>
Enum pick(const std::string& value, const std::vector<std::pair<const char*, Enum>>& table) {
  for (const auto& [name, e] : table) {
    if (value == name) return e;
  }
  return table.front().second;  // the schema has checked the choice
}

}  // namespace

const std::vector<SettingSpec>& SplattingSettings::specs() {
  static const std::vector<SettingSpec> specs = {
      integer_setting("vpl_count", 1024, 1, 65536, R::kLighting,
                      "virtual point lights taken from the reflective shadow maps (the preview: "
                      "256 unless set)"),
      text_setting("vpl_sampling", "regular", {"regular", "importance"}, R::kLighting,
                   "regular: the paper's fixed grid over each map; importance: texels drawn "
                   "by reflected flux"),
      integer_setting("rsm_resolution", 128, 4, 2048, R::kLighting,
                      "texels per side of each light's reflective shadow maps"),
      integer_setting("rsm_spots", 16, 1, 1024, R::kLighting,
                      "views per area light, for emissive meshes and for the world"),
      integer_setting("base_resolution", 32, 1, 4096, R::kLighting,
                      "the bake: cells of the coarsest level per side of the points' extent; "
                      "the preview: texels of the coarsest level along the image's larger side "
                      "(16 unless set, the paper's)"),
      integer_setting("max_resolution", 0, 0, 16384, R::kLighting,
                      "texels of the finest subsplat level along the larger side; 0: pixels"),
      text_setting("refinement", "shared", {"shared", "illumination", "none"}, R::kLighting,
                   "shared: one subsplat set for all VPLs refined at depth and normal "
                   "discontinuities (paper 3.3); illumination: refined per VPL where its light "
                   "differs (3.3.1); none: every pixel (full-resolution splatting)"),
      text_setting("depth_test", "range", {"range", "derivative"}, R::kLighting,
                   "min-max mipmap of relative depth, or max-mipmap of |grad z|/z (3.2.1)"),
      number_setting("depth_threshold", 0.03, 0.0, 100.0, R::kLighting,
                     "relative depth range (or derivative per pixel) that splits a subsplat"),
      text_setting("normal_test", "components", {"components", "curvature"}, R::kLighting,
                   "min-max of each normal component, or max curvature 2 sin(angle/2) (3.2.2); "
                   "the preview: curvature unless set (the bake's point cells test components)"),
      number_setting("normal_threshold", 0.5, 0.0, 2.0, R::kLighting,
                     "normal component range (or curvature) that splits a subsplat; the "
                     "preview's curvature test: 0.1 unless set"),
      text_setting("refine_neighbours", "diagonal", {"none", "diagonal", "all"}, R::kLighting,
                   "neighbours whose discontinuity also splits a subsplat (paper 5.2); the "
                   "preview: none unless set"),
      number_setting("illumination_threshold", 0.25, 0.0, 100.0, R::kLighting,
                     "refinement 'illumination': relative difference that splits a subsplat"),
      number_setting("light_threshold", 0.05, 0.0, 100.0, R::kLighting,
                     "refinement 'shared': also split where the summed light's second "
                     "difference between neighbouring subsplats exceeds this fraction of it "
                     "(flat surfaces near bright VPLs); 0: depth and normal tests only"),
      text_setting("upsampling", "interpolated", {"interpolated", "nearest", "bilinear"},
                   R::kLighting,
                   "combining the levels: the paper's interpolation (3.5), or the nearest and "
                   "naive bilinear upsampling of its Fig. 7"),
      number_setting("detail_alpha", 0.0, 0.0, 1.0, R::kLighting,
                     "surface detail from the view angle (paper 4.3, equation 3); 0: off"),
      integer_setting("direct_samples", 1, 0, 4096, R::kLighting,
                      "preview: light samples per pixel for direct light"),
      number_setting("glossy_fold_exponent", 16.0, 0.0, 1e6, R::kLighting,
                     "preview: glossy lobes with a lower exponent reflect as diffuse (energy "
                     "kept; 16 is roughness above about 0.42, a Principled coat's 7.5 folds); "
                     "0 keeps every lobe"),
      integer_setting("visibility_clusters", 64, 0, 4096, R::kLighting,
                      "shadow rays per receiver towards clustered VPLs (0: no visibility for "
                      "the indirect bounce, as in the paper; the preview: 0 unless set)"),
      number_setting("near_field_split", 2.0, 0.0, 100.0, R::kLighting,
                     "a VPL closer than this many radii of the surface it stands for sends its "
                     "texels' light instead (the near field the paper clamps); 0: never. The "
                     "preview uses 0 unless this is set"),
      integer_setting("gather_rays", 32, 0, 4096, R::kLighting,
                      "bake: cosine rays per point that add the near field the VPLs leave out "
                      "(their geometry term is clamped there; bias compensation); 0: none, the "
                      "VPLs bounded by their own surface (and near_field_split)"),
      number_setting("gather_radii", 4.0, 0.1, 100.0, R::kLighting,
                     "bake: where the clamp starts, in radii of a VPL's mean surface"),
  };
  return specs;
}

SplattingSettings SplattingSettings::from(const Settings& settings) {
  const SettingReader read(settings, method_schema("splatting"));
  SplattingSettings s;
  s.vpl_count = uint32_t(read.get_int("vpl_count"));
  s.vpl_sampling = pick<VplSampling>(
      read.get_string("vpl_sampling"),
      {{"regular", VplSampling::kRegular}, {"importance", VplSampling::kImportance}});
  s.rsm.resolution = uint32_t(read.get_int("rsm_resolution"));
  s.rsm.spots = uint32_t(read.get_int("rsm_spots"));
  s.base_resolution = uint32_t(read.get_int("base_resolution"));
  s.max_resolution = uint32_t(read.get_int("max_resolution"));
  s.refinement = pick<SubsplatRefinement>(read.get_string("refinement"),
                                          {{"shared", SubsplatRefinement::kShared},
                                           {"illumination", SubsplatRefinement::kIllumination},
                                           {"none", SubsplatRefinement::kNone}});
  s.discontinuity.depth =
      pick<DepthTest>(read.get_string("depth_test"),
                      {{"range", DepthTest::kRange}, {"derivative", DepthTest::kDerivative}});
  s.discontinuity.depth_threshold = float(read.get_float("depth_threshold"));
  s.discontinuity.normal = pick<NormalTest>(
      read.get_string("normal_test"),
      {{"components", NormalTest::kComponents}, {"curvature", NormalTest::kCurvature}});
  s.discontinuity.normal_threshold = float(read.get_float("normal_threshold"));
  s.discontinuity.neighbours = pick<NeighbourTest>(read.get_string("refine_neighbours"),
                                                   {{"diagonal", NeighbourTest::kDiagonal},
                                                    {"none", NeighbourTest::kNone},
                                                    {"all", NeighbourTest::kAll}});
  s.illumination_threshold = float(read.get_float("illumination_threshold"));
  s.light_threshold = float(read.get_float("light_threshold"));
  s.upsampling =
      pick<Upsampling>(read.get_string("upsampling"), {{"interpolated", Upsampling::kInterpolated},
                                                       {"nearest", Upsampling::kNearest},
                                                       {"bilinear", Upsampling::kBilinear}});
  s.detail_alpha = float(read.get_float("detail_alpha"));
  s.glossy_fold_exponent = float(read.get_float("glossy_fold_exponent"));
  s.direct_samples = uint32_t(read.get_int("direct_samples"));
  s.visibility_clusters = uint32_t(read.get_int("visibility_clusters"));
  s.near_field_split = float(read.get_float("near_field_split"));
  s.gather_rays = uint32_t(read.get_int("gather_rays"));
  s.gather_radii = float(read.get_float("gather_radii"));
  s.seed = uint64_t(read.get_int("seed"));
  return s;
}

}  // namespace bakegi
