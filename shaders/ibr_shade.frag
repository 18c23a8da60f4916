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

// Picture quality (docs/design.md, step 5; the CPU twins are in hv/ibr/weights.h and
// hv::ibr::referenceBlend): how the weights are made, feathering, mipmaps.
uniform int u_weighting;           // hv::ibr::Weighting: 0 distance (the papers'), 1 geometry
uniform float u_resolutionWeight;  // geometry: lambda
uniform float u_penaltyEpsilon;    // geometry: f(p) = 1/(epsilon^2 + p^2)
uniform int u_geometryK;           // geometry: images blended per pixel (hv::ibr::geometryBlendCount)
uniform float u_viewFocal;         // the view's focal length, pixels
uniform float u_feather;           // photograph pixels; 0: no feathering
uniform bool u_maskFeather;        // feather toward mask edges too (from a mip level of the mask)
// Mipmaps: 0 off (level 0); 1 the level of the footprint's area (log2 of the square root of the
// texel area a view pixel covers, textureLod); 2 textureGrad with anisotropic filtering.
uniform int u_mipmaps;
uniform float u_sliceWidth;        // texels of a slice
// The transient filter's spread (RGB in [0, 1]); 0: off. Twin: hv::ibr::consensusWeights.
uniform float u_consensus;

// The orthophoto draped on untextured terrain (Scene::orthophoto; de Castro & Brédif 2022's terrain
// texture): straight RGBA, texture coordinates (dot(u_orthoU, (x, y, 1)), dot(u_orthoV, ...)) of
// the render-frame point, hv::orthophotoAffine; its CPU twin is hv::sampleOrthophoto.
// Not in the naive binding, whose sampler pairs take every texture unit the context has.
#ifndef HV_NAIVE
uniform bool u_orthophotoOn;
uniform highp sampler2D u_orthophoto;
uniform vec3 u_orthoU;
uniform vec3 u_orthoV;
#endif

// Per-configuration programs (src/hv/render/gl/shade_config.h): with HV_CONFIG the options above
// are compile-time constants (HV_CONF_*), so the code of what is off is not in the program (on
// llvmpipe both sides of an `if` run, docs/performance.md), and the geometry weights' per-pixel
// lists have constant sizes (HV_CONF_K, HV_CONF_RANK) and constant indices. Without HV_CONFIG
// (the generic program, the naive binding) each is read from its uniform.
#ifdef HV_CONFIG
#define HV_GEOMETRY (HV_CONF_GEOMETRY == 1)
#define HV_CONSENSUS_ON (HV_CONF_CONSENSUS == 1)
#define HV_MIPMAPS HV_CONF_MIPMAPS
#define HV_FEATHER_ON (HV_CONF_FEATHER == 1)
#define HV_LAYERS_ON (HV_CONF_LAYERS == 1)
#else
#define HV_GEOMETRY (u_weighting == 1 && u_method != 1)
#define HV_CONSENSUS_ON (u_consensus > 0.0 && u_method != 1)
#define HV_MIPMAPS u_mipmaps
#define HV_FEATHER_ON (u_feather > 0.0)
#define HV_LAYERS_ON true
#endif

out vec4 o_color;

// hv::ibr::kMaxGeometryK + 1: a pixel's best K and the K+1-th.
#define HV_MAX_BEST 17
// hv::ibr::kMaxGeometryRank: the candidates of a pixel ranked by penalty before any is tested.
#define HV_MAX_RANK 32
// hv::ibr::kMaxConsensusSamples: the samples the transient filter looks at.
#define HV_MAX_CONSENSUS 16

bool colourMode() { return u_mode == 0 || u_mode >= 4; }

void writeBackground() {
  o_color = colourMode() ? vec4(u_background, 0.0) : vec4(0.0);
}

