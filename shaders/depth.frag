#version 300 es
// Stores *linear* depth (distance along the camera axis) mapped to [0, 1] between near and far,
// so that the shadow bias is in scene units and the precision is uniform over the range
// (DESIGN.md §2 step 3). gl_FragCoord.w is 1 / clip w = 1 / z_camera.
// A surface that did not exist at the photograph's date is not drawn: the photograph sees
// through it (issue 3, time). With HV_WRITE_BUILDING (the view's geometry pass) the building index
// is written too, for the shading pass's validity test.
precision highp float;
uniform float u_near;
uniform float u_far;
uniform vec2 u_date;  // the photograph's date interval, days
flat in vec2 v_validity;
flat in float v_building;
#ifdef HV_WRITE_BUILDING
out vec4 o_building;
#endif
void main() {
  if (v_validity.y < u_date.x || v_validity.x > u_date.y) discard;
  gl_FragDepth = clamp((1.0 / gl_FragCoord.w - u_near) / (u_far - u_near), 0.0, 1.0);
#ifdef HV_WRITE_BUILDING
  // 24-bit index in r, g, b; exact in RGBA8 for up to 16 million buildings.
  float id = v_building;
  o_building = vec4(mod(id, 256.0), mod(floor(id / 256.0), 256.0), floor(id / 65536.0), 255.0) / 255.0;
#endif
}
