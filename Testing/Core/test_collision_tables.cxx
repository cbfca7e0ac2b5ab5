// Collision tables against references nobody here wrote: analytic bodies (exact radii,
// normals, inside tests), the interpolation error bound of bilinear interpolation, CGAL's
// exact point-in-mesh test on the bundled body, and the analytic solution of a critically
// damped oscillator for the reaction constraint.
#include "AnalyticBodies.h"
#include "collision/BodyPartList.h"
#include "collision/CollisionTable.h"
#include "collision/PosedPart.h"
#include "contact/ReactionConstraint.h"
#include "geometry/MeshIO.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

using namespace hair;
using namespace hairtest;

namespace
{
constexpr double Pi = 3.14159265358979323846;

/// The ray of table coordinates (θ, s) as TableSpec documents it, written out here
/// independently of CollisionTable.
void ray(const TableSpec& spec, double th, double s, Eigen::Vector3d& o, Eigen::Vector3d& d)
{
  const Eigen::Matrix3d b = spec.frame.basis();
  if (spec.projection == Projection::Cylindrical)
  {
    o = spec.frame.origin + s * b.col(2);
    d = b * Eigen::Vector3d(std::cos(th), std::sin(th), 0);
  }
  else
  {
    o = spec.frame.origin;
    d = b * Eigen::Vector3d(std::sin(s) * std::cos(th), std::sin(s) * std::sin(th), std::cos(s));
  }
}

double sMin(const TableSpec& t)
{
  return t.projection == Projection::Cylindrical ? t.heightMin : 0.0;
}
double sMax(const TableSpec& t)
{
  return t.projection == Projection::Cylindrical ? t.heightMax : Pi;
}

/// Exact outer radius and normal along the ray (θ, s) of a convex body holding the origin.
bool exact(const AnalyticBody& body, const TableSpec& spec, double th, double s, double& r,
           Eigen::Vector3d& n)
{
  Eigen::Vector3d o, d;
  ray(spec, th, s, o, d);
  std::vector<RayHit> hits;
  body.castAll(o, d, hits);
  if (hits.empty())
  {
    return false;
  }
  r = hits.back().t;
  n = hits.back().normal;
  return true;
}

/// The bound of bilinear interpolation on a cell hθ × hs:
///   |f − I f| ≤ hθ²/8 max|f_θθ| + hs²/8 max|f_ss|
/// (the one-dimensional linear-interpolation bound applied in each direction). The second
/// derivatives of the exact radius and normal are estimated by central differences of the
/// analytic body over a fine grid.
struct Bound
{
  double radius, normal;
};
Bound interpolationBound(const AnalyticBody& body, const TableSpec& spec)
{
  const double hth = 2 * Pi / spec.azimuthSamples;
  const double hs = (sMax(spec) - sMin(spec)) / (spec.secondSamples - 1);
  const double e = 1e-3;
  double rtt = 0, rss = 0, ntt = 0, nss = 0;
  for (int a = 0; a < 200; ++a)
  {
    for (int b = 0; b <= 100; ++b)
    {
      const double th = 2 * Pi * a / 200;
      const double s = sMin(spec) + e + (sMax(spec) - sMin(spec) - 2 * e) * b / 100;
      double r0, rp, rm, sp, sm;
      Eigen::Vector3d n0, np, nm, mp, mm;
      if (!exact(body, spec, th, s, r0, n0) || !exact(body, spec, th + e, s, rp, np) ||
          !exact(body, spec, th - e, s, rm, nm) || !exact(body, spec, th, s + e, sp, mp) ||
          !exact(body, spec, th, s - e, sm, mm))
      {
        continue;
      }
      rtt = std::max(rtt, std::abs(rp - 2 * r0 + rm) / (e * e));
      rss = std::max(rss, std::abs(sp - 2 * r0 + sm) / (e * e));
      ntt = std::max(ntt, (np - 2 * n0 + nm).norm() / (e * e));
      nss = std::max(nss, (mp - 2 * n0 + mm).norm() / (e * e));
    }
  }
  // 10 % margin for the finite-difference estimate of the second derivatives' maxima,
  // which a 200 x 100 grid can miss between its nodes.
  const double margin = 1.1;
  return {margin * (hth * hth / 8 * rtt + hs * hs / 8 * rss),
          margin * (hth * hth / 8 * ntt + hs * hs / 8 * nss)};
}

struct Errors
{
  double meanRadius = 0, maxRadius = 0, maxNormalAngle = 0;
};

Errors measure(const AnalyticBody& body, const TableSpec& spec, int samples = 3000)
{
  CollisionTable table;
  const Status s = table.build(spec, body);
  EXPECT_TRUE(s.ok()) << s.message();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  Errors e;
  int n = 0;
  for (int k = 0; k < samples; ++k)
  {
    const double th = 2 * Pi * U(rng);
    const double sc = sMin(spec) + (sMax(spec) - sMin(spec)) * (0.02 + 0.96 * U(rng));
    double r;
    Eigen::Vector3d nrm, o, d;
    if (!exact(body, spec, th, sc, r, nrm))
    {
      continue;
    }
    ray(spec, th, sc, o, d);
    const TableQuery q = table.query(o + 0.5 * r * d);
    EXPECT_TRUE(q.covered);
    EXPECT_TRUE(q.inside);
    const double err = std::abs(q.surfaceRadius - r);
    e.meanRadius += err;
    e.maxRadius = std::max(e.maxRadius, err);
    e.maxNormalAngle =
        std::max(e.maxNormalAngle, std::acos(std::clamp(q.normal.dot(nrm), -1.0, 1.0)));
    ++n;
  }
  e.meanRadius /= std::max(n, 1);
  return e;
}

/// Least-squares slope of log(error) against log(resolution).
double fittedOrder(const std::vector<int>& res, const std::vector<double>& err)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = res.size();
  for (std::size_t i = 0; i < res.size(); ++i)
  {
    const double x = std::log(double(res[i])), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

struct Case
{
  const char* name;
  std::shared_ptr<AnalyticBody> body;
  TableSpec spec;
};

std::vector<Case> analyticCases()
{
  std::vector<Case> cases;
  {
    // Sphere R = 1, table centred 0.3 off its centre: r(θ, φ) varies smoothly.
    TableSpec t;
    t.projection = Projection::Spherical;
    t.frame.origin = Eigen::Vector3d(0.2, 0.1, -0.2);
    cases.push_back({"sphere",
                     std::make_shared<Ellipsoid>(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 1)),
                     t});
  }
  {
    TableSpec t;
    t.projection = Projection::Spherical;
    t.frame.origin = Eigen::Vector3d(0.1, -0.1, 0.05);
    t.frame.axis = Eigen::Vector3d(0.2, 1, 0.1);
    t.frame.reference = Eigen::Vector3d(0, 0, 1);
    cases.push_back(
        {"ellipsoid",
         std::make_shared<Ellipsoid>(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.8, 1.2, 0.6)), t});
  }
  {
    // Capped cylinder R = 0.5, heights ±1, axis of the table 0.15 off the cylinder's; the
    // table's rows stop short of the caps (a ray in a cap's plane only grazes it).
    TableSpec t;
    t.projection = Projection::Cylindrical;
    t.frame.origin = Eigen::Vector3d(0.15, 0, 0.05);
    t.heightMin = -0.999;
    t.heightMax = 0.999;
    cases.push_back({"capped cylinder",
                     std::make_shared<CappedCylinder>(Eigen::Vector3d::Zero(), 0.5, 1.0), t});
  }
  return cases;
}

} // namespace