// Where no photograph contributes, alpha 0 (not covered). In the picture (u_mode 0) a surface is
// shaded and a pixel without geometry shows the sky (untextured.glsl), each unless switched off;
// otherwise, and in the debug views, the background colour. Terrain under the orthophoto shows it
// as it is, over the shading (or the background) by its alpha.
void writeUncovered(bool surface, vec3 ray, vec3 normal, vec3 P, bool terrain) {
  vec4 ortho = vec4(0.0);
#ifndef HV_NAIVE
  if (u_mode == 0 && surface && terrain && u_orthophotoOn) {
    vec2 uv = vec2(dot(u_orthoU, vec3(P.xy, 1.0)), dot(u_orthoV, vec3(P.xy, 1.0)));
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0))))
      ortho = textureLod(u_orthophoto, uv, 0.0);
  }
#endif
  if (u_mode == 0 && surface && u_shading) {
    o_color = vec4(hv_shadeUntextured(dot(normal, ray) > 0.0 ? -normal : normal), 0.0);
  } else if (u_mode == 0 && !surface && u_sky) {
    o_color = vec4(hv_skyColor(ray), 0.0);
  } else {
    writeBackground();
  }
  o_color.rgb = mix(o_color.rgb, ortho.rgb, ortho.a);
}

vec4 encodeCount(int n) { return vec4(float(n & 255) / 255.0, float(n >> 8) / 255.0, 0.0, 1.0); }

// Whether image `im` may texture P: projection, distortion domain, image bounds, and whether the
// surface existed at the photograph's date. Outputs the depth-map and image texture coordinates
// and the depth of P in the image.
// Also outputs the ideal and distorted pixels p, pd (feathering).
bool hv_appliesAt(HvImage im, vec3 P, vec2 existed, out vec2 dt, out vec2 uv, out vec2 p, out vec2 pd,
                  out float z) {
  dt = vec2(0.0);
  uv = vec2(0.0);
  if (!hv_project(im, P, p, pd, z)) return false;
  if (!hv_existedAt(im, existed)) return false;
  dt = hv_depthCoord(im, p);
  uv = (pd - im.uvOffset) * im.uvScale;
  // A sub-image textures the points whose projection falls in its window (uv in [0, 1]^2).
  return !HV_LAYERS_ON || im.layer <= 0.0 || (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0))));
}

bool hv_applies(HvImage im, vec3 P, vec2 existed, out vec2 dt, out vec2 uv, out float z) {
  vec2 p, pd;
  return hv_appliesAt(im, P, existed, dt, uv, p, pd, z);
}

// The geometry penalty at P with surface normal n of the photograph whose centre is C and focal
// length `focal` (pixels), twin of hv::ibr::geometryPenalty: the angle between the photograph's
// and the view's rays plus lambda * max(0, ln rho), rho the photograph's texel footprint on the
// surface over the view's pixel footprint (cosines clamped at hv::ibr::kMinCosine).
float hv_penalty(vec3 C, float focal, vec3 P, vec3 n) {
  vec3 toI = P - C, toV = P - u_viewCenter;
  float di = length(toI), dv = length(toV);
  vec3 a = toI / di, b = toV / dv;
  float theta = atan(length(cross(a, b)), dot(a, b));
  float ci = max(abs(dot(n, a)), 0.05), cv = max(abs(dot(n, b)), 0.05);
  float rho = (di * u_viewFocal * cv) / (dv * focal * ci);
  return theta + u_resolutionWeight * max(0.0, log(rho));
}

// The step on the surface plane (P, n) to the view ray `rayNext` of a neighbouring pixel, its
// denominator clamped (a ray along the plane); mipmaps take the photograph's footprint from it.
vec3 hv_surfaceStep(vec3 P, vec3 n, vec3 rayNext) {
  float b = dot(rayNext, n);
  float bmin = 0.05 * length(rayNext);
  b = b < 0.0 ? min(b, -bmin) : max(b, bmin);
  return u_viewCenter + rayNext * (dot(P - u_viewCenter, n) / b) - P;
}

