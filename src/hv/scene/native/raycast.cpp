#include "hv/scene/native/raycast.h"

#include <embree3/rtcore.h>

#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hv {

// Embree traces in float. Vertices are stored in a local frame, `local = world - worldFromLocal`
// with the translation at the mesh's bounding-box centre, so a city a few kilometres across keeps
// sub-millimetre float resolution even when its projected coordinates are in the millions.
struct RayCaster::Impl {
  // A copy of what refinement needs, so the caster does not depend on the caller's mesh lifetime.
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec3> triangles;
  glm::dvec3 worldFromLocal{0.0};
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  glm::dvec3 triangleNormal(std::uint32_t tri) const {
    const glm::uvec3& t = triangles[tri];
    // Counter-clockwise winding seen from the side the normal points to (hv/scene/mesh.h).
    return glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
  }
};

namespace {

void throwOnDeviceError(RTCDevice device, const char* what) {
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(err)) +
                             ")");
}

RTCRayHit makeRay(const glm::dvec3& originLocal, const glm::dvec3& dirUnit, double tMin, double tMax) {
  RTCRayHit rh{};
  rh.ray.org_x = float(originLocal.x);
  rh.ray.org_y = float(originLocal.y);
  rh.ray.org_z = float(originLocal.z);
  rh.ray.dir_x = float(dirUnit.x);
  rh.ray.dir_y = float(dirUnit.y);
  rh.ray.dir_z = float(dirUnit.z);
  rh.ray.tnear = float(std::max(tMin, 0.0));
  rh.ray.tfar = float(std::min(tMax, double(std::numeric_limits<float>::max())));
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.time = 0.0f;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

RayCaster::RayCaster(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.positions = mesh.positions;
  im.triangles = mesh.triangles;
  im.worldFromLocal = mesh.bounds().empty() ? glm::dvec3(0.0) : mesh.bounds().center();

  im.device = rtcNewDevice(nullptr);
  if (!im.device)
    throw std::runtime_error("Embree: rtcNewDevice failed (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  im.scene = rtcNewScene(im.device);
  // Robust traversal: rays grazing shared edges of the closed LOD1 prisms must not slip through.
  rtcSetSceneFlags(im.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);

  if (!mesh.triangles.empty()) {
    RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    throwOnDeviceError(im.device, "vertex buffer allocation");
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const glm::dvec3 local = mesh.positions[i] - im.worldFromLocal;
      vertices[3 * i + 0] = float(local.x);
      vertices[3 * i + 1] = float(local.y);
      vertices[3 * i + 2] = float(local.z);
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
    throwOnDeviceError(im.device, "index buffer allocation");
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      const glm::uvec3& t = mesh.triangles[i];
      assert(t.x < mesh.positions.size() && t.y < mesh.positions.size() && t.z < mesh.positions.size());
      indices[3 * i + 0] = t.x;
      indices[3 * i + 1] = t.y;
      indices[3 * i + 2] = t.z;
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(im.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(im.scene);
  throwOnDeviceError(im.device, "scene build");
}

RayCaster::~RayCaster() = default;

std::optional<RayHit> RayCaster::intersect(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                                           double tMax) const {
  const Impl& im = *impl_;
  const double len = glm::length(direction);
  if (!(len > 0.0) || !(tMax >= tMin)) return std::nullopt;
  const glm::dvec3 dir = direction / len;

  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRay(origin - im.worldFromLocal, dir, tMin, tMax);
  // rtcIntersect1 only reads the committed scene, so concurrent calls are safe (Embree 3 API docs).
  rtcIntersect1(im.scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

  RayHit hit;
  hit.triangle = rh.hit.primID;
  hit.barycentric = glm::dvec2(rh.hit.u, rh.hit.v);
  hit.t = rh.ray.tfar;
  // Embree's t carries float error relative to the local frame (millimetres at kilometre range);
  // re-intersect the hit triangle's plane in double: t = n.(p0 - o) / n.d.
  const glm::dvec3 n = im.triangleNormal(hit.triangle);
  const double nLen = glm::length(n);
  const double denom = glm::dot(n, dir);
  if (nLen > 0.0 && std::abs(denom) > 1e-12 * nLen) {
    const double tPlane = glm::dot(n, im.positions[im.triangles[hit.triangle].x] - origin) / denom;
    // Keep Embree's value if the refinement disagrees wildly (a grazing, ill-conditioned hit).
    if (std::abs(tPlane - hit.t) <= 1e-3 * std::max(1.0, hit.t)) hit.t = tPlane;
  }
  hit.position = origin + hit.t * dir;
  if (nLen > 0.0) {
    hit.normal = n / nLen;
  } else {
    // Degenerate in double yet hit in float: fall back on Embree's Ng, which has the same sense as
    // the counter-clockwise normal (v1 - v0) x (v2 - v0): Embree 3.13 reports +z for the triangle
    // (0,0,0), (1,0,0), (0,1,0).
    hit.normal = glm::normalize(glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  }
  return hit;
}

bool RayCaster::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double tMin,
                         double tMax) const {
  const Impl& im = *impl_;
  const double len = glm::length(direction);
  if (!(len > 0.0) || !(tMax > tMin)) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = makeRay(origin - im.worldFromLocal, direction / len, tMin, tMax).ray;
  rtcOccluded1(im.scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

}  // namespace hv