TEST(CollisionTable, RadiusAndNormalErrorWithinBilinearBoundAndSecondOrder)
{
  for (const Case& c : analyticCases())
  {
    std::vector<int> res;
    std::vector<double> meanErr, maxErr, angErr;
    for (int n : {10, 20, 40, 80})
    {
      TableSpec t = c.spec;
      t.azimuthSamples = t.secondSamples = n;
      const Errors e = measure(*c.body, t);
      const Bound b = interpolationBound(*c.body, t);
      EXPECT_LE(e.maxRadius, b.radius) << c.name << " at " << n << " x " << n;
      // Normalising the interpolated normal turns a vector error of at most b.normal into an
      // angle of at most asin(b.normal) (b.normal < 1).
      if (b.normal < 1)
      {
        EXPECT_LE(e.maxNormalAngle, std::asin(b.normal)) << c.name << " at " << n;
      }
      res.push_back(n);
      meanErr.push_back(e.meanRadius);
      maxErr.push_back(e.maxRadius);
      angErr.push_back(e.maxNormalAngle);
      std::printf("%-16s %3d x %-3d  radius error mean %.3e max %.3e (bound %.3e)  normal "
                  "%.4f deg (bound %.4f deg)\n",
                  c.name, n, n, e.meanRadius, e.maxRadius, b.radius, e.maxNormalAngle * 180 / Pi,
                  std::asin(std::min(b.normal, 1.0)) * 180 / Pi);
    }
    // Bilinear interpolation is second order: the error falls by 4 when the resolution
    // doubles. The fitted slope over 10 ... 80 must be 2 within 0.25 (pre-asymptotic
    // effects at 10 x 10 and sampling noise of the mean).
    const double order = fittedOrder(res, meanErr);
    const double orderNormal = fittedOrder(res, angErr);
    std::printf("%-16s fitted order: radius %.2f, normal %.2f (expected 2)\n", c.name, order,
                orderNormal);
    EXPECT_NEAR(order, 2.0, 0.25) << c.name;
    EXPECT_NEAR(orderNormal, 2.0, 0.35) << c.name;
  }
}

