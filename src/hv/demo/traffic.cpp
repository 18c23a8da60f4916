// The demo city's traffic: SUMO on the street grid (docs/traffic.md). The city knows its streets
// (World::streets, full-length lines on a grid); they become a SUMO plain network, netconvert
// builds it, randomTrips.py draws trips with a fixed seed, and sumo writes the floating car data
// that scene.json's "traffic" reads.
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "hv/demo/demo_city.h"

namespace hv::demo {
namespace {

namespace fs = std::filesystem;

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool haveTool(const std::string& name) {
  return std::system(("command -v " + quoted(name) + " >/dev/null 2>&1").c_str()) == 0;
}

// Runs `command` (which stops itself after `timeoutSeconds`: timeout(1)) with its output into
// `log`; "" or why it failed.
std::string run(const std::string& what, const std::string& command, const fs::path& log, double timeoutSeconds) {
  const std::string line = "(" + command + ") >" + quoted(log.string()) + " 2>&1";
  const int rc = std::system(line.c_str());
  if (rc == 0) return "";
  const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::string tail;
  {
    std::ifstream in(log);
    std::string l;
    while (std::getline(in, l)) tail = l.empty() ? tail : l;
  }
  if (code == 124) return what + " ran past " + std::to_string(int(timeoutSeconds)) + " s (log: " + log.string() + ")";
  return what + " failed (exit " + std::to_string(code) + ": " + tail + "; log: " + log.string() + ")";
}

std::string fixed(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(2);
  s << v;
  return s.str();
}

}  // namespace

TrafficResult simulateTraffic(const World& world, const TrafficOptions& options, const std::string& outDir) {
  const auto t0 = std::chrono::steady_clock::now();
  TrafficResult result;
  const fs::path dir = fs::path(outDir) / "traffic";
  fs::create_directories(dir);
  const char* sumoHomeEnv = std::getenv("SUMO_HOME");
  const std::string sumoHome = sumoHomeEnv && *sumoHomeEnv ? sumoHomeEnv : "/usr/share/sumo";
  const fs::path randomTrips = fs::path(sumoHome) / "tools" / "randomTrips.py";
  for (const char* tool : {"sumo", "netconvert", "python3"})
    if (!haveTool(tool)) {
      result.message = std::string("'") + tool +
                       "' not found: SUMO is a dependency of the demo's traffic (Debian packages sumo sumo-tools, "
                       "tools/install-deps.sh)";
      return result;
    }
  if (!fs::exists(randomTrips)) {
    result.message = randomTrips.string() + " not found: install sumo-tools (tools/install-deps.sh) or set SUMO_HOME";
    return result;
  }

  // The plain network: a node at every crossing of two streets, an edge each way between
  // consecutive crossings along a street. Coordinates relative to the city's origin (SUMO keeps
  // two decimals), kept as they are by netconvert (--offset.disable-normalization).
  const glm::dvec2 origin = world.options.city.originXY;
  std::map<std::pair<long long, long long>, std::string> nodeIds;  // by centimetres
  std::ostringstream nodes, edges;
  nodes << "<nodes>\n";
  edges << "<edges>\n";
  auto node = [&](glm::dvec2 p) {
    const auto key = std::make_pair(std::llround(p.x * 100.0), std::llround(p.y * 100.0));
    auto it = nodeIds.find(key);
    if (it != nodeIds.end()) return it->second;
    const std::string id = "n" + std::to_string(nodeIds.size());
    nodeIds.emplace(key, id);
    nodes << "  <node id=\"" << id << "\" x=\"" << fixed(p.x - origin.x) << "\" y=\"" << fixed(p.y - origin.y)
          << "\" type=\"priority\"/>\n";
    return id;
  };
  const double speed = 13.89;  // 50 km/h
  int edgeCount = 0;
  for (const Street& s : world.streets) {
    std::vector<double> along;  // the crossings' positions along the street
    for (const Street& o : world.streets)
      if (o.alongX != s.alongX && o.centre >= s.from && o.centre <= s.to && s.centre >= o.from && s.centre <= o.to)
        along.push_back(o.centre);
    std::sort(along.begin(), along.end());
    for (size_t k = 1; k < along.size(); ++k) {
      const auto at = [&](double a) { return s.alongX ? glm::dvec2(a, s.centre) : glm::dvec2(s.centre, a); };
      const std::string a = node(at(along[k - 1])), b = node(at(along[k]));
      const std::string id = "e" + std::to_string(edgeCount++);
      edges << "  <edge id=\"" << id << "\" from=\"" << a << "\" to=\"" << b << "\" numLanes=\"1\" speed=\"" << speed
            << "\"/>\n";
      edges << "  <edge id=\"-" << id << "\" from=\"" << b << "\" to=\"" << a << "\" numLanes=\"1\" speed=\"" << speed
            << "\"/>\n";
    }
  }
  nodes << "</nodes>\n";
  edges << "</edges>\n";
  if (edgeCount == 0) {
    result.message = "the city has no street crossings to make a road network of";
    return result;
  }
  std::ofstream(dir / "streets.nod.xml") << nodes.str();
  std::ofstream(dir / "streets.edg.xml") << edges.str();

  const fs::path net = dir / "streets.net.xml", trips = dir / "trips.xml";
  const fs::path fcd = fs::path(outDir) / "fcd.xml";
  // The tools' own options (named apart from histoview's: they are SUMO's command lines, not
  // options of ours).
  const auto opt = [](const char* name, const std::string& value) { return std::string(" --") + name + " " + value; };
  // Run in the traffic folder with relative names: SUMO copies its command line into its outputs.
  const std::string env = "cd " + quoted(dir.string()) + " && timeout " +
                          std::to_string(int(std::ceil(options.timeoutSeconds))) +
                          " env SUMO_HOME=" + quoted(sumoHome) + " ";
  std::string failed = run("netconvert",
                           env + "netconvert" + opt("node-files", "streets.nod.xml") +
                               opt("edge-files", "streets.edg.xml") + opt("offset.disable-normalization", "true") +
                               opt("no-turnarounds", "true") + opt("output-file", "streets.net.xml"),
                           dir / "netconvert.log", options.timeoutSeconds);
  if (failed.empty()) {
    const double lastTrip = std::max(options.period, options.seconds * 2.0 / 3.0);
    failed = run("randomTrips.py",
                 env + "python3 " + quoted(randomTrips.string()) + " -n streets.net.xml -o trips.xml" +
                     opt("seed", std::to_string(options.seed)) + " -b 0 -e " + fixed(lastTrip) + " -p " +
                     fixed(options.period) + opt("min-distance", "60"),
                 dir / "randomTrips.log", options.timeoutSeconds);
  }
  if (failed.empty())
    failed = run("sumo",
                 env + "sumo -n streets.net.xml -r trips.xml" + opt("begin", "0") + opt("end", fixed(options.seconds)) +
                     opt("step-length", fixed(options.stepLength)) + opt("seed", std::to_string(options.seed)) +
                     opt("no-step-log", "true") + opt("ignore-route-errors", "true") + opt("fcd-output", "../fcd.xml"),
                 dir / "sumo.log", options.timeoutSeconds);
  result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!failed.empty()) {
    result.message = failed;
    return result;
  }
  // SUMO dates its outputs ("generated on <date> <time> by ..."): left out, so that two
  // runs write the same bytes, as the rest of the demo city.
  for (const fs::path& p : {fcd, net, trips}) {
    std::ifstream in(p, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const std::string mark = "generated on ";
    const std::size_t at = text.find(mark);
    if (at == std::string::npos || at > 512) continue;
    const std::size_t by = text.find(" by ", at);  // sumo: "<date> <time>", randomTrips.py: "<time>.<us>"
    if (by == std::string::npos || by > at + 64) continue;
    text.erase(at + mark.size() - 4, by - (at + mark.size() - 4));  // "generated by ..."
    std::ofstream(p, std::ios::binary) << text;
  }
  result.ok = true;
  result.fcdPath = fcd.string();
  result.offset = origin;
  result.message = "SUMO: " + std::to_string(nodeIds.size()) + " crossings, " + std::to_string(2 * edgeCount) +
                   " edges, " + fixed(options.seconds) + " s simulated in " + fixed(result.wallSeconds) + " s";
  return result;
}

}  // namespace hv::demo
