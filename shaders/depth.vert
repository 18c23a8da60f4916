#version 300 es
// Depth pass: the scene as seen from one pinhole camera (a photograph's depth map, or the view's
// geometry pass). Positions are in the render frame (world minus the scene origin).
precision highp float;
layout(location = 0) in vec3 a_position;
uniform mat4 u_clipFromRender;  // hv::ibr::clipFromRender (src/hv/ibr/frame_plan.cpp)
void main() { gl_Position = u_clipFromRender * vec4(a_position, 1.0); }
