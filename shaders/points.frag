#version 300 es
// Point sprites, fragment side (de Castro & Brédif 2022 §2.3; docs/design.md). Each fragment finds
// the plane point X under its pixel p = (gl_FragCoord.xy, 1) through the vector N' of its point:
// the depth of X in the target camera is 1 / (N'.p), and X lies in the point's disk when
// |X - P| <= u_radius.
// HV_DEPTH_ONLY: writes that depth (linear, as depth.frag) — the photographs' depth maps and the
// view's point depth pass. Otherwise the colour pass: a fragment goes on only where its depth is
// the one the depth pass kept (u_viewDepth), then is textured through the homography of each
// image, p_i = H'_i p + (N'.p) E_i (2022 form) or p_i = H_i p (2016 form, HV_MAT3_K), then
// through the mesh pass's per-image test chain (image_test.glsl: distortion, domain, date, shadow,
// mask, blend; depth of X in image i: p_i.z / (N'.p)). Twins: hv::ibr::spriteProject, spriteDepth
// (src/hv/ibr/sprite_homography.h).
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler2DArray;

uniform mat3 u_Minv;      // M^-1 of the target camera
uniform float u_near;
uniform float u_far;
uniform float u_radius;
uniform float u_depthOffset;  // hybrid rendering: points drawn this much nearer (= mesh pushed back)

flat in vec3 v_nPrime;
flat in vec3 v_PC;
flat in vec4 v_color;

// Linear depth of the plane point under this fragment, normalised between near and far; false
// when the pixel misses the front of the plane or falls outside the point's disk.
bool hv_spriteDepth(vec3 p, out float z, out float stored) {
  float np = dot(v_nPrime, p);
  z = 0.0;
  stored = 1.0;
  if (np <= 0.0) return false;
  z = 1.0 / np;
  vec3 ray = u_Minv * p;
  vec3 d = z * ray - v_PC;  // X - P
  if (dot(d, d) > u_radius * u_radius) return false;
  // Hybrid rendering: the point drawn as if moved u_depthOffset towards the camera along its
  // normal (the mesh pushed back), u_depthOffset / cos(theta) along the ray (as depth.frag).
  float push = 0.0;
  if (u_depthOffset > 0.0) {
    vec3 normal = transpose(u_Minv) * v_nPrime;  // parallel to N (render frame)
    push = u_depthOffset / max(abs(dot(normalize(normal), normalize(ray))), 0.1);
  }
  stored = clamp((z - push - u_near) / (u_far - u_near), 0.0, 1.0);
  return true;
}

#ifdef HV_DEPTH_ONLY
void main() {
  float z, stored;
  if (!hv_spriteDepth(vec3(gl_FragCoord.xy, 1.0), z, stored)) discard;
  gl_FragDepth = stored;
}
#else
#include "ibr_common.glsl"
#include "image_test.glsl"

uniform highp sampler2DArray u_images;
uniform highp sampler2DArray u_depthMaps;
uniform highp sampler2D u_pointParams;  // per image: rows of H' (xyz) and E (w), 3 texels
uniform highp sampler2D u_viewDepth;    // the depth pass (mesh, then points), same target
uniform int u_imageCount;
uniform int u_method;           // 0 blend, 1 nearest
uniform bool u_occlusion;
uniform bool u_epsilonTest;     // filtering without classification (2022 §2.4)
uniform float u_epsilon;        // scene units
uniform bool u_eyeDome;
uniform float u_edlStrength;
uniform float u_edlRadius;      // target pixels
uniform vec3 u_C;               // target camera centre, render frame
uniform float u_depthTolerance; // normalised depth: the colour pass keeps the depth pass's winner

#ifdef HV_MAT3_K
flat in mat3 v_H[HV_MAT3_K];
#endif

out vec4 o_color;  // rgb; a = 1 textured, 0.5 untextured (own colour), 0 no point

float hv_linearDepth(float stored) { return mix(u_near, u_far, stored); }

