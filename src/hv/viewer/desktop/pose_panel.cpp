#include "hv/viewer/desktop/pose_panel.h"

#include "hv/io/cameras_json.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace hv::viewer {

namespace fs = std::filesystem;
using pose::PosePair;
using pose::PoseSession;
using pose::ResidualLine;
using pose::WorldRay;

bool PosePanel::enter(const Scene& scene, int photo) {
  leave();
  const Photo& p = scene.photos[size_t(photo)];
  try {
    image_ = readImage(p.imagePath, 3);
  } catch (const std::exception& e) {
    message_ = std::string("pose mode: ") + e.what();
    return false;
  }
  photo_ = photo;
  original_ = p.camera;
  savedVersion_ = -1;
  textureSize_ = glm::ivec2(0);
  session_ = std::make_unique<PoseSession>(p.camera);
  std::snprintf(savePath_, sizeof savePath_, "%s-posed.json", p.camera.id.c_str());
  message_.clear();
  return true;
}

void PosePanel::leave() {
  session_.reset();
  photo_ = -1;
}

void PosePanel::clickView(const Camera& view, glm::dvec2 px, const RayQuery* scene) {
  if (!session_) return;
  std::optional<glm::dvec3> hit;
  const WorldRay r = pose::rayThroughPixel(view, px);
  if (r.valid && scene)
    if (const auto h = scene->intersect(r.origin, r.direction)) hit = h->position;
  session_->clickScene(hit);
}

bool PosePanel::save(const Scene& scene, const std::string& path, bool replace) {
  if (!session_ || !session_->solution()) {
    message_ = "nothing to save: the camera is not solved (" + std::to_string(session_ ? session_->pairsNeeded() : 4) +
               " pairs or more)";
    return false;
  }
  std::error_code ec;
  const std::string refusal = pose::checkSavePath(path, inputs_, fs::exists(path, ec), replace);
  if (!refusal.empty()) {
    message_ = "not saved: " + refusal;
    return false;
  }
  const fs::path out = fs::absolute(path, ec);
  if (out.has_parent_path()) fs::create_directories(out.parent_path(), ec);
  Photo written = scene.photos[size_t(photo_)];
  written.camera = session_->solution()->camera;
  if (!written.imagePath.empty()) written.imagePath = fs::absolute(written.imagePath, ec).lexically_normal().string();
  if (!written.maskPath.empty()) written.maskPath = fs::absolute(written.maskPath, ec).lexically_normal().string();
  std::ofstream f(out, std::ios::binary | std::ios::trunc);
  f << cameraJson({written}, out.parent_path().string()) << "\n";
  f.close();
  if (!f) {
    message_ = "not saved: " + out.string() + ": cannot write";
    return false;
  }
  savedVersion_ = session_->solutionVersion();
  message_ = "wrote " + out.string();
  std::cout << "pose: " << message_ << "\n";
  return true;
}

