// Cameras: pinhole projection with optional radial lens distortion.
//
// Conventions (owned here, repeated in docs/conventions.md):
// - World frame: the scene CRS (projected, metres, z up), always double precision on the CPU.
// - Camera frame: x right, y down, z forward (the viewing direction). `camFromWorld` is the
//   rotation R that maps world directions to camera directions: x_cam = R (X_world - C).
// - Pixels: origin at the top-left *corner* of the image, x right, y down; the centre of the
//   top-left pixel is (0.5, 0.5). An image of W x H pixels covers [0, W] x [0, H].
// - Projection (DESIGN.md §1): p~ = K R (P - C), ideal pixel p = p~.xy / p~.z, depth z = p~.z
//   (distance along the camera axis, scene units).
// - Radial distortion (Brédif 2013, fig. 2): r = p - center, p_d = p + r (c3|r|^2 + c5|r|^4 + c7|r|^6),
//   defined where |r|^2 <= r2max. The photograph is looked up at p_d; depth maps stay in the
//   undistorted (ideal) pinhole frame.
// The GLSL twin of project/distort is `hv_project` / `hv_distort` in shaders/ibr_common.glsl.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace hv {

struct RadialDistortion {
  glm::dvec2 center{0.0};  // pixels
  double c3 = 0.0, c5 = 0.0, c7 = 0.0;
  double r2max = 1e30;  // pixels^2; beyond it the polynomial is not valid

  bool isIdentity() const { return c3 == 0.0 && c5 == 0.0 && c7 == 0.0; }
  bool inDomain(glm::dvec2 pxIdeal) const;
  glm::dvec2 distort(glm::dvec2 pxIdeal) const;
  // Inverse of distort() by Newton iteration on the radius; nullopt outside the domain or when
  // the iteration does not converge (a non-monotonic polynomial).
  std::optional<glm::dvec2> undistort(glm::dvec2 pxDistorted) const;
};

struct Projection {
  glm::dvec2 pxIdeal{0.0};      // pinhole pixel (undistorted)
  glm::dvec2 pxDistorted{0.0};  // where to look in the photograph
  double depth = 0.0;           // along the camera axis; > 0 in front
  bool inFront = false;
  bool inDistortionDomain = false;
  bool inImage = false;         // in front, in the distortion domain and inside [0,W]x[0,H]
};

class Camera {
 public:
  std::string id;
  int width = 0, height = 0;          // image size, pixels
  glm::dvec3 center{0.0};             // C, world
  glm::dmat3 camFromWorld{1.0};       // R, world -> camera (glm is column-major: R[col][row])
  glm::dvec2 focal{1.0};              // fx, fy (pixels)
  glm::dvec2 principal{0.0};          // cx, cy (pixels, top-left corner origin)
  double skew = 0.0;
  std::optional<RadialDistortion> distortion;

  // K (pixels from camera frame); column-major glm.
  glm::dmat3 pixFromCam() const;
  glm::dmat3 camFromPix() const;  // K^-1
  // M = K R: homogeneous ideal pixels from world *directions* (apply to P - C).
  glm::dmat3 pixFromWorld() const { return pixFromCam() * camFromWorld; }

  Projection project(const glm::dvec3& world) const;
  glm::dvec2 distort(glm::dvec2 pxIdeal) const;
  std::optional<glm::dvec2> undistort(glm::dvec2 pxDistorted) const;
  // World direction of the ray through an ideal pixel, scaled so that its camera z is 1
  // (so P = C + depth * dir).
  glm::dvec3 rayDirection(glm::dvec2 pxIdeal) const;

  // The camera with its intrinsics scaled by `s` (image size, focal, principal point, distortion);
  // used by `render --size`.
  Camera scaled(double s, int newWidth, int newHeight) const;
  // The camera at another output size, intrinsics scaled uniformly. Throws std::invalid_argument
  // naming the camera when the aspect ratio differs by more than a pixel.
  Camera resized(int newWidth, int newHeight) const;
};

// A pinhole camera at `center` looking at `target` with `up` pointing up in the image (camera y,
// down, is opposite to it), square pixels of `focal`, principal point at the image centre. For
// synthetic scenes, tests, benchmarks and viewers. `target - center` must not be parallel to `up`.
Camera lookAtCamera(const std::string& id, const glm::dvec3& center, const glm::dvec3& target, int width,
                    int height, double focal, const glm::dvec3& up = glm::dvec3(0.0, 0.0, 1.0));

// Checks a camera's fields (finite values, positive focal and size, orthonormal rotation) and
// re-orthonormalises a rotation whose defect is below `orthoTolerance` (max |R R^T - I|).
// Throws InputError naming the field otherwise.
void validateCamera(Camera& camera, double orthoTolerance = 1e-5);

// Nearest orthonormal matrix (polar decomposition through SVD).
glm::dmat3 orthonormalize(const glm::dmat3& m);

// Row-major 9-vector <-> glm column-major matrix.
glm::dmat3 mat3FromRowMajor(const double* rowMajor);
void mat3ToRowMajor(const glm::dmat3& m, double* rowMajor);

}  // namespace hv
