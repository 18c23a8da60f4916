// The --from/--to time window, from the command line (app::timeWindow) to the frame plan's
// selection (ibr::planFrame).
#include "hv/session/session.h"

#include "hv/ibr/frame_plan.h"
#include "hv/util/dates.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace hv {
namespace {

// The time window in the frame plan (hv::ibr::planFrame): a small scene of dated and undated
// photographs along the x axis, no geometry, the view at the origin; every photograph is a
// candidate but for the window (frustum filter off), so the plan's images are what the window keeps.
class TimeWindowPlan : public ::testing::Test {
 protected:
  void SetUp() override {
    add("undated", 0.5, "");
    add("bad-date", 0.8, "around 1905");  // unparseable: undated
    add("p1900", 1.0, "1900-05-01");
    add("p1905", 2.0, "1905");
    add("p1910", 3.0, "1910-03");
    add("p1905-06-15", 4.0, "1905-06-15T10:30:00+01:00");
    std::vector<glm::dvec3> centers;
    for (const auto& p : scene_.photos) centers.push_back(p.camera.center);
    index_ = std::make_unique<ibr::CameraIndex>(centers);
    view_ = scene_.photos.front().camera;
    view_.center = glm::dvec3(0.0);
  }

  void add(const std::string& id, double x, const std::string& date) {
    Photo p;
    p.camera.id = id;
    p.camera.width = 64;
    p.camera.height = 48;
    p.camera.focal = {50, 50};
    p.camera.principal = {32, 24};
    p.camera.center = {x, 0.0, 0.0};
    p.date = date;
    scene_.photos.push_back(p);
  }

  // Ids of the selected photographs, nearest first.
  std::vector<std::string> selected(const std::string& from, const std::string& to, bool datedOnly,
                                    int k = 8) {
    ibr::BlendSettings s;
    s.selection = ibr::Selection::Global;  // the K nearest (the window filters any selection)
    s.k = k;
    s.sigma = 1.0;
    s.frustumFilter = false;
    s.window = app::timeWindow(from, to);
    s.datedOnly = datedOnly;
    plan_ = ibr::planFrame(scene_, *index_, view_, s, Aabb{});
    std::vector<std::string> ids;
    for (const auto& im : plan_.images) ids.push_back(scene_.photos[size_t(im.photo)].camera.id);
    return ids;
  }

