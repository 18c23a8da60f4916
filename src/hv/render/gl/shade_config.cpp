#include "hv/render/gl/shade_config.h"

#include "hv/ibr/frame_plan.h"

#include <algorithm>
#include <atomic>

namespace hv::render::gl {

namespace {
std::atomic<bool> gSpecialise{true};
}  // namespace

void setShadeSpecialisation(bool on) { gSpecialise = on; }
bool shadeSpecialisation() { return gSpecialise; }

std::vector<std::string> shadeConfigDefines(const Frame& f, int candidates, float maxAnisotropy) {
  const ibr::BlendSettings& b = f.blend;
  const bool nearest = b.method == ibr::BlendMethod::Nearest;
  const bool geometry = b.weighting == ibr::Weighting::Geometry && !nearest;
  const bool consensus = b.consensus > 0.0 && !nearest;
  // What the frame's photographs need (ibr::packImageParams): layered sub-images, lens models,
  // fish-eyes.
  bool layers = false, lens = false, fisheye = false;
  const size_t stride = size_t(ibr::kTexelsPerImage) * 4;
  for (size_t i = 0; i + stride <= f.packedParams.size(); i += stride) {
    const float* o = &f.packedParams[i];
    layers = layers || o[35] > 0.0f;
    lens = lens || o[17] >= 0.0f;
    fisheye = fisheye || (o[17] >= 0.0f && o[42] > 0.5f);
  }
  const int rank = std::clamp((std::max(candidates, 1) + 3) / 4 * 4, 4, ibr::kMaxGeometryRank);
  const bool anisotropic = b.mipmaps && maxAnisotropy > 1.0f && b.anisotropy > 1.0;  // as bindShadeInputs
  std::vector<std::string> d = {"HV_CONFIG",
                                "HV_CONF_GEOMETRY=" + std::to_string(geometry ? 1 : 0),
                                "HV_CONF_K=" + std::to_string(geometry ? ibr::geometryBlendCount(b.k, b.geometryK) : 1),
                                "HV_CONF_RANK=" + std::to_string(geometry ? rank : 4),
                                "HV_CONF_CONSENSUS=" + std::to_string(consensus ? 1 : 0),
                                "HV_CONF_MIPMAPS=" + std::to_string(!b.mipmaps ? 0 : anisotropic ? 2 : 1),
                                "HV_CONF_FEATHER=" + std::to_string(b.featherPx > 0.0 ? 1 : 0),
                                "HV_CONF_LAYERS=" + std::to_string(layers ? 1 : 0),
                                "HV_CONF_LENS=" + std::to_string(fisheye ? 2 : lens ? 1 : 0)};
  return d;
}

std::string shadeConfigKey(const std::vector<std::string>& defines) {
  std::string key;
  for (const std::string& d : defines) key += d + " ";
  return key;
}

}  // namespace hv::render::gl
