#version 300 es
// Debug lines in 3D (the photographs' frusta, hv/camera/frustum_outline.h): render-frame
// positions through the view's pinhole transform.
precision highp float;
layout(location = 0) in vec3 a_position;
uniform mat4 u_clipFromRender;  // hv::ibr::clipFromRender (src/hv/ibr/frame_plan.cpp)
void main() {
  gl_Position = u_clipFromRender * vec4(a_position, 1.0);
}