#ifdef HV_NAIVE
// One image of the naive binding, on its own sampler pair; called once per pair by hv_naiveBlend,
// which the generated include declares with the pairs (hv::gpu::naiveBindingGlsl,
// src/hv/gpu/shader_assembly.cpp).
void hv_naiveStep(int i, highp sampler2D image, highp sampler2D depth, vec3 P, vec3 normal, vec2 existed,
                  inout HvBlend b) {
  if (b.done || i >= u_imageCount) return;
  HvImage im = hv_fetchImage(i);
  if (im.layer > 0.0) return;  // layered photographs: the array binding only (docs/layers.md)
  vec2 dt, uv;
  float z;
  if (!hv_applies(im, P, existed, dt, uv, z)) return;
  if (u_occlusion && hv_shadowed(im, z, texture(depth, dt).r, normal, P, u_meshPushBack)) return;
  hv_accumulate(i, im, hv_correctColour(im, textureLod(image, uv, 0.0)), u_method == 1, u_debugImage, b);
}
#include "generated:naive_binding"
#endif

#ifndef HV_NAIVE
// The two-sided depth test of a layered photograph's sub-image (Layered projective texture maps,
// 2003, §5; twin of hv::layers::onPeeledSurface): its slot's depth map holds D_k, the nearest
// surface of visibility layers >= k, over the sub-image's sheared frustum. P passes when its
// distance from the camera lies within the range of the four texels a bilinear lookup at dt reads
// (those with a surface), widened by biasAbs + biasRel * distance (the sub-image's tolerance);
// the texels' depths along the axis become distances along P's ray (times |P - C| / z).
bool hv_onPeeledSurface(HvImage im, float z, vec2 dt, vec3 P) {
  ivec2 size = textureSize(u_depthMaps, 0).xy;
  ivec2 t0 = ivec2(floor(dt * vec2(size) - 0.5));
  float lo = 1e30, hi = -1e30;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 t = clamp(t0 + ivec2(dx, dy), ivec2(0), size - 1);
      float stored = texelFetch(u_depthMaps, ivec3(t, int(im.slice + 0.5)), 0).r;
      if (stored >= 1.0) continue;  // no surface of these layers on that ray
      float zMap = mix(im.near, im.far, stored);
      lo = min(lo, zMap);
      hi = max(hi, zMap);
    }
  if (lo > hi) return false;
  float d = length(P - im.C);
  float toDistance = d / z;
  float tol = im.biasAbs + im.biasRel * d;
  return d >= lo * toDistance - tol && d <= hi * toDistance + tol;
}

// The transient filter (docs/design.md, step 5, "Consensus"), twin of hv::ibr::consensusWeights:
// from the component-wise median of the contributing samples' colours, three mean-shift steps with
// a Gaussian kernel weighted by the blend weights, then each weight times the kernel at its
// colour, relative to the sample nearest the mode. Fewer than three contributing samples: as is.
void hv_consensus(vec4 t[HV_MAX_CONSENSUS], inout float w[HV_MAX_CONSENSUS], int n) {
  vec3 col[HV_MAX_CONSENSUS];
  int m = 0;
  for (int i = 0; i < n; ++i) {
    col[i] = t[i].rgb / max(t[i].a, 1e-20);
    if (w[i] > 0.0) m += 1;
  }
  if (m < 3) return;
  vec3 mode = vec3(0.0);
  float v[HV_MAX_CONSENSUS];
  for (int c = 0; c < 3; ++c) {
    int k = 0;
    for (int i = 0; i < n; ++i) {
      if (w[i] <= 0.0) continue;
      float x = col[i][c];
      int j = k;
      while (j > 0 && v[j - 1] > x) {
        v[j] = v[j - 1];
        --j;
      }
      v[j] = x;
      k += 1;
    }
    mode[c] = (m & 1) == 1 ? v[m / 2] : 0.5 * (v[m / 2 - 1] + v[m / 2]);
  }
  float kk = 0.5 / (u_consensus * u_consensus);
  float g[HV_MAX_CONSENSUS];
  for (int step = 0; step < 4; ++step) {
    float least = 1e30;
    for (int i = 0; i < n; ++i) {
      vec3 d = col[i] - mode;
      g[i] = dot(d, d);
      if (w[i] > 0.0) least = min(least, g[i]);
    }
    for (int i = 0; i < n; ++i) g[i] = w[i] > 0.0 ? exp(-kk * (g[i] - least)) : 0.0;
    if (step == 3) break;
    vec3 s = vec3(0.0);
    float total = 0.0;
    for (int i = 0; i < n; ++i) {
      s += w[i] * g[i] * col[i];
      total += w[i] * g[i];
    }
    mode = s / total;
  }
  for (int i = 0; i < n; ++i) w[i] *= g[i];
}

