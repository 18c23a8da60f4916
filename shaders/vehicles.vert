#version 300 es
// The traffic (render/gl/vehicles_pass.cpp): a vehicle class's model instanced per vehicle, or the
// contact-shadow quad under each. The model (hv/traffic/vehicle_model.h) is in the vehicle frame
// as fractions of the vehicle's size: x of its width (right), y of its length (forward), z of its
// height (up).
precision highp float;
layout(location = 0) in vec3 a_local;    // fractions of (width, length, height)
layout(location = 1) in vec3 a_normal;   // vehicle frame
layout(location = 2) in vec4 a_colour;   // material colour, w 1: the vehicle's paint instead
layout(location = 3) in vec3 i_position; // render frame, the footprint's centre on the terrain
layout(location = 4) in vec3 i_right;
layout(location = 5) in vec3 i_forward;
layout(location = 6) in vec3 i_up;
layout(location = 7) in vec3 i_size;     // length, width, height (metres)
layout(location = 8) in vec3 i_colour;
uniform mat4 u_clipFromRender;  // hv::ibr::clipFromRender (src/hv/ibr/frame_plan.cpp)
uniform float u_shadowLift;     // metres above the terrain (render/vehicles.h, kShadowLift)
uniform float u_shadow;         // 1: the contact-shadow quad
out vec3 v_normal;   // render frame
out vec3 v_colour;
out vec2 v_shadowUv; // the shadow quad's corners at +-1
void main() {
  vec3 m = a_local * vec3(i_size.y, i_size.x, i_size.z);
  vec3 p = i_position + m.x * i_right + m.y * i_forward + m.z * i_up + u_shadow * u_shadowLift * i_up;
  // The model's normals are fitted to the unit box (hv::fitToUnitBox): scaled by the inverse size
  // they are normal to the scaled surface again.
  vec3 n = a_normal / vec3(i_size.y, i_size.x, i_size.z);
  v_normal = n.x * i_right + n.y * i_forward + n.z * i_up;
  v_colour = mix(a_colour.rgb, i_colour, a_colour.w);
  v_shadowUv = sign(a_local.xy);
  gl_Position = u_clipFromRender * vec4(p, 1.0);
}