TEST(CollisionTable, InsideAgreesWithExactFartherThanOneCell)
{
  for (const Case& c : analyticCases())
  {
    CollisionTable table;
    ASSERT_TRUE(table.build(c.spec, *c.body).ok());
    // One cell, in space: the largest radius times the larger angular step (and the height
    // step for a cylinder).
    double rmax = 0;
    for (std::size_t s = 0; s < table.outerRadius().size(); ++s)
    {
      rmax = std::max(rmax, table.outerRadius()[s]);
    }
    const double dth = 2 * Pi / c.spec.azimuthSamples;
    const double ds = (sMax(c.spec) - sMin(c.spec)) / (c.spec.secondSamples - 1);
    const double cell = c.spec.projection == Projection::Spherical ? rmax * std::max(dth, ds)
                                                                   : std::hypot(rmax * dth, ds);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1.4, 1.4);
    int tested = 0, wrong = 0, insideCount = 0;
    for (int k = 0; k < 100000; ++k)
    {
      const Eigen::Vector3d p(U(rng), U(rng), U(rng));
      if (c.body->distanceBound(p) <= cell)
      {
        continue;
      }
      ++tested;
      const bool truth = c.body->inside(p);
      insideCount += truth;
      wrong += table.query(p).inside != truth;
    }
    std::printf("%-16s cell %.3f: %d points tested (%d inside), %d disagree\n", c.name, cell,
                tested, insideCount, wrong);
    EXPECT_GT(insideCount, 500);
    EXPECT_EQ(wrong, 0) << c.name;
  }
}

TEST(CollisionTable, NearestPointAndDepthOnSphere)
{
  // A table centred at a sphere's centre: the radius is constant, so Q = R·(P − c)/|P − c| is
  // exact, and the only error is that of the interpolated normal. For the radial field
  // n(θ, φ) on a unit sphere |n_θθ| = sin φ ≤ 1 and |n_φφ| = 1, so bilinear interpolation
  // errs by at most (hθ² + hφ²)/8 (then normalised: an angle α ≤ asin of that). The depth
  // (Q − P)·N then errs by at most |R − r|(1 − cos α) and T = P + depth N lies within
  // |R − r| sin α of Q.
  Ellipsoid sphere(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.5, 0.5, 0.5));
  TableSpec t;
  t.projection = Projection::Spherical;
  t.frame.origin = sphere.centre;
  CollisionTable table;
  ASSERT_TRUE(table.build(t, sphere).ok());
  const double hth = 2 * Pi / t.azimuthSamples, hph = Pi / (t.secondSamples - 1);
  const double alpha = std::asin((hth * hth + hph * hph) / 8);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.9, 0.9);
  for (int k = 0; k < 1000; ++k)
  {
    const Eigen::Vector3d p = sphere.centre + Eigen::Vector3d(U(rng), U(rng), U(rng));
    const double r = (p - sphere.centre).norm();
    const Eigen::Vector3d radial = (p - sphere.centre) / r;
    const TableQuery q = table.query(p);
    ASSERT_TRUE(q.covered);
    EXPECT_EQ(q.inside, r < 0.5);
    EXPECT_LT((q.surfacePoint - (sphere.centre + 0.5 * radial)).norm(), 1e-12);
    EXPECT_LE(std::acos(std::min(1.0, q.normal.dot(radial))), alpha + 1e-9);
    EXPECT_LE(std::abs(q.depth - (0.5 - r)), std::abs(0.5 - r) * (1 - std::cos(alpha)) + 1e-12);
    EXPECT_LE((q.nearest - q.surfacePoint).norm(), std::abs(0.5 - r) * std::sin(alpha) + 1e-12);
  }
}

TEST(CollisionTable, AxisOutsideTheSolidKeepsTheInnerSurface)
{
  // A cylindrical table whose axis runs outside a ball (as the head's axis runs in front of
  // the neck): rays cross the ball twice, the table keeps [inner, outer], and points between
  // the axis and the ball are outside.
  Ellipsoid ball(Eigen::Vector3d(0, 0, -0.6), Eigen::Vector3d(0.4, 0.4, 0.4));
  TableSpec t;
  t.projection = Projection::Cylindrical;
  t.heightMin = -0.3;
  t.heightMax = 0.3;
  t.azimuthSamples = 80;
  t.secondSamples = 40;
  CollisionTable table;
  ASSERT_TRUE(table.build(t, ball).ok());
  EXPECT_FALSE(table.query(Eigen::Vector3d(0, 0, -0.1)).inside); // between axis and ball
  EXPECT_TRUE(table.query(Eigen::Vector3d(0, 0, -0.6)).inside);  // the ball's centre
  EXPECT_FALSE(table.query(Eigen::Vector3d(0, 0, -1.1)).inside); // past the ball
  EXPECT_FALSE(table.query(Eigen::Vector3d(0, 0, 0.6)).inside);  // the other side: no hit
  EXPECT_FALSE(table.query(Eigen::Vector3d(0, 0, 0.6)).covered);
  // Near the inner surface, the nearer surface is the inner one, with its normal facing the
  // axis (out of the solid).
  const TableQuery q = table.query(Eigen::Vector3d(0, 0, -0.25));
  ASSERT_TRUE(q.inside);
  EXPECT_NEAR(q.normal.z(), 1.0, 0.02);
  EXPECT_NEAR(q.depth, 0.05, 0.002); // inner surface at z = −0.2
}

