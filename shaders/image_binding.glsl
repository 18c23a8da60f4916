// Texture binding of the photographs and depth maps, included by ibr_shade.frag.
// HV_NAIVE: the baseline the papers improve on (Brédif 2013; de Castro & Brédif 2022 §2.1): one
// sampler2D per photograph and one per depth map, two texture units per image, up to
// HV_NAIVE_COUNT (<= 16) images. GLSL ES 3.00 indexes sampler arrays only with constant
// expressions, hence the explicit chain. Otherwise: one texture2DArray of each.
#ifdef HV_NAIVE
#if HV_NAIVE_COUNT > 0
uniform highp sampler2D u_image0;
uniform highp sampler2D u_depth0;
#endif
#if HV_NAIVE_COUNT > 1
uniform highp sampler2D u_image1;
uniform highp sampler2D u_depth1;
#endif
#if HV_NAIVE_COUNT > 2
uniform highp sampler2D u_image2;
uniform highp sampler2D u_depth2;
#endif
#if HV_NAIVE_COUNT > 3
uniform highp sampler2D u_image3;
uniform highp sampler2D u_depth3;
#endif
#if HV_NAIVE_COUNT > 4
uniform highp sampler2D u_image4;
uniform highp sampler2D u_depth4;
#endif
#if HV_NAIVE_COUNT > 5
uniform highp sampler2D u_image5;
uniform highp sampler2D u_depth5;
#endif
#if HV_NAIVE_COUNT > 6
uniform highp sampler2D u_image6;
uniform highp sampler2D u_depth6;
#endif
#if HV_NAIVE_COUNT > 7
uniform highp sampler2D u_image7;
uniform highp sampler2D u_depth7;
#endif
#if HV_NAIVE_COUNT > 8
uniform highp sampler2D u_image8;
uniform highp sampler2D u_depth8;
#endif
#if HV_NAIVE_COUNT > 9
uniform highp sampler2D u_image9;
uniform highp sampler2D u_depth9;
#endif
#if HV_NAIVE_COUNT > 10
uniform highp sampler2D u_image10;
uniform highp sampler2D u_depth10;
#endif
#if HV_NAIVE_COUNT > 11
uniform highp sampler2D u_image11;
uniform highp sampler2D u_depth11;
#endif
#if HV_NAIVE_COUNT > 12
uniform highp sampler2D u_image12;
uniform highp sampler2D u_depth12;
#endif
#if HV_NAIVE_COUNT > 13
uniform highp sampler2D u_image13;
uniform highp sampler2D u_depth13;
#endif
#if HV_NAIVE_COUNT > 14
uniform highp sampler2D u_image14;
uniform highp sampler2D u_depth14;
#endif
#if HV_NAIVE_COUNT > 15
uniform highp sampler2D u_image15;
uniform highp sampler2D u_depth15;
#endif
vec4 hv_sampleImage(int i, vec2 uv) {
#if HV_NAIVE_COUNT > 0
  if (i == 0) return textureLod(u_image0, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 1
  if (i == 1) return textureLod(u_image1, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 2
  if (i == 2) return textureLod(u_image2, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 3
  if (i == 3) return textureLod(u_image3, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 4
  if (i == 4) return textureLod(u_image4, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 5
  if (i == 5) return textureLod(u_image5, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 6
  if (i == 6) return textureLod(u_image6, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 7
  if (i == 7) return textureLod(u_image7, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 8
  if (i == 8) return textureLod(u_image8, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 9
  if (i == 9) return textureLod(u_image9, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 10
  if (i == 10) return textureLod(u_image10, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 11
  if (i == 11) return textureLod(u_image11, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 12
  if (i == 12) return textureLod(u_image12, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 13
  if (i == 13) return textureLod(u_image13, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 14
  if (i == 14) return textureLod(u_image14, uv, 0.0);
#endif
#if HV_NAIVE_COUNT > 15
  if (i == 15) return textureLod(u_image15, uv, 0.0);
#endif
  return vec4(0.0);
}
float hv_sampleDepth(int i, vec2 uv) {
#if HV_NAIVE_COUNT > 0
  if (i == 0) return texture(u_depth0, uv).r;
#endif
#if HV_NAIVE_COUNT > 1
  if (i == 1) return texture(u_depth1, uv).r;
#endif
#if HV_NAIVE_COUNT > 2
  if (i == 2) return texture(u_depth2, uv).r;
#endif
#if HV_NAIVE_COUNT > 3
  if (i == 3) return texture(u_depth3, uv).r;
#endif
#if HV_NAIVE_COUNT > 4
  if (i == 4) return texture(u_depth4, uv).r;
#endif
#if HV_NAIVE_COUNT > 5
  if (i == 5) return texture(u_depth5, uv).r;
#endif
#if HV_NAIVE_COUNT > 6
  if (i == 6) return texture(u_depth6, uv).r;
#endif
#if HV_NAIVE_COUNT > 7
  if (i == 7) return texture(u_depth7, uv).r;
#endif
#if HV_NAIVE_COUNT > 8
  if (i == 8) return texture(u_depth8, uv).r;
#endif
#if HV_NAIVE_COUNT > 9
  if (i == 9) return texture(u_depth9, uv).r;
#endif
#if HV_NAIVE_COUNT > 10
  if (i == 10) return texture(u_depth10, uv).r;
#endif
#if HV_NAIVE_COUNT > 11
  if (i == 11) return texture(u_depth11, uv).r;
#endif
#if HV_NAIVE_COUNT > 12
  if (i == 12) return texture(u_depth12, uv).r;
#endif
#if HV_NAIVE_COUNT > 13
  if (i == 13) return texture(u_depth13, uv).r;
#endif
#if HV_NAIVE_COUNT > 14
  if (i == 14) return texture(u_depth14, uv).r;
#endif
#if HV_NAIVE_COUNT > 15
  if (i == 15) return texture(u_depth15, uv).r;
#endif
  return 1.0;
}
#else
uniform highp sampler2DArray u_images;     // premultiplied RGBA8, alpha = mask
uniform highp sampler2DArray u_depthMaps;  // linear depth in [0, 1] between near and far
vec4 hv_sampleImage(int i, vec2 uv) { return textureLod(u_images, vec3(uv, float(i)), 0.0); }
float hv_sampleDepth(int i, vec2 uv) { return texture(u_depthMaps, vec3(uv, float(i))).r; }
#endif
