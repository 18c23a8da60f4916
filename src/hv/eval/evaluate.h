// Quality evaluation (docs/evaluation.md): render views with one or several blending methods and score
// them against ground-truth images on the pixels that every method and the truth cover.
#pragma once

#include "hv/eval/report.h"
#include "hv/render/renderer.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <functional>
#include <string>
#include <vector>

namespace hv::eval {

enum class Method { Blend, Nearest, NoOcclusion };
Method parseMethod(const std::string& name);  // throws std::invalid_argument listing the choices
std::string methodName(Method m);
// Sets the renderer's blending rule for a method (the other settings stay).
void applyMethod(Method m, render::RenderSettings& settings);

struct EvalOptions {
  std::vector<Method> methods{Method::Blend};
  std::string truthDir;        // <id>.png or <id>.jpg, optional <id>.coverage.png
  glm::ivec2 size{0};          // output size; (0, 0): each view at its own size
  // Leave-one-out: the views are the scene's photographs; each is rendered from the *other*
  // photographs and scored against itself (resized to the output size), over its unmasked pixels.
  // truthDir is not used.
  bool leaveOneOut = false;
  // The file-name stem of a view's truth image in truthDir, called once per view in order: the
  // stem `histoview render` writes for the view's id (hv::app::OutputNames, so an id such as
  // "../x" never names a file outside truthDir). Unset: the id itself, refused when it is not a
  // plain file name.
  std::function<std::string(const std::string& id)> truthStem;
  // The seam metric (metrics.h, borderSeams): each view is rendered once more without feathering
  // and with its contributing-image counts, whose changes between neighbouring pixels are the
  // photograph borders every method is measured at (the same pixels whatever the feather width).
  bool borderSeams = false;
};

// Renders and scores every view. A view whose truth is missing or unreadable is reported in
// `diag` and left out of the report; the others are scored. `progress` gets one line per view.
EvalReport evaluate(render::Renderer& renderer, const std::vector<Photo>& views, const EvalOptions& options,
                    Diagnostics& diag, const std::function<void(const std::string&)>& progress = {});

}  // namespace hv::eval
