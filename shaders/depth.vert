#version 300 es
// Depth pass: the scene as seen from one pinhole camera (a photograph's depth map, or the view's
// geometry pass). Positions are in the render frame (world minus the scene origin).
precision highp float;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_validity;   // days [first, last] the surface existed (buildings)
layout(location = 2) in float a_building;  // building index + 1 (0: terrain)
uniform mat4 u_clipFromRender;  // hv::ibr::clipFromRender (src/hv/ibr/frame_plan.cpp)
flat out vec2 v_validity;
flat out float v_building;
out vec3 v_position;  // render frame, for the surface normal (depth.frag's push-back)
void main() {
  v_position = a_position;
  v_validity = a_validity;
  v_building = a_building;
  gl_Position = u_clipFromRender * vec4(a_position, 1.0);
}
