#include "hv/io/native/sumo_fcd.h"

#include "hv/util/input_file.h"
#include "hv/util/text.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace hv {
namespace {

constexpr std::size_t kMaxRows = 50000000;

// The 1-based line of a byte offset of the text.
int lineOf(std::string_view text, std::ptrdiff_t offset) {
  if (offset < 0) return 0;
  const std::size_t end = std::min(text.size(), std::size_t(offset));
  return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(end), '\n'));
}

}  // namespace

Trajectories parseSumoFcd(std::string_view xml, const std::string& source, Diagnostics& diag) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(xml.data(), xml.size());
  if (!r)
    throw InputError(source + ": line " + std::to_string(lineOf(xml, r.offset)) + ": not well-formed XML (" +
                     r.description() + ")");
  const pugi::xml_node root = doc.child("fcd-export");
  if (!root) {
    const pugi::xml_node first = doc.first_child();
    throw InputError(source + ": expected SUMO floating car data (a root element <fcd-export>), got <" +
                     shownText(first ? first.name() : "") + ">");
  }
  TrajectoryBuilder builder;
  for (const pugi::xml_node step : root.children("timestep")) {
    const auto number = [&](pugi::xml_node node, const char* attribute, const std::string& what) {
      const pugi::xml_attribute a = node.attribute(attribute);
      // The line is counted only for a message: counting it for every row would be quadratic.
      const auto where = [&] {
        return source + ": line " + std::to_string(lineOf(xml, node.offset_debug())) + ": " + what + ": attribute '" +
               attribute + "'";
      };
      if (!a) throw InputError(where() + ": missing");
      const std::string v = a.value();
      char* end = nullptr;
      const double d = v.empty() ? 0.0 : std::strtod(v.c_str(), &end);
      if (v.empty() || end != v.c_str() + v.size() || !std::isfinite(d))
        throw InputError(where() + ": expected a finite number, got '" + shownText(v) + "'");
      return d;
    };
    const double t = number(step, "time", "timestep");
    for (const pugi::xml_node v : step.children("vehicle")) {
      const std::string id = v.attribute("id").value();
      if (id.empty())
        throw InputError(source + ": line " + std::to_string(lineOf(xml, v.offset_debug())) +
                         ": vehicle: attribute 'id': expected the vehicle's id");
      const std::string what = "vehicle '" + id.substr(0, 40) + "'";
      const double x = number(v, "x", what), y = number(v, "y", what), angle = number(v, "angle", what);
      const std::string type = v.attribute("type").value();
      if (builder.rows() >= kMaxRows)
        throw InputError(source + ": more than " + std::to_string(kMaxRows) + " vehicle rows");
      // The front bumper back to the centre: half the length along the heading.
      const double half = 0.5 * vehicleSizeOf(type).length;
      TrajectorySample s;
      s.t = t;
      s.xy = glm::dvec2(x, y) - half * forwardFromSumoAngle(angle);
      s.angleDeg = angle;
      builder.add(id, type, s);
    }
  }
  return builder.finish(source, diag);
}

Trajectories readSumoFcd(const std::string& path, Diagnostics& diag) {
  return parseSumoFcd(readTextFile(path, kMaxTextBytes, "SUMO FCD output"), path, diag);
}

Trajectories readTrajectoriesCsv(const std::string& path, Diagnostics& diag) {
  return parseTrajectoriesCsv(readTextFile(path, kMaxTextBytes, "trajectories"), path, diag);
}

}  // namespace hv
