// Then and now (viewer/then_now.h): the photograph's place in the window, the overlay quad, and
// the CPU reference of the blend, against values worked out by hand.
#include "hv/viewer/then_now.h"

#include "hv/viewer/navigation.h"

#include <gtest/gtest.h>

namespace hv::viewer {
namespace {

void expectRect(const PixelRect& r, glm::dvec2 lo, glm::dvec2 hi) {
  EXPECT_NEAR(r.lo.x, lo.x, 1e-9);
  EXPECT_NEAR(r.lo.y, lo.y, 1e-9);
  EXPECT_NEAR(r.hi.x, hi.x, 1e-9);
  EXPECT_NEAR(r.hi.y, hi.y, 1e-9);
}

TEST(ThenNow, ThePhotographFillsOrIsLetterboxed) {
  expectRect(photoRectInWindow({400, 300}, {800, 600}), {0, 0}, {800, 600});
  // 800x400: scale min(2, 4/3); 533.33 wide, centred.
  expectRect(photoRectInWindow({400, 300}, {800, 400}), {400.0 / 3.0, 0}, {800 - 400.0 / 3.0, 400});
  expectRect(photoRectInWindow({400, 300}, {400, 600}), {0, 150}, {400, 450});
  EXPECT_EQ(photoRectInWindow({0, 300}, {400, 600}), PixelRect{});
}

TEST(ThenNow, TheRectangleIsWherePhotoInWindowProjectsThePhotograph) {
  // A point seen by the photograph at pixel p is seen by the letterboxed view (photoInWindow) at
  // the same place of the photograph's rectangle: lo + p / photoSize * (hi - lo).
  const Camera photo = lookAtCamera("p", {0, -20, 2}, {3, 0, 5}, 400, 300, 350.0);
  for (glm::ivec2 window : {glm::ivec2(800, 400), glm::ivec2(400, 600), glm::ivec2(800, 600)}) {
    const Camera view = photoInWindow(photo, window.x, window.y);
    const PixelRect r = photoRectInWindow({photo.width, photo.height}, window);
    for (glm::dvec3 p : {glm::dvec3(3, 0, 5), glm::dvec3(-4, 5, 1), glm::dvec3(6, 2, 9)}) {
      const glm::dvec2 inPhoto = photo.project(p).pxIdeal, inView = view.project(p).pxIdeal;
      const glm::dvec2 expected = r.lo + inPhoto / glm::dvec2(photo.width, photo.height) * (r.hi - r.lo);
      EXPECT_NEAR(inView.x, expected.x, 1e-9);
      EXPECT_NEAR(inView.y, expected.y, 1e-9);
    }
  }
}

TEST(ThenNow, OpacityAndSwipeQuads) {
  ThenNowSettings s;
  s.opacity = 0.5;
  auto q = thenNowQuad({400, 300}, {800, 600}, s);
  ASSERT_TRUE(q);
  EXPECT_DOUBLE_EQ(q->alpha, 128.0 / 255.0);  // 127.5 rounds up
  expectRect(q->uv, {0, 0}, {1, 1});
  s.opacity = 0.0;
  EXPECT_FALSE(thenNowQuad({400, 300}, {800, 600}, s));
  s.opacity = 7.0;
  EXPECT_DOUBLE_EQ(thenNowQuad({400, 300}, {800, 600}, s)->alpha, 1.0);

  s.mode = ThenNowMode::Swipe;
  s.swipe = 0.25;
  q = thenNowQuad({400, 300}, {800, 600}, s);
  ASSERT_TRUE(q);
  expectRect(q->window, {0, 0}, {200, 600});
  expectRect(q->uv, {0, 0}, {0.25, 1});
  EXPECT_EQ(q->alpha, 1.0);
  // Letterboxed: half of the 533.33 pixels from 133.33.
  s.swipe = 0.5;
  q = thenNowQuad({400, 300}, {800, 400}, s);
  ASSERT_TRUE(q);
  expectRect(q->window, {400.0 / 3.0, 0}, {400, 400});
  s.swipe = 0.0;
  EXPECT_FALSE(thenNowQuad({400, 300}, {800, 600}, s));
}

TEST(ThenNow, CompositeReference) {
  // A 4x2 render of (10, 20, 30); a 2x1 photograph, (200, 100, 0) left and (0, 0, 250) right,
  // scaled 2x to fill it.
  Image8 render(4, 2, 3), photo(2, 1, 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) render.at(x, y, 0) = 10, render.at(x, y, 1) = 20, render.at(x, y, 2) = 30;
  photo.at(0, 0, 0) = 200, photo.at(0, 0, 1) = 100, photo.at(0, 0, 2) = 0;
  photo.at(1, 0, 0) = 0, photo.at(1, 0, 1) = 0, photo.at(1, 0, 2) = 250;
  auto rgb = [](const Image8& im, int x, int y) { return glm::ivec3(im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)); };

  ThenNowSettings s;
  s.opacity = 1.0;
  Image8 out = compositeThenNow(render, photo, s);
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(rgb(out, 0, y), glm::ivec3(200, 100, 0));
    EXPECT_EQ(rgb(out, 1, y), glm::ivec3(200, 100, 0));
    EXPECT_EQ(rgb(out, 2, y), glm::ivec3(0, 0, 250));
    EXPECT_EQ(rgb(out, 3, y), glm::ivec3(0, 0, 250));
  }
  // Opacity 0.5 is alpha 128/255: 128/255 * 200 + 127/255 * 10 = 105.37, and so on.
  s.opacity = 0.5;
  out = compositeThenNow(render, photo, s);
  EXPECT_EQ(rgb(out, 0, 1), glm::ivec3(105, 60, 15));
  EXPECT_EQ(rgb(out, 3, 0), glm::ivec3(5, 10, 140));

  s.mode = ThenNowMode::Swipe;
  s.swipe = 0.5;  // the line at x = 2: columns 0 and 1 the photograph's left half, 2 and 3 the render
  out = compositeThenNow(render, photo, s);
  EXPECT_EQ(rgb(out, 1, 0), glm::ivec3(200, 100, 0));
  EXPECT_EQ(rgb(out, 2, 0), glm::ivec3(10, 20, 30));
  s.swipe = 0.6;  // x = 2.4: column 2's centre (2.5) is still the render's
  EXPECT_EQ(rgb(compositeThenNow(render, photo, s), 2, 1), glm::ivec3(10, 20, 30));
  s.swipe = 0.7;  // x = 2.8: column 2 shows the photograph's right texel (u = 0.625)
  EXPECT_EQ(rgb(compositeThenNow(render, photo, s), 2, 1), glm::ivec3(0, 0, 250));
  EXPECT_EQ(rgb(compositeThenNow(render, photo, s), 3, 1), glm::ivec3(10, 20, 30));

  EXPECT_THROW(compositeThenNow(Image8(4, 2, 1), photo, s), std::invalid_argument);
}

}  // namespace
}  // namespace hv::viewer
