#pragma once
// The collision representation of Kurihara, Anjyo and Thalmann (1993): a body part turned
// into a table of radii r(azimuth, height) around an axis (cylindrical) or r(azimuth,
// polar angle) around a centre (spherical), built once by casting rays, so that a
// collision test is one table look-up whatever the size of the mesh.
#include "common/Progress.h"
#include "common/Status.h"
#include "geometry/TriangleMesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hair
{

enum class Projection
{
  Cylindrical = 0,
  Spherical = 1
};

const char* toString(Projection p);

/// A body part's own frame. Cylindrical: points are (r, θ, h) about the line through
/// `origin` along `axis`. Spherical: (ρ, θ, φ) about `origin`, φ measured from `axis`.
/// In both, θ = 0 is `reference` (made orthogonal to the axis) and θ grows towards
/// axis × reference.
struct TableFrame
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  Eigen::Vector3d reference = Eigen::Vector3d::UnitZ();

  /// Refuses non-finite or zero vectors and a reference parallel to the axis.
  Status validate() const;
  /// Orthonormal basis: columns (reference⊥, axis × reference⊥, axis).
  Eigen::Matrix3d basis() const;
};

/// What to build: projection, frame, resolution and extent.
struct TableSpec
{
  Projection projection = Projection::Cylindrical;
  TableFrame frame;
  int azimuthSamples = 40; ///< θ samples over [0, 2π), periodic (the paper: 40)
  int secondSamples = 40;  ///< heights (cylindrical) or polar angles (spherical, poles included)
  double heightMin = 0;    ///< cylindrical only: heights along the axis, both included
  double heightMax = 1;
  /// Rays are cast up to this distance from the axis or centre; solid that continues past it
  /// is cut there (a cap). Lets a head table ignore the chest below the chin.
  double maxRadius = std::numeric_limits<double>::infinity();

  static constexpr int MaximumSamples = 4096;
  Status validate() const;
  /// Refuses a frame and extent that reach farther than ten times the body's size from the
  /// body's box (lo, hi): rays from there cannot meet it, and coordinates like 1e308 overflow
  /// CGAL's exact predicates.
  Status fitsBody(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
};

/// Result of looking up one point.
struct TableQuery
{
  bool covered = false;     ///< the table has a surface at the point's (θ, second) coordinate
  bool inside = false;      ///< covered, and strictly between the inner and outer surface
  double pointRadius = 0;   ///< the point's distance from the axis (or centre)
  double surfaceRadius = 0; ///< r_q: the interpolated outer surface radius
  double innerRadius = 0;   ///< interpolated inner radius (0 when the solid holds the axis)
  Eigen::Vector3d surfacePoint = Eigen::Vector3d::Zero(); ///< Q: nearer surface at same θ
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();      ///< N at Q, unit, out of the solid
  Eigen::Vector3d nearest = Eigen::Vector3d::Zero();      ///< T = P + ((Q − P)·N) N
  double depth = 0; ///< (Q − P)·N: penetration when > 0, distance outside when < 0
};

/// A built table. Each sample keeps the outermost solid interval [inner, outer] met along
/// its ray (inner = 0 when the solid holds the axis, as it does when the axis runs inside
/// the part; > 0 when it runs outside, e.g. in front of the neck), the outward normals at
/// both ends, and whether the ray met the part at all.
class CollisionTable
{
public:
  CollisionTable() = default;
  /// Builds the table by casting rays against `body`. Leaves *this untouched on error.
  Status build(const TableSpec& spec, const RayCaster& body, const Progress& progress = {});

  /// Makes a table from stored samples (e.g. read back from a VTK image); checks sizes.
  Status assign(const TableSpec& spec, std::vector<std::uint8_t> hit, std::vector<double> outer,
                std::vector<double> inner, std::vector<Eigen::Vector3d> outerNormal,
                std::vector<Eigen::Vector3d> innerNormal);

  /// Looks up a point given in the table's frame coordinates (world coordinates of the
  /// part at rest). One cell look-up: cost independent of the mesh.
  TableQuery query(const Eigen::Vector3d& p) const;
  /// query(p).inside, without the surface point and normal: the cheaper test for a point
  /// that is most likely outside.
  bool inside(const Eigen::Vector3d& p) const;

  const TableSpec& spec() const { return Spec; }
  /// spec().frame.basis(), kept: columns (reference⊥, axis × reference⊥, unit axis).
  const Eigen::Matrix3d& basis() const { return Basis; }
  bool empty() const { return Hit.empty(); }
  int numberOfHits() const;
  /// Sample index of (azimuth i, second j).
  int index(int i, int j) const { return j * Spec.azimuthSamples + i; }
  double azimuth(int i) const;
  double second(int j) const; ///< height or polar angle of row j
  /// Unit direction of the ray of sample (i, j) in frame coordinates, and its start point
  /// (on the axis for cylindrical, the centre for spherical).
  Eigen::Vector3d rayDirection(int i, int j) const;
  Eigen::Vector3d rayOrigin(int i, int j) const;

  const std::vector<std::uint8_t>& hit() const { return Hit; }
  const std::vector<double>& outerRadius() const { return Outer; }
  const std::vector<double>& innerRadius() const { return Inner; }
  /// Normals in world coordinates of the part at rest (the frame's own coordinates).
  const std::vector<Eigen::Vector3d>& outerNormal() const { return OuterNormal; }
  const std::vector<Eigen::Vector3d>& innerNormal() const { return InnerNormal; }
  /// The largest outer radius of the samples that met the part: no point farther from the
  /// axis (cylindrical) or the centre (spherical) is inside it.
  double reach() const { return Reach; }
  /// The largest outer radius of the samples whose cells a point within `delta` of p (frame
  /// coordinates) can fall in: the window of heights h ± δ (cylindrical) or polar angles
  /// φ ± asin(δ/ρ) (spherical) and azimuths θ ± asin(δ/r_xy), all azimuths when the ball
  /// holds the axis; the angles widened by the look-up's arctangent error (1e-5 rad). A point
  /// within δ of p that is farther than this from the axis (or centre) is outside the part, without
  /// a look-up. +∞ for a spherical table's ball that holds the centre. What lets the rendered hair
  /// skip the look-up of a point near a guide.
  double windowReach(const Eigen::Vector3d& p, double delta) const;

private:
  TableQuery lookUp(const Eigen::Vector3d& p, bool insideOnly) const; ///< query and inside
  void updateDerived(); ///< basis and scales that follow from Spec (query's hot path)
  void updateReach();   ///< Reach, from the samples
  TableSpec Spec;
  Eigen::Matrix3d Basis = Eigen::Matrix3d::Identity();
  double AzimuthScale = 1, SecondScale = 1, Reach = 0;
  std::vector<std::uint8_t> Hit;
  std::vector<double> Outer, Inner;
  std::vector<Eigen::Vector3d> OuterNormal, InnerNormal;
};

} // namespace hair
