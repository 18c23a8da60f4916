// What the service cache and its progress lines make of GDAL's requests
// (hv/io/native/private/service_fetch.h, docs/services.md "Cache", "Progress"). The cache itself is
// tested against real servers by tests/services_cache_test.sh.
#include "hv/io/native/private/service_fetch.h"

#include <gtest/gtest.h>

namespace hv::gdal {
namespace {

TEST(ServiceFetch, NamesARequestByItsRequestParameterElseItsPath) {
  EXPECT_EQ(requestName("http://h/mapserv?map=city&SERVICE=WFS&REQUEST=GetFeature&STARTINDEX=0"), "GetFeature");
  EXPECT_EQ(requestName("http://h/mapserv?request=GetCoverage&SERVICE=WCS"), "GetCoverage");
  EXPECT_EQ(requestName("http://h/ogcapi/collections/buildings/items?f=json&limit=1000"), "items");
  EXPECT_EQ(requestName("http://h/ogcapi/collections/buildings"), "buildings");
  EXPECT_EQ(requestName("http://h/mapserv?map=city&XREQUEST=no"), "mapserv");  // not REQUEST=
  EXPECT_EQ(requestName("http://h/"), "http://h/");
}

TEST(ServiceFetch, TellsExceptionReports) {
  EXPECT_TRUE(isExceptionReport("<?xml version='1.0'?><ows:ExceptionReport><ows:Exception/></ows:ExceptionReport>"));
  EXPECT_TRUE(isExceptionReport("<ServiceExceptionReport><ServiceException>msWFSGetFeature()"));
  EXPECT_FALSE(isExceptionReport("<wfs:FeatureCollection numberMatched='8'/>"));
  EXPECT_FALSE(isExceptionReport(R"({"type": "FeatureCollection", "features": []})"));
}

TEST(ServiceFetch, ProgressScopesNest) {
  EXPECT_EQ(ServiceProgress::current(), nullptr);
  {
    ServiceProgress outer("terrain", "WCS:http://h/mapserv");
    EXPECT_EQ(ServiceProgress::current(), &outer);
    {
      ServiceProgress inner("buildings", "WFS:http://h/mapserv");
      EXPECT_EQ(ServiceProgress::current(), &inner);
      inner.response("http://h/mapserv?REQUEST=GetFeature", 10, false);
      EXPECT_EQ(inner.requests(), 1u);
    }
    EXPECT_EQ(ServiceProgress::current(), &outer);
    EXPECT_EQ(outer.requests(), 0u);
  }
  EXPECT_EQ(ServiceProgress::current(), nullptr);
}

}  // namespace
}  // namespace hv::gdal