TEST(CollisionTable, MaxRadiusCapsTheRayAndIgnoresWhatLiesBeyond)
{
  // Two balls on the table's axis line: the far one is beyond maxRadius and must not count.
  struct Two : AnalyticBody
  {
    Ellipsoid a{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.3, 0.3)};
    Ellipsoid b{Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0.3, 0.3, 0.3)};
    void castAll(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                 std::vector<RayHit>& hits) const override
    {
      std::vector<RayHit> ha, hb;
      a.castAll(o, d, ha);
      b.castAll(o, d, hb);
      hits = ha;
      hits.insert(hits.end(), hb.begin(), hb.end());
      std::sort(hits.begin(), hits.end(), [](auto& x, auto& y) { return x.t < y.t; });
    }
    bool inside(const Eigen::Vector3d& p) const override { return a.inside(p) || b.inside(p); }
    double distanceBound(const Eigen::Vector3d&) const override { return 0; }
  } two;
  TableSpec t;
  t.projection = Projection::Spherical;
  t.frame.origin = Eigen::Vector3d::Zero();
  t.frame.axis = Eigen::Vector3d::UnitY();
  t.frame.reference = Eigen::Vector3d::UnitZ();
  CollisionTable far, near;
  ASSERT_TRUE(far.build(t, two).ok());
  t.maxRadius = 0.5;
  ASSERT_TRUE(near.build(t, two).ok());
  // Without a limit the outermost interval towards +z is the far ball: the near ball's
  // interior at z = 0.1 is then "outside" for that table; with the limit it is inside.
  EXPECT_FALSE(far.query(Eigen::Vector3d(0, 0, 0.1)).inside);
  EXPECT_TRUE(near.query(Eigen::Vector3d(0, 0, 0.1)).inside);
  EXPECT_FALSE(near.query(Eigen::Vector3d(0, 0, 1.0)).inside);
}

TEST(CollisionTable, RigidMotionMovesTheTableWithoutRebuild)
{
  Ellipsoid body(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.8, 1.2, 0.6));
  TableSpec t;
  t.projection = Projection::Spherical;
  CollisionTable table;
  ASSERT_TRUE(table.build(t, body).ok());
  PosedPart part = PosedPart::still(table);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, -1, 2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.3, 1.3);
  for (int k = 0; k < 500; ++k)
  {
    const Eigen::Vector3d p(U(rng), U(rng), U(rng));
    part.pose = Eigen::Isometry3d::Identity();
    const TableQuery rest = part.query(p);
    part.pose = pose;
    const TableQuery moved = part.query(pose * p);
    ASSERT_EQ(rest.covered, moved.covered);
    EXPECT_EQ(rest.inside, moved.inside);
    if (rest.covered)
    {
      EXPECT_NEAR(rest.depth, moved.depth, 1e-12);
      EXPECT_LT((pose * rest.nearest - moved.nearest).norm(), 1e-12);
      EXPECT_LT((pose.linear() * rest.normal - moved.normal).norm(), 1e-12);
    }
  }
}

