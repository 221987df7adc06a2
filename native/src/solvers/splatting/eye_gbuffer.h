// The eye's G-buffer (Nichols & Wyman 2009, §3.1, after Saito & Takahashi): per pixel the
// surface the camera sees (position, shading normal, linear depth, albedo, emission), traced
// with Embree, and the direct light there. The preview keeps it while only lights change.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct Scene;
class RayTracer;
class DirectLight;

// A pinhole camera: the image plane spans vertical field of view fov_y (radians) and the
// pixel aspect width/height, shifted by (shift_x, shift_y) in units of the larger side (as
// Blender's lens shift). Orthographic when ortho_scale > 0: the larger side spans it.
struct PreviewCamera {
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y = 0.8f;
  float shift_x = 0.0f, shift_y = 0.0f;
  float ortho_scale = 0.0f;
  bool operator==(const PreviewCamera&) const = default;
};

struct EyeGBuffer {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> hit;  // 1 where a surface was seen
  std::vector<float> depth;  // along the camera's forward axis; +inf where missed
  std::vector<glm::vec3> position;
  std::vector<glm::vec3> normal;     // shading normal facing the camera
  std::vector<glm::vec3> geometric;  // geometric normal facing the camera
  std::vector<glm::vec3> albedo;
  std::vector<glm::vec3> glossy;       // the Phong lobe's reflectance (0: diffuse only)
  std::vector<float> glossy_exponent;  // its exponent where glossy
  std::vector<glm::vec3> emission;     // radiance towards the camera
  std::vector<glm::vec3> view;         // unit direction from the surface to the eye
  size_t size() const { return size_t(width) * height; }
  size_t index(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
};

// Traces one ray per pixel centre (row 0 at the top of the image).
EyeGBuffer trace_eye_gbuffer(const Scene& scene, const RayTracer& tracer,
                             const PreviewCamera& camera, uint32_t width, uint32_t height);

// Direct irradiance / pi at every seen pixel (0 elsewhere), `samples` samples per pixel
// seeded per pixel: DirectLight::lamp_irradiance (one shadow ray per light) where the world
// is black, else irradiance_sample (MIS with one cosine ray that also finds the world).
std::vector<glm::vec3> eye_direct_light(const EyeGBuffer& gbuffer, const DirectLight& direct,
                                        uint32_t samples, uint64_t seed);

}  // namespace bakegi
