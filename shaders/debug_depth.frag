#version 300 es
// DebugView::DepthMap (hv/render/renderer.h): one photograph's depth map stretched over the
// rectangle [u_rectMin, u_rectMin + u_rectSize) of the output (its frustum's aspect ratio), the
// stored value as 16 bits in r, g (as encodeCount in ibr_shade.frag) and b = 1 inside the
// rectangle. The renderer reads it back and colours it between the nearest and farthest depths
// it finds (a range a shader cannot know without a reduction pass).
// Offscreen targets are stored top row first, and so are depth maps: t = (0, 0) is the top-left.
precision highp float;
precision highp int;
precision highp sampler2DArray;

uniform highp sampler2DArray u_depthMaps;
uniform float u_slice;
uniform vec2 u_rectMin;
uniform vec2 u_rectSize;

out vec4 o_value;

vec4 encode16(int v, float inside) { return vec4(float(v & 255) / 255.0, float(v >> 8) / 255.0, inside, 1.0); }

void main() {
  vec2 t = (gl_FragCoord.xy - u_rectMin) / u_rectSize;
  if (any(lessThan(t, vec2(0.0))) || any(greaterThanEqual(t, vec2(1.0)))) {
    o_value = encode16(65535, 0.0);
    return;
  }
  float d = texture(u_depthMaps, vec3(t, u_slice)).r;
  o_value = encode16(int(clamp(d, 0.0, 1.0) * 65535.0 + 0.5), 1.0);
}
