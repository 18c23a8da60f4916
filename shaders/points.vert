#version 300 es
// Point sprites (Devaux & Brédif 2016 §3, de Castro & Brédif 2022 §2.3; docs/design.md).
// Each point is a screen-aligned sprite bounding the disk of radius u_radius in its tangent plane;
// the fragment shader (points.frag) finds the plane point under each of its pixels exactly. The
// target's pixels are gl_FragCoord.xy: u_M = targetFromPix K R (hv::ibr::targetCameraMatrix).
// Twins: hv::ibr::spriteNormal, spritePlaneVector, spriteSizePixels, spriteHomography2016
// (src/hv/ibr/sprite_homography.h).
precision highp float;
precision highp int;
precision highp sampler2D;

layout(location = 0) in vec3 a_position;  // render frame
layout(location = 1) in vec3 a_normal;    // (0, 0, 0): none
layout(location = 2) in vec4 a_color;     // own colour (rgb), ASPRS class / 255 (a)

uniform mat3 u_M;        // target camera matrix
uniform mat3 u_MinvT;    // M^-T
uniform vec3 u_C;        // target camera centre, render frame
uniform vec2 u_targetSize;
uniform float u_near;
uniform float u_far;
uniform float u_radius;  // world radius of the sprites of this draw
uniform float u_maxPointSize;
uniform bool u_classify;       // classification filter on (else every point is "kept")
uniform uint u_keptClasses[8]; // bit c: class c is non-transient (textured, in depth maps)
uniform bool u_dropTransient;  // transient points are not drawn at all (depth maps, or hidden)

flat out vec3 v_nPrime;  // N' = M^-T N / (N^T (P - C))
flat out vec3 v_PC;      // P - C
flat out vec4 v_color;   // own colour; a = 1 when the point may be textured

#ifdef HV_MAT3_K
// The 2016 form: one homography per image, H_i = H'_i + E_i N'^T = (M_i + E_i N^T / (N^T (P - C))) M^-1.
uniform highp sampler2D u_pointParams;  // per image: rows of H' (xyz) and E (w), 3 texels
uniform int u_imageCount;
flat out mat3 v_H[HV_MAT3_K];
#endif

bool hv_kept(int cls) {
  if (!u_classify) return true;
  return ((u_keptClasses[cls >> 5] >> uint(cls & 31)) & 1u) != 0u;
}

// Twin of hv::ibr::spriteSizePixels.
float hv_spriteSize(vec3 q, float radius) {
  float z = q.z;
  if (z - radius <= 0.0) return 0.0;
  vec2 p = q.xy / z;
  vec3 m1 = vec3(u_M[0][0], u_M[1][0], u_M[2][0]);
  vec3 m2 = vec3(u_M[0][1], u_M[1][1], u_M[2][1]);
  vec3 m3 = vec3(u_M[0][2], u_M[1][2], u_M[2][2]);
  vec3 j1 = m1 - p.x * m3, j2 = m2 - p.y * m3;
  float a = dot(j1, j1), b = dot(j1, j2), c = dot(j2, j2);
  float lambda = 0.5 * (a + c) + sqrt(0.25 * (a - c) * (a - c) + b * b);
  return 2.0 * radius * sqrt(lambda) / (z - radius);
}

void main() {
  int cls = int(a_color.a * 255.0 + 0.5);
  bool kept = hv_kept(cls);
  vec3 PC = a_position - u_C;
  vec3 q = u_M * PC;
  float size = hv_spriteSize(q, u_radius);
  if ((!kept && u_dropTransient) || size <= 0.0 || q.z > u_far) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: not drawn
    gl_PointSize = 1.0;
    v_nPrime = vec3(0.0);
    v_PC = vec3(0.0);
    v_color = vec4(0.0);
    return;
  }
  // Twin of hv::ibr::spriteNormal: the point's own normal unless absent or edge-on (cos < 0.1).
  vec3 toView = -PC;
  float dist = length(toView);
  vec3 N = toView / dist;
  float len = length(a_normal);
  if (len > 0.0 && abs(dot(a_normal, toView)) >= 0.002 * len * dist) N = a_normal / len;
  v_nPrime = u_MinvT * N / dot(N, PC);
  v_PC = PC;
  v_color = vec4(a_color.rgb, kept ? 1.0 : 0.0);
  // Pixels x, y of the target map to NDC 2 x / W - 1 (offscreen targets are stored top row
  // first); depth is written by the fragment shader, so clip z only keeps the point inside.
  gl_Position = vec4(2.0 * q.xy / u_targetSize - q.z, 0.0, q.z);
  gl_PointSize = clamp(size, 1.0, u_maxPointSize);
#ifdef HV_MAT3_K
  for (int i = 0; i < HV_MAT3_K; ++i) {
    if (i >= u_imageCount) {
      v_H[i] = mat3(0.0);
      continue;
    }
    vec4 r0 = texelFetch(u_pointParams, ivec2(0, i), 0);
    vec4 r1 = texelFetch(u_pointParams, ivec2(1, i), 0);
    vec4 r2 = texelFetch(u_pointParams, ivec2(2, i), 0);
    mat3 Hp = transpose(mat3(r0.xyz, r1.xyz, r2.xyz));
    vec3 E = vec3(r0.w, r1.w, r2.w);
    v_H[i] = Hp + outerProduct(E, v_nPrime);
  }
#endif
}
