#include "geometry/TriangleMesh.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace hair
{

Status TriangleMesh::validate(const std::string& what) const
{
  if (points.empty())
  {
    return Status::Error(what + " has no points: give a surface mesh with triangles or polygons.");
  }
  if (triangles.empty())
  {
    return Status::Error(
        what + " has " + std::to_string(points.size()) +
        " points but no polygons: give a surface (e.g. apply Extract Surface first).");
  }
  const auto n = static_cast<int>(points.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    for (int v : triangles[t])
    {
      if (v < 0 || v >= n)
      {
        return Status::Error(what + ": triangle " + std::to_string(t) + " refers to point " +
                             std::to_string(v) + ", which does not exist (the mesh has " +
                             std::to_string(n) + " points).");
      }
    }
  }
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (!points[i].allFinite())
    {
      return Status::Error(
          what + ": point " + std::to_string(i) +
          " has a NaN or infinite coordinate; clean the mesh (remove or fix that point) first.");
    }
  }
  return Status::Ok();
}

double TriangleMesh::signedVolume() const
{
  double volume = 0;
  for (const auto& t : triangles)
  {
    volume += points[t[0]].dot(points[t[1]].cross(points[t[2]])) / 6;
  }
  return volume;
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> TriangleMesh::bounds() const
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& t : triangles)
  {
    for (int v : t)
    {
      lo = lo.cwiseMin(points[v]);
      hi = hi.cwiseMax(points[v]);
    }
  }
  return {lo, hi};
}

namespace
{
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using FaceIndex = SurfaceMesh::Face_index;
using VertexIndex = SurfaceMesh::Vertex_index;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Traits = CGAL::AABB_traits<Kernel, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
namespace PMP = CGAL::Polygon_mesh_processing;

Eigen::Vector3d toEigen(const Point& p)
{
  return {p.x(), p.y(), p.z()};
}
Eigen::Vector3d toEigen(const Vector& v)
{
  return {v.x(), v.y(), v.z()};
}
} // namespace

struct MeshQueries::Impl
{
  SurfaceMesh Mesh;
  std::vector<Eigen::Vector3d> VertexNormals;
  std::vector<Eigen::Vector3d> FaceNormals;
  Tree AabbTree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>> Side;
  double Volume = 0;
  double MergeDistance = 0;
};

MeshQueries::MeshQueries(const TriangleMesh& mesh) : P(std::make_unique<Impl>())
{
  // Triangle soup -> consistently oriented polygon mesh (orient_polygon_soup duplicates
  // points where the soup is not manifold, so any soup is accepted).
  std::vector<Point> points;
  points.reserve(mesh.points.size());
  for (const auto& p : mesh.points)
  {
    points.emplace_back(p.x(), p.y(), p.z());
  }
  std::vector<std::array<std::size_t, 3>> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
  {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    {
      continue; // degenerate by index: carries no surface
    }
    polygons.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
  }
  PMP::orient_polygon_soup(points, polygons);
  PMP::polygon_soup_to_polygon_mesh(points, polygons, P->Mesh);

  P->Volume = CGAL::is_closed(P->Mesh) ? PMP::volume(P->Mesh) : 0.0;
  if (P->Volume < 0)
  {
    PMP::reverse_face_orientations(P->Mesh);
  }

  auto fnormals = P->Mesh.add_property_map<FaceIndex, Vector>("f:n", CGAL::NULL_VECTOR).first;
  auto vnormals = P->Mesh.add_property_map<VertexIndex, Vector>("v:n", CGAL::NULL_VECTOR).first;
  PMP::compute_normals(P->Mesh, vnormals, fnormals);
  P->VertexNormals.resize(P->Mesh.number_of_vertices());
  for (auto v : P->Mesh.vertices())
  {
    P->VertexNormals[v.idx()] = toEigen(vnormals[v]);
  }
  P->FaceNormals.resize(P->Mesh.number_of_faces());
  for (auto f : P->Mesh.faces())
  {
    P->FaceNormals[f.idx()] = toEigen(fnormals[f]);
  }

  P->AabbTree.insert(faces(P->Mesh).first, faces(P->Mesh).second, P->Mesh);
  P->AabbTree.build();
  P->AabbTree.accelerate_distance_queries();
  P->Side = std::make_unique<CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>>(P->AabbTree);

  const auto bb = P->AabbTree.bbox();
  const double diag =
      std::sqrt(CGAL::square(bb.xmax() - bb.xmin()) + CGAL::square(bb.ymax() - bb.ymin()) +
                CGAL::square(bb.zmax() - bb.zmin()));
  P->MergeDistance = 1e-9 * std::max(diag, 1e-300);
}

