// The per-image test chain shared by the mesh pass (ibr_shade.frag) and the point pass
// (points.frag): whether photograph `im` textures a surface point, and what it adds to the pixel
// (Brédif 2013 eq. 1-2 and §2.2; docs/design.md). In chain order:
//   project      the pass's own (hv_project for a mesh point, the sprite homography for a point)
//   lens, domain hv_inImage      distortion domain and image bounds
//   date         hv_existedAt    the surface existed at the photograph's date
//   depth test   hv_shadowed     the photograph's depth map, slope-scaled bias
//   mask, blend  hv_accumulate   alpha = mask; weights or nearest
// Needs ibr_common.glsl (HvImage, hv_distort) included before it. The C++ twin of the whole chain
// is the loop body of hv::ibr::referenceBlend (src/hv/ibr/reference_blend.cpp).

uniform highp sampler2D u_viewBuilding;  // building index + 1 of each view-depth texel (RGBA8)
uniform highp sampler2D u_validity;      // per building index: days [first, last] (RGBA32F rows)
uniform int u_validityWidth;

// When the surface drawn at view-depth texel `dpix` by the view's geometry pass existed, in days
// (depth.frag writes the building index, u_validity holds each building's interval); terrain and
// pixels without a building (0, or 0xFFFFFF: the scene.json mesh, hv::render::kMeshSurfaceId): always. The intervals are hv::ibr::gpuDays (src/hv/ibr/frame_plan.h)
// of Scene::buildingValidity, uploaded by the renderer.
vec2 hv_surfaceExisted(ivec2 dpix) {
  vec2 existed = vec2(-1e7, 1e7);
  vec4 b = texelFetch(u_viewBuilding, dpix, 0) * 255.0;
  int building = int(b.r + 0.5) + 256 * int(b.g + 0.5) + 65536 * int(b.b + 0.5);
  if (building > 0 && building < 16777215) {
    int index = building - 1;
    existed = texelFetch(u_validity, ivec2(index % u_validityWidth, index / u_validityWidth), 0).xy;
  }
  return existed;
}

// Lens and domain: the distorted pixel pd of ideal pixel p, false outside the distortion domain or
// the image. The tail of hv::ibr::projectIntoImage (src/hv/ibr/reference_blend.cpp).
bool hv_inImage(HvImage im, vec2 p, out vec2 pd) {
  if (!hv_distort(im, p, pd)) return false;
  return all(greaterThanEqual(pd, vec2(0.0))) && all(lessThanEqual(pd, im.size));
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
  return hv_inImage(im, p, pd);
}

// Date: whether a surface that existed over `existed` (days) was there at the photograph's date;
// otherwise the photograph neither textures it nor is hidden by it (depth.frag leaves it out of
// the depth map). Twin of hv::overlaps (src/hv/util/dates.h) on hv::ibr::gpuDays intervals.
bool hv_existedAt(HvImage im, vec2 existed) {
  return !(existed.y < im.date.x || existed.x > im.date.y);
}

// Depth-map texture coordinates of ideal pixel p (the depth map covers the ideal rectangle
// [depthMin, depthMin + 1 / depthInvSize], hv::ibr::idealRectCoveringImage).
vec2 hv_depthCoord(HvImage im, vec2 p) { return (p - im.depthMin) * im.depthInvSize; }

// Depth-map test with a slope-scaled bias: within one depth-map texel, a surface seen at angle
// theta from its normal spans footprint * tan(theta) of depth, so the bias grows with tan(theta)
// (clamped). `n` is the surface normal, `toP` the unit direction from the photograph to P.
// Twin of hv::ibr::shadowBias (src/hv/ibr/frame_plan.cpp).
float hv_shadowBias(HvImage im, float z, vec3 n, vec3 toP) {
  float c = max(abs(dot(n, toP)), 0.1);
  float tanTheta = sqrt(max(1.0 - c * c, 0.0)) / c;
  return im.biasAbs + im.biasRel * z * (1.0 + tanTheta);
}

