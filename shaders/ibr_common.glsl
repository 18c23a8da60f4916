// Per-image parameters and the lens model of a photograph. The C++ twins are
// hv::ibr::packImageParams (layout, src/hv/ibr/frame_plan.h) and hv::LensDistortion::distort,
// tested together by src/hv/render/renderer_gltest.cpp and lens_gltest.cpp. The projection into a
// photograph and the rest of the per-image test chain are in image_test.glsl.

uniform highp sampler2D u_params;  // RGBA32F, kTexelsPerImage texels per row, one row per image

struct HvImage {
  mat3 M;         // K R, applied to (P - C)
  vec3 C;         // camera centre, render frame
  vec2 dc;        // distortion centre
  vec2 dscale;    // pixels per normalised unit
  float c3, c5, c7;
  float p1, p2;   // tangential
  float l1, l2;   // fish-eye affine terms
  bool fisheye;
  float r2max;    // normalised; < 0: no distortion
  vec2 size;      // image width, height (pixels)
  vec2 uvScale;   // texture uv = (p_distorted - uvOffset) * uvScale
  vec2 uvOffset;  // 0, or a sub-image's window corner (Layered projective texture maps, 2003, §5.1)
  float layer;    // a layered photograph's sub-image: its visibility layer k; 0: a photograph
  float group;    // a sub-image: its photograph's index + 1 (one weight per group); 0: none
  float slice;
  float weight;
  vec2 depthMin, depthInvSize;
  float near, far, biasAbs, biasRel;
  vec2 date;      // the photograph's date interval, days (+-1e7 when open)
  float focal;    // pixels (mean of fx, fy): the geometry weights' footprint
  vec3 gain, offset;  // colour correction (hv::ColourCorrection)
};

HvImage hv_fetchImage(int i) {
  vec4 t0 = texelFetch(u_params, ivec2(0, i), 0);
  vec4 t1 = texelFetch(u_params, ivec2(1, i), 0);
  vec4 t2 = texelFetch(u_params, ivec2(2, i), 0);
  vec4 t3 = texelFetch(u_params, ivec2(3, i), 0);
  vec4 t4 = texelFetch(u_params, ivec2(4, i), 0);
  vec4 t5 = texelFetch(u_params, ivec2(5, i), 0);
  vec4 t6 = texelFetch(u_params, ivec2(6, i), 0);
  vec4 t7 = texelFetch(u_params, ivec2(7, i), 0);
  vec4 t8 = texelFetch(u_params, ivec2(8, i), 0);
  vec4 t9 = texelFetch(u_params, ivec2(9, i), 0);
  vec4 t10 = texelFetch(u_params, ivec2(10, i), 0);
  vec4 t11 = texelFetch(u_params, ivec2(11, i), 0);
  vec4 t12 = texelFetch(u_params, ivec2(12, i), 0);
  HvImage im;
  // Rows in the texture, GLSL matrices are column-major: transpose.
  im.M = transpose(mat3(t0.xyz, t1.xyz, t2.xyz));
  im.C = vec3(t0.w, t1.w, t2.w);
  im.dc = t3.xy;
  im.c3 = t3.z;
  im.c5 = t3.w;
  im.c7 = t4.x;
  im.r2max = t4.y;
  im.size = t4.zw;
  im.uvScale = t5.xy;
  im.slice = t5.z;
  im.weight = t5.w;
  im.depthMin = t6.xy;
  im.depthInvSize = t6.zw;
  im.near = t7.x;
  im.far = t7.y;
  im.biasAbs = t7.z;
  im.biasRel = t7.w;
  im.date = t8.xy;
  im.focal = t8.z;
  im.layer = t8.w;
  im.dscale = t9.xy;
  im.p1 = t9.z;
  im.p2 = t9.w;
  im.l1 = t10.x;
  im.l2 = t10.y;
  im.fisheye = t10.z > 0.5;
  im.group = t10.w;
  im.gain = t11.rgb;
  im.offset = t12.rgb;
  im.uvOffset = vec2(t11.w, t12.w);
  return im;
}

// The photograph's colour correction on a premultiplied texel: straight colour c becomes
// clamp(gain c + offset, 0, 1), so premultiplied a c becomes clamp(gain (a c) + a offset, 0, a).
// Twin of hv::ibr::correctTexel (src/hv/ibr/reference_blend.h).
vec4 hv_correctColour(HvImage im, vec4 texel) {
  return vec4(clamp(im.gain * texel.rgb + texel.a * im.offset, vec3(0.0), vec3(texel.a)), texel.a);
}

// Lens distortion, twin of hv::LensDistortion::distort (its comment in camera.h has the models):
// normalised x = (p - centre) / scale, the fish-eye angle step, radial, tangential and affine terms,
// p_d = p + scale * (x_d - x). Returns false outside the domain |x|^2 <= r2max.
// HV_CONF_LENS (the shade pass's per-configuration programs, src/hv/render/gl/shade_config.h): 0
// no photograph of the frame has a lens model, 1 none is a fish-eye, 2 some are.
#ifdef HV_CONF_LENS
#define HV_LENS_ANY (HV_CONF_LENS >= 1)
#define HV_LENS_FISHEYE (HV_CONF_LENS == 2)
#else
#define HV_LENS_ANY true
#define HV_LENS_FISHEYE true
#endif
bool hv_distort(HvImage im, vec2 p, out vec2 pd) {
  pd = p;
  if (!HV_LENS_ANY || im.r2max < 0.0) return true;
  vec2 x = (p - im.dc) / im.dscale;
  float R2 = dot(x, x);
  if (R2 > im.r2max) return false;
  vec2 a = x;
  if (HV_LENS_FISHEYE && im.fisheye && R2 > 0.0) {
    float R = sqrt(R2);
    a = x * (atan(R) / R);
  }
  float r2 = dot(a, a);
  vec2 d = a * (r2 * (im.c3 + r2 * (im.c5 + r2 * im.c7))) + (a - x);
  d += vec2(2.0 * im.p1 * a.x * a.y + im.p2 * (r2 + 2.0 * a.x * a.x),
            im.p1 * (r2 + 2.0 * a.y * a.y) + 2.0 * im.p2 * a.x * a.y);
  d += vec2(im.l1 * a.x - im.l2 * a.y, -im.l2 * a.x);
  pd = p + im.dscale * d;
  return true;
}
