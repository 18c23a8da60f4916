#include "hv/viewer/source_status.h"

#include <gtest/gtest.h>

namespace hv::viewer {
namespace {

TEST(SourceStatus, LinesSayWhatWasReadWhatStreamsAndWhatIsMissing) {
  SourceStatus s;
  EXPECT_TRUE(sourceStatusLines(s).empty());
  s.progress.push_back({"buildings", "WFS:http://h/wfs", 5, 2, 12 * 1024, "…"});
  s.missing.push_back({"terrain", "WCS:http://h/404/wcs", "HTTP error code : 404"});
  s.missing.push_back({"building tile", "WFS:http://h/wfs: tile 2", "HTTP error code : 500", true, 1});
  s.buildingTilesPending = 3;
  s.buildingTilesRetrying = 1;
  const SourceStatusLines l = sourceStatusLines(s);
  ASSERT_EQ(l.progress.size(), 1u);
  EXPECT_EQ(l.progress[0], "read buildings from WFS:http://h/wfs: 5 responses, 12 KB (2 from the cache)");
  ASSERT_EQ(l.streaming.size(), 2u);
  EXPECT_EQ(l.streaming[0], "3 building tiles being read");
  EXPECT_EQ(l.streaming[1], "1 building tile failed, to be read again");
  ASSERT_EQ(l.missing.size(), 2u);
  EXPECT_EQ(l.missing[0], "missing terrain: WCS:http://h/404/wcs: HTTP error code : 404");
  EXPECT_EQ(l.missing[1], "missing building tile: WFS:http://h/wfs: tile 2: HTTP error code : 500 (retrying, 1 try)");
}

}  // namespace
}  // namespace hv::viewer
