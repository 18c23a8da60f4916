// `histoview layers export SCENE --image ID OUT.ora [--size WxH] [--no-prefill]`: a photograph's
// visibility layers as an OpenRaster file for an image editor (Layered projective texture maps,
// 2003; hv/layers/native/layer_export.h, docs/layers.md).
#pragma once

namespace CLI {
class App;
}

namespace hv::app {

void addLayersCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
