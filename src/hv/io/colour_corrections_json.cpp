#include "hv/io/colour_corrections_json.h"

#include "hv/io/json_input.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace hv {
namespace {

using nlohmann::json;

glm::dvec3 vec3Field(const json& entry, const char* field, double lo, double hi) {
  if (!entry.contains(field)) throw InputError(std::string(field) + ": missing (expected an array of 3 numbers)");
  const json& v = entry.at(field);
  if (!v.is_array() || v.size() != 3) throw InputError(std::string(field) + ": expected an array of 3 numbers");
  glm::dvec3 out(0.0);
  for (int i = 0; i < 3; ++i) {
    const json& e = v[size_t(i)];
    if (!e.is_number()) throw InputError(std::string(field) + ": expected numbers (r, g, b)");
    out[i] = e.get<double>();
    if (!std::isfinite(out[i]) || out[i] < lo || out[i] > hi)
      throw InputError(std::string(field) + ": expected finite numbers in [" + json(lo).dump() + ", " +
                       json(hi).dump() + "], got " + e.dump());
  }
  return out;
}

}  // namespace

std::vector<ColourCorrectionEntry> parseColourCorrections(const std::string& text, const std::string& path,
                                                          Diagnostics& diag) {
  const json doc = parseJsonInput(text, path, diag);
  if (!doc.is_object()) throw InputError(inputMessage(path, "", "expected a JSON object with a \"corrections\" array"));
  for (const std::string& m : unknownKeys(doc, {"model", "corrections", "statistics"}))
    diag.warn(inputMessage(path, "", m + " (ignored)"));
  if (doc.contains("model") && (!doc["model"].is_string() || doc["model"].get<std::string>() != "gain-offset"))
    throw InputError(inputMessage(path, "model", "expected \"gain-offset\""));
  if (!doc.contains("corrections") || !doc["corrections"].is_array())
    throw InputError(inputMessage(path, "corrections", "expected an array"));
  std::vector<ColourCorrectionEntry> out;
  std::set<std::string> seen;
  const json& list = doc["corrections"];
  for (size_t i = 0; i < list.size(); ++i) {
    const json& e = list[i];
    std::string name = "corrections[" + std::to_string(i) + "]";
    try {
      if (!e.is_object()) throw InputError("expected an object");
      if (!e.contains("id") || !e["id"].is_string() || e["id"].get<std::string>().empty())
        throw InputError("id: expected a non-empty string (the photograph's camera id)");
      ColourCorrectionEntry entry;
      entry.id = e["id"].get<std::string>();
      name += " ('" + entry.id + "')";
      for (const std::string& m : unknownKeys(e, {"id", "gain", "offset", "pairs"}))
        diag.warn(inputMessage(path, name, m + " (ignored)"));
      entry.colour.gain = vec3Field(e, "gain", 0.0, kMaxColourGain);
      entry.colour.offset = vec3Field(e, "offset", -kMaxColourOffset, kMaxColourOffset);
      if (e.contains("pairs")) {
        const json& p = e["pairs"];
        if (!p.is_number_integer() || p.get<double>() < 0.0 || p.get<double>() > 2e9)
          throw InputError("pairs: expected a non-negative integer");
        entry.pairs = int(p.get<double>());
      }
      if (!seen.insert(entry.id).second) throw InputError("id: repeated (the first entry is kept)");
      out.push_back(entry);
    } catch (const InputError& err) {
      diag.error(inputMessage(path, name, std::string(err.what()) + " (left out: the photograph keeps its colours)"));
    }
  }
  return out;
}

std::vector<ColourCorrectionEntry> readColourCorrections(const std::string& path, Diagnostics& diag) {
  return parseColourCorrections(readTextFile(path, kMaxJsonBytes, "colour corrections"), path, diag);
}

void applyColourCorrections(std::vector<Photo>& photos, const std::vector<ColourCorrectionEntry>& entries,
                            const std::string& path, Diagnostics& diag) {
  std::map<std::string, size_t> byId;
  for (size_t i = 0; i < photos.size(); ++i) byId.emplace(photos[i].camera.id, i);
  std::vector<bool> given(photos.size(), false);
  size_t unknown = 0;
  std::string firstUnknown;
  for (const ColourCorrectionEntry& e : entries) {
    const auto it = byId.find(e.id);
    if (it == byId.end()) {
      if (unknown++ == 0) firstUnknown = e.id;
      continue;
    }
    photos[it->second].colour = e.colour;
    given[it->second] = true;
  }
  if (unknown > 0)
    diag.warn(inputMessage(path, "corrections",
                           std::to_string(unknown) + " entr" + (unknown == 1 ? "y names" : "ies name") +
                               " no photograph of the scene (first: '" + firstUnknown + "')"));
  const size_t missing = size_t(std::count(given.begin(), given.end(), false));
  if (missing > 0 && !entries.empty())
    diag.warn(inputMessage(path, "corrections",
                           std::to_string(missing) + " photograph" + (missing == 1 ? "" : "s") +
                               " without a correction keep their colours"));
}

std::string colourCorrectionsJson(const std::vector<ColourCorrectionEntry>& entries) {
  json list = json::array();
  for (const ColourCorrectionEntry& e : entries) {
    json j;
    j["id"] = e.id;
    j["gain"] = {e.colour.gain.r, e.colour.gain.g, e.colour.gain.b};
    j["offset"] = {e.colour.offset.r, e.colour.offset.g, e.colour.offset.b};
    if (e.pairs >= 0) j["pairs"] = e.pairs;
    list.push_back(j);
  }
  json doc;
  doc["model"] = "gain-offset";
  doc["corrections"] = list;
  return doc.dump(1) + "\n";
}

}  // namespace hv
