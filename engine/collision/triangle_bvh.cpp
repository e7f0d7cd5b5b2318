#include "engine/collision/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sinew {
namespace {

// Embree works in float: the query point and the boxes built from rounded vertices are
// off by a few float ulps of the coordinates (2^-24 relative). The query radius gets a
// slack of 2^-20 times the coordinates' size, 16 such ulps, so no triangle is culled that
// the double distance would keep.
float query_radius(double distance, double slack) {
  if (!std::isfinite(distance)) return std::numeric_limits<float>::infinity();
  return static_cast<float>(distance + slack);
}

struct QueryState {
  const TriangleBvh* bvh;
  Vec3 p;
  double max_distance_sq;
  double slack;
  NearestTriangle best;
};

// Embree callback for each triangle whose box meets the query sphere: exact distance in
// double, then shrink the sphere to the best distance so far.
bool visit_triangle(RTCPointQueryFunctionArguments* args) {
  QueryState& q = *static_cast<QueryState*>(args->userPtr);
  const auto& t = q.bvh->triangles()[args->primID];
  const auto& v = q.bvh->vertices();
  const TriangleClosest c = closest_point_on_triangle(q.p, v[t[0]], v[t[1]], v[t[2]]);
  const double d2 = (c.point - q.p).squaredNorm();
  // Ties go to the lower triangle index, as in the brute-force search.
  if (d2 > q.max_distance_sq || d2 > q.best.distance_sq ||
      (d2 == q.best.distance_sq && int(args->primID) > q.best.triangle))
    return false;
  q.best = {int(args->primID), c, d2};
  args->query->radius = query_radius(std::sqrt(d2), q.slack);
  return true;
}

void check(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed (" + std::to_string(int(error)) + ")");
}

}  // namespace

TriangleBvh::TriangleBvh(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles, bool deforming)
    : m_vertices(std::move(vertices)), m_triangles(std::move(triangles)) {
  m_device = rtcNewDevice(nullptr);
  if (!m_device) throw std::runtime_error("Embree: rtcNewDevice failed");
  m_scene = rtcNewScene(m_device);
  // Refitting takes all three: a dynamic, two-level (LOW) scene whose geometry is built for
  // REFIT (without the dynamic flag Embree rebuilds: 16 ms instead of 1 ms for 86k triangles).
  // A static BVH (surface picking's raycasts) is ROBUST: watertight ray tests, so that a ray
  // passing within float round-off of a shared edge cannot slip between the two triangles and
  // hit the far side (one of 200 rays at an ellipsoid did). The deforming BVHs of collision
  // only answer point queries, which the flag does not change.
  rtcSetSceneFlags(m_scene, deforming ? RTC_SCENE_FLAG_DYNAMIC : RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(m_scene, deforming ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH);
  m_geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(m_geometry, deforming ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_HIGH);
  m_vertex_buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      m_geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m_vertices.size()));
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      m_geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m_triangles.size()));
  check(m_device, "buffer allocation");
  for (size_t t = 0; t < m_triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) index[3 * t + k] = static_cast<unsigned>(m_triangles[t][k]);
  upload_vertices();
  rtcCommitGeometry(m_geometry);
  rtcAttachGeometry(m_scene, m_geometry);
  rtcCommitScene(m_scene);
  check(m_device, "BVH build");
}

TriangleBvh::~TriangleBvh() {
  if (m_geometry) rtcReleaseGeometry(m_geometry);
  if (m_scene) rtcReleaseScene(m_scene);
  if (m_device) rtcReleaseDevice(m_device);
}

void TriangleBvh::upload_vertices() {
  m_extent = 0;
  for (const Vec3& v : m_vertices) m_extent = std::max(m_extent, v.cwiseAbs().maxCoeff());
  for (size_t i = 0; i < m_vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) m_vertex_buffer[3 * i + k] = static_cast<float>(m_vertices[i][k]);
}

void TriangleBvh::update(const std::vector<Vec3>& vertices) {
  if (vertices.size() != m_vertices.size()) throw std::invalid_argument("TriangleBvh::update: vertex count changed");
  m_vertices = vertices;
  upload_vertices();
  rtcUpdateGeometryBuffer(m_geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(m_geometry);
  rtcCommitScene(m_scene);  // refits: the geometry was built with RTC_BUILD_QUALITY_REFIT
  check(m_device, "BVH refit");
}

NearestTriangle TriangleBvh::nearest(const Vec3& p, double max_distance) const {
  const double size = 1 + std::max(p.cwiseAbs().maxCoeff(), m_extent);
  QueryState q{this, p, max_distance * max_distance, std::ldexp(size, -20), {}};
  RTCPointQuery query;
  query.x = float(p.x()), query.y = float(p.y()), query.z = float(p.z());
  query.time = 0;
  query.radius = query_radius(max_distance, q.slack);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(m_scene, &query, &context, visit_triangle, &q);
  return q.best;
}

NearestTriangle TriangleBvh::nearest_brute_force(const Vec3& p, double max_distance) const {
  NearestTriangle best;
  for (size_t t = 0; t < m_triangles.size(); ++t) {
    const auto& tri = m_triangles[t];
    const TriangleClosest c = closest_point_on_triangle(p, m_vertices[tri[0]], m_vertices[tri[1]], m_vertices[tri[2]]);
    const double d2 = (c.point - p).squaredNorm();
    if (d2 <= max_distance * max_distance && d2 < best.distance_sq) best = {int(t), c, d2};
  }
  return best;
}

Aabb TriangleBvh::bounds() const {
  Aabb box;
  for (const Vec3& v : m_vertices) box.extend(v);
  return box;
}

RayHit TriangleBvh::raycast(const Vec3& origin, const Vec3& direction) const {
  RTCRayHit query{};
  query.ray.org_x = float(origin.x()), query.ray.org_y = float(origin.y()), query.ray.org_z = float(origin.z());
  query.ray.dir_x = float(direction.x()), query.ray.dir_y = float(direction.y()), query.ray.dir_z = float(direction.z());
  query.ray.tnear = 0;
  query.ray.tfar = std::numeric_limits<float>::infinity();
  query.ray.mask = ~0u;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(m_scene, &context, &query);
  RayHit hit;
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.triangle = int(query.hit.primID);
  hit.t = query.ray.tfar;
  hit.barycentric = Vec3(1 - query.hit.u - query.hit.v, query.hit.u, query.hit.v);
  return hit;
}

}  // namespace sinew
