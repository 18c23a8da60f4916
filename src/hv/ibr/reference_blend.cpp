#include "hv/ibr/reference_blend.h"

#include "hv/ibr/consensus.h"

#include <algorithm>
#include <cmath>

namespace hv::ibr {

std::optional<ImageHit> projectIntoImage(const ImageParams& im, const glm::dvec3& P) {
  const glm::dvec3 ph = im.pixFromWorld * (P - im.centerRender);
  if (ph.z <= 0.0) return std::nullopt;
  ImageHit hit;
  hit.depth = ph.z;
  hit.pxIdeal = glm::dvec2(ph) / ph.z;
  const Camera& cam = im.camera;
  if (cam.distortion && !cam.distortion->isIdentity() && !cam.distortion->inDomain(hit.pxIdeal)) return std::nullopt;
  hit.pxDistorted = cam.distort(hit.pxIdeal);
  if (hit.pxDistorted.x < 0.0 || hit.pxDistorted.y < 0.0 || hit.pxDistorted.x > cam.width ||
      hit.pxDistorted.y > cam.height)
    return std::nullopt;
  return hit;
}

double borderDistance(const ImageParams& im, const ImageHit& hit) {
  const Camera& cam = im.camera;
  const glm::dvec2 pd = hit.pxDistorted;
  double b = std::min({pd.x, pd.y, cam.width - pd.x, cam.height - pd.y});
  if (cam.distortion && !cam.distortion->isIdentity() && cam.distortion->r2max < 1e29) {
    const LensDistortion& d = *cam.distortion;
    const glm::dvec2 x = (hit.pxIdeal - d.center) / d.scale;
    b = std::min(b, (std::sqrt(d.r2max) - glm::length(x)) * std::min(d.scale.x, d.scale.y));
  }
  return b;
}

double featherLevel(const ImageParams& im, double featherPx, int sliceWidth) {
  return std::max(0.0, std::log2(std::max(featherPx * im.layout.uvScale.x * sliceWidth, 1.0)));
}

glm::dvec4 correctTexel(const ColourCorrection& colour, const glm::dvec4& texel) {
  const glm::dvec3 c = colour.gain * glm::dvec3(texel) + texel.a * colour.offset;
  return {glm::clamp(c, glm::dvec3(0.0), glm::dvec3(texel.a)), texel.a};
}

BlendResult referenceBlend(const glm::dvec3& P, const std::vector<ImageParams>& images, BlendMethod method,
                           const TextureLookup& texture, const VisibilityTest& visible, Selection selection, int k,
                           const BlendOptions& opt) {
  BlendResult out;
  out.contribution.assign(images.size(), 0.0);
  glm::dvec3 sum(0.0);
  const bool geometry = opt.weighting == Weighting::Geometry;
  // Region: the images that passed so far, with their texels (the first K blend, the K+1-th ends it).
  std::vector<std::pair<size_t, glm::dvec4>> passed;
  std::vector<double> feather(images.size(), 1.0), penalty(images.size(), 0.0);
  // The pixel's samples: image i's texel with weight w (times its feather), in visiting order.
  struct Sample {
    size_t image;
    glm::dvec4 texel;
    double weight;
  };
  std::vector<Sample> samples;
  const auto add = [&](size_t i, const glm::dvec4& texel, double weight) {
    const double w = weight * feather[i];
    if (w > 0.0) samples.push_back({i, texel, w});
  };
  // The blend of the samples, after the transient filter when it is on (its first
  // kMaxConsensusSamples samples, as the shader's arrays hold).
  const auto finish = [&] {
    if (opt.consensusSpread > 0.0) {
      if (samples.size() > size_t(kMaxConsensusSamples)) samples.resize(kMaxConsensusSamples);
      std::vector<glm::dvec3> colour;
      std::vector<double> weight;
      for (const Sample& s : samples) {
        colour.push_back(glm::dvec3(s.texel) / s.texel.a);
        weight.push_back(s.weight);
      }
      consensusWeights(colour, weight, opt.consensusSpread);
      for (size_t j = 0; j < samples.size(); ++j) samples[j].weight = weight[j];
    }
    for (const Sample& s : samples) {
      if (s.weight <= 0.0) continue;
      sum += s.weight * glm::dvec3(s.texel);  // premultiplied: rgb already times alpha
      out.alpha += s.weight * s.texel.a;
      out.contribution[s.image] = s.weight * s.texel.a;
      ++out.count;
    }
    if (out.alpha > 0.0) out.color = sum / out.alpha;
    return out;
  };
  for (size_t i = 0; i < images.size(); ++i) {
    const ImageParams& im = images[i];
    const auto hit = projectIntoImage(im, P);
    if (!hit) continue;
    const bool layered = i < opt.layered.size() && opt.layered[i];
    const glm::dvec2 uv = hit->pxDistorted * im.layout.uvScale;
    glm::dvec4 texel(0.0);
    if (layered) {
      const std::optional<glm::dvec4> t = opt.layered[i](P);
      if (!t) continue;
      texel = correctTexel(im.colour, *t);
    } else {
      if (visible && !visible(i, P, hit->depth)) continue;
      texel = correctTexel(im.colour, texture(im.layout.slice, uv));
    }
    if (texel.a <= 0.0) continue;
    if (opt.featherPx > 0.0) {
      feather[i] = featherFactor(borderDistance(im, *hit), opt.featherPx);
      if (opt.mask && !layered)
        feather[i] *= maskFeather(opt.mask(im.layout.slice, uv, featherLevel(im, opt.featherPx, opt.sliceWidth)));
    }
    if (geometry && method != BlendMethod::Nearest) {
      GeometryPenaltyInput g;
      g.point = P;
      g.viewCenter = opt.viewCenter;
      g.imageCenter = im.centerRender;
      g.normal = opt.normal;
      g.viewFocal = opt.viewFocal;
      g.imageFocal = 0.5 * (im.camera.focal.x + im.camera.focal.y);
      penalty[i] = geometryPenalty(g, opt.resolutionWeight);
      passed.emplace_back(i, texel);
      continue;
    }
    if (method == BlendMethod::Nearest) {
      // Images are sorted by distance: the first that passes every test wins.
      out.color = glm::dvec3(texel) / texel.a;
      out.alpha = 1.0;
      out.count = 1;
      out.contribution[i] = 1.0;
      return out;
    }
    if (selection == Selection::Region) {
      passed.emplace_back(i, texel);
      if (int(passed.size()) > std::max(k, 1)) break;
      continue;
    }
    add(i, texel, im.weight);
  }
  if (geometry && method != BlendMethod::Nearest) {
    std::stable_sort(passed.begin(), passed.end(),
                     [&](const auto& a, const auto& b) { return penalty[a.first] < penalty[b.first]; });
    const size_t blended = std::min(passed.size(), size_t(geometryBlendCount(k, opt.geometryK)));
    const double fNext =
        passed.size() > blended ? blendFalloff(penalty[passed[blended].first], opt.penaltyEpsilon) : 0.0;
    for (size_t j = 0; j < blended; ++j)
      add(passed[j].first, passed[j].second,
          std::max(0.0, blendFalloff(penalty[passed[j].first], opt.penaltyEpsilon) - fNext));
    return finish();
  }
  if (selection == Selection::Region) {
    const size_t blended = std::min(passed.size(), size_t(std::max(k, 1)));
    const double fNext = passed.size() > blended ? images[passed[blended].first].weight : 0.0;
    // With the transient filter, the shader keeps the first kMaxConsensusSamples that pass.
    const size_t kept = opt.consensusSpread > 0.0 ? std::min(blended, size_t(kMaxConsensusSamples)) : blended;
    for (size_t j = 0; j < kept; ++j) add(passed[j].first, passed[j].second, images[passed[j].first].weight - fNext);
  }
  return finish();
}

glm::dvec4 sampleBilinear(const Image8& img, glm::dvec2 uv) {
  const double fx = uv.x * img.width - 0.5, fy = uv.y * img.height - 0.5;
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const double tx = fx - x0f, ty = fy - y0f;
  auto texel = [&](int x, int y) {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    glm::dvec4 v(0.0, 0.0, 0.0, 1.0);
    for (int c = 0; c < std::min(img.channels, 4); ++c) v[c] = img.at(x, y, c) / 255.0;
    return v;
  };
  const int x0 = int(x0f), y0 = int(y0f);
  return (1 - ty) * ((1 - tx) * texel(x0, y0) + tx * texel(x0 + 1, y0)) +
         ty * ((1 - tx) * texel(x0, y0 + 1) + tx * texel(x0 + 1, y0 + 1));
}

glm::dvec4 sampleTrilinear(const std::vector<Image8>& chain, glm::dvec2 uv, double lod) {
  const double l = std::clamp(lod, 0.0, double(chain.size()) - 1.0);
  const size_t l0 = size_t(std::floor(l)), l1 = std::min(l0 + 1, chain.size() - 1);
  const double t = l - double(l0);
  const glm::dvec4 a = sampleBilinear(chain[l0], uv);
  return t > 0.0 ? (1.0 - t) * a + t * sampleBilinear(chain[l1], uv) : a;
}

}  // namespace hv::ibr
