#version 300 es
// One texel of the view's linear depth (depth.frag: [0, 1] between near and far) packed into
// RGBA8, for a read-back that WebGL2 allows (a depth texture cannot be read with glReadPixels):
// 24 bits, r the low byte; alpha 1. Decoded by render/gl/pick_pass.cpp (GlBackend::readViewDepth).
precision highp float;
uniform highp sampler2D u_viewDepth;
uniform ivec2 u_texel;
out vec4 o_packed;
void main() {
  float d = clamp(texelFetch(u_viewDepth, u_texel, 0).r, 0.0, 1.0);
  // Integers up to 2^24 are exact in a highp float, but not 2^24 - 0.5: the cleared depth 1 would
  // round up to 2^24 (and wrap); hence the min.
  float v = min(floor(d * 16777215.0 + 0.5), 16777215.0);
  float b = floor(v / 65536.0);
  float g = floor((v - b * 65536.0) / 256.0);
  float r = v - b * 65536.0 - g * 256.0;
  o_packed = vec4(r, g, b, 255.0) / 255.0;
}
