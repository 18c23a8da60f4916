// Cameras: pinhole projection with optional radial lens distortion.
//
// Conventions (owned here, repeated in docs/conventions.md):
// - World frame: the scene CRS (projected, metres, z up), always double precision on the CPU.
// - Camera frame: x right, y down, z forward (the viewing direction). `camFromWorld` is the
//   rotation R that maps world directions to camera directions: x_cam = R (X_world - C).
// - Pixels: origin at the top-left *corner* of the image, x right, y down; the centre of the
//   top-left pixel is (0.5, 0.5). An image of W x H pixels covers [0, W] x [0, H].
// - Projection (docs/conventions.md): p~ = K R (P - C), ideal pixel p = p~.xy / p~.z, depth z = p~.z
//   (distance along the camera axis, scene units).
// - Lens distortion (LensDistortion below) maps an ideal pinhole pixel to the pixel where the
//   photograph is looked up. The photograph is looked up at p_d; depth maps stay in the undistorted
//   (ideal) pinhole frame.
// The GLSL twin of project/distort is `hv_project` / `hv_distort` in shaders/ibr_common.glsl.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

namespace hv {

struct Diagnostics;

// Lens distortion, one model for the formats histoview reads (docs/conventions.md, "Lens models").
// Coordinates are normalised about a centre: x = (p - center) / scale for an ideal pixel p. Then
//   fish-eye only (equilinear, iTowns/MicMac): x <- x atan|x| / |x|  (the angle from the axis);
//   radial:     x_d = x (1 + c3 |x|^2 + c5 |x|^4 + c7 |x|^6);
//   tangential: x_d += (2 p1 x y + p2 (|x|^2 + 2 x^2),  p1 (|x|^2 + 2 y^2) + 2 p2 x y)  (OpenCV);
//   fish-eye affine terms (iTowns' l1l2, written in histoview's y-down pixels):
//               x_d += (l1 x - l2 y, -l2 x);
// and p_d = center + scale * x_d. The models are:
//   - radial polynomial in pixels (Brédif 2013, fig. 2; iTowns poly357, MicMac ModRad): scale 1,
//     center the distortion centre, c3 c5 c7 in pixels^-2, ^-4, ^-6;
//   - COLMAP's radial k1 k2 and OpenCV's k1 k2 p1 p2 k3: scale the focal lengths, center the
//     principal point, (c3, c5, c7) = (k1, k2, k3);
//   - the equilinear fish-eye: scale its focal F (iTowns `etats`), center its pps; also COLMAP's
//     OPENCV_FISHEYE/RADIAL_FISHEYE (theta_d = theta (1 + k1 theta^2 + ...)) with l1 = l2 = 0.
// The model is valid where |x|^2 <= r2max (x before the fish-eye step); fitDomain() shrinks that to
// where it can be inverted.
struct LensDistortion {
  enum class Model { Polynomial, Fisheye };
  Model model = Model::Polynomial;
  glm::dvec2 center{0.0};  // pixels
  glm::dvec2 scale{1.0};   // pixels per normalised unit
  double c3 = 0.0, c5 = 0.0, c7 = 0.0;
  double p1 = 0.0, p2 = 0.0;  // tangential (Polynomial)
  double l1 = 0.0, l2 = 0.0;  // affine (Fisheye)
  double r2max = 1e30;        // normalised units squared; beyond it the model is not valid

  // True when distort() is the identity (a Polynomial model with every coefficient 0).
  bool isIdentity() const;
  bool inDomain(glm::dvec2 pxIdeal) const;
  glm::dvec2 distort(glm::dvec2 pxIdeal) const;
  // Inverse of distort() by Newton iteration; nullopt outside the domain or when the iteration does
  // not converge.
  std::optional<glm::dvec2> undistort(glm::dvec2 pxDistorted) const;
  // The model at another image scale (pixels times s).
  LensDistortion scaled(double s) const;
  // Shrinks r2max to the radius where the radial profile stops increasing (iTowns' `limit` sits near
  // that turning point; beyond it two radii map to one pixel) and, for a fish-eye, to the widest
  // angle a pinhole depth map can cover (kFisheyeMaxAngleDeg). Returns what changed, for a warning;
  // empty when nothing did.
  std::string fitDomain();
};

// The widest angle from the axis at which a fish-eye photograph is used: its depth map is a pinhole
// frustum, whose half-width grows as tan(angle).
inline constexpr double kFisheyeMaxAngleDeg = 75.0;

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
  std::optional<LensDistortion> distortion;

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

// Fits the camera's lens distortion to the domain where it can be used (LensDistortion::fitDomain)
// and says so in a warning "<where>: camera '<id>': distortion: ..." when that shrinks it.
void fitLensDomain(Camera& camera, const std::string& where, Diagnostics& diag);

// Nearest orthonormal matrix (polar decomposition through SVD).
glm::dmat3 orthonormalize(const glm::dmat3& m);

// Row-major 9-vector <-> glm column-major matrix.
glm::dmat3 mat3FromRowMajor(const double* rowMajor);
void mat3ToRowMajor(const glm::dmat3& m, double* rowMajor);

}  // namespace hv
