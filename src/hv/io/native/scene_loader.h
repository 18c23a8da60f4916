// scene.json: what a scene is made of (paths relative to the file). Schema in docs/formats.md.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>

namespace hv {

// Loads terrain, buildings and cameras. A broken source (missing file, unreadable raster, bad
// camera) is reported in `diag` and left out; the rest loads. Throws InputError only when
// scene.json itself cannot be read or parsed.
Scene loadScene(const std::string& path, Diagnostics& diag);

}  // namespace hv
