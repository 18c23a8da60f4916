// Built instead of hv/viewer/desktop/ when CMake did not find GLFW and Dear ImGui.
#include "hv/viewer/desktop/viewer.h"

#include <iostream>

namespace hv::viewer {

bool available() { return false; }

int run(const ViewerOptions&) {
  std::cerr << "error: this histoview was built without the viewer: GLFW and Dear ImGui were not found "
               "(Debian: libglfw3-dev libimgui-dev; tools/install-deps.sh installs them), then rebuild\n";
  return 2;
}

}  // namespace hv::viewer
