#version 300 es
// Tile depth ranges for per-tile culling (hv::ibr::buildTileLists): one fragment per tile of the
// view's depth buffer; min and max of the normalised linear depth over the tile's surface texels,
// as two 16-bit values (min rounded down, max rounded up, so the range stays conservative).
// A tile with no surface writes min = 65535 > max = 0. Decoded by hv::ibr::decodeTileDepth.
precision highp float;
precision highp int;
precision highp sampler2D;

uniform highp sampler2D u_viewDepth;
uniform ivec2 u_depthSize;
uniform int u_tileSize;

out vec4 o_range;

vec2 encode16(uint v) { return vec2(float(v >> 8u), float(v & 255u)) / 255.0; }

void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * u_tileSize;
  float lo = 2.0, hi = -1.0;
  for (int y = 0; y < u_tileSize; ++y) {
    for (int x = 0; x < u_tileSize; ++x) {
      ivec2 p = base + ivec2(x, y);
      if (p.x >= u_depthSize.x || p.y >= u_depthSize.y) continue;
      float d = texelFetch(u_viewDepth, p, 0).r;
      if (d >= 1.0) continue;  // background
      lo = min(lo, d);
      hi = max(hi, d);
    }
  }
  if (hi < 0.0) {
    o_range = vec4(encode16(65535u), encode16(0u));
    return;
  }
  o_range = vec4(encode16(uint(floor(lo * 65535.0))), encode16(uint(min(ceil(hi * 65535.0), 65535.0))));
}
