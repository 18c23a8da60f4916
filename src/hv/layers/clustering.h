// Image layers (Layered projective texture maps, 2003, §4.2): the objects of one visibility layer,
// projected into the photograph, are grouped into sub-images by their 2D bounding boxes, so that
// objects far apart in the image do not share one texture full of empty space.
//
// Boxes are in photograph pixels (hv/camera/camera.h: origin at the top-left corner, x right,
// y down), integer and half-open: a box covers the pixels x0 <= x < x1, y0 <= y < y1.
#pragma once

#include <cstdint>
#include <vector>

namespace hv::layers {

struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool operator==(const PixelBox&) const = default;
};

// The smallest box covering both.
PixelBox unionBox(const PixelBox& a, const PixelBox& b);

// The smallest power of two >= n (1 for n <= 1).
std::int64_t powerOfTwoAtLeast(std::int64_t n);

// The area of the smallest texture whose sides are powers of two and which holds the box
// (the paper's A_i): powerOfTwoAtLeast(width) * powerOfTwoAtLeast(height); 0 for an empty box.
std::int64_t powerOfTwoArea(const PixelBox& box);

struct BoxCluster {
  PixelBox box;                      // the union of its members' boxes
  std::vector<std::size_t> members;  // indices into the input, increasing
};

// The paper's clustering rule: two clusters c1, c2 are merged when A12 < A1 + A2, A being the
// power-of-two area above and A12 that of the union of their boxes; repeated until no pair
// qualifies (a fixpoint). Of the qualifying pairs the one saving the most area (A1 + A2 - A12) is
// merged first, ties to the lowest indices, so the result does not depend on anything but the
// input order. Empty boxes are left out. Clusters come out ordered by their first member.
// O(n^3) in the number of boxes: meant for the objects of one layer (tens to a few hundred).
std::vector<BoxCluster> clusterBoxes(const std::vector<PixelBox>& boxes);

}  // namespace hv::layers
