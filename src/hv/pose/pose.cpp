#include "hv/pose/pose.h"

#include "hv/util/diagnostics.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>

namespace hv::pose {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Vector3d toE(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
glm::dvec3 toG(const Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Matrix3d toE(const glm::dmat3& m) {
  Matrix3d r;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) r(row, col) = m[col][row];
  return r;
}
glm::dmat3 toG(const Matrix3d& m) {
  glm::dmat3 r;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) r[col][row] = m(row, col);
  return r;
}

// Real roots of c[0] x^n + ... + c[n] (highest degree first), polished by Newton's method.
std::vector<double> realRoots(std::vector<double> c) {
  const double scale = std::max(1e-300, std::abs(*std::max_element(c.begin(), c.end(), [](double a, double b) {
    return std::abs(a) < std::abs(b);
  })));
  while (c.size() > 1 && std::abs(c.front()) < 1e-12 * scale) c.erase(c.begin());
  const int n = int(c.size()) - 1;
  if (n < 1) return {};
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) companion(0, i) = -c[size_t(i + 1)] / c[0];
  for (int i = 1; i < n; ++i) companion(i, i - 1) = 1.0;
  Eigen::EigenSolver<Eigen::MatrixXd> es(companion, false);
  std::vector<double> roots;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> z = es.eigenvalues()[i];
    if (std::abs(z.imag()) > 1e-6 * (1.0 + std::abs(z.real()))) continue;
    double x = z.real();
    for (int it = 0; it < 4; ++it) {
      double p = 0.0, dp = 0.0;
      for (int k = 0; k <= n; ++k) {
        dp = dp * x + p;
        p = p * x + c[size_t(k)];
      }
      if (dp == 0.0) break;
      x -= p / dp;
    }
    roots.push_back(x);
  }
  return roots;
}

// The reprojection of `world` through `camera` (its lens model included), or nullopt behind it.
std::optional<glm::dvec2> reproject(const Camera& camera, const glm::dvec3& world) {
  const Projection p = camera.project(world);
  if (!p.inFront || !std::isfinite(p.pxDistorted.x) || !std::isfinite(p.pxDistorted.y)) return std::nullopt;
  return p.pxDistorted;
}

constexpr double kBehind = 1e6;  // the residual of a point behind the camera, pixels

std::vector<double> residualsOf(const Camera& camera, const std::vector<ControlPoint>& pts) {
  std::vector<double> r(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const auto px = reproject(camera, pts[i].world);
    r[i] = px ? glm::length(*px - pts[i].pixel) : kBehind;
  }
  return r;
}

// The parameters Levenberg–Marquardt moves, about a reference camera: a rotation vector applied
// in the camera frame, the centre's offset, then the freed intrinsics.
struct Layout {
  Refine refine;
  int size() const { return 6 + (refine.focal ? 1 : 0) + (refine.principal ? 2 : 0) + (refine.radial ? 2 : 0); }
};

Camera apply(const Camera& ref, const Layout& layout, const Eigen::VectorXd& x) {
  Camera c = ref;
  const Vector3d w(x[0], x[1], x[2]);
  const double angle = w.norm();
  const Matrix3d dR = angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Matrix3d::Identity();
  c.camFromWorld = toG(Matrix3d(dR * toE(ref.camFromWorld)));
  c.center = ref.center + glm::dvec3(x[3], x[4], x[5]);
  int k = 6;
  if (layout.refine.focal) {
    const double f = ref.focal.x + x[k++];
    c.focal = glm::dvec2(f, f * ref.focal.y / ref.focal.x);
  }
  if (layout.refine.principal) {
    c.principal = ref.principal + glm::dvec2(x[k], x[k + 1]);
    k += 2;
  }
  if (layout.refine.radial) {
    LensDistortion d;
    d.model = LensDistortion::Model::Polynomial;
    d.center = c.principal;
    d.scale = c.focal;
    d.c3 = x[k];
    d.c5 = x[k + 1];
    c.distortion = d;
  }
  return c;
}