TEST(MeshQueries, TriangulatedSphereMatchesTheSphereWithinItsFaceting)
{
  const double R = 0.1;
  const TriangleMesh mesh = triangulatedSphere(Eigen::Vector3d(0, 1, 0), R, 5); // 8192 faces
  ASSERT_TRUE(mesh.validate().ok());
  MeshQueries exactMesh(mesh);
  EXPECT_EQ(exactMesh.numberOfTriangles(), 8192u);
  // Volume of the inscribed polyhedron: below the ball's, by less than 1 % at this size.
  EXPECT_GT(exactMesh.signedVolume(), 0.99 * 4.0 / 3 * Pi * R * R * R);
  EXPECT_LT(exactMesh.signedVolume(), 4.0 / 3 * Pi * R * R * R);
  // Longest edge e; the flat triangle lies at most its sagitta e²/(8R)... (a triangle's
  // circumradius is at most e/√3, so the gap is at most R − √(R² − e²/3)).
  double e = 0;
  for (const auto& t : mesh.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      e = std::max(e, (mesh.points[t[k]] - mesh.points[t[(k + 1) % 3]]).norm());
    }
  }
  const double gap = R - std::sqrt(R * R - e * e / 3);
  TableSpec t;
  t.projection = Projection::Spherical;
  t.frame.origin = Eigen::Vector3d(0.01, 1.02, 0);
  CollisionTable fromMesh, fromSphere;
  ASSERT_TRUE(fromMesh.build(t, exactMesh).ok());
  ASSERT_TRUE(
      fromSphere.build(t, Ellipsoid(Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(R, R, R))).ok());
  double maxDiff = 0, maxAngle = 0;
  for (std::size_t s = 0; s < fromMesh.hit().size(); ++s)
  {
    ASSERT_TRUE(fromMesh.hit()[s]);
    maxDiff = std::max(maxDiff, std::abs(fromMesh.outerRadius()[s] - fromSphere.outerRadius()[s]));
    maxAngle = std::max(
        maxAngle, std::acos(std::clamp(fromMesh.outerNormal()[s].dot(fromSphere.outerNormal()[s]),
                                       -1.0, 1.0)));
  }
  // The radius along a ray differs by at most the faceting gap over the cosine of the ray's
  // incidence (the table centre is 0.022 R-units off: cos ≥ 0.97 here).
  EXPECT_LT(maxDiff, gap / 0.97);
  // Interpolated vertex normals turn by less than the angle an edge subtends at the centre.
  EXPECT_LT(maxAngle, 2 * std::asin(e / (2 * R)));
  std::printf("triangulated sphere: edge %.4f, faceting gap %.2e, max radius diff %.2e, max "
              "normal angle %.3f deg\n",
              e, gap, maxDiff, maxAngle * 180 / Pi);
  // Exact queries.
  EXPECT_TRUE(exactMesh.isInside(Eigen::Vector3d(0, 1, 0)));
  EXPECT_FALSE(exactMesh.isInside(Eigen::Vector3d(0, 1.2, 0)));
  EXPECT_NEAR(
      (exactMesh.closestPoint(Eigen::Vector3d(0, 1.3, 0)) - Eigen::Vector3d(0, 1.1, 0)).norm(), 0,
      1e-9);
}

TEST(MeshQueries, InwardFacingMeshIsReorientedOutward)
{
  TriangleMesh mesh = triangulatedSphere(Eigen::Vector3d::Zero(), 1, 2);
  for (auto& t : mesh.triangles)
  {
    std::swap(t[1], t[2]);
  }
  MeshQueries q(mesh);
  std::vector<RayHit> hits;
  q.castAll(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), hits);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_GT(hits[0].normal.x(), 0.9);
  // A ray through a vertex (the octahedron's corner (1, 0, 0) touches many triangles) is one
  // crossing, not several.
  q.castAll(Eigen::Vector3d(-2, 0, 0), Eigen::Vector3d::UnitX(), hits);
  EXPECT_EQ(hits.size(), 2u);
}

namespace
{
std::string dataFile(const char* name)
{
  return std::string(HAIR_DATA_DIR) + "/" + name;
}
} // namespace

TEST(BundledBody, ReadsAsAClosedHumanSizedSurface)
{
  TriangleMesh body;
  const Status s = readVtkPolyData(dataFile("body.vtk"), body);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(body.points.size(), 13380u);
  EXPECT_EQ(body.triangles.size(), 26756u);
  MeshQueries q(body);
  // An adult's volume is about mass / density ≈ 70 kg / 1010 kg/m³ ≈ 0.07 m³.
  EXPECT_GT(std::abs(q.signedVolume()), 0.04);
  EXPECT_LT(std::abs(q.signedVolume()), 0.12);
  const auto [lo, hi] = body.bounds();
  EXPECT_NEAR(lo.y(), 0.0, 0.01);
  EXPECT_NEAR(hi.y(), 1.66, 0.01);
}

