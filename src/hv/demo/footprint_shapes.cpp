#include "hv/demo/footprint_shapes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace hv::demo::detail {

bool insideRings(const std::vector<std::vector<glm::dvec2>>& rings, glm::dvec2 p) {
  bool in = false;
  for (const auto& ring : rings)
    for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const glm::dvec2 a = ring[i], b = ring[j];
      if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
    }
  return in;
}

double signedArea(const std::vector<glm::dvec2>& ring) {
  double a = 0.0;
  for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
    a += ring[j].x * ring[i].y - ring[i].x * ring[j].y;
  return 0.5 * a;
}


CellSet cellsOf(Shape s) {
  CellSet c{};
  for (auto& col : c) col.fill(true);
  switch (s) {
    case Shape::Rect:
      break;
    case Shape::L:
      c[2][1] = c[2][2] = false;
      break;
    case Shape::LMirror:
      c[0][1] = c[0][2] = false;
      break;
    case Shape::U:
      c[1][1] = c[1][2] = false;
      break;
    case Shape::T:
      c[0][1] = c[0][2] = c[2][1] = c[2][2] = false;
      break;
    case Shape::NotchCorner:
      c[2][2] = false;
      break;
    case Shape::NotchBack:
      c[1][2] = false;
      break;
    case Shape::Step:
      c[0][1] = c[0][2] = c[1][2] = false;
      break;
    case Shape::Courtyard:
      c[1][1] = false;
      break;
    case Shape::Count:
      break;
  }
  return c;
}

std::vector<std::vector<glm::ivec2>> traceRings(const CellSet& cells) {
  auto in = [&](int i, int j) { return i >= 0 && j >= 0 && i < 3 && j < 3 && cells[i][j]; };
  std::map<std::pair<int, int>, glm::ivec2> next;  // start vertex -> end vertex
  auto edge = [&](glm::ivec2 a, glm::ivec2 b) {
    if (!next.emplace(std::make_pair(a.x, a.y), b).second)
      throw std::logic_error("demo city: pinched footprint");
  };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!in(i, j)) continue;
      if (!in(i, j - 1)) edge({i, j}, {i + 1, j});
      if (!in(i + 1, j)) edge({i + 1, j}, {i + 1, j + 1});
      if (!in(i, j + 1)) edge({i + 1, j + 1}, {i, j + 1});
      if (!in(i - 1, j)) edge({i, j + 1}, {i, j});
    }
  std::vector<std::vector<glm::ivec2>> rings;
  while (!next.empty()) {
    std::vector<glm::ivec2> ring;
    glm::ivec2 v(next.begin()->first.first, next.begin()->first.second);
    while (true) {
      auto it = next.find({v.x, v.y});
      if (it == next.end()) break;
      ring.push_back(v);
      v = it->second;
      next.erase(it);
    }
    std::vector<glm::ivec2> simple;
    for (size_t k = 0; k < ring.size(); ++k) {
      const glm::ivec2 prev = ring[(k + ring.size() - 1) % ring.size()], cur = ring[k],
                       nxt = ring[(k + 1) % ring.size()];
      const glm::ivec2 d1 = cur - prev, d2 = nxt - cur;
      if (d1.x * d2.y - d1.y * d2.x != 0) simple.push_back(cur);
    }
    rings.push_back(simple);
  }
  return rings;
}

}  // namespace hv::demo::detail
