// What the subcommands share: loading a scene and its views, parsing option values, and the
// headless renderer set-up.
#pragma once

#include "hv/gpu/context.h"
#include "hv/render/renderer.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

// Options shared by render and eval.
struct ViewOptions {
  std::string scenePath;
  std::string viewsPath;
  std::string size;                 // "WxH", empty: each view's own
  int k = 8;
  double sigma = -1.0;
  std::vector<std::string> exclude;
  int depthSize = 1024;
  std::string background = "0,0,0";
};
void addViewOptions(CLI::App& cmd, ViewOptions& o);

// "640x480" -> (640, 480); throws std::invalid_argument with the expected form.
glm::ivec2 parseSize(const std::string& s);
// "R,G,B" (0-255) -> [0, 1]; throws std::invalid_argument.
glm::dvec3 parseColour(const std::string& s);

// The view camera at the requested output size: intrinsics scaled uniformly; a different aspect
// ratio is an error (std::invalid_argument naming the view).
Camera resizeView(const Camera& view, const std::string& size);

struct Session {
  Scene scene;
  std::vector<Photo> views;
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<render::Renderer> renderer;
};

// Loads the scene and views, prints what failed, creates the context and renderer.
// Returns nullopt (after printing why) when nothing can be rendered.
std::unique_ptr<Session> openSession(const ViewOptions& o, Diagnostics& diag);
render::RenderSettings renderSettings(const ViewOptions& o);

}  // namespace hv::app
