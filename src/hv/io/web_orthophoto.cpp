#include "hv/io/web_orthophoto.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hv {

using nlohmann::json;
namespace fs = std::filesystem;

json writeWebOrthophoto(const Orthophoto& o, const std::string& dir) {
  const fs::path file = fs::path(dir) / kWebOrthophotoFile;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(o.rgba.data()), std::streamsize(o.rgba.size()));
  if (!out) throw std::runtime_error(file.string() + ": cannot be written");
  return {{"path", kWebOrthophotoFile},
          {"width", o.width},
          {"height", o.height},
          {"rect", {o.minX, o.minY, o.maxX, o.maxY}},
          {"source", o.path}};
}

std::shared_ptr<const Orthophoto> readWebOrthophoto(const json& manifest, const std::string& dir,
                                                    const std::string& manifestPath, Diagnostics& diag) {
  if (!manifest.is_object() || !manifest.contains("orthophoto")) return nullptr;
  const std::string where = manifestPath + ": orthophoto";
  try {
    const json& e = manifest["orthophoto"];
    if (!e.is_object() || !e.contains("path") || !e["path"].is_string())
      throw InputError(where + ": expected {\"path\": \"orthophoto.rgba\", \"width\", \"height\", \"rect\"}");
    auto side = [&](const char* k) {
      if (!e.contains(k) || !e[k].is_number_integer() || e[k].get<long long>() < 1 || e[k].get<long long>() > 16384)
        throw InputError(where + "." + k + ": expected a whole number of pixels, 1 to 16384");
      return int(e[k].get<long long>());
    };
    auto o = std::make_shared<Orthophoto>();
    o->width = side("width");
    o->height = side("height");
    const json& r = e.value("rect", json());
    if (!r.is_array() || r.size() != 4)
      throw InputError(where + ".rect: expected [minX, minY, maxX, maxY]");
    double v[4];
    for (int k = 0; k < 4; ++k) {
      if (!r[std::size_t(k)].is_number() || !std::isfinite(r[std::size_t(k)].get<double>()))
        throw InputError(where + ".rect: expected 4 finite numbers");
      v[k] = r[std::size_t(k)].get<double>();
    }
    if (!(v[2] > v[0]) || !(v[3] > v[1])) throw InputError(where + ".rect: expected minX < maxX and minY < maxY");
    o->minX = v[0], o->minY = v[1], o->maxX = v[2], o->maxY = v[3];
    o->path = e.value("source", e["path"].get<std::string>());
    const std::string file = (fs::path(dir) / e["path"].get<std::string>()).string();
    const std::vector<std::uint8_t> bytes = readFileBytes(file);
    const std::size_t want = std::size_t(o->width) * std::size_t(o->height) * 4;
    if (bytes.size() != want)
      throw InputError(file + ": " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(want) +
                       " (width x height x 4, RGBA)");
    o->rgba = bytes;
    return o;
  } catch (const std::exception& ex) {
    diag.error(std::string(ex.what()) + " (orthophoto left out)");
    return nullptr;
  }
}

std::shared_ptr<const Orthophoto> readWebOrthophoto(const std::string& manifestPath, Diagnostics& diag) {
  std::ifstream in(manifestPath);
  const json m = json::parse(in, nullptr, false);
  if (m.is_discarded()) return nullptr;
  const fs::path dir = fs::path(manifestPath).parent_path();
  return readWebOrthophoto(m, dir.empty() ? "." : dir.string(), manifestPath, diag);
}

}  // namespace hv
