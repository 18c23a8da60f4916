#version 300 es
// Mesh pass, deferred: for each output pixel, the surface point P is rebuilt from the view's
// linear depth along the pixel's exact ray, then textured by the selected photographs
// (docs/design.md; Brédif 2013 eq. 1-2), through the per-image test chain of image_test.glsl.
// The CPU twin is hv::ibr::referenceBlend.
// Offscreen targets are stored top row first, so gl_FragCoord.xy is the pixel position in the
// top-left-corner convention of hv/camera/camera.h.
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler2DArray;

#include "ibr_common.glsl"
#include "image_test.glsl"
#include "colormap.glsl"
#include "untextured.glsl"

// The photographs and their depth maps: one texture2DArray of each, or with HV_NAIVE the baseline
// the papers improve on (Brédif 2013; de Castro & Brédif 2022 §2.1), one sampler2D per photograph
// and per depth map, HV_NAIVE_COUNT pairs declared further down by the generated naive binding.
#ifndef HV_NAIVE
uniform highp sampler2DArray u_images;     // premultiplied RGBA8, alpha = mask
uniform highp sampler2DArray u_depthMaps;  // linear depth in [0, 1] between near and far
#endif

uniform highp sampler2D u_viewDepth;       // the view's geometry pass, same encoding
uniform highp sampler2D u_idealLookup;     // distorted views: ideal pixel of each output pixel
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
// 0 colour; raw, 16 bits in r, g: 1 contributing-image count, 2 loop length, 3 share of image
// u_debugImage * 65535; colour-mapped (hv::render::DebugView): 4 count, 5 share of u_debugImage.
uniform int u_mode;
uniform int u_debugImage;       // index among the frame's images; -1: none
uniform vec3 u_background;
// > 0: pixels without geometry see a sphere of this radius around the view (iTowns'
// backgroundDistance); from a photograph's own centre it shows the photograph whatever the radius.
uniform float u_sphereRadius;
uniform bool u_points;                     // the point pass ran (points.frag)
uniform float u_meshPushBack;              // hybrid: the mesh's push-back in the depth maps (depth.frag)
uniform highp sampler2D u_pointColor;      // its colour, per view-depth texel (points.frag)

out vec4 o_color;

bool colourMode() { return u_mode == 0 || u_mode >= 4; }

void writeBackground() {
  o_color = colourMode() ? vec4(u_background, 0.0) : vec4(0.0);
}

// Where no photograph contributes, alpha 0 (not covered). In the picture (u_mode 0) a surface is
// shaded and a pixel without geometry shows the sky (untextured.glsl), each unless switched off;
// otherwise, and in the debug views, the background colour.
void writeUncovered(bool surface, vec3 ray, vec3 normal) {
  if (u_mode == 0 && surface && u_shading) {
    o_color = vec4(hv_shadeUntextured(dot(normal, ray) > 0.0 ? -normal : normal), 0.0);
  } else if (u_mode == 0 && !surface && u_sky) {
    o_color = vec4(hv_skyColor(ray), 0.0);
  } else {
    writeBackground();
  }
}

vec4 encodeCount(int n) { return vec4(float(n & 255) / 255.0, float(n >> 8) / 255.0, 0.0, 1.0); }

// Whether image `im` may texture P: projection, distortion domain, image bounds, and whether the
// surface existed at the photograph's date. Outputs the depth-map and image texture coordinates
// and the depth of P in the image.
bool hv_applies(HvImage im, vec3 P, vec2 existed, out vec2 dt, out vec2 uv, out float z) {
  vec2 p, pd;
  dt = vec2(0.0);
  uv = vec2(0.0);
  if (!hv_project(im, P, p, pd, z)) return false;
  if (!hv_existedAt(im, existed)) return false;
  dt = hv_depthCoord(im, p);
  uv = pd * im.uvScale;
  return true;
}

#ifdef HV_NAIVE
// One image of the naive binding, on its own sampler pair; called once per pair by hv_naiveBlend,
// which the generated include declares with the pairs (hv::gpu::naiveBindingGlsl,
// src/hv/gpu/shader_assembly.cpp).
void hv_naiveStep(int i, highp sampler2D image, highp sampler2D depth, vec3 P, vec3 normal, vec2 existed,
                  inout HvBlend b) {
  if (b.done || i >= u_imageCount) return;
  HvImage im = hv_fetchImage(i);
  vec2 dt, uv;
  float z;
  if (!hv_applies(im, P, existed, dt, uv, z)) return;
  if (u_occlusion && hv_shadowed(im, z, texture(depth, dt).r, normal, P, u_meshPushBack)) return;
  hv_accumulate(i, im, hv_correctColour(im, textureLod(image, uv, 0.0)), u_method == 1, u_debugImage, b);
}
#include "generated:naive_binding"
#endif