// Eye-dome lighting as Potree does it: darken where neighbours are nearer (log depth).
float hv_eyeDome(float z) {
  if (!u_eyeDome) return 1.0;
  ivec2 size = textureSize(u_viewDepth, 0);
  float sum = 0.0;
  const vec2 dirs[4] = vec2[4](vec2(1.0, 0.0), vec2(-1.0, 0.0), vec2(0.0, 1.0), vec2(0.0, -1.0));
  for (int k = 0; k < 4; ++k) {
    ivec2 q = clamp(ivec2(gl_FragCoord.xy + u_edlRadius * dirs[k]), ivec2(0), size - 1);
    float zn = hv_linearDepth(texelFetch(u_viewDepth, q, 0).r);
    sum += max(0.0, log2(z) - log2(zn));
  }
  return exp(-sum / 4.0 * 300.0 * u_edlStrength);
}

void main() {
  vec3 p = vec3(gl_FragCoord.xy, 1.0);
  float z, stored;
  if (!hv_spriteDepth(p, z, stored)) discard;
  // Only the sprite that won the depth pass shades this pixel.
  if (abs(texelFetch(u_viewDepth, ivec2(gl_FragCoord.xy), 0).r - stored) > u_depthTolerance) discard;
  float np = dot(v_nPrime, p);
  // Against its neighbours as the depth pass stored them (points pulled forward by the hybrid
  // offset alike), not against its own unshifted depth.
  vec3 own = v_color.rgb * hv_eyeDome(hv_linearDepth(stored));
  if (v_color.a < 0.5) {  // transient: never textured
    o_color = vec4(own, 0.5);
    return;
  }
  // The surface normal for the slope-scaled bias: N is parallel to M^T N' (render frame).
  vec3 normal = normalize(transpose(u_Minv) * v_nPrime);
  vec3 X = u_C + z * (u_Minv * p);  // render frame
  // When the surface under this pixel existed, as the mesh pass reads it: the building the view's
  // geometry pass drew there (the one a façade's points sample), else always.
  vec2 existed = hv_surfaceExisted(ivec2(gl_FragCoord.xy));
  HvBlend blend = hv_noBlend();
  int n = u_imageCount;
#ifdef HV_MAT3_K
  n = min(n, HV_MAT3_K);
#endif
  for (int i = 0; i < n; ++i) {
    HvImage im = hv_fetchImage(i);
    if (im.layer > 0.0) continue;  // layered photographs texture the mesh pass only (docs/layers.md)
#ifdef HV_MAT3_K
    vec3 pi = v_H[i] * p;
#else
    vec4 r0 = texelFetch(u_pointParams, ivec2(0, i), 0);
    vec4 r1 = texelFetch(u_pointParams, ivec2(1, i), 0);
    vec4 r2 = texelFetch(u_pointParams, ivec2(2, i), 0);
    vec3 pi = vec3(dot(r0.xyz, p), dot(r1.xyz, p), dot(r2.xyz, p)) + np * vec3(r0.w, r1.w, r2.w);
#endif
    if (pi.z <= 0.0) continue;
    float zi = pi.z / np;
    vec2 pIdeal = pi.xy / pi.z;
    vec2 pd;
    if (!hv_inImage(im, pIdeal, pd)) continue;
    if (!hv_existedAt(im, existed)) continue;
    float storedMap = texture(u_depthMaps, vec3(hv_depthCoord(im, pIdeal), im.slice)).r;
    if (u_epsilonTest) {
      // Without classification the depth maps hold the city model only: a point well in front of
      // it (a tree, a car) is not what the photograph shows there (2022 §2.4).
      if (abs(zi - mix(im.near, im.far, storedMap)) > u_epsilon) continue;
    } else if (u_occlusion && hv_shadowed(im, zi, storedMap, normal, X, 0.0)) {
      continue;
    }
    hv_accumulate(i, im, hv_correctColour(im, textureLod(u_images, vec3(pd * im.uvScale, im.slice), 0.0)), u_method == 1, -1, blend);
    if (blend.done) break;
  }
  o_color = blend.alpha > 0.0 ? vec4(blend.sum / blend.alpha, 1.0) : vec4(own, 0.5);
}
#endif