// Texture coordinates of a render-frame point in image `im` (its distorted pixel, through the lens
// model, times uvScale), for the footprint's derivatives.
vec2 hv_uvAt(HvImage im, vec3 Q) {
  vec3 ph = im.M * (Q - im.C);
  vec2 pd;
  hv_distort(im, ph.xy / max(ph.z, 1e-6), pd);  // outside the domain: the ideal pixel
  return pd * im.uvScale;
}

// The one place a photograph's colour is read (premultiplied, alpha = mask): level 0 (the
// papers'), or with mipmaps at the level of the view pixel's footprint in the photograph, the uv
// derivatives taken as differences of the distorted coordinates of the pixel's neighbours on the
// surface (P + dPdx, P + dPdy). A per-photograph colour transform applies to what this returns.
// Without anisotropic filtering the level is that of the footprint's area: the square root of
// the texel area a view pixel covers (GL's isotropic rule takes the longer axis, which blurs a
// surface seen obliquely, the street, across its whole width).
vec4 hv_samplePhoto(HvImage im, vec2 uv, vec3 P, vec3 dPdx, vec3 dPdy) {
  vec3 at = vec3(uv, im.slice);
  if (HV_MIPMAPS == 0) return textureLod(u_images, at, 0.0);
  vec2 gx = hv_uvAt(im, P + dPdx) - uv, gy = hv_uvAt(im, P + dPdy) - uv;
  if (HV_MIPMAPS == 2) return textureGrad(u_images, at, gx, gy);
  vec2 size = vec2(textureSize(u_images, 0).xy);
  vec2 jx = gx * size, jy = gy * size;
  float area = abs(jx.x * jy.y - jx.y * jy.x);
  return textureLod(u_images, at, 0.5 * log2(max(area, 1e-12)));
}

// The feather factor of image `im` at ideal pixel p, distorted pd, texture uv: twin of
// hv::ibr::featherFactor(borderDistance) times maskFeather at featherLevel.
float hv_feather(HvImage im, vec2 p, vec2 pd, vec2 uv) {
  if (!HV_FEATHER_ON) return 1.0;
  float b = min(min(pd.x, pd.y), min(im.size.x - pd.x, im.size.y - pd.y));
  if (im.r2max >= 0.0 && im.r2max < 1e29) {
    vec2 x = (p - im.dc) / im.dscale;
    b = min(b, (sqrt(im.r2max) - length(x)) * min(im.dscale.x, im.dscale.y));
  }
  float f = smoothstep(0.0, u_feather, b);
  if (u_maskFeather && (!HV_LAYERS_ON || im.layer <= 0.0) && f > 0.0) {  // a sub-image's alpha is not a mask
    float level = max(0.0, log2(max(u_feather * im.uvScale.x * u_sliceWidth, 1.0)));
    f *= clamp(2.0 * textureLod(u_images, vec3(uv, im.slice), level).a - 1.0, 0.0, 1.0);
  }
  return f;
}

#include "ibr_geometry_blend.glsl"
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
    else writeUncovered(false, ray, normal, P, false);
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
  // Mipmaps: the view pixel's neighbours on the surface plane.
  vec3 dPdx = vec3(0.0), dPdy = vec3(0.0);
  if (HV_MIPMAPS != 0) {
    dPdx = hv_surfaceStep(P, normal, u_viewDirFromPix * vec3(pIdeal + vec2(1.0, 0.0), 1.0));
    dPdy = hv_surfaceStep(P, normal, u_viewDirFromPix * vec3(pIdeal + vec2(0.0, 1.0), 1.0));
  }