PosePanel::Result PosePanel::draw(const Scene& scene, double& opacity) {
  Result r;
  if (!session_) return r;
  PoseSession& s = *session_;
  const int versionBefore = s.solutionVersion();
  const ImGuiIO& io = ImGui::GetIO();
  const std::string& id = scene.photos[size_t(photo_)].camera.id;
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 8, 8), ImGuiCond_FirstUseEver, ImVec2(1, 0));
  bool open = true;
  ImGui::Begin(("pose: " + id + "###pose").c_str(), &open, ImGuiWindowFlags_AlwaysAutoResize);

  // The photograph, fitted into 45 % of the window's width (resampled once per size on the CPU).
  const double width = std::clamp(double(io.DisplaySize.x) * 0.45, 160.0, 900.0);
  const glm::ivec2 want(int(width), std::max(1, int(std::lround(width * image_.height / image_.width))));
  if (want != textureSize_) {
    texture_.upload(resizeImage(image_, want.x, want.y));
    textureSize_ = want;
  }
  const ImVec2 at = ImGui::GetCursorScreenPos();
  ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture_.id())),
               ImVec2(float(want.x), float(want.y)));
  const double scale = double(want.x) / image_.width;  // window units per photograph pixel
  auto toScreen = [&](glm::dvec2 px) { return ImVec2(at.x + float(px.x * scale), at.y + float(px.y * scale)); };
  if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Left))
    s.clickPhoto({(io.MousePos.x - at.x) / scale, (io.MousePos.y - at.y) / scale});
  ImDrawList* dl = ImGui::GetWindowDrawList();
  for (size_t i = 0; i < s.pairs().size(); ++i) {
    const ImVec2 c = toScreen(s.pairs()[i].pixel);
    dl->AddCircle(c, 5.0f, IM_COL32(255, 220, 0, 255), 12, 2.0f);
    dl->AddText(ImVec2(c.x + 6, c.y - 14), IM_COL32(255, 220, 0, 255), std::to_string(i + 1).c_str());
  }
  for (const ResidualLine& l : s.residualLines())
    dl->AddLine(toScreen(l.clicked), toScreen(l.projected),
                l.inlier ? IM_COL32(0, 255, 80, 255) : IM_COL32(255, 40, 40, 255), 2.0f);
  if (s.pending()) dl->AddCircle(toScreen(*s.pending()), 7.0f, IM_COL32(0, 200, 255, 255), 12, 2.0f);

  ImGui::TextWrapped("%s", s.message().c_str());
  if (s.pending() && ImGui::Button("cancel the pending click")) s.cancel();
  bool focal = s.solveFocal();
  if (ImGui::Checkbox("solve the focal (6 pairs)", &focal)) s.setSolveFocal(focal);
  const std::vector<ResidualLine> lines = s.residualLines();
  int remove = -1;
  for (size_t i = 0; i < s.pairs().size(); ++i) {
    const PosePair& p = s.pairs()[i];
    ImGui::PushID(int(i));
    if (ImGui::SmallButton("x")) remove = int(i);
    ImGui::SameLine();
    if (i < lines.size())
      ImGui::Text("%zu: (%.1f, %.1f) px  %.2f px%s", i + 1, p.pixel.x, p.pixel.y, lines[i].pixels,
                  lines[i].inlier ? "" : "  outlier");
    else
      ImGui::Text("%zu: (%.1f, %.1f) px", i + 1, p.pixel.x, p.pixel.y);
    ImGui::PopID();
  }
  if (remove >= 0) s.removePair(remove);
  if (s.solution()) {
    const Camera& c = s.solution()->camera;
    ImGui::Text("centre (%.2f, %.2f, %.2f), %.2f m from before", c.center.x, c.center.y, c.center.z,
                glm::distance(c.center, original_.center));
    if (ImGui::Button("look from it (then and now)")) r.lookFromSolved = true;
    float a = float(opacity);
    if (ImGui::SliderFloat("photograph opacity", &a, 0.0f, 1.0f, "%.2f")) opacity = a;
  }
  ImGui::InputText("cameras.json", savePath_, sizeof savePath_);
  ImGui::Checkbox("replace", &replace_);
  ImGui::SameLine();
  if (ImGui::Button("save")) save(scene, savePath_, replace_);
  if (!message_.empty()) ImGui::TextWrapped("%s", message_.c_str());
  ImGui::End();
  r.cameraChanged = s.solutionVersion() != versionBefore;
  r.leave = !open;
  return r;
}

std::vector<std::string> PosePanel::runScript(const std::string& path, const Scene& scene, const Camera& view,
                                              const RayQuery* caster) {
  std::vector<std::string> errors;
  std::ifstream f(path);
  if (!f) return {path + ": cannot read the pose script"};
  std::string line;
  int n = 0;
  while (errors.empty() && std::getline(f, line)) {
    ++n;
    std::istringstream in(line);
    std::string cmd;
    if (!(in >> cmd) || cmd[0] == '#') continue;
    const std::string where = path + ": line " + std::to_string(n) + ": ";
    auto fail = [&](const std::string& what) { errors.push_back(where + what); };
    if (cmd == "enter") {
      std::string id;
      in >> id;
      int found = -1;
      for (size_t i = 0; i < scene.photos.size(); ++i)
        if (scene.photos[i].camera.id == id) found = int(i);
      if (found < 0)
        fail("enter: no photograph '" + id + "'");
      else if (!enter(scene, found))
        fail(message_);
      continue;
    }
    if (!session_) {
      fail("'" + cmd + "' outside pose mode (expected 'enter ID' first)");
      continue;
    }
    double a = 0.0, b = 0.0;
    if (cmd == "photo" || cmd == "view") {
      if (!(in >> a >> b)) {
        fail(cmd + ": expected two numbers (pixels)");
      } else if (cmd == "photo") {
        if (!session_->clickPhoto({a, b})) fail(session_->message());
      } else {
        clickView(view, {a, b}, caster);
        if (session_->pending()) fail(session_->message());
      }
    } else if (cmd == "remove") {
      int i = 0;
      if (!(in >> i) || !session_->removePair(i - 1)) fail("remove: expected a pair number from 1");
    } else if (cmd == "focal") {
      std::string v;
      in >> v;
      if (v != "on" && v != "off") fail("focal: expected on or off");
      session_->setSolveFocal(v == "on");
    } else if (cmd == "save") {
      std::string out, flag;
      in >> out >> flag;
      if (!save(scene, out, flag == "replace")) fail(message_);
    } else if (cmd == "leave") {
      leave();
    } else {
      fail("unknown command '" + cmd + "' (expected enter, photo, view, remove, focal, save or leave)");
    }
  }
  if (session_) std::cout << "pose: " << session_->message() << "\n";
  return errors;
}

}  // namespace hv::viewer
