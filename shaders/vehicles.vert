#version 300 es
// The traffic (render/gl/vehicles_pass.cpp): instanced boxes and a contact-shadow quad per vehicle.
// The model (render/vehicles.h, vehicleParts) is in the vehicle frame as fractions of the
// vehicle's size: x of its width (right), y of its length (forward), z of its height (up).
precision highp float;
layout(location = 0) in vec3 a_local;    // fractions of (width, length, height)
layout(location = 1) in vec3 a_normal;   // vehicle frame
layout(location = 2) in float a_kind;    // 0 body, 1 glass, 2 the contact shadow
layout(location = 3) in vec3 i_position; // render frame, the footprint's centre on the terrain
layout(location = 4) in vec3 i_right;
layout(location = 5) in vec3 i_forward;
layout(location = 6) in vec3 i_up;
layout(location = 7) in vec3 i_size;     // length, width, height (metres)
layout(location = 8) in vec3 i_colour;
uniform mat4 u_clipFromRender;  // hv::ibr::clipFromRender (src/hv/ibr/frame_plan.cpp)
uniform float u_shadowLift;     // metres above the terrain (render/vehicles.h, kShadowLift)
out vec3 v_normal;   // render frame
out vec3 v_colour;
out vec2 v_shadowUv; // the shadow quad's corners at +-1
flat out float v_kind;
void main() {
  vec3 m = a_local * vec3(i_size.y, i_size.x, i_size.z);
  vec3 p = i_position + m.x * i_right + m.y * i_forward + m.z * i_up;
  if (a_kind > 1.5) p += u_shadowLift * i_up;
  v_normal = a_normal.x * i_right + a_normal.y * i_forward + a_normal.z * i_up;
  v_colour = i_colour;
  v_shadowUv = sign(a_local.xy);
  v_kind = a_kind;
  gl_Position = u_clipFromRender * vec4(p, 1.0);
}