TEST(BundledBody, HeadTablesAgreeWithExactPointInMesh)
{
  TriangleMesh body;
  ASSERT_TRUE(readVtkPolyData(dataFile("body.vtk"), body).ok());
  std::vector<BodyPartSpec> specs;
  const Status sp = readBodyParts(dataFile("body_parts.txt"), specs);
  ASSERT_TRUE(sp.ok()) << sp.message();
  MeshQueries exactBody(body);
  std::vector<CollisionTable> tables(specs.size());
  for (std::size_t k = 0; k < specs.size(); ++k)
  {
    const Status s = tables[k].build(specs[k].spec, exactBody);
    ASSERT_TRUE(s.ok()) << specs[k].name << ": " << s.message();
  }
  // Random points in a box around the head and neck (the head spans x ±0.084, y 1.44–1.66,
  // z −0.049–0.160), kept when farther than 2 mm from the surface.
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> X(-0.12, 0.12), Y(1.40, 1.70), Z(-0.09, 0.20);
  int tested = 0, agree = 0, inside = 0, missedInside = 0, falseInside = 0;
  for (int k = 0; k < 40000 && tested < 20000; ++k)
  {
    const Eigen::Vector3d p(X(rng), Y(rng), Z(rng));
    if ((exactBody.closestPoint(p) - p).norm() <= 0.002)
    {
      continue;
    }
    ++tested;
    const bool truth = exactBody.isInside(p);
    bool byTables = false;
    for (const auto& t : tables)
    {
      byTables = byTables || t.query(p).inside;
    }
    inside += truth;
    agree += byTables == truth;
    missedInside += truth && !byTables;
    falseInside += !truth && byTables;
  }
  const double rate = double(agree) / tested;
  std::printf("bundled head: %d points farther than 2 mm (%d inside), tables agree on %.2f %%; "
              "%d inside points called outside, %d outside points called inside\n",
              tested, inside, 100 * rate, missedInside, falseInside);
  RecordProperty("agreement_percent", std::to_string(100 * rate));
  EXPECT_GT(inside, 2000);
  EXPECT_GE(rate, 0.99);
}

TEST(BadInput, RefusedWithMessages)
{
  Ellipsoid ball(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 1, 1));
  CollisionTable table;
  TableSpec t;
  t.projection = Projection::Spherical;
  auto refuse = [&](const TableSpec& spec, const char* expect)
  {
    const Status s = table.build(spec, ball);
    EXPECT_FALSE(s.ok());
    EXPECT_NE(s.message().find(expect), std::string::npos) << s.message();
    EXPECT_TRUE(table.empty()); // nothing half-built is left behind
  };
  TableSpec bad = t;
  bad.azimuthSamples = 0;
  refuse(bad, "resolution");
  bad = t;
  bad.secondSamples = 1000000;
  refuse(bad, "resolution");
  bad = t;
  bad.frame.origin.x() = std::nan("");
  refuse(bad, "origin");
  bad = t;
  bad.frame.axis = Eigen::Vector3d::Zero();
  refuse(bad, "axis");
  bad = t;
  bad.frame.reference = bad.frame.axis * 2;
  refuse(bad, "parallel");
  bad = t;
  bad.projection = Projection::Cylindrical;
  bad.heightMin = bad.heightMax = 0.5;
  refuse(bad, "height range");
  bad = t;
  bad.maxRadius = std::nan("");
  refuse(bad, "maximum radius");
  bad = t;
  bad.frame.origin = Eigen::Vector3d(10, 0, 0); // rays from here miss the ball...
  bad.projection = Projection::Cylindrical;     // ...when they run in planes off it
  bad.heightMin = 5;
  bad.heightMax = 6;
  refuse(bad, "misses");

  TriangleMesh empty;
  EXPECT_NE(empty.validate("input 0").message().find("no points"), std::string::npos);
  TriangleMesh noPolys;
  noPolys.points = {Eigen::Vector3d::Zero()};
  EXPECT_NE(noPolys.validate().message().find("no polygons"), std::string::npos);
  TriangleMesh nan = triangulatedSphere(Eigen::Vector3d::Zero(), 1, 1);
  nan.points[3].y() = std::nan("");
  EXPECT_NE(nan.validate().message().find("NaN"), std::string::npos);
  TriangleMesh outOfRange = triangulatedSphere(Eigen::Vector3d::Zero(), 1, 1);
  outOfRange.triangles[0][1] = 999;
  EXPECT_NE(outOfRange.validate().message().find("does not exist"), std::string::npos);

  // A query of a NaN point is simply not covered.
  ASSERT_TRUE(table.build(t, ball).ok());
  EXPECT_FALSE(table.query(Eigen::Vector3d(std::nan(""), 0, 0)).covered);
}

TEST(BadInput, TruncatedAndForeignMeshFilesAreRefused)
{
  const std::string dir = ::testing::TempDir();
  {
    std::ifstream in(dataFile("body.vtk"));
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir + "/truncated.vtk") << all.substr(0, all.size() / 3);
  }
  std::ofstream(dir + "/foreign.vtk") << "solid cube\nfacet normal 0 0 1\n";
  TriangleMesh m;
  Status s = readVtkPolyData(dir + "/truncated.vtk", m);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("truncated"), std::string::npos) << s.message();
  s = readVtkPolyData(dir + "/foreign.vtk", m);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("not a legacy VTK file"), std::string::npos) << s.message();
  s = readVtkPolyData(dir + "/does-not-exist.vtk", m);
  EXPECT_NE(s.message().find("cannot open"), std::string::npos) << s.message();
  EXPECT_TRUE(m.points.empty()); // nothing was half-read into the output
}

