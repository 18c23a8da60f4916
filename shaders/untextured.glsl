// What shows where no photograph does (docs/design.md, "Untextured surfaces and the sky"): a
// neutral Lambert material under a hemisphere light and a sun, and a sky gradient. Twins of
// hv::render::shadeUntextured and hv::render::skyColor (src/hv/render/untextured.cpp; the same
// formulas, the settings of hv::render::UntexturedSettings as these uniforms);
// src/hv/render/untextured_gltest.cpp checks that they agree.
uniform bool u_shading;        // untextured surfaces shaded, else the background colour
uniform bool u_sky;            // pixels without geometry show the sky, else the background colour
uniform vec3 u_up;             // Scene::up, unit, render frame
uniform vec3 u_sunDir;         // unit, towards the sun (hv::render::sunDirection)
uniform vec3 u_albedo;
uniform vec3 u_skyLight;
uniform vec3 u_groundLight;
uniform vec3 u_sunLight;
uniform vec3 u_horizon;
uniform vec3 u_zenith;

// `normal`: unit, facing the viewer.
vec3 hv_shadeUntextured(vec3 normal) {
  float t = 0.5 * (1.0 + dot(normal, u_up));
  vec3 ambient = mix(u_groundLight, u_skyLight, t);
  float sun = max(0.0, dot(normal, u_sunDir));
  return clamp(u_albedo * (ambient + u_sunLight * sun), 0.0, 1.0);
}

// `direction`: any length > 0.
vec3 hv_skyColor(vec3 direction) {
  float e = clamp(dot(normalize(direction), u_up), 0.0, 1.0);
  return mix(u_horizon, u_zenith, sqrt(e));
}