struct Reprojection {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const Camera* ref = nullptr;
  Layout layout;
  const std::vector<ControlPoint>* pts = nullptr;
  std::vector<size_t> use;

  int inputs() const { return layout.size(); }
  int values() const { return int(2 * use.size()); }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    const Camera c = apply(*ref, layout, x);
    for (size_t i = 0; i < use.size(); ++i) {
      const ControlPoint& p = (*pts)[use[i]];
      const auto px = reproject(c, p.world);
      const glm::dvec2 d = px ? *px - p.pixel : glm::dvec2(kBehind);
      f[Eigen::Index(2 * i)] = d.x;
      f[Eigen::Index(2 * i + 1)] = d.y;
    }
    return 0;
  }
};

std::string unknownsText(const Refine& r) {
  std::string s = "the centre, the rotation";
  if (r.focal) s += ", the focal";
  if (r.principal) s += ", the principal point";
  if (r.radial) s += ", the radial distortion";
  return s;
}

}  // namespace

Refine parseRefine(const std::string& list) {
  Refine r;
  r.focal = false;
  if (list == "none" || list.empty()) return r;
  std::stringstream ss(list);
  std::string word;
  while (std::getline(ss, word, ',')) {
    if (word == "focal")
      r.focal = true;
    else if (word == "principal")
      r.principal = true;
    else if (word == "radial")
      r.radial = true;
    else
      throw InputError("--refine: unknown '" + word + "' (expected focal, principal, radial, comma-separated, or none)");
  }
  return r;
}

std::vector<Pose> solveP3P(const std::array<glm::dvec3, 3>& bearings, const std::array<glm::dvec3, 3>& world) {
  // Grunert (1841) as reviewed by Haralick et al. (1994): s_i the distances from the centre to
  // the points, s2 = u s1, s3 = v s1; the three laws of cosines give a quartic in v.
  const Vector3d f1 = toE(glm::normalize(bearings[0])), f2 = toE(glm::normalize(bearings[1])),
                 f3 = toE(glm::normalize(bearings[2]));
  const double a2 = glm::dot(world[1] - world[2], world[1] - world[2]);
  const double b2 = glm::dot(world[0] - world[2], world[0] - world[2]);
  const double c2 = glm::dot(world[0] - world[1], world[0] - world[1]);
  if (!(a2 > 0.0 && b2 > 0.0 && c2 > 0.0)) return {};
  const double ca = f2.dot(f3), cb = f1.dot(f3), cg = f1.dot(f2);
  const double amc = (a2 - c2) / b2, apc = (a2 + c2) / b2;
  const double A4 = (amc - 1) * (amc - 1) - 4 * c2 / b2 * ca * ca;
  const double A3 = 4 * (amc * (1 - amc) * cb - (1 - apc) * ca * cg + 2 * c2 / b2 * ca * ca * cb);
  const double A2 = 2 * (amc * amc - 1 + 2 * amc * amc * cb * cb + 2 * (b2 - c2) / b2 * ca * ca -
                         4 * apc * ca * cb * cg + 2 * (b2 - a2) / b2 * cg * cg);
  const double A1 = 4 * (-amc * (1 + amc) * cb + 2 * a2 / b2 * cg * cg * cb - (1 - apc) * ca * cg);
  const double A0 = (1 + amc) * (1 + amc) - 4 * a2 / b2 * cg * cg;
  std::vector<Pose> poses;
  for (const double v : realRoots({A4, A3, A2, A1, A0})) {
    if (!(v > 0.0)) continue;
    const double d = 1 + v * v - 2 * v * cb;
    if (!(d > 0.0)) continue;
    const double s1 = std::sqrt(b2 / d);
    // u from the law of cosines of the side c (two roots), the one that satisfies the side a.
    const double q = 1 - c2 * d / b2;
    const double disc = std::max(0.0, cg * cg - q);
    double u = -1.0, best = std::numeric_limits<double>::infinity();
    for (const double cand : {cg + std::sqrt(disc), cg - std::sqrt(disc)}) {
      if (!(cand > 0.0)) continue;
      const double err = std::abs(s1 * s1 * (cand * cand + v * v - 2 * cand * v * ca) - a2);
      if (err < best) best = err, u = cand;
    }
    if (u <= 0.0 || best > 1e-3 * a2) continue;
    Eigen::Matrix3d src, dst;
    for (int i = 0; i < 3; ++i) src.col(i) = toE(world[size_t(i)]);
    dst.col(0) = s1 * f1;
    dst.col(1) = u * s1 * f2;
    dst.col(2) = v * s1 * f3;
    // The rigid motion camera <- world (Umeyama 1991, no scale).
    const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
    const Matrix3d R = T.topLeftCorner<3, 3>();
    const Vector3d t = T.topRightCorner<3, 1>();
    if (!R.allFinite() || !t.allFinite()) continue;
    poses.emplace_back(toG(R), toG(Vector3d(-R.transpose() * t)));
  }
  return poses;
}