// ---- Reaction constraint (Platt and Barr 1988; Kurihara et al. 1993) ----

TEST(ReactionConstraint, RemovesTheInwardForceAndKeepsTheTangentialOne)
{
  const Eigen::Vector3d N(0, 1, 0), P(0.3, -0.01, 0), T(0.3, 0, 0), V(0.5, -0.2, 0);
  const Eigen::Vector3d Fin(2, -9.81, 1);
  ReactionConstraintOptions o;
  o.stiffness = 400;
  const Eigen::Vector3d F = reactionConstraint(Fin, V, P, T, N, o);
  EXPECT_DOUBLE_EQ(F.x(), 2);
  EXPECT_DOUBLE_EQ(F.z(), 1);
  // Normal part: −(k (P − T)·N + c V·N) with c = 2√k = 40.
  EXPECT_NEAR(F.y(), -(400 * -0.01 + 40 * -0.2), 1e-12);
}

TEST(ReactionConstraint, InelasticRuleLetsALiftingForceAct)
{
  const Eigen::Vector3d N(0, 0, 1), P(0, 0, -0.01), T(0, 0, 0), V(0, 0, -1);
  const Eigen::Vector3d lifting(1, 0, 5);
  EXPECT_EQ(reactionConstraint(lifting, V, P, T, N), lifting);
  ReactionConstraintOptions elastic;
  elastic.inelastic = false;
  EXPECT_NE(reactionConstraint(lifting, V, P, T, N, elastic), lifting);
}

namespace
{
/// Depth history of a node pushed into a flat surface by a constant force, under the
/// constraint (RK4, small step), from depth d0 at rest.
std::vector<double> settle(const ReactionConstraintOptions& o, double d0, double dt, int steps)
{
  const Eigen::Vector3d N(0, 0, 1), T(0, 0, 0), Fin(0, 0, -9.81);
  auto accel = [&](double x, double v)
  {
    return reactionConstraint(Fin, Eigen::Vector3d(0, 0, v), Eigen::Vector3d(0, 0, x), T, N, o).z();
  };
  double x = -d0, v = 0;
  std::vector<double> xs{x};
  for (int i = 0; i < steps; ++i)
  {
    const double k1x = v, k1v = accel(x, v);
    const double k2x = v + dt / 2 * k1v, k2v = accel(x + dt / 2 * k1x, v + dt / 2 * k1v);
    const double k3x = v + dt / 2 * k2v, k3v = accel(x + dt / 2 * k2x, v + dt / 2 * k2v);
    const double k4x = v + dt * k3v, k4v = accel(x + dt * k3x, v + dt * k3v);
    x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    xs.push_back(x);
  }
  return xs;
}
} // namespace

TEST(ReactionConstraint, CriticallyDampedReturnMatchesTheAnalyticSolution)
{
  // With F_in pushing in, the normal motion is x'' = −k x − c x'. With c = 2√k (critical)
  // the solution from x0 at rest is x(t) = x0 (1 + ωt) e^{−ωt}, ω = √k: it never overshoots.
  ReactionConstraintOptions o;
  o.stiffness = 2500; // ω = 50 /s
  const double w = 50, d0 = 0.004, dt = 1e-4;
  const auto xs = settle(o, d0, dt, 4000);
  double maxErr = 0;
  for (std::size_t i = 0; i < xs.size(); ++i)
  {
    const double t = i * dt;
    maxErr = std::max(maxErr, std::abs(xs[i] - (-d0) * (1 + w * t) * std::exp(-w * t)));
    EXPECT_LE(xs[i], 0.0) << "overshoot at t = " << t;
  }
  // RK4 at ω dt = 0.005: local error ~ (ω dt)⁵ / 120 per step, far below 1e-9 of d0.
  EXPECT_LT(maxErr, 1e-9 * d0 * 1e3);
  // The damping written in the design note, √(2k), is a damping ratio of 1/√2: it overshoots
  // (by e^{−π ζ/√(1−ζ²)} = e^{−π} ≈ 4.3 % of d0), which is why the code uses 2√k.
  o.damping = std::sqrt(2 * o.stiffness);
  const auto under = settle(o, d0, dt, 4000);
  const double overshoot = *std::max_element(under.begin(), under.end());
  EXPECT_NEAR(overshoot / d0, std::exp(-Pi), 2e-3);
}

