// The web scene's orthophoto (hv/io/web_scene.h; docs/web.md): the image the renderer drapes on
// untextured terrain (hv/scene/orthophoto.h), as web-export writes it from scene.json's
// "orthophoto" or as the page writes it from a WMTS (docs/services.md, "In the browser"):
//   "orthophoto": {"path": "orthophoto.rgba", "width": W, "height": H,
//                  "rect": [minX, minY, maxX, maxY], "source": "…"}
//   orthophoto.rgba  W*H*4 bytes, straight RGBA, row 0 the northern edge (Orthophoto::rgba)
// rect: the scene-frame rectangle the image covers (Orthophoto's minX, minY, maxX, maxY).
#pragma once

#include "hv/scene/orthophoto.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace hv {

inline constexpr const char* kWebOrthophotoFile = "orthophoto.rgba";

// Writes orthophoto.rgba into `dir` and returns the manifest entry. Throws std::runtime_error
// naming the file when it cannot be written.
nlohmann::json writeWebOrthophoto(const Orthophoto& o, const std::string& dir);

// The manifest's orthophoto, its file relative to `dir`; null when the entry is absent. A bad
// entry or file is reported in `diag` naming it (the orthophoto left out).
std::shared_ptr<const Orthophoto> readWebOrthophoto(const nlohmann::json& manifest, const std::string& dir,
                                                    const std::string& manifestPath, Diagnostics& diag);

// The same from the manifest file at `manifestPath` (the file beside it); a manifest that cannot be
// read gives null (its reader reports it).
std::shared_ptr<const Orthophoto> readWebOrthophoto(const std::string& manifestPath, Diagnostics& diag);

}  // namespace hv
