// Per-image parameters and the projection into a photograph. The C++ twins are
// hv::ibr::packImageParams (layout) and hv::ibr::projectIntoImage (src/hv/ibr/), tested together
// by src/hv/render/renderer_gltest.cpp.

uniform highp sampler2D u_params;  // RGBA32F, kTexelsPerImage texels per row, one row per image

struct HvImage {
  mat3 M;         // K R, applied to (P - C)
  vec3 C;         // camera centre, render frame
  vec2 dc;        // distortion centre
  float c3, c5, c7;
  float r2max;    // < 0: no distortion
  vec2 size;      // image width, height (pixels)
  vec2 uvScale;   // texture uv = p_distorted * uvScale
  float slice;
  float weight;
  vec2 depthMin, depthInvSize;
  float near, far, biasAbs, biasRel;
  vec2 date;      // the photograph's date interval, days (+-1e7 when open)
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
  return im;
}

// Radial distortion (Brédif 2013, fig. 2): p_d = p + r (c3|r|^2 + c5|r|^4 + c7|r|^6), r = p - centre.
// Twin of hv::RadialDistortion::distort. Returns false outside the domain |r|^2 <= r2max.
bool hv_distort(HvImage im, vec2 p, out vec2 pd) {
  pd = p;
  if (im.r2max < 0.0) return true;
  vec2 r = p - im.dc;
  float r2 = dot(r, r);
  if (r2 > im.r2max) return false;
  pd = p + r * (r2 * (im.c3 + r2 * (im.c5 + r2 * im.c7)));
  return true;
}

// Projects a render-frame point into image `im`: ideal pixel p, distorted pixel pd, depth z.
// Twin of hv::ibr::projectIntoImage. False when behind, outside the domain or the image.
bool hv_project(HvImage im, vec3 P, out vec2 p, out vec2 pd, out float z) {
  vec3 ph = im.M * (P - im.C);
  z = ph.z;
  p = vec2(0.0);
  pd = vec2(0.0);
  if (z <= 0.0) return false;
  p = ph.xy / z;
  if (!hv_distort(im, p, pd)) return false;
  return all(greaterThanEqual(pd, vec2(0.0))) && all(lessThanEqual(pd, im.size));
}
