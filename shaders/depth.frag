#version 300 es
// Stores *linear* depth (distance along the camera axis) mapped to [0, 1] between near and far,
// so that the shadow bias is in scene units and the precision is uniform over the range
// (Brédif 2013 §2.2; docs/design.md, step 3). gl_FragCoord.w is 1 / clip w = 1 / z_camera.
// A surface that did not exist at the photograph's date is not drawn: the photograph sees
// through it (building validity dates, docs/formats.md). With HV_WRITE_BUILDING (the view's
// geometry pass) the building index is written too, for the date test of the mesh and point passes
// (hv_surfaceExisted in image_test.glsl).
precision highp float;
uniform float u_near;
uniform float u_far;
uniform vec2 u_date;  // the photograph's date interval, days
// Hybrid rendering (2016 §4.2): in a photograph's depth map that also holds points, the mesh is
// stored as if moved u_pushBack (scene units) back along its normal, so that points up to that far
// behind the LOD1 surface (windows, doors, a road under a coarse DTM) are not shadowed by it. Along
// the camera's ray that is u_pushBack / cos(theta), theta between the ray and the normal (cos
// clamped at 0.1, the shadow bias's clamp). 0: the true depth.
uniform float u_pushBack;
uniform vec3 u_center;  // the camera centre, render frame
in vec3 v_position;
flat in vec2 v_validity;
flat in float v_building;
#ifdef HV_WRITE_BUILDING
out vec4 o_building;
#endif
void main() {
  // Derivatives first, in uniform control flow.
  vec3 n = cross(dFdx(v_position), dFdy(v_position));
  if (v_validity.y < u_date.x || v_validity.x > u_date.y) discard;
  float push = 0.0;
  if (u_pushBack > 0.0) {
    float len = length(n);
    float c = len > 0.0 ? abs(dot(n / len, normalize(v_position - u_center))) : 1.0;
    push = u_pushBack / max(c, 0.1);
  }
  gl_FragDepth = clamp((1.0 / gl_FragCoord.w + push - u_near) / (u_far - u_near), 0.0, 1.0);
#ifdef HV_WRITE_BUILDING
  // 24-bit index in r, g, b; exact in RGBA8 for up to 16 million buildings.
  float id = v_building;
  o_building = vec4(mod(id, 256.0), mod(floor(id / 256.0), 256.0), floor(id / 65536.0), 255.0) / 255.0;
#endif
}
