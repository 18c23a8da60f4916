#version 300 es
// The view's depth for the traffic (render/gl/vehicles_pass.cpp): the linear depth that depth.frag
// stores (distance along the camera axis mapped to [0, 1] between near and far) rewritten as the
// rasteriser's own depth for the same pinhole projection (hv::clipFromRender: window depth
// far (z - near) / ((far - near) z) for a camera depth z). The vehicles are then drawn against it
// without writing gl_FragDepth, so that the rasteriser tests their depth before shading them
// (early depth test), and compare with the picture's geometry as before.
precision highp float;
uniform highp sampler2D u_viewDepth;
uniform float u_near;
uniform float u_far;
void main() {
  float linear = texelFetch(u_viewDepth, ivec2(gl_FragCoord.xy), 0).r;
  // 1: nothing there (the cleared depth), the far plane either way.
  float z = u_near + linear * (u_far - u_near);
  gl_FragDepth = linear >= 1.0 ? 1.0 : clamp(u_far * (z - u_near) / ((u_far - u_near) * z), 0.0, 1.0);
}
