#include "hv/viewer/desktop/sources_panel.h"

#include <imgui.h>

#include <algorithm>
#include <iostream>

namespace hv::viewer {

void SourcesPanel::update(const Scene& scene, const render::Renderer& renderer) {
  const render::RenderStats& st = renderer.stats();
  const std::size_t version = scene.missing ? scene.missing->version() : 0;
  std::vector<SourceProgress> progress = loadProgress();
  SourceStatus s;
  s.buildingTilesPending = st.buildingTilesPending;
  s.buildingTilesRetrying = st.buildingTilesRetrying;
  s.terrainTilesPending = st.terrainTilesPending;
  s.imagesWaiting = st.imagesWaiting;
  const bool changed = version != missingVersion_ || progress.size() != progressCount_;
  s.progress = std::move(progress);
  if (scene.missing) s.missing = scene.missing->list();
  lines_ = sourceStatusLines(s);
  if (!changed) return;
  missingVersion_ = version;
  progressCount_ = s.progress.size();
  // Printed once each: the load's sources (their counts as they stood when first printed) and
  // every missing entry as it changes (a tile's tries).
  auto print = [&](const std::vector<std::string>& lines) {
    for (const std::string& l : lines)
      if (std::find(printed_.begin(), printed_.end(), l) == printed_.end()) {
        std::cout << "viewer: sources: " << l << "\n";
        printed_.push_back(l);
      }
  };
  print(lines_.progress);
  print(lines_.missing);
  std::cout << std::flush;
}

void SourcesPanel::draw() const {
  if (lines_.empty()) return;
  if (!lines_.missing.empty()) ImGui::SetNextItemOpen(true, ImGuiCond_Once);
  const std::string title = lines_.missing.empty()
                                ? std::string("Sources")
                                : "Sources (" + std::to_string(lines_.missing.size()) + " missing)###Sources";
  if (!ImGui::CollapsingHeader(title.c_str())) return;
  for (const std::string& l : lines_.missing) ImGui::TextColored(ImVec4(1.0f, 0.6f, 0.3f, 1.0f), "%s", l.c_str());
  for (const std::string& l : lines_.streaming) ImGui::TextWrapped("%s", l.c_str());
  if (!lines_.progress.empty()) {
    ImGui::TextDisabled("read at load, before the first frame:");
    for (const std::string& l : lines_.progress) ImGui::TextDisabled("%s", l.c_str());
  }
}

}  // namespace hv::viewer
