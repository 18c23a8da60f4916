#version 300 es
// Layered projective texture maps (2003, §4.1) on the GPU: the objects of a scene seen from a
// photograph's camera, each triangle with its object id (bit 31: a terrain triangle) and its
// geometric normal as wound, (v1 - v0) x (v2 - v0), as the ray caster orients it.
precision highp float;
layout(location = 0) in vec3 a_position;  // render frame (world minus the origin)
layout(location = 1) in vec3 a_normal;
layout(location = 2) in uint a_object;
uniform mat4 u_clipFromRender;  // hv::clipFromRender (camera/frustum.h)
out vec3 v_position;
flat out vec3 v_normal;
flat out uint v_object;
void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_object = a_object;
  gl_Position = u_clipFromRender * vec4(a_position, 1.0);
}
