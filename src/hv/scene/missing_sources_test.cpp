#include "hv/scene/missing_sources.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <thread>

namespace hv {
namespace {

TEST(MissingSources, ListsEachSourceOnceWithItsLocationAndReason) {
  MissingSources m;
  EXPECT_TRUE(m.empty());
  EXPECT_EQ(m.summary(), "");
  const std::string wfs = "WFS:http://127.0.0.1:8080/404/mapserv?map=city&TYPENAME=ms:buildings";
  m.add({"buildings", wfs, wfs + ": cannot open as a vector source: HTTP error code : 404"});
  m.add({"photograph", "http://127.0.0.1:8080/a.jpg", "HTTP error code : 500"});
  m.add({"photograph", "http://127.0.0.1:8080/b.jpg", "HTTP error code : 500"});
  ASSERT_EQ(m.size(), 3u);
  const std::vector<MissingSource> l = m.list();
  EXPECT_EQ(l[0].kind, "buildings");
  EXPECT_EQ(l[0].location, wfs);
  EXPECT_EQ(l[0].reason, "cannot open as a vector source: HTTP error code : 404") << "the location said once";
  EXPECT_EQ(m.lines()[0], "buildings: " + wfs + ": cannot open as a vector source: HTTP error code : 404");
  EXPECT_EQ(m.summary(), "missing: buildings (" + wfs + "), 2 photographs");
}

TEST(MissingSources, ATileFailingAgainIsOneEntryAndGoesWhenItArrives) {
  MissingSources m;
  const std::size_t v0 = m.version();
  m.add({"building tile", "WFS:http://h/b: tile 3", "HTTP error code : 500", true, 1});
  m.add({"building tile", "WFS:http://h/b: tile 3", "Empty reply from server", true, 2});
  EXPECT_GT(m.version(), v0);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m.list()[0].attempts, 2);
  EXPECT_EQ(m.lines()[0], "building tile: WFS:http://h/b: tile 3: Empty reply from server (retrying, 2 tries)");
  EXPECT_EQ(m.summary(), "missing: building tile (WFS:http://h/b: tile 3) retrying");
  m.add({"building tile", "WFS:http://h/b: tile 4", "HTTP error code : 500", false, 6});
  EXPECT_EQ(m.lines()[1], "building tile: WFS:http://h/b: tile 4: HTTP error code : 500 (6 tries, given up)");
  EXPECT_EQ(m.summary(), "missing: 2 building tiles (1 retrying)");
  EXPECT_FALSE(m.resolve("building tile", "WFS:http://h/b: tile 5"));
  EXPECT_TRUE(m.resolve("building tile", "WFS:http://h/b: tile 3"));
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m.list()[0].location, "WFS:http://h/b: tile 4");
}

TEST(MissingSources, IsSharedByCopiesOfASceneAndSafeAcrossThreads) {
  Scene a;
  const Scene b = a;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 100; ++i) b.missing->add({"point tile", std::to_string(t * 100 + i), "404"});
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(a.missing->size(), 400u);
  EXPECT_EQ(a.missing->summary(), "missing: 400 point tiles");
}

}  // namespace
}  // namespace hv
