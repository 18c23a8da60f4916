#version 300 es
// Mesh pass, deferred: for each output pixel, the surface point P is rebuilt from the view's
// linear depth along the pixel's exact ray, then textured by the selected photographs
// (DESIGN.md §2 step 5; Brédif 2013 eq. 1-2). The CPU twin is hv::ibr::referenceBlend.
// Offscreen targets are stored top row first, so gl_FragCoord.xy is the pixel position in the
// top-left-corner convention of hv/camera/camera.h.
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler2DArray;

#include "ibr_common.glsl"
#include "image_binding.glsl"

uniform highp sampler2D u_viewDepth;       // the view's geometry pass, same encoding
uniform highp sampler2D u_idealLookup;     // distorted views: ideal pixel of each output pixel
uniform highp sampler2D u_viewBuilding;    // building index + 1 of each view-depth texel (RGBA8)
uniform highp sampler2D u_validity;        // per building index: days [first, last] (RGBA32F rows)
uniform int u_validityWidth;
uniform highp usampler2D u_tileLists;      // per tile (row tileY * tilesX + tileX): count, then indices
uniform bool u_culling;
uniform int u_tileSize;                    // in view-depth texels
uniform int u_tilesX;
uniform bool u_useLookup;
uniform vec2 u_viewRectMin;
uniform vec2 u_viewRectInvSize;
uniform ivec2 u_viewDepthSize;
uniform float u_viewNear;
uniform float u_viewFar;
uniform vec3 u_viewCenter;      // render frame
uniform mat3 u_viewDirFromPix;  // R^T K^-1: world direction (camera z = 1) of an ideal pixel
uniform int u_imageCount;
uniform int u_method;           // 0 blend, 1 nearest
uniform bool u_occlusion;
uniform int u_mode;             // 0 colour, 1 contributing-image count, 2 loop length (16 bits in r, g)
uniform vec3 u_background;

out vec4 o_color;

void writeBackground() {
  o_color = u_mode != 0 ? vec4(0.0) : vec4(u_background, 0.0);
}

vec4 encodeCount(int n) { return vec4(float(n & 255) / 255.0, float(n >> 8) / 255.0, 0.0, 1.0); }

// Depth-map test with a slope-scaled bias: within one depth-map texel, a surface seen at angle
// theta from its normal spans footprint * tan(theta) of depth, so the bias grows with tan(theta)
// (clamped). `n` is the surface normal, `toP` the unit direction from the photograph to P.
// Twin of hv::ibr::shadowBias (src/hv/ibr/frame_plan.h).
float hv_shadowBias(HvImage im, float z, vec3 n, vec3 toP) {
  float c = max(abs(dot(n, toP)), 0.1);
  float tanTheta = sqrt(max(1.0 - c * c, 0.0)) / c;
  return im.biasAbs + im.biasRel * z * (1.0 + tanTheta);
}

void main() {
  // Everything up to the normal runs in uniform control flow: derivatives are only defined there.
  vec2 pIdeal = gl_FragCoord.xy;
  bool background = false;
  if (u_useLookup) {
    vec4 l = texelFetch(u_idealLookup, ivec2(gl_FragCoord.xy), 0);
    background = l.z < 0.5;  // outside the distortion domain
    pIdeal = l.xy;
  }
  vec2 t = (pIdeal - u_viewRectMin) * u_viewRectInvSize;
  ivec2 dpix = clamp(ivec2(floor(t * vec2(u_viewDepthSize))), ivec2(0), u_viewDepthSize - 1);
  float d = texelFetch(u_viewDepth, dpix, 0).r;
  background = background || d >= 1.0;
  float zView = mix(u_viewNear, u_viewFar, d);
  vec3 P = u_viewCenter + zView * (u_viewDirFromPix * vec3(pIdeal, 1.0));
  vec3 normal = cross(dFdx(P), dFdy(P));
  normal = dot(normal, normal) > 0.0 ? normalize(normal) : vec3(0.0, 0.0, 1.0);
  if (background) {
    writeBackground();
    return;
  }
  // When the surface under this pixel existed (terrain: always).
  vec2 existed = vec2(-1e7, 1e7);
  vec4 b = texelFetch(u_viewBuilding, dpix, 0) * 255.0;
  int building = int(b.r + 0.5) + 256 * int(b.g + 0.5) + 65536 * int(b.b + 0.5);
  if (building > 0) {
    int index = building - 1;
    existed = texelFetch(u_validity, ivec2(index % u_validityWidth, index / u_validityWidth), 0).xy;
  }

  // The images to visit: this tile's list (hv::ibr::buildTileLists), or every selected image.
  int row = 0;
  int n = u_imageCount;
  if (u_culling) {
    ivec2 tile = dpix / u_tileSize;
    row = tile.y * u_tilesX + tile.x;
    n = int(texelFetch(u_tileLists, ivec2(0, row), 0).r);
  }
  vec3 sum = vec3(0.0);
  float alpha = 0.0;
  int count = 0;
  for (int k = 0; k < n; ++k) {
    int i = u_culling ? int(texelFetch(u_tileLists, ivec2(k + 1, row), 0).r) : k;
    HvImage im = hv_fetchImage(i);
    vec2 p, pd;
    float z;
    if (!hv_project(im, P, p, pd, z)) continue;
    if (existed.y < im.date.x || existed.x > im.date.y) continue;  // not built yet, or gone, at its date
    if (u_occlusion) {
      vec2 dt = (p - im.depthMin) * im.depthInvSize;
      float zMap = mix(im.near, im.far, hv_sampleDepth(int(im.slice), dt));
      if (z > zMap + hv_shadowBias(im, z, normal, normalize(P - im.C))) continue;  // shadowed (Brédif 2013 §2.2)
    }
    vec4 texel = hv_sampleImage(int(im.slice), pd * im.uvScale);
    if (texel.a <= 0.0) continue;
    if (u_method == 1) {  // nearest: images are sorted by distance, the first that passes wins
      sum = texel.rgb;
      alpha = texel.a;
      count = 1;
      break;
    }
    if (im.weight <= 0.0) continue;
    sum += im.weight * texel.rgb;
    alpha += im.weight * texel.a;
    ++count;
  }
  if (u_mode != 0) {
    o_color = encodeCount(u_mode == 1 ? count : n);
    return;
  }
  if (alpha <= 0.0) {
    writeBackground();
    return;
  }
  o_color = vec4(sum / alpha, 1.0);
}