bool solveDlt(const std::vector<glm::dvec2>& pixels, const std::vector<glm::dvec3>& world, DltCamera& out) {
  const size_t n = pixels.size();
  if (n < 6 || world.size() != n) return false;
  // Hartley's normalisation: centroids at the origin, mean distances sqrt(2) and sqrt(3).
  glm::dvec2 m2(0.0);
  glm::dvec3 m3(0.0);
  for (size_t i = 0; i < n; ++i) m2 += pixels[i], m3 += world[i];
  m2 /= double(n), m3 /= double(n);
  double d2 = 0.0, d3 = 0.0;
  for (size_t i = 0; i < n; ++i) d2 += glm::length(pixels[i] - m2), d3 += glm::length(world[i] - m3);
  if (!(d2 > 0.0 && d3 > 0.0)) return false;
  const double s2 = std::sqrt(2.0) * double(n) / d2, s3 = std::sqrt(3.0) * double(n) / d3;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(Eigen::Index(2 * n), 12);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2 x = (pixels[i] - m2) * s2;
    const glm::dvec3 X = (world[i] - m3) * s3;
    const Eigen::RowVector4d Xh(X.x, X.y, X.z, 1.0);
    const Eigen::Index r = Eigen::Index(2 * i);
    A.block<1, 4>(r, 0) = Xh;
    A.block<1, 4>(r, 8) = -x.x * Xh;
    A.block<1, 4>(r + 1, 4) = Xh;
    A.block<1, 4>(r + 1, 8) = -x.y * Xh;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (!(sv[10] > 1e-9 * sv[0])) return false;  // a second null vector: the points do not determine P
  const Eigen::VectorXd p = svd.matrixV().col(11);
  Eigen::Matrix<double, 3, 4> Pn;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) Pn(r, c) = p[r * 4 + c];
  Matrix3d T2inv = Matrix3d::Identity();
  T2inv(0, 0) = T2inv(1, 1) = 1.0 / s2;
  T2inv(0, 2) = m2.x, T2inv(1, 2) = m2.y;
  Eigen::Matrix4d T3 = Eigen::Matrix4d::Identity() * s3;
  T3(3, 3) = 1.0;
  T3.topRightCorner<3, 1>() = -s3 * toE(m3);
  Eigen::Matrix<double, 3, 4> P = T2inv * Pn * T3;
  Matrix3d M = P.leftCols<3>();
  if (M.determinant() < 0.0) P = -P, M = -M;
  if (!(std::abs(M.determinant()) > 0.0)) return false;
  const Vector3d C = -M.inverse() * P.col(3);
  // M = K R by an RQ decomposition (a QR of the row-flipped transpose).
  Matrix3d flip;
  flip << 0, 0, 1, 0, 1, 0, 1, 0, 0;
  Eigen::HouseholderQR<Matrix3d> qr((flip * M).transpose());
  const Matrix3d Q = qr.householderQ();
  const Matrix3d U = qr.matrixQR().triangularView<Eigen::Upper>();
  Matrix3d K = flip * U.transpose() * flip, R = flip * Q.transpose();
  for (int i = 0; i < 3; ++i)
    if (K(i, i) < 0.0) K.col(i) *= -1.0, R.row(i) *= -1.0;
  if (R.determinant() < 0.0 || !(K(2, 2) > 0.0)) return false;
  K /= K(2, 2);
  out.pose = {toG(R), toG(C)};
  out.focal = 0.5 * (K(0, 0) + K(1, 1));
  out.principal = {K(0, 2), K(1, 2)};
  return std::isfinite(out.focal) && out.focal > 0.0 && C.allFinite();
}