TEST(BundledBody, WindowReachIsABoundNoInsidePointEscapes)
{
  // CollisionTable::windowReach(p, δ): every point within δ of p farther from the axis (or
  // centre) than it is outside. Checked on the bundled body's tables (the head's spherical,
  // the trunk's and limbs' cylindrical), the inside test itself as the judge: random centres
  // near the surface, random points in their balls; not one that the bound calls outside
  // may be inside. And the bound must be useful: most points a few millimetres outside the
  // head are cleared by it. `inside` agrees with the full query everywhere.
  TriangleMesh body;
  ASSERT_TRUE(readVtkPolyData(dataFile("body.vtk"), body).ok());
  std::vector<BodyPartSpec> specs;
  ASSERT_TRUE(readBodyParts(dataFile("body_parts.txt"), specs).ok());
  MeshQueries exactBody(body);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  int cleared = 0, tested = 0, escaped = 0, disagree = 0;
  for (const BodyPartSpec& spec : specs)
  {
    CollisionTable table;
    ASSERT_TRUE(table.build(spec.spec, exactBody).ok()) << spec.name;
    for (int k = 0; k < 400; ++k)
    {
      // A centre near the table's surface: a random sample's surface point, moved out by
      // up to 2 cm.
      const int i = int((U(rng) + 1) / 2 * (spec.spec.azimuthSamples - 1));
      const int j = int((U(rng) + 1) / 2 * (spec.spec.secondSamples - 1));
      if (!table.hit()[table.index(i, j)])
        continue;
      const Eigen::Vector3d d = table.rayDirection(i, j);
      const Eigen::Vector3d p = table.rayOrigin(i, j) +
                                (table.outerRadius()[table.index(i, j)] + 0.01 * (U(rng) + 1)) * d;
      for (const double delta : {0.008, 0.025})
      {
        const double reach = table.windowReach(p, delta);
        for (int m = 0; m < 50; ++m)
        {
          Eigen::Vector3d x(U(rng), U(rng), U(rng));
          if (x.norm() > 1)
            continue;
          x = p + delta * x;
          const TableQuery q = table.query(x);
          disagree += q.inside != table.inside(x);
          ++tested;
          // The point's distance from the axis (cylindrical) or centre (spherical).
          const Eigen::Vector3d local = table.basis().transpose() * (x - spec.spec.frame.origin);
          const double radius = spec.spec.projection == Projection::Cylindrical
                                    ? std::hypot(local.x(), local.y())
                                    : local.norm();
          if (radius > reach)
          {
            ++cleared;
            escaped += q.inside;
          }
        }
      }
    }
  }
  std::printf("window reach: %d points in balls of 8 and 25 mm about points near the tables, "
              "%d cleared by the bound, %d of those inside\n",
              tested, cleared, escaped);
  EXPECT_GT(tested, 10000);
  EXPECT_EQ(escaped, 0);
  EXPECT_EQ(disagree, 0);
  EXPECT_GT(cleared, tested / 4);
}

TEST(Drape, StraightStrandThroughABallComesOutLyingOnIt)
{
  // A straight strand grown from the side of a ball (radius 0.1 m, exact spherical table)
  // tilted 60° into it: draped, no point is inside, each point is at least the clearance
  // out or where the strand left the ball, the root and every segment's length are kept,
  // the move is reported; a strand already outside is left exactly as it was.
  const hairtest::Ellipsoid ball(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1));
  CollisionTable table;
  TableSpec spec;
  spec.projection = Projection::Spherical;
  ASSERT_TRUE(table.build(spec, ball).ok());
  const std::vector<PosedPart> parts = {PosedPart::still(table)};
  const Eigen::Vector3d root(0.1, 0, 0);
  const Eigen::Vector3d into = Eigen::Vector3d(-0.5, -std::sqrt(0.75), 0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= 30; ++i)
    points.push_back(root + 0.01 * i * into);
  const double clearance = 1e-3;
  const double moved = drapeOutside(parts, clearance, points);
  EXPECT_GT(moved, clearance); // it was inside: 30° into the ball
  EXPECT_EQ(points[0], root);
  double closest = 1;
  for (std::size_t i = 1; i < points.size(); ++i)
  {
    EXPECT_FALSE(insideAny(parts, points[i])) << i;
    EXPECT_NEAR((points[i] - points[i - 1]).norm(), 0.01, 1e-12) << i;
    closest = std::min(closest, points[i].norm() - 0.1);
  }
  // It lies on the ball: the nearest point within the clearance (and round-off) of it.
  EXPECT_LT(closest, clearance + 1e-6);
  std::printf("draped: moved %.1f mm, nearest point %.3f mm from the ball\n", 1e3 * moved,
              1e3 * closest);
  std::vector<Eigen::Vector3d> outside;
  for (int i = 0; i <= 30; ++i)
    outside.push_back(root + 0.01 * i * Eigen::Vector3d::UnitX());
  const std::vector<Eigen::Vector3d> before = outside;
  EXPECT_EQ(drapeOutside(parts, clearance, outside), 0.0);
  EXPECT_EQ(outside, before);
}