  using Ids = std::vector<std::string>;
  Scene scene_;
  std::unique_ptr<ibr::CameraIndex> index_;
  Camera view_;
  ibr::FramePlan plan_;
};

TEST_F(TimeWindowPlan, WithoutAWindowEveryPhotographIsACandidate) {
  EXPECT_EQ(selected("", "", false), (Ids{"undated", "bad-date", "p1900", "p1905", "p1910", "p1905-06-15"}));
  // --dated-only alone leaves out the undated ones, the unparseable date included.
  EXPECT_EQ(selected("", "", true), (Ids{"p1900", "p1905", "p1910", "p1905-06-15"}));
}

TEST_F(TimeWindowPlan, DatedPhotographsAreKeptWhenTheirIntervalOverlapsTheWindow) {
  // 1905 as a window is the whole year: the year-dated photograph and the June one.
  EXPECT_EQ(selected("1905", "1905", false), (Ids{"undated", "bad-date", "p1905", "p1905-06-15"}));
  EXPECT_EQ(selected("1905", "1905", true), (Ids{"p1905", "p1905-06-15"}));
  // A window inside 1905 still overlaps "1905" (partial dates match by overlap).
  EXPECT_EQ(selected("1905-07-01", "1905-07-31", true), (Ids{"p1905"}));
  // Open ends.
  EXPECT_EQ(selected("1905-06-16", "", true), (Ids{"p1905", "p1910"}));
  EXPECT_EQ(selected("", "1905-06-14", true), (Ids{"p1900", "p1905"}));
  EXPECT_EQ(selected("1910-03-31", "", true), (Ids{"p1910"}));
  EXPECT_EQ(selected("1910-04", "", true), Ids{});
}

TEST_F(TimeWindowPlan, SelectionAndWeightsApplyWithinTheWindow) {
  // K = 1 in 1905..1910 with dated photographs only: the nearest kept is p1905 (2 m), and the
  // K+1-th distance of eq. 2 is p1910's (3 m), not the nearer p1900's or the undated ones'.
  EXPECT_EQ(selected("1905", "1910", true, 1), (Ids{"p1905"}));
  EXPECT_DOUBLE_EQ(plan_.nextDistance, 3.0);
  ASSERT_EQ(plan_.images.size(), 1u);
  EXPECT_NEAR(plan_.images[0].weight, 1.0 / (1.0 + 4.0) - 1.0 / (1.0 + 9.0), 1e-15);
}

// A window that keeps nothing is said, with the span of the dates (the undated photographs pass a
// window, so only --dated-only can leave a scene with undated ones empty).
TEST_F(TimeWindowPlan, AWindowSelectingNoPhotographIsSaidWithTheDatesSpan) {
  scene_.path = "scene.json";
  ibr::BlendSettings blend;
  blend.window = app::timeWindow("1990", "");
  EXPECT_EQ(app::timeWindowSelection(scene_, blend), "");  // the two undated photographs pass
  blend.datedOnly = true;
  EXPECT_EQ(app::timeWindowSelection(scene_, blend),
            "the time window 1990-01-01 .. open with --dated-only (--from/--to) selects 0 of 6 photographs of "
            "scene.json (the photographs' dates span 1900-05-01 .. 1910-03-31, 2 undated): the views show the "
            "geometry untextured");
  blend.window = app::timeWindow("1905", "1905");
  EXPECT_EQ(app::timeWindowSelection(scene_, blend), "");
  scene_.photos.erase(scene_.photos.begin(), scene_.photos.begin() + 2);  // the undated ones
  blend.datedOnly = false;
  blend.window = app::timeWindow("", "1899");
  EXPECT_EQ(app::timeWindowSelection(scene_, blend),
            "the time window open .. 1899-12-31 (--from/--to) selects 0 of 4 photographs of scene.json (the "
            "photographs' dates span 1900-05-01 .. 1910-03-31): the views show the geometry untextured");
}

TEST(TimeWindowOptions, FromAndToMakeOneClosedInterval) {
  EXPECT_FALSE(app::timeWindow("", "").has_value());
  const auto w = app::timeWindow("1905-06", "1910");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->first, daysFromCivil(1905, 6, 1));
  EXPECT_EQ(w->last, daysFromCivil(1910, 12, 31));
  EXPECT_EQ(app::timeWindow("1905", "")->last, DateInterval{}.last);
  EXPECT_EQ(app::timeWindow("", "1905")->first, DateInterval{}.first);
  EXPECT_EQ(app::timeWindow("1905", "1905")->last - app::timeWindow("1905", "1905")->first, 364);
  auto message = [](const std::string& from, const std::string& to) {
    try {
      app::timeWindow(from, to);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message("1905-13", "").find("--from: expected an ISO 8601 date"), std::string::npos);
  EXPECT_NE(message("1905-13", "").find("'1905-13'"), std::string::npos);
  EXPECT_NE(message("", "last year").find("--to: expected an ISO 8601 date"), std::string::npos);
  EXPECT_NE(message("1910", "1905").find("is after --to"), std::string::npos);
}

TEST(TimeWindowOptions, UnparseablePhotoDatesAreWarnedAboutByCameraAndField) {
  Scene scene;
  scene.path = "scene.json";
  Photo ok, bad, none;
  ok.camera.id = "ok";
  ok.date = "1905-06-01";
  bad.camera.id = "p17";
  bad.date = "June 1905";
  none.camera.id = "none";
  scene.photos = {ok, bad, none};
  Diagnostics diag;
  app::checkPhotoDates(scene, diag);
  ASSERT_EQ(diag.warnings.size(), 1u);
  EXPECT_NE(diag.warnings[0].find("camera 'p17': date"), std::string::npos) << diag.warnings[0];
  EXPECT_NE(diag.warnings[0].find("'June 1905'"), std::string::npos) << diag.warnings[0];
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv
