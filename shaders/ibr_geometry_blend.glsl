// The geometry weights' blend of a per-configuration program (included by ibr_shade.frag after
// its helpers: hv_uvAt, hv_sampleImage, hv_feather, HvBlend). Twin of the generic loop in
// ibr_shade.frag's main() and of hv::ibr's CPU reference (docs/design.md, "Picture quality").

#if defined(HV_CONFIG) && HV_CONF_GEOMETRY == 1 && HV_CONF_CONSENSUS == 0
#define HV_FAST_GEOMETRY
// The geometry weights in a per-configuration program: the same ranking, test chain and weights
// as the generic loop in main() (docs/design.md), with K and the ranking's length compile-time
// constants, so both per-pixel lists sit at constant indices. The ranking inserts each candidate
// by a chain of compare-and-swaps over its HV_CONF_RANK entries (ties in list order: a later equal
// penalty goes after), the test loop takes the head and shifts the rest down, and the passing
// images enter the best K + 1 at its end, the earlier ones shifting down, so after the loop they
// are in ascending penalty from index HV_CAP - nBest on.
#define HV_CAP (HV_CONF_K + 1)
void hv_geometryBlend(int n, int row, vec3 P, vec3 normal, vec2 existed, vec3 dPdx, vec3 dPdy, inout HvBlend blend) {
  float rankP[HV_CONF_RANK];
  int rankI[HV_CONF_RANK];
  for (int j = 0; j < HV_CONF_RANK; ++j) {
    rankP[j] = 3.0e38;
    rankI[j] = -1;  // no candidate
  }
  for (int k = 0; k < n; ++k) {
    int i = u_culling ? int(texelFetch(u_tileLists, ivec2(k + 1, row), 0).r) : k;
    // C and the focal length: t0.w, t1.w, t2.w and t8.z (hv_fetchImage).
    vec3 C = vec3(texelFetch(u_params, ivec2(0, i), 0).w, texelFetch(u_params, ivec2(1, i), 0).w,
                  texelFetch(u_params, ivec2(2, i), 0).w);
    float pen = hv_penalty(C, texelFetch(u_params, ivec2(8, i), 0).z, P, normal);
    for (int j = 0; j < HV_CONF_RANK; ++j) {
      bool before = pen < rankP[j];
      float tp = rankP[j];
      int ti = rankI[j];
      rankP[j] = before ? pen : tp;
      rankI[j] = before ? i : ti;
      pen = before ? tp : pen;
      i = before ? ti : i;
    }
  }
  int nRank = min(n, HV_CONF_RANK);
  float bestP[HV_CAP];
  vec4 bestT[HV_CAP];
  float bestF[HV_CAP];
  int bestI[HV_CAP];
  for (int j = 0; j < HV_CAP; ++j) {
    bestP[j] = 0.0;
    bestT[j] = vec4(0.0);
    bestF[j] = 0.0;
    bestI[j] = -1;
  }
  int nBest = 0;
  float doneGroup = 0.0;
  for (int k = 0; k < nRank; ++k) {
    int i = rankI[0];
    float pen = rankP[0];
    if (i < 0) break;  // fewer ranked than listed (a penalty that is not a number)
    for (int j = 0; j < HV_CONF_RANK - 1; ++j) {
      rankI[j] = rankI[j + 1];
      rankP[j] = rankP[j + 1];
    }
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
    for (int j = 0; j < HV_CAP - 1; ++j) {
      bestP[j] = bestP[j + 1];
      bestT[j] = bestT[j + 1];
      bestF[j] = bestF[j + 1];
      bestI[j] = bestI[j + 1];
    }
    bestP[HV_CAP - 1] = pen;
    bestT[HV_CAP - 1] = texel;
    bestF[HV_CAP - 1] = hv_feather(im, p, pd, uv);
    bestI[HV_CAP - 1] = i;
    nBest += 1;
    if (nBest == HV_CAP) break;
  }
  // w_j = (f(p_j) - f(p_K+1)) * feather_j over the best K (hv::ibr::blendWeights of the penalties).
  float e2 = u_penaltyEpsilon * u_penaltyEpsilon;
  bool full = nBest == HV_CAP;
  float fNext = full ? 1.0 / (e2 + bestP[HV_CAP - 1] * bestP[HV_CAP - 1]) : 0.0;
  int first = HV_CAP - nBest, last = full ? HV_CAP - 2 : HV_CAP - 1;
  for (int j = 0; j < HV_CAP; ++j) {
    float w = max(0.0, 1.0 / (e2 + bestP[j] * bestP[j]) - fNext) * bestF[j];
    if (j < first || j > last || w <= 0.0) continue;
    blend.sum += w * bestT[j].rgb;
    blend.alpha += w * bestT[j].a;
    blend.count += 1;
    if (bestI[j] == u_debugImage) blend.mine = w * bestT[j].a;
  }
}
#endif
