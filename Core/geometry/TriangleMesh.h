#pragma once
// A triangle soup in plain arrays, the form in which a body part's surface reaches Core.
#include "common/Status.h"

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hair
{

struct TriangleMesh
{
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;

  /// Refuses an empty mesh, a mesh with no triangles, indices out of range and
  /// non-finite coordinates. `what` names the input in the message (e.g. "input 0").
  Status validate(const std::string& what = "the mesh") const;

  /// Volume enclosed as the triangles are ordered (the sum of the origin–triangle
  /// tetrahedra): negative when they face inwards. Meaningful for a closed surface.
  double signedVolume() const;

  /// Bounding box (min, max) of the points used by triangles.
  std::pair<Eigen::Vector3d, Eigen::Vector3d> bounds() const;
};

/// One crossing of a ray with a surface: distance along the (unit) ray, and the unit
/// normal of the surface there, interpolated from the vertex normals and oriented so that
/// it points out of the solid.
struct RayHit
{
  double t = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

/// Anything rays can be cast against. Collision tables are built from this interface, so
/// tests can give an analytic body (exact) and the product a triangle mesh (CGAL).
class RayCaster
{
public:
  virtual ~RayCaster() = default;
  /// Every crossing of the ray origin + t·direction (direction unit, t > 0) with the
  /// surface, sorted by t, with coincident crossings (a ray through an edge) merged.
  virtual void castAll(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                       std::vector<RayHit>& hits) const = 0;
};

/// Exact queries on a closed triangle mesh with CGAL's AABB tree: ray casting (for
/// building tables), closest point and point-in-solid (the references that tables are
/// checked and benchmarked against).
class MeshQueries : public RayCaster
{
public:
  /// Builds the tree. The mesh must have passed validate(). Triangles are oriented so
  /// that normals point out of the solid (by the sign of the enclosed volume).
  explicit MeshQueries(const TriangleMesh& mesh);
  ~MeshQueries() override;
  MeshQueries(const MeshQueries&) = delete;
  MeshQueries& operator=(const MeshQueries&) = delete;

  void castAll(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
               std::vector<RayHit>& hits) const override;

  /// The closest point of the surface to p.
  Eigen::Vector3d closestPoint(const Eigen::Vector3d& p) const;
  /// The closest point of the surface to p and the unit normal of the triangle it lies on
  /// (out of the solid for a closed mesh; as the triangles are ordered for an open one).
  void closestPointAndNormal(const Eigen::Vector3d& p, Eigen::Vector3d& point,
                             Eigen::Vector3d& normal) const;
  /// Whether p lies inside the closed surface (CGAL's Side_of_triangle_mesh).
  bool isInside(const Eigen::Vector3d& p) const;
  /// Signed volume the mesh encloses as given (negative if its triangles face inwards).
  double signedVolume() const;
  std::size_t numberOfTriangles() const;

private:
  struct Impl;
  std::unique_ptr<Impl> P;
};

} // namespace hair