PoseResult solvePose(const std::vector<ControlPoint>& input, const Camera& startIn, bool startPose,
                     const PoseOptions& options) {
  const Refine& refine = options.refine;
  const Layout layout{refine};
  const size_t n = input.size();
  if (startIn.width <= 0 || startIn.height <= 0)
    throw InputError("the photograph's size is unknown (give a first camera with its width and height)");
  const bool focalKnown = startIn.focal.x > 0.0 && std::isfinite(startIn.focal.x);
  if (!refine.focal && !focalKnown)
    throw InputError("the focal is neither given nor solved: give a first camera with it, or add 'focal' to --refine");
  const size_t minimum = refine.focal ? 6 : 4;
  const size_t needed = std::max(minimum, size_t(layout.size() / 2 + 1));
  if (n < needed)
    throw InputError(std::to_string(n) + " control point(s): solving " + unknownsText(refine) + " needs at least " +
                     std::to_string(needed) + "; add points" +
                     (refine.focal ? " (or keep the first camera's focal: --refine none)" : ""));

  // Work about the points' centroid: world coordinates of a projected CRS are large.
  glm::dvec3 origin(0.0);
  for (const auto& p : input) origin += p.world;
  origin /= double(n);
  std::vector<ControlPoint> pts = input;
  for (auto& p : pts) p.world -= origin;
  Camera start = startIn;
  start.center -= origin;

  PoseResult result;
  // The world points' spread: a line (or a point) determines no pose; a plane gives no DLT.
  Eigen::MatrixXd W(3, Eigen::Index(n));
  for (size_t i = 0; i < n; ++i) W.col(Eigen::Index(i)) = toE(pts[i].world);
  const Vector3d spread = Eigen::JacobiSVD<Eigen::MatrixXd>(W).singularValues();
  if (!(spread[1] > 1e-6 * spread[0]))
    throw InputError("the control points' world positions lie on one line (or at one point): add points away from it");
  const bool coplanar = !(spread[2] > 1e-3 * spread[0]);
  if (coplanar) result.notes.push_back("the control points lie on a plane: poses from three points, no DLT");
  if (!focalKnown && coplanar)
    throw InputError("the focal is unknown and the control points lie on one plane: give a first camera with a focal "
                     "(--start), or add points off the plane");

  const double tau = options.inlierPixels > 0.0
                         ? options.inlierPixels
                         : std::max(2.0, 0.005 * std::hypot(double(start.width), double(start.height)));
  std::vector<glm::dvec3> bearings(n);
  std::vector<bool> hasBearing(n, false);
  if (focalKnown)
    for (size_t i = 0; i < n; ++i)
      if (const auto ideal = start.undistort(pts[i].pixel)) {
        bearings[i] = glm::normalize(start.camFromPix() * glm::dvec3(*ideal, 1.0));
        hasBearing[i] = true;
      }

  // RANSAC (MSAC scoring: inliers, then the truncated squared residuals).
  Camera best;
  int bestCount = -1;
  double bestCost = std::numeric_limits<double>::infinity();
  auto consider = [&](const Camera& c) {
    const std::vector<double> r = residualsOf(c, pts);
    int count = 0;
    double cost = 0.0;
    for (double e : r) {
      count += e < tau;
      cost += std::min(e * e, tau * tau);
    }
    if (count > bestCount || (count == bestCount && cost < bestCost)) best = c, bestCount = count, bestCost = cost;
  };
  if (startPose && focalKnown) consider(start);
  std::mt19937_64 rng(options.seed);
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  const bool useDlt = !coplanar && n >= 6 && (refine.focal || !focalKnown);
  const bool useP3P = focalKnown;
  int required = options.maxIterations;
  for (int it = 0; it < std::min(required, options.maxIterations); ++it) {
    const bool dlt = useDlt && (!useP3P || it % 2 == 1);
    const size_t s = dlt ? 6 : 3;
    for (size_t k = 0; k < s; ++k) std::swap(order[k], order[k + size_t(rng() % (n - k))]);
    if (dlt) {
      std::vector<glm::dvec2> px;
      std::vector<glm::dvec3> X;
      for (size_t k = 0; k < 6; ++k) {
        // The DLT is a pinhole: it takes the ideal pixels when the first camera has a lens model.
        const auto ideal = start.undistort(pts[order[k]].pixel);
        px.push_back(ideal ? *ideal : pts[order[k]].pixel);
        X.push_back(pts[order[k]].world);
      }
      DltCamera d;
      if (!solveDlt(px, X, d)) continue;
      Camera c = start;
      c.camFromWorld = d.pose.first;
      c.center = d.pose.second;
      c.focal = glm::dvec2(d.focal, d.focal * (focalKnown ? start.focal.y / start.focal.x : 1.0));
      consider(c);
    } else {
      if (!hasBearing[order[0]] || !hasBearing[order[1]] || !hasBearing[order[2]]) continue;
      for (const Pose& p : solveP3P({bearings[order[0]], bearings[order[1]], bearings[order[2]]},
                                    {pts[order[0]].world, pts[order[1]].world, pts[order[2]].world})) {
        Camera c = start;
        c.camFromWorld = p.first;
        c.center = p.second;
        consider(c);
      }
    }
    // Enough samples for 99.9 % confidence of one all-inlier sample at the inlier ratio found.
    const double w = double(std::max(bestCount, 0)) / double(n);
    const double allIn = std::pow(w, double(s));
    if (allIn > 0.0 && bestCount >= int(needed))
      required = allIn >= 1.0 ? it + 1 : int(std::ceil(std::log(1e-3) / std::log1p(-allIn))) + 1;
    required = std::max(required, 20);
  }
  if (bestCount < int(needed)) {
    std::ostringstream msg;
    msg << "no camera puts more than " << std::max(bestCount, 0) << " of the " << n << " control points within "
        << tau << " px of their pixels (" << needed << " needed): check the pairs (pixels from the photograph's "
        << "top-left corner, world positions in the scene CRS)" << (startPose ? " and the first camera" : "");
    throw InputError(msg.str());
  }

  // Levenberg–Marquardt on the inliers, the inliers re-chosen until they settle.
  Camera cam = best;
  if (refine.radial && !(cam.distortion && cam.distortion->model == LensDistortion::Model::Polynomial)) {
    cam.distortion.reset();
  }
  std::vector<bool> inl(n);
  std::vector<double> r = residualsOf(cam, pts);
  for (size_t i = 0; i < n; ++i) inl[i] = r[i] < tau;
  Reprojection f;
  f.layout = layout;
  f.pts = &pts;
  Eigen::VectorXd x;
  for (int round = 0; round < 4; ++round) {
    f.ref = &cam;
    f.use.clear();
    for (size_t i = 0; i < n; ++i)
      if (inl[i]) f.use.push_back(i);
    x = Eigen::VectorXd::Zero(layout.size());
    if (refine.radial && cam.distortion) {
      const int k = layout.size() - 2;
      x[k] = cam.distortion->c3, x[k + 1] = cam.distortion->c5;
    }
    Eigen::NumericalDiff<Reprojection> nd(f, 1e-12);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Reprojection>, double> lm(nd);
    lm.parameters.maxfev = 4000;
    lm.minimize(x);
    const Camera next = apply(cam, layout, x);
    r = residualsOf(next, pts);
    std::vector<bool> now(n);
    for (size_t i = 0; i < n; ++i) now[i] = r[i] < tau;
    cam = next;
    if (now == inl) break;
    inl = now;
    if (size_t(std::count(inl.begin(), inl.end(), true)) < needed)
      throw InputError("the refined camera keeps fewer than " + std::to_string(needed) +
                       " control points within " + std::to_string(tau) + " px: check the pairs");
  }
  for (size_t i = 0; i < n; ++i) inl[i] = r[i] < tau;

  // The covariance of the solution: sigma^2 (J^T J)^-1 at the optimum, J about the final camera.
  f.ref = &cam;
  f.use.clear();
  for (size_t i = 0; i < n; ++i)
    if (inl[i]) f.use.push_back(i);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(layout.size());
  if (refine.radial && cam.distortion) {
    const int k = layout.size() - 2;
    x0[k] = cam.distortion->c3, x0[k + 1] = cam.distortion->c5;
  }
  Eigen::NumericalDiff<Reprojection> nd(f, 1e-12);
  Eigen::MatrixXd J(f.values(), f.inputs());
  nd.df(x0, J);
  Eigen::VectorXd res(f.values());
  f(x0, res);
  const Eigen::Index p = J.cols(), m = J.rows();
  Eigen::VectorXd colNorm = J.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < p; ++j)
    if (!(colNorm[j] > 0.0)) colNorm[j] = 1.0;
  const Eigen::MatrixXd Jn = J * colNorm.cwiseInverse().asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Jn.transpose() * Jn);
  const Eigen::VectorXd ev = eig.eigenvalues();
  if (!(ev[0] > 1e-12 * ev[p - 1])) {
    static const char* names[] = {"rotation", "rotation", "rotation", "centre", "centre", "centre"};
    Eigen::Index worst = 0;
    eig.eigenvectors().col(0).cwiseAbs().maxCoeff(&worst);
    std::string what = worst < 6 ? names[worst] : "intrinsics";
    if (worst >= 6 && refine.focal && worst == 6) what = "focal";
    throw InputError("a critical configuration: the control points do not determine the " + what +
                     " (spread them over the photograph and at different distances from the camera)");
  }
  const double dof = double(m - p);
  const double sigma2 = dof > 0.0 ? res.squaredNorm() / dof : 0.0;
  const Eigen::MatrixXd cov = sigma2 * (J.transpose() * J).inverse();

  cam.center += origin;
  result.camera = cam;
  result.residuals = r;
  result.inliers = inl;
  result.inlierCount = int(std::count(inl.begin(), inl.end(), true));
  double ss = 0.0;
  for (size_t i = 0; i < n; ++i)
    if (inl[i]) ss += r[i] * r[i];
  result.rmsPixels = std::sqrt(ss / std::max(1, result.inlierCount));
  result.centerSigma = {std::sqrt(cov(3, 3)), std::sqrt(cov(4, 4)), std::sqrt(cov(5, 5))};
  result.rotationSigmaDegrees =
      std::sqrt(std::max({cov(0, 0), cov(1, 1), cov(2, 2)})) * 180.0 / 3.14159265358979323846;
  result.focalSigma = refine.focal ? std::sqrt(cov(6, 6)) : 0.0;
  return result;
}

}  // namespace hv::pose