// The shadow test of P, at depth z in image `im`, against the depth map's stored value (Brédif
// 2013 §2.2). `pushBack`: the surface counts as moved that much back along its normal (the mesh in
// hybrid rendering, depth.frag; 0 for points), so only what stands more than that in front of it
// (not the points sampling it) shadows it; along the ray that is pushBack / cos(theta).
// hv::ibr::referenceBlend takes visibility as a callback: the GL tests check this test against
// ray casting (src/hv/render/renderer_gltest.cpp).
bool hv_shadowed(HvImage im, float z, float stored, vec3 normal, vec3 P, float pushBack) {
  if (stored >= 1.0) return false;  // the photograph saw no geometry there: nothing occludes
  float zMap = mix(im.near, im.far, stored);
  vec3 toP = normalize(P - im.C);
  float push = pushBack > 0.0 ? pushBack / max(abs(dot(normal, toP)), 0.1) : 0.0;
  return z > zMap + push + hv_shadowBias(im, z, normal, toP);
}

// Which photographs a pixel blends (hv::ibr::Selection): false, the papers' global selection,
// each image's weight is its global w_i = f(d_i) - f(d_K+1); true, per pixel, each image carries
// f(d_i) and the first u_blendK images that pass every test are blended with the K+1-th that
// passes at this pixel subtracted.
uniform bool u_region;
uniform int u_blendK;

// The running blend of one pixel (Brédif 2013 eq. 1-2, premultiplied). sum and alpha always hold
// the blend so far, so a caller reads them whenever its loop ends.
struct HvBlend {
  vec3 sum;
  float alpha;
  int count;
  bool done;   // nearest: the first image that passes every test wins; region: the K+1-th passed
  float mine;  // what image `debugImage` added to alpha (its share is mine / alpha)
  // Region: sum and alpha are S1 = sum f_i a_i c_i and A1 = sum f_i a_i over the first K passing;
  // these are S0 = sum a_i c_i, A0 = sum a_i, the debug image's a_i, how many passed, and the
  // last f with how many of the last passing share it (they lose their weight on a tie with
  // f(d_K+1)).
  vec3 sum0;
  float alpha0;
  float mine0;
  int passed;
  float fLast;
  int ties;
};

HvBlend hv_noBlend() { return HvBlend(vec3(0.0), 0.0, 0, false, 0.0, vec3(0.0), 0.0, 0.0, 0, 0.0, 0); }

// Mask and blend: image `i`'s texel (premultiplied, alpha = mask) added to `b`; `nearest`: images
// are sorted by distance, the first that passes wins. An image whose mask is 0 here does not pass
// (it does not show this surface), so in region selection the next one takes its place.
// `debugImage`: the image whose share is kept in b.mine (-1: none). Twin of the loop body of
// hv::ibr::referenceBlend.
// `feather` (hv::ibr::featherFactor and maskFeather, 1 without feathering) multiplies the image's
// weight: w_i = (f(d_i) - f(d_K+1)) * feather_i.
void hv_accumulateFeathered(int i, HvImage im, vec4 texel, float feather, bool nearest, int debugImage,
                            inout HvBlend b) {
  if (texel.a <= 0.0) return;
  if (nearest) {
    b = HvBlend(texel.rgb, texel.a, 1, true, i == debugImage ? texel.a : 0.0, vec3(0.0), 0.0, 0.0, 1, 0.0, 0);
    return;
  }
  if (u_region) {
    float f = im.weight;  // f(d_i), images in ascending distance
    if (b.passed == u_blendK) {
      // The K+1-th passing image: (S1 - f S0) / (A1 - f A0), the pixel's own eq. 2.
      b.sum -= f * b.sum0;
      b.alpha -= f * b.alpha0;
      b.mine -= f * b.mine0;
      if (f >= b.fLast) b.count -= b.ties;
      if (b.count == 0) {
        b.sum = vec3(0.0);
        b.alpha = 0.0;
        b.mine = 0.0;
      }
      b.done = true;
      return;
    }
    b.passed += 1;
    b.sum += f * feather * texel.rgb;
    b.alpha += f * feather * texel.a;
    b.sum0 += feather * texel.rgb;
    b.alpha0 += feather * texel.a;
    b.count += 1;
    b.ties = f == b.fLast ? b.ties + 1 : 1;
    b.fLast = f;
    if (i == debugImage) {
      b.mine = f * feather * texel.a;
      b.mine0 = feather * texel.a;
    }
    return;
  }
  float w = im.weight * feather;
  if (w <= 0.0) return;
  b.sum += w * texel.rgb;
  b.alpha += w * texel.a;
  b.count += 1;
  if (i == debugImage) b.mine = w * texel.a;
}

void hv_accumulate(int i, HvImage im, vec4 texel, bool nearest, int debugImage, inout HvBlend b) {
  hv_accumulateFeathered(i, im, texel, 1.0, nearest, debugImage, b);
}