MeshQueries::~MeshQueries() = default;

double MeshQueries::signedVolume() const
{
  return P->Volume;
}

std::size_t MeshQueries::numberOfTriangles() const
{
  return P->Mesh.number_of_faces();
}

void MeshQueries::castAll(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                          std::vector<RayHit>& hits) const
{
  hits.clear();
  const Kernel::Ray_3 ray(Point(origin.x(), origin.y(), origin.z()),
                          Vector(direction.x(), direction.y(), direction.z()));
  using Hit = Tree::Intersection_and_primitive_id<Kernel::Ray_3>::Type;
  std::vector<Hit> raw;
  P->AabbTree.all_intersections(ray, std::back_inserter(raw));

  struct Crossing
  {
    double t;
    double side; // sign of (face normal · direction): < 0 entering, > 0 leaving
    Eigen::Vector3d normal;
  };
  std::vector<Crossing> crossings;
  crossings.reserve(raw.size());
  for (const auto& h : raw)
  {
    const Point* p = boost::get<Point>(&h.first);
    if (p == nullptr)
    {
      continue; // the ray runs inside a triangle's plane: it grazes, it does not cross
    }
    const FaceIndex f = h.second;
    const Eigen::Vector3d x = toEigen(*p);
    const double t = (x - origin).dot(direction);
    if (t <= 0)
    {
      continue;
    }
    // Interpolate the vertex normals at the hit (barycentric coordinates in the triangle).
    Eigen::Vector3d corner[3];
    int idx[3];
    int k = 0;
    for (auto v : vertices_around_face(P->Mesh.halfedge(f), P->Mesh))
    {
      corner[k] = toEigen(P->Mesh.point(v));
      idx[k] = static_cast<int>(v.idx());
      ++k;
    }
    const Eigen::Vector3d e1 = corner[1] - corner[0], e2 = corner[2] - corner[0];
    const Eigen::Vector3d ep = x - corner[0];
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const double dp1 = ep.dot(e1), dp2 = ep.dot(e2);
    const double det = d11 * d22 - d12 * d12;
    Eigen::Vector3d n = P->FaceNormals[f.idx()];
    if (det > 0)
    {
      const double b1 = (d22 * dp1 - d12 * dp2) / det;
      const double b2 = (d11 * dp2 - d12 * dp1) / det;
      const double b0 = 1 - b1 - b2;
      const Eigen::Vector3d smooth = b0 * P->VertexNormals[idx[0]] + b1 * P->VertexNormals[idx[1]] +
                                     b2 * P->VertexNormals[idx[2]];
      if (smooth.squaredNorm() > 1e-24)
      {
        n = smooth.normalized();
      }
    }
    crossings.push_back({t, P->FaceNormals[f.idx()].dot(direction), n});
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& a, const Crossing& b) { return a.t < b.t; });

  // A ray through an edge or a vertex meets several triangles at one point. Triangles that
  // all face the same way there make one crossing; triangles facing both ways mean the ray
  // only touches the surface (a silhouette edge): no crossing at all.
  for (std::size_t i = 0; i < crossings.size();)
  {
    std::size_t j = i + 1;
    bool entering = crossings[i].side<0, leaving = crossings[i].side> 0;
    while (j < crossings.size() && crossings[j].t - crossings[i].t <= P->MergeDistance)
    {
      entering = entering || crossings[j].side < 0;
      leaving = leaving || crossings[j].side > 0;
      ++j;
    }
    if (!(entering && leaving))
    {
      hits.push_back({crossings[i].t, crossings[i].normal});
    }
    i = j;
  }
}

Eigen::Vector3d MeshQueries::closestPoint(const Eigen::Vector3d& p) const
{
  return toEigen(P->AabbTree.closest_point(Point(p.x(), p.y(), p.z())));
}

void MeshQueries::closestPointAndNormal(const Eigen::Vector3d& p, Eigen::Vector3d& point,
                                        Eigen::Vector3d& normal) const
{
  const auto hit = P->AabbTree.closest_point_and_primitive(Point(p.x(), p.y(), p.z()));
  point = toEigen(hit.first);
  normal = P->FaceNormals[hit.second.idx()];
  if (normal.norm() > 0)
  {
    normal.normalize();
  }
}

bool MeshQueries::isInside(const Eigen::Vector3d& p) const
{
  return (*P->Side)(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE;
}

} // namespace hair