void main() {
  // Everything up to the normal runs in uniform control flow: derivatives are only defined there.
  vec2 pIdeal = gl_FragCoord.xy;
  bool background = false;
  bool outsideLens = false;
  if (u_useLookup) {
    vec4 l = texelFetch(u_idealLookup, ivec2(gl_FragCoord.xy), 0);
    outsideLens = l.z < 0.5;  // outside the distortion domain: no ray
    background = outsideLens;
    pIdeal = l.xy;
  }
  vec2 t = (pIdeal - u_viewRectMin) * u_viewRectInvSize;
  ivec2 dpix = clamp(ivec2(floor(t * vec2(u_viewDepthSize))), ivec2(0), u_viewDepthSize - 1);
  float d = texelFetch(u_viewDepth, dpix, 0).r;
  // No geometry under the pixel: the background sphere around the view when there is one.
  bool onSphere = d >= 1.0 && u_sphereRadius > 0.0;
  background = background || (d >= 1.0 && !onSphere);
  vec3 ray = u_viewDirFromPix * vec3(pIdeal, 1.0);
  vec3 P = onSphere ? u_viewCenter + u_sphereRadius * normalize(ray)
                    : u_viewCenter + mix(u_viewNear, u_viewFar, d) * ray;
  vec3 normal = cross(dFdx(P), dFdy(P));
  normal = dot(normal, normal) > 0.0 ? normalize(normal) : vec3(0.0, 0.0, 1.0);
  if (background) {
    if (outsideLens) writeBackground();
    else writeUncovered(false, ray, normal);
    return;
  }
  // When the surface under this pixel existed (terrain: always).
  vec2 existed = hv_surfaceExisted(dpix);

  // A point sprite won the view's depth test here: its colour pass already textured it
  // (shaders/points.frag; a = 1 textured, 0.5 shown in its own colour, not covered).
  if (u_points && u_mode == 0) {
    vec4 pc = texelFetch(u_pointColor, dpix, 0);
    if (pc.a > 0.0) {
      o_color = vec4(pc.rgb, pc.a > 0.75 ? 1.0 : 0.0);
      return;
    }
  }

  HvBlend blend = hv_noBlend();
#ifdef HV_NAIVE
  // The naive binding: one step per selected image, each with its own samplers.
  int n = u_imageCount;
  hv_naiveBlend(P, normal, existed, blend);
#else
  // The images to visit: this tile's list (hv::ibr::buildTileLists), or every selected image.
  int row = 0;
  int n = u_imageCount;
  if (u_culling) {
    ivec2 tile = dpix / u_tileSize;
    row = tile.y * u_tilesX + tile.x;
    n = int(texelFetch(u_tileLists, ivec2(0, row), 0).r);
  }
  for (int k = 0; k < n; ++k) {
    int i = u_culling ? int(texelFetch(u_tileLists, ivec2(k + 1, row), 0).r) : k;
    HvImage im = hv_fetchImage(i);
    vec2 dt, uv;
    float z;
    if (!hv_applies(im, P, existed, dt, uv, z)) continue;
    if (u_occlusion && hv_shadowed(im, z, texture(u_depthMaps, vec3(dt, im.slice)).r, normal, P, u_meshPushBack))
      continue;
    hv_accumulate(i, im, hv_correctColour(im, textureLod(u_images, vec3(uv, im.slice), 0.0)), u_method == 1, u_debugImage, blend);
    if (blend.done) break;
  }
#endif
  vec3 sum = blend.sum;
  float alpha = blend.alpha;
  int count = blend.count;
  float share = alpha > 0.0 ? blend.mine / alpha : 0.0;
  if (u_mode == 1 || u_mode == 2) {
    o_color = encodeCount(u_mode == 1 ? count : n);
    return;
  }
  if (u_mode == 3) {
    o_color = encodeCount(int(share * 65535.0 + 0.5));
    return;
  }
  if (u_mode == 4) {
    o_color = count > 0 ? vec4(hv_colorRamp(float(count) / float(max(u_imageCount, 1))), 1.0) : vec4(0.0);
    return;
  }
  if (alpha <= 0.0) {
    writeUncovered(!onSphere, ray, normal);
    return;
  }
  o_color = u_mode == 5 ? vec4(hv_colorRamp(share), 1.0) : vec4(sum / alpha, 1.0);
}
