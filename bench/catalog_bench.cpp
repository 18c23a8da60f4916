// Camera catalog benchmark: a benchmark, not a test. For each collection size it prints
//   1. the time to load N cameras into PostGIS (OGR's PostgreSQL driver, COPY) and to build the
//      in-memory kd-tree (hv::ibr::CameraIndex) over the same centres;
//   2. the latency of one nearest-cameras query (k = 9, the K + 1 of the default K = 8) at 1,000
//      random view positions: PostGIS (`<<->>` on the n-D GiST index, through OGR, one round trip
//      to a server on loopback) against the in-memory index, medians and the ratio, in the same
//      process (these shared machines are noisy: the ratio is what to compare);
//   3. the same 1,000 positions in one batched query (CameraCatalog::nearestCameras of a list: one
//      round trip), per position: the server's own cost;
//   4. that the selections agree on the first 100 queries (single + batched).
// Cameras are spread uniformly over a square whose side grows as sqrt(N) (10 m between
// neighbours, a street of photographs every 10 m), at 30..60 m high.
// Usage: catalog_bench [--connection postgresql://...] [--sizes 10000,1000000]
//   Without --connection, a private cluster is started for the run (tools/catalog.sh) and removed.
// Results and how to read them: docs/performance.md, "Camera catalog".

#include "hv/camera/camera.h"
#include "hv/ibr/selection.h"
#include "hv/io/native/camera_catalog.h"
#include "hv/testing/catalog_server.h"

#include "bench_common.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kNeighbours = 9;
constexpr int kQueries = 1000;
constexpr int kCheckedQueries = 100;
constexpr double kSpacing = 10.0;  // metres between neighbouring cameras

int run(const std::string& connection, const std::vector<std::size_t>& sizes) {
  using hv::bench::Clock;
  using hv::bench::msSince;
  std::printf("camera catalog: k = %zu nearest, %d queries per size; %d CPUs, load %s\n", kNeighbours, kQueries,
              hv::bench::cpuCount(), hv::bench::loadAverage().c_str());
  std::printf("%10s %12s %12s %14s %14s %14s %10s %9s %8s\n", "cameras", "load PG (s)", "kd-tree (ms)", "PostGIS (us)",
              "batched (us)", "in-memory (us)", "ratio", "batched", "agree");
  for (const std::size_t n : sizes) {
    std::mt19937_64 rng(n);
    const double side = kSpacing * std::sqrt(double(n));
    std::uniform_real_distribution<double> ux(650000.0, 650000.0 + side), uy(6860000.0, 6860000.0 + side),
        uz(30.0, 60.0);
    std::vector<hv::Photo> photos(n);
    std::vector<glm::dvec3> centres(n);
    for (std::size_t i = 0; i < n; ++i) {
      centres[i] = {ux(rng), uy(rng), uz(rng)};
      hv::Camera& c = photos[i].camera;
      c.id = "p" + std::to_string(i);
      c.width = 4000, c.height = 3000;
      c.center = centres[i];
      c.focal = {3000.0, 3000.0};
      c.principal = {2000.0, 1500.0};
      photos[i].imagePath = "/photos/p" + std::to_string(i) + ".jpg";
    }
    const std::string table = "bench_" + std::to_string(n);
    auto t0 = Clock::now();
    hv::writeCameraCatalog(photos, "EPSG:2154", connection, table);
    const double loadS = msSince(t0) / 1e3;
    t0 = Clock::now();
    const hv::ibr::CameraIndex index(centres);
    const double treeMs = msSince(t0);
    const hv::CameraCatalog catalog(connection, table);

    std::vector<glm::dvec3> views(kQueries);
    for (glm::dvec3& v : views) v = {ux(rng), uy(rng), uz(rng) - 20.0};
    catalog.nearestCameras(views[0], kNeighbours);  // the first query pays for the plan and the caches
    std::vector<double> pg, mem;
    int agree = 0, agreeBatch = 0;
    for (int q = 0; q < kQueries; ++q) {
      t0 = Clock::now();
      const auto sql = catalog.nearestCameras(views[q], kNeighbours);
      pg.push_back(msSince(t0) * 1e3);
      t0 = Clock::now();
      const auto m = index.nearest(views[q], kNeighbours);
      mem.push_back(msSince(t0) * 1e3);
      if (q < kCheckedQueries) {
        bool same = sql.size() == m.size();
        for (std::size_t i = 0; same && i < m.size(); ++i) same = sql[i].fid - 1 == m[i].photo;
        agree += same;
      }
    }
    // All the positions in one query: the server's own cost per query, without the round trips
    // and OGR's cursor set-up around each.
    t0 = Clock::now();
    const auto batch = catalog.nearestCameras(views, kNeighbours);
    const double batchUs = msSince(t0) * 1e3 / kQueries;
    for (int q = 0; q < kCheckedQueries; ++q) {
      const auto m = index.nearest(views[q], kNeighbours);
      bool same = batch[q].size() == m.size();
      for (std::size_t i = 0; same && i < m.size(); ++i) same = batch[q][i].fid - 1 == m[i].photo;
      agreeBatch += same;
    }
    const double pgUs = hv::bench::median(pg), memUs = hv::bench::median(mem);
    std::printf("%10zu %12.2f %12.1f %14.1f %14.1f %14.2f %10.0f %9.0f %5d+%d/%d\n", n, loadS, treeMs, pgUs, batchUs,
                memUs, pgUs / memUs, batchUs / memUs, agree, agreeBatch, kCheckedQueries);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string connection;
  std::vector<std::size_t> sizes = {10000};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--connection" && i + 1 < argc) {
      connection = argv[++i];
    } else if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::stringstream list(argv[++i]);
      for (std::string s; std::getline(list, s, ',');) sizes.push_back(std::stoul(s));
    } else {
      std::fprintf(stderr, "usage: catalog_bench [--connection postgresql://...] [--sizes 10000,1000000]\n");
      return 2;
    }
  }
  try {
    std::unique_ptr<hv::testing::CatalogServer> server;
    if (connection.empty()) {
      server = std::make_unique<hv::testing::CatalogServer>(HV_SOURCE_DIR);
      if (server->connection().empty()) {
        std::fprintf(stderr, "catalog_bench: no server: %s\n", server->error().c_str());
        return 1;
      }
      connection = server->connection();
    }
    return run(connection, sizes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "catalog_bench: %s\n", e.what());
    return 1;
  }
}
