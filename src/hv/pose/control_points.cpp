#include "hv/pose/control_points.h"

#include "hv/util/diagnostics.h"
#include "hv/util/text.h"

#include <cmath>
#include <cstdlib>
#include <map>

namespace hv::pose {
namespace {

constexpr size_t kMaxPoints = 1000000;

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> out;
  size_t start = 0;
  for (size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == ',') {
      out.push_back(trimField(line.substr(start, i - start)));
      start = i + 1;
    }
  return out;
}

}  // namespace

std::vector<ControlPoint> parseControlPoints(std::string_view text, const std::string& source) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 BOM
  std::vector<ControlPoint> points;
  std::map<std::string, size_t> column;
  size_t width = 0;
  int lineNo = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = trimField(text.substr(pos, end - pos));
    pos = end + 1;
    ++lineNo;
    if (line.empty() || line.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    const std::vector<std::string_view> fields = splitFields(line);
    if (column.empty()) {  // the header
      for (size_t i = 0; i < fields.size(); ++i) column.emplace(asciiLower(fields[i]), i);
      for (const char* need : {"u", "v", "x", "y", "z"})
        if (!column.count(need))
          throw InputError(source + ": line " + std::to_string(lineNo) + ": the header has no column '" + need +
                           "' (expected a header naming u,v,x,y,z: pixel u, v with the top-left-corner origin, "
                           "world x, y, z in the scene CRS; got '" + shownText(line) + "')");
      width = fields.size();
      if (end == text.size()) break;
      continue;
    }
    if (fields.size() != width)
      throw InputError(source + ": line " + std::to_string(lineNo) + ": " + std::to_string(fields.size()) +
                       " fields where the header has " + std::to_string(width));
    if (points.size() >= kMaxPoints)
      throw InputError(source + ": more than " + std::to_string(kMaxPoints) + " control points");
    auto number = [&](const char* name) {
      const std::string_view f = fields[column.at(name)];
      const std::string copy(f);  // strtod: the browser build's library has no floating-point from_chars
      char* endp = nullptr;
      const double v = copy.empty() ? 0.0 : std::strtod(copy.c_str(), &endp);
      if (copy.empty() || endp != copy.c_str() + copy.size() || !std::isfinite(v))
        throw InputError(source + ": line " + std::to_string(lineNo) + ": column '" + name +
                         "': expected a finite number, got '" + shownText(f) + "'");
      return v;
    };
    ControlPoint p;
    p.pixel = {number("u"), number("v")};
    p.world = {number("x"), number("y"), number("z")};
    for (const char* key : {"id", "label", "name"})
      if (column.count(key) && !fields[column.at(key)].empty()) {
        p.label = std::string(fields[column.at(key)]);
        break;
      }
    if (p.label.empty()) p.label = "line " + std::to_string(lineNo);
    points.push_back(std::move(p));
    if (end == text.size()) break;
  }
  if (column.empty()) throw InputError(source + ": empty (expected a CSV header naming u,v,x,y,z, then one row per point)");
  return points;
}

}  // namespace hv::pose
