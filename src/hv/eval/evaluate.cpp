#include "hv/eval/evaluate.h"

#include "hv/eval/metrics.h"

#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace hv::eval {

namespace fs = std::filesystem;

Method parseMethod(const std::string& name) {
  if (name == "blend") return Method::Blend;
  if (name == "nearest") return Method::Nearest;
  if (name == "no-occlusion") return Method::NoOcclusion;
  throw std::invalid_argument("--method: expected blend, nearest or no-occlusion, got '" + name + "'");
}

std::string methodName(Method m) {
  switch (m) {
    case Method::Blend: return "blend";
    case Method::Nearest: return "nearest";
    case Method::NoOcclusion: return "no-occlusion";
  }
  return "?";
}

void applyMethod(Method m, render::RenderSettings& s) {
  s.blend.method = m == Method::Nearest ? ibr::BlendMethod::Nearest : ibr::BlendMethod::Blend;
  s.blend.occlusion = m != Method::NoOcclusion;
}

namespace {

std::string findTruth(const std::string& dir, const std::string& id) {
  for (const char* ext : {".png", ".jpg", ".jpeg", ".JPG", ".PNG"}) {
    const fs::path p = fs::path(dir) / (id + ext);
    if (fs::is_regular_file(p)) return p.string();
  }
  return {};
}

}  // namespace

EvalReport evaluate(render::Renderer& renderer, const std::vector<Photo>& views, const EvalOptions& opt,
                    Diagnostics& diag, const std::function<void(const std::string&)>& progress) {
  EvalReport report;
  for (Method m : opt.methods) report.methods.push_back(methodName(m));
  const render::RenderSettings saved = renderer.settings();
  size_t index = 0;
  for (const Photo& v : views) {
    ++index;
    const std::string id = v.camera.id;
    try {
      const Camera cam = opt.size.x > 0 ? v.camera.resized(opt.size.x, opt.size.y) : v.camera;
      std::string stem = id;
      if (!opt.leaveOneOut) {
        stem = opt.truthStem ? opt.truthStem(id) : id;
        if (stem.empty() || stem.find_first_of(std::string("/\\\0", 3)) != std::string::npos || stem[0] == '.')
          throw InputError("view '" + id + "': the id is not a plain file name, so it names no truth image in " +
                           opt.truthDir);
      }
      const std::string truthPath = opt.leaveOneOut ? v.imagePath : findTruth(opt.truthDir, stem);
      if (truthPath.empty())
        throw InputError(opt.truthDir + ": no truth image " + stem + ".png or " + stem + ".jpg");
      Image8 truth = readImage(truthPath, 3);
      if (opt.leaveOneOut && (truth.width != cam.width || truth.height != cam.height))
        truth = resizeImage(truth, cam.width, cam.height);
      if (truth.width != cam.width || truth.height != cam.height)
        throw InputError(truthPath + ": truth is " + std::to_string(truth.width) + "x" + std::to_string(truth.height) +
                         ", the view renders at " + std::to_string(cam.width) + "x" + std::to_string(cam.height));
      const size_t n = size_t(cam.width) * cam.height;
      std::vector<std::uint8_t> scored(n, 1);
      const fs::path covPath = opt.leaveOneOut ? fs::path(v.maskPath) : fs::path(opt.truthDir) / (stem + ".coverage.png");
      if (opt.leaveOneOut && !v.maskPath.empty()) {
        Image8 mask = readImage(v.maskPath, 1);
        if (mask.width != cam.width || mask.height != cam.height) mask = resizeImage(mask, cam.width, cam.height);
        for (size_t i = 0; i < n; ++i) scored[i] = mask.data[i] > 0;
      } else if (!opt.leaveOneOut && fs::is_regular_file(covPath)) {
        const Image8 cov = readImage(covPath.string(), 1);
        if (cov.width != cam.width || cov.height != cam.height)
          throw InputError(covPath.string() + ": coverage size differs from the truth's");
        for (size_t i = 0; i < n; ++i) scored[i] = cov.data[i] > 0;
      }
      std::vector<Image8> renders;
      std::vector<double> coverage;
      if (opt.leaveOneOut) {
        renderer.settings().blend.exclude = saved.blend.exclude;
        renderer.settings().blend.exclude.push_back(id);
      }
      // The traffic's vehicles are no error of a method: the truth is the empty street.
      renderer.settings().traffic.enabled = false;
      Image16 borderCounts;
      if (opt.borderSeams) {
        applyMethod(opt.methods.empty() ? Method::Blend : opt.methods.front(), renderer.settings());
        const double feather = renderer.settings().blend.featherPx;
        renderer.settings().blend.featherPx = 0.0;
        borderCounts = renderer.render(cam, true).counts;
        renderer.settings().blend.featherPx = feather;
      }
      for (Method m : opt.methods) {
        applyMethod(m, renderer.settings());
        render::RenderOutput out = renderer.render(cam);
        size_t covered = 0;
        for (size_t i = 0; i < n; ++i) {
          const bool c = out.rgba.data[4 * i + 3] > 0;
          covered += c;
          scored[i] = scored[i] && c;
        }
        coverage.push_back(double(covered) / double(n));
        renders.push_back(std::move(out.rgba));
      }
      const double scoredFraction = double(countScored(scored)) / double(n);
      std::ostringstream line;
      line << "[" << index << "/" << views.size() << "] " << id;
      for (size_t k = 0; k < opt.methods.size(); ++k) {
        const Scores s = compareImages(renders[k], truth, scored);
        ViewScore row{id, methodName(opt.methods[k]), s.psnr, s.ssim, coverage[k], scoredFraction};
        if (opt.borderSeams) row.seam = eval::borderSeams(renders[k], truth, borderCounts, scored).excess;
        report.rows.push_back(row);
        line << "  " << methodName(opt.methods[k]) << " " << s.psnr << " dB";
      }
      if (progress) progress(line.str());
    } catch (const std::exception& e) {
      // Any failure of one view (a file system error on its truth, memory, a renderer error) is
      // that view's alone: the others are still scored (docs/reliability.md).
      diag.error(std::string(e.what()) + " (view '" + id + "' not scored)");
    }
  }
  renderer.settings() = saved;
  return report;
}

}  // namespace hv::eval
