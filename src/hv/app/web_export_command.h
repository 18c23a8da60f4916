// `histoview web-export SCENE OUT/`: the scene as a self-contained static folder for the browser
// build (hv/io/web_scene.h, docs/web.md): triangulated meshes, the point cloud, cameras.json, the
// photographs as JPEG, masks, and the page (web/) with the WebAssembly build when it exists.
#pragma once

#include <cstddef>
#include <string>

namespace CLI {
class App;
}

namespace hv::app {

void addWebExportCommand(CLI::App& app, int& exitCode);

struct WebExportOptions {
  std::string scenePath;
  std::string out;
  std::string viewsPath;  // optional: copied as views.json (the page's ?camera= may name them)
  std::string pageDir;    // the page's sources (index.html, histoview.js); default: the source tree's web/
  std::string wasmDir;    // the Emscripten build's output; default: the source tree's build-web/dist
  int jpegQuality = 90;   // for photographs that are not JPEG already
  // At most this many of the scene's points (hv::subsampleChunks: a uniform subsample); 0: all.
  std::size_t maxPoints = 0;
};
// Returns the exit status (hv/app/outputs.h): 0 written, 3 written with items left out (named).
int runWebExport(const WebExportOptions& o);

}  // namespace hv::app
