#include "hv/io/json_input.h"
#include "hv/util/input_file.h"

#include <algorithm>
#include <cctype>
#include <set>

namespace hv {
namespace {

using nlohmann::json;

bool wordChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }

// The bare NaN / Infinity / -Infinity outside strings, quoted; everything else as it is.
std::string quoteNonFiniteLiterals(const std::string& text) {
  if (text.find("NaN") == std::string::npos && text.find("Infinity") == std::string::npos) return text;
  std::string out;
  out.reserve(text.size() + 64);
  bool inString = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      out += c;
      if (c == '\\' && i + 1 < text.size()) out += text[++i];
      else if (c == '"') inString = false;
      continue;
    }
    if (c == '"') {
      inString = true;
      out += c;
      continue;
    }
    bool replaced = false;
    if (i == 0 || !wordChar(text[i - 1])) {
      for (const char* word : {"-Infinity", "Infinity", "NaN"}) {
        const size_t n = std::char_traits<char>::length(word);
        if (text.compare(i, n, word) == 0 && (i + n == text.size() || !wordChar(text[i + n]))) {
          out += '"';
          out += word;
          out += '"';
          i += n - 1;
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out += c;
  }
  return out;
}

// One open object or array while parsing: its keys so far, the last one, and the repeated keys
// found in it or in the unnamed objects below it (as dotted paths).
struct Frame {
  bool object = false;
  std::set<std::string> keys;
  std::string lastKey;
  std::vector<std::string> repeated;
};

std::string idOf(const json& object) {
  if (!object.is_object() || !object.contains("id")) return "";
  const json& id = object["id"];
  if (id.is_string()) return id.get<std::string>();
  if (id.is_number_integer()) return std::to_string(id.get<long long>());
  return "";
}

}  // namespace

bool isNonFiniteLiteral(const json& v) {
  return v.is_string() && (v == "NaN" || v == "Infinity" || v == "-Infinity");
}

json parseJsonInput(const std::string& text, const std::string& file, Diagnostics& diag) {
  std::vector<Frame> stack;
  std::vector<std::string> found;
  const auto close = [&](const json& parsed) {
    Frame f = std::move(stack.back());
    stack.pop_back();
    if (f.repeated.empty()) return;
    const std::string id = idOf(parsed);
    if (!id.empty() || stack.empty()) {
      for (const std::string& k : f.repeated)
        found.push_back(inputMessage(file, id.empty() ? "" : "id '" + id + "'",
                                     "duplicate key '" + k + "' (the last of its values is used)"));
      return;
    }
    Frame& parent = stack.back();
    for (const std::string& k : f.repeated)
      parent.repeated.push_back(parent.object ? parent.lastKey + "." + k : k);
  };
  const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: stack.push_back(Frame{true, {}, {}, {}}); break;
      case json::parse_event_t::array_start: stack.push_back(Frame{false, {}, {}, {}}); break;
      case json::parse_event_t::key:
        if (!stack.empty()) {
          Frame& f = stack.back();
          const std::string key = parsed.get<std::string>();
          if (!f.keys.insert(key).second) f.repeated.push_back(key);
          f.lastKey = key;
        }
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack.empty()) close(parsed);
        break;
      case json::parse_event_t::value: break;
    }
    return true;
  };
  json doc;
  try {
    doc = json::parse(quoteNonFiniteLiterals(text), callback);
  } catch (const json::exception& e) {  // parse errors, and numbers out of range (1e400)
    throw InputError(file + ": not valid JSON: " + e.what());
  }
  for (std::string& m : found) diag.warn(std::move(m));
  return doc;
}

json readJsonInput(const std::string& path, const std::string& what, Diagnostics& diag) {
  return parseJsonInput(readTextFile(path, kMaxJsonBytes, what), path, diag);
}

std::vector<std::string> unknownKeys(const json& object, const std::vector<std::string>& known) {
  std::vector<std::string> out;
  if (!object.is_object()) return out;
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    const std::string near = closestName(key, known);
    out.push_back("unknown key '" + key + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)"));
  }
  return out;
}

nlohmann::json parseFeatureCollection(const std::string& text, const std::string& name, std::string& next) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object() || doc.value("type", std::string()) != "FeatureCollection" || !doc.contains("features") ||
      !doc["features"].is_array())
    throw InputError(name +
                     ": expected a GeoJSON FeatureCollection (\"type\": \"FeatureCollection\", \"features\": [...])");
  next.clear();
  if (doc.contains("links") && doc["links"].is_array())
    for (const nlohmann::json& l : doc["links"])
      if (l.is_object() && l.value("rel", std::string()) == "next" && l.contains("href") && l["href"].is_string())
        next = l["href"].get<std::string>();
  return doc;
}

}  // namespace hv