#ifdef HV_FAST_GEOMETRY
  hv_geometryBlend(n, row, P, normal, existed, dPdx, dPdy, blend);
#else
  // Geometry weights: the pixel's best K + 1 by penalty, ascending (ties: list order), with
  // their texels, feather factors and indices.
  bool geometry = HV_GEOMETRY;
  int cap = clamp(u_geometryK, 1, HV_MAX_BEST - 1) + 1;
  float bestP[HV_MAX_BEST];
  vec4 bestT[HV_MAX_BEST];
  float bestF[HV_MAX_BEST];
  int bestI[HV_MAX_BEST];
  int nBest = 0;
  // The transient filter: the pixel's samples (texel, f or w, feather, index) kept for reweighting.
  bool consensus = HV_CONSENSUS_ON;
  vec4 sampT[HV_MAX_CONSENSUS];
  float sampW[HV_MAX_CONSENSUS];
  float sampF[HV_MAX_CONSENSUS];
  int sampI[HV_MAX_CONSENSUS];
  int nSamp = 0;
  int nPassed = 0;
  float fNextRegion = 0.0;
  // Geometry weights: the penalty depends only on the photograph's centre and focal length, so the
  // candidates are ranked by it first (ascending, ties in list order; the best HV_MAX_RANK kept)
  // and then tested best first: the loop below ends at the K+1-th that passes every test, and a
  // photograph that cannot enter the best K + 1 is never projected, depth-tested nor read.
  float rankP[HV_MAX_RANK];
  int rankI[HV_MAX_RANK];
  int nRank = 0;
  if (geometry) {
    for (int k = 0; k < n; ++k) {
      int i = u_culling ? int(texelFetch(u_tileLists, ivec2(k + 1, row), 0).r) : k;
      // C and the focal length: t0.w, t1.w, t2.w and t8.z (hv_fetchImage).
      vec3 C = vec3(texelFetch(u_params, ivec2(0, i), 0).w, texelFetch(u_params, ivec2(1, i), 0).w,
                    texelFetch(u_params, ivec2(2, i), 0).w);
      float pen = hv_penalty(C, texelFetch(u_params, ivec2(8, i), 0).z, P, normal);
      if (nRank == HV_MAX_RANK && pen >= rankP[HV_MAX_RANK - 1]) continue;
      int j = min(nRank, HV_MAX_RANK - 1);
      while (j > 0 && rankP[j - 1] > pen) {
        rankP[j] = rankP[j - 1];
        rankI[j] = rankI[j - 1];
        --j;
      }
      rankP[j] = pen;
      rankI[j] = i;
      nRank = min(nRank + 1, HV_MAX_RANK);
    }
  }
  // A layered photograph's sub-images are consecutive with one group (in the list, and in the
  // ranking: they share the photograph's centre and focal length): the first that passes stands
  // for the photograph, the rest of its group are skipped.
  float doneGroup = 0.0;
  int visits = geometry ? nRank : n;
  for (int k = 0; k < visits; ++k) {
    int i = geometry ? rankI[k] : u_culling ? int(texelFetch(u_tileLists, ivec2(k + 1, row), 0).r) : k;
    float pen = geometry ? rankP[k] : 0.0;
    HvImage im = hv_fetchImage(i);
    if (HV_LAYERS_ON && im.group > 0.0 && im.group == doneGroup) continue;
    vec2 dt, uv, p, pd;
    float z;
    if (!hv_appliesAt(im, P, existed, dt, uv, p, pd, z)) continue;
    if (HV_LAYERS_ON && im.layer > 0.0) {
      if (!hv_onPeeledSurface(im, z, dt, P)) continue;
    } else if (u_occlusion &&
               hv_shadowed(im, z, texture(u_depthMaps, vec3(dt, im.slice)).r, normal, P, u_meshPushBack)) {
      continue;
    }
    vec4 texel = hv_correctColour(im, hv_samplePhoto(im, uv, P, dPdx, dPdy));
    if (texel.a <= 0.0) continue;
    doneGroup = im.group;
    float feather = hv_feather(im, p, pd, uv);
    if (!geometry && consensus) {
      // As hv_accumulateFeathered: region, the first K that pass, f(d_K+1) from the next one;
      // global, every image with a weight.
      if (u_region && nPassed == u_blendK) {
        fNextRegion = im.weight;
        break;
      }
      nPassed += 1;
      if (nSamp < HV_MAX_CONSENSUS && (u_region || im.weight * feather > 0.0)) {
        sampT[nSamp] = texel;
        sampW[nSamp] = im.weight;
        sampF[nSamp] = feather;
        sampI[nSamp] = i;
        nSamp += 1;
      }
      continue;
    }
    if (!geometry) {
      hv_accumulateFeathered(i, im, texel, feather, u_method == 1, u_debugImage, blend);
      if (blend.done) break;
      continue;
    }
    // Visited in ascending penalty: the best list grows at its end, and is complete with the
    // K+1-th.
    bestP[nBest] = pen;
    bestT[nBest] = texel;
    bestF[nBest] = feather;
    bestI[nBest] = i;
    nBest += 1;
    if (nBest == cap) break;
  }
  if (consensus) {
    // The samples' blend weights, as below and in hv_accumulateFeathered, then the filter.
    if (geometry) {
      float e2 = u_penaltyEpsilon * u_penaltyEpsilon;
      float fNextG = nBest == cap ? 1.0 / (e2 + bestP[cap - 1] * bestP[cap - 1]) : 0.0;
      for (int j = 0; j < min(nBest, cap - 1); ++j) {
        sampT[j] = bestT[j];
        sampW[j] = max(0.0, 1.0 / (e2 + bestP[j] * bestP[j]) - fNextG) * bestF[j];
        sampI[j] = bestI[j];
      }
      nSamp = min(nBest, cap - 1);
    } else {
      for (int j = 0; j < nSamp; ++j) sampW[j] = (u_region ? max(0.0, sampW[j] - fNextRegion) : sampW[j]) * sampF[j];
    }
    hv_consensus(sampT, sampW, nSamp);
    for (int j = 0; j < nSamp; ++j) {
      float w = sampW[j];
      if (w <= 0.0) continue;
      blend.sum += w * sampT[j].rgb;
      blend.alpha += w * sampT[j].a;
      blend.count += 1;
      if (sampI[j] == u_debugImage) blend.mine = w * sampT[j].a;
    }
  } else if (geometry) {
    // w_j = (f(p_j) - f(p_K+1)) * feather_j over the best K (hv::ibr::blendWeights of the penalties).
    float e2 = u_penaltyEpsilon * u_penaltyEpsilon;
    float fNext = nBest == cap ? 1.0 / (e2 + bestP[cap - 1] * bestP[cap - 1]) : 0.0;
    for (int j = 0; j < min(nBest, cap - 1); ++j) {
      float w = max(0.0, 1.0 / (e2 + bestP[j] * bestP[j]) - fNext) * bestF[j];
      if (w <= 0.0) continue;
      blend.sum += w * bestT[j].rgb;
      blend.alpha += w * bestT[j].a;
      blend.count += 1;
      if (bestI[j] == u_debugImage) blend.mine = w * bestT[j].a;
    }
  }
#endif  // HV_FAST_GEOMETRY
#endif  // HV_NAIVE
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
    // Terrain: building index 0 (depth.frag; buildings and the mesh write theirs).
    writeUncovered(!onSphere, ray, normal, P, texelFetch(u_viewBuilding, dpix, 0).rgb == vec3(0.0));
    return;
  }
  o_color = u_mode == 5 ? vec4(hv_colorRamp(share), 1.0) : vec4(sum / alpha, 1.0);
}
