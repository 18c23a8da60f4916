// What a view shows where no photograph does: surfaces no photograph textures are shaded with a
// neutral material under a hemisphere light and a sun, and pixels that see no geometry show a sky
// gradient, as the base materials of iTowns, Potree and Cesium do, so that a scene without
// photographs (or a view beyond them) still shows its geometry. Neither counts as coverage: the
// output alpha stays 0 there (docs/design.md, "Untextured surfaces and the sky").
//
// Colours are linear [0, 1] RGB written as they are (no tone mapping). Directions are in the
// render frame; `up` is Scene::up. The GLSL twins (hv_shadeUntextured, hv_skyColor) are in
// shaders/untextured.glsl; render/untextured_gltest.cpp checks that they agree.
#pragma once

#include <glm/glm.hpp>

namespace hv::render {

struct UntexturedSettings {
  // Surfaces no photograph textures are shaded (false: the background colour, as in the papers).
  bool shading = true;
  // Pixels without geometry show the sky gradient (false: the background colour).
  bool sky = true;
  // Untextured terrain shows the scene's orthophoto (Scene::orthophoto, scene.json "orthophoto")
  // where it covers it, as it is (not relit: it carries its own light), instead of the shading.
  bool orthophoto = true;
  glm::dvec3 albedo{0.80, 0.80, 0.78};  // the neutral material (Lambert)
  // Hemisphere light (ambient): groundLight on a surface facing down, skyLight on one facing up,
  // mixed by (1 + n.up) / 2 in between.
  glm::dvec3 skyLight{0.55, 0.57, 0.62};
  glm::dvec3 groundLight{0.22, 0.21, 0.20};
  glm::dvec3 sunLight{0.50, 0.49, 0.46};  // the directional term, times max(0, n.sun)
  // Where the sun is: azimuth clockwise from `north` towards `east` (tangentFrame), elevation
  // above the horizon.
  double sunAzimuthDeg = 150.0;
  double sunElevationDeg = 45.0;
  glm::dvec3 horizon{0.78, 0.85, 0.93};  // sky colour at elevation 0 and below
  glm::dvec3 zenith{0.33, 0.52, 0.82};   // sky colour straight up
};

// Two horizontal unit directions completing `up` (normalised) to a right-handed frame:
// east x north = up. east is the scene's x axis made horizontal (its y axis when up is near x), as
// the viewer's navigation frame (hv/viewer/navigation.cpp).
struct TangentFrame {
  glm::dvec3 east, north, up;
};
TangentFrame tangentFrame(const glm::dvec3& up);

// Unit direction towards the sun (render frame) for s.sunAzimuthDeg / s.sunElevationDeg.
glm::dvec3 sunDirection(const glm::dvec3& up, const UntexturedSettings& s);

// The colour of an untextured surface with unit normal `normal` facing the viewer:
// albedo * (mix(groundLight, skyLight, (1 + n.up) / 2) + sunLight * max(0, n.sun)), clamped to [0, 1].
glm::dvec3 shadeUntextured(const glm::dvec3& normal, const glm::dvec3& up, const UntexturedSettings& s);

// The sky seen along `direction` (any length > 0): mix(horizon, zenith, sqrt(e)) with e the sine of
// the direction's elevation above the horizon, clamped to [0, 1] (below the horizon: the horizon
// colour). The square root makes the sky pale near the horizon only, as a clear sky is.
glm::dvec3 skyColor(const glm::dvec3& direction, const glm::dvec3& up, const UntexturedSettings& s);

}  // namespace hv::render
