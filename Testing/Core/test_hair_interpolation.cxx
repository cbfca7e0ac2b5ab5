// Rendered hair from guides (render/HairInterpolation): exactness at a guide, weights, rigid
// motion, the tip-distance criterion of Bertails et al. 2006 (§4.1, Figure 4d), curl, the
// push-out, and the same result on any number of threads.
#include "AnalyticBodies.h"
#include "DemoScene.h"
#include "collision/CollisionTable.h"
#include "render/HairInterpolation.h"
#include "simulation/Simulation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <iostream>

using namespace hair;

namespace
{

/// A flat strip of scalp in the plane y = 0, normal +y, x in [x0, x1], z in [z0, z1].
TriangleMesh strip(double x0, double x1, double z0, double z1, int nx = 20, int nz = 4)
{
  TriangleMesh m;
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= nz; ++j)
      m.points.emplace_back(x0 + (x1 - x0) * i / nx, 0, z0 + (z1 - z0) * j / nz);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nz; ++j)
    {
      const int a = i * (nz + 1) + j, b = a + nz + 1;
      m.triangles.push_back({a, a + 1, b});
      m.triangles.push_back({b, a + 1, b + 1});
    }
  return m;
}

GuideStrand guideAt(const Eigen::Vector3d& root, const Eigen::Vector3d& growth)
{
  GuideStrand g;
  g.root = root;
  g.growth = growth;
  g.normal = Eigen::Vector3d::UnitY();
  g.length = 0.3;
  g.elements = 10;
  return g;
}

/// A helix of radius r and step h (per turn) from the guide's root, leaving it along its
/// growth direction with the guide's rest root frame as material frame there (as a model's
/// strand does at t = 0): points evenly spaced in arc length, tangents and first directors
/// (the principal normals) exact.
void helixGuide(const GuideStrand& g, double r, double h, int points, GuideCurves& out,
                const Eigen::Isometry3d& motion = Eigen::Isometry3d::Identity())
{
  const double c = h / (2 * M_PI), speed = std::sqrt(r * r + c * c);
  // In helix coordinates x(φ) = (c φ, r (cos φ − 1), r sin φ), principal normal
  // (0, −cos φ, −sin φ); Q turns the frame at φ = 0 into the rest root frame.
  auto tangentAt = [&](double phi) -> Eigen::Vector3d
  { return Eigen::Vector3d(c, -r * std::sin(phi), r * std::cos(phi)) / speed; };
  auto normalAt = [&](double phi) -> Eigen::Vector3d
  { return Eigen::Vector3d(0, -std::cos(phi), -std::sin(phi)); };
  Eigen::Matrix3d H0;
  H0.col(0) = tangentAt(0);
  H0.col(1) = normalAt(0);
  H0.col(2) = H0.col(0).cross(H0.col(1));
  const Eigen::Matrix3d Q = g.rootFrame() * H0.transpose();
  for (int i = 0; i < points; ++i)
  {
    const double s = g.length * i / (points - 1), phi = s / speed;
    const Eigen::Vector3d local(c * phi, r * (std::cos(phi) - 1), r * std::sin(phi));
    out.points.push_back(motion * (g.root + Q * local));
    out.tangents.push_back(motion.linear() * (Q * tangentAt(phi)));
    out.directors.push_back(motion.linear() * (Q * normalAt(phi)));
  }
  out.offsets.push_back(out.points.size());
}

GuideCurves curvesOf(const std::vector<GuideStrand>& guides, double r, double h, int points,
                     const Eigen::Isometry3d& motion = Eigen::Isometry3d::Identity())
{
  GuideCurves c;
  c.offsets.push_back(0);
  for (const GuideStrand& g : guides)
    helixGuide(g, r, h, points, c, motion);
  return c;
}

/// Mean |curvature| of a polyline from its turning angles, over its inner points.
double meanCurvature(const float* p, int n)
{
  double sum = 0;
  for (int j = 1; j + 1 < n; ++j)
  {
    const Eigen::Vector3d a(p[3 * (j - 1)], p[3 * (j - 1) + 1], p[3 * (j - 1) + 2]);
    const Eigen::Vector3d b(p[3 * j], p[3 * j + 1], p[3 * j + 2]);
    const Eigen::Vector3d c(p[3 * (j + 1)], p[3 * (j + 1) + 1], p[3 * (j + 1) + 2]);
    const Eigen::Vector3d u = (b - a), v = (c - b);
    const double angle = std::atan2(u.cross(v).norm(), u.dot(v));
    sum += angle / (0.5 * (u.norm() + v.norm()));
  }
  return sum / (n - 2);
}

std::vector<GuideStrand> row(int count, double spacing, const Eigen::Vector3d& growth)
{
  std::vector<GuideStrand> guides;
  for (int i = 0; i < count; ++i)
    guides.push_back(guideAt(Eigen::Vector3d(spacing * (i - 0.5 * (count - 1)), 0, 0), growth));
  return guides;
}

} // namespace

TEST(HairInterpolation, AStrandRootedAtAGuideReproducesIt)
{
  // Tolerance: the output is single precision (float eps 6e-8 × coordinates of 0.3 m).
  const std::vector<GuideStrand> guides = row(5, 0.01, Eigen::Vector3d(0, -1, 0));
  const GuideCurves curves = curvesOf(guides, 0.006, 0.005, 33);
  for (InterpolationMethod method :
       {InterpolationMethod::SemiInterpolation, InterpolationMethod::Clusters})
  {
    InterpolationOptions o;
    o.method = method;
    o.pointsPerStrand = 33;
    o.variation = 0;
    HairInterpolation hi;
    ASSERT_TRUE(hi.bind(guides, {guides[2].root}, o).ok());
    RenderedHair out;
    ASSERT_TRUE(hi.evaluate(curves, {}, out).ok());
    double worst = 0;
    for (int j = 0; j < 33; ++j)
      for (int a = 0; a < 3; ++a)
        worst = std::max(worst, std::abs(out.points[3 * j + a] - curves.points[2 * 33 + j][a]));
    EXPECT_LT(worst, 1e-7) << int(method);
  }
}

TEST(HairInterpolation, WeightsSumToOneAndTheRootsLieOnTheScalp)
{
  const std::vector<GuideStrand> guides = row(9, 0.01, Eigen::Vector3d(0, -1, 0));
  InterpolationOptions o;
  o.strands = 2000;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, strip(-0.06, 0.06, -0.01, 0.01), o).ok());
  ASSERT_EQ(hi.strandCount(), 2000u);
  for (const HairInterpolation::Binding& b : hi.bindings())
  {
    double sum = 0;
    for (int i = 0; i < b.count; ++i)
    {
      EXPECT_GE(b.weights[i], 0);
      sum += b.weights[i];
    }
    EXPECT_NEAR(sum, 1, 1e-14);
    EXPECT_EQ(b.root.y(), 0);
    // Near the guides: within 1.5 spacings of a root (and the strip's edge).
    EXPECT_LE(std::abs(b.root.x()), 0.04 + 0.015 + 1e-12);
  }
}

TEST(HairInterpolation, TheRenderedHairMovesRigidlyWithTheHead)
{
  const std::vector<GuideStrand> guides = row(9, 0.01, Eigen::Vector3d(0.3, -1, 0.2).normalized());
  InterpolationOptions o;
  o.strands = 500;
  o.pointsPerStrand = 24;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o).ok());
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  motion.pretranslate(Eigen::Vector3d(0.1, -0.2, 0.05));
  RenderedHair rest, moved;
  ASSERT_TRUE(hi.evaluate(curvesOf(guides, 0.01, 0.005, 41), {}, rest).ok());
  ASSERT_TRUE(hi.evaluate(curvesOf(guides, 0.01, 0.005, 41, motion), {}, moved).ok());
  double worst = 0;
  for (std::size_t k = 0; k < rest.points.size() / 3; ++k)
  {
    const Eigen::Vector3d a(rest.points[3 * k], rest.points[3 * k + 1], rest.points[3 * k + 2]);
    const Eigen::Vector3d b(moved.points[3 * k], moved.points[3 * k + 1], moved.points[3 * k + 2]);
    worst = std::max(worst, (motion * a - b).norm());
  }
  // Single-precision output of coordinates below 0.5 m: 3 × 6e-8 × 0.5.
  EXPECT_LT(worst, 1e-7);
  // The head's pose from the guides' roots and root frames (for the tables that move with
  // it): the motion, to round-off.
  const Eigen::Isometry3d fitted = hi.rootMotion(curvesOf(guides, 0.01, 0.005, 41, motion));
  EXPECT_LT((fitted.matrix() - motion.matrix()).norm(), 1e-12);
  // And the roots of the rendered strands are where the motion takes their rest roots.
  for (std::size_t r = 0; r < hi.strandCount(); ++r)
  {
    const Eigen::Vector3d x(moved.points[3 * r * 24], moved.points[3 * r * 24 + 1],
                            moved.points[3 * r * 24 + 2]);
    EXPECT_LT((x - motion * hi.bindings()[r].root).norm(), 1e-7);
  }
}

TEST(HairInterpolation, GuidesPartedOverARidgeAreNeverBridged)
{
  // Two groups of straight guides rooted along x, parted at x = 0 as hair over a ridge (or
  // a shoulder): the left group falls to −x, the right one to +x. Their tips are 0.42 m
  // apart where their roots are 1 cm apart. A rendered strand that interpolates across
  // the parting has its tip between them, near x = 0.
  std::vector<GuideStrand> guides;
  for (int i = 0; i < 10; ++i)
  {
    const double x = 0.01 * (i - 4.5);
    guides.push_back(guideAt(Eigen::Vector3d(x, 0, 0),
                             Eigen::Vector3d(x < 0 ? -0.7 : 0.7, -0.7, 0).normalized()));
  }
  GuideCurves straight;
  straight.offsets.push_back(0);
  for (const GuideStrand& g : guides)
  {
    for (int i = 0; i < 21; ++i)
    {
      straight.points.push_back(g.root + g.length * i / 20.0 * g.growth.normalized());
      straight.tangents.push_back(g.growth.normalized());
      straight.directors.push_back(g.rootFrame().col(1));
    }
    straight.offsets.push_back(straight.points.size());
  }
  auto bridged = [&](double tipDistance)
  {
    InterpolationOptions o;
    o.strands = 3000;
    o.tipDistance = tipDistance;
    o.clumpStart = o.clumpEnd = 1; // interpolated all along: the hardest case
    HairInterpolation hi;
    EXPECT_TRUE(hi.bind(guides, strip(-0.06, 0.06, -0.005, 0.005), o).ok());
    RenderedHair out;
    EXPECT_TRUE(hi.evaluate(straight, {}, out).ok());
    int count = 0;
    for (std::size_t r = 0; r < hi.strandCount(); ++r)
    {
      const std::size_t tip = (r * o.pointsPerStrand + o.pointsPerStrand - 1) * 3;
      // The guides' tips are at |x| ≥ 0.005 + 0.3 · 0.707 · 0.9 (the shortest strand).
      if (std::abs(out.points[tip]) < 0.1)
        ++count;
    }
    return count;
  };
  const int with = bridged(0.04), without = bridged(1e3);
  RecordProperty("bridging_strands_with_criterion", with);
  RecordProperty("bridging_strands_without_criterion", without);
  EXPECT_EQ(with, 0);
  EXPECT_GT(without, 30); // the strands rooted in the 1 cm gap between the groups
}

TEST(HairInterpolation, CurlyRenderedHairIsAsCurlyAsItsGuides)
{
  // Curly helices (the curly preset's radius 6 mm and step 5 mm), in phase as grown, 1 cm
  // apart (offsets up to 1.7 times the helix radius): rendered strands keep their
  // curvature within 10 % (the criterion).
  std::vector<GuideStrand> guides = row(9, 0.01, Eigen::Vector3d(0, -1, 0));
  for (GuideStrand& g : guides)
    g.hair = HairParameters::preset(HairType::Curly);
  const GuideCurves curves = curvesOf(guides, 0.006, 0.005, 601);
  InterpolationOptions o;
  o.strands = 400;
  o.pointsPerStrand = 400;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, strip(-0.04, 0.04, -0.005, 0.005), o).ok());
  RenderedHair out;
  ASSERT_TRUE(hi.evaluate(curves, {}, out).ok());
  double rendered = 0;
  for (std::size_t r = 0; r < hi.strandCount(); ++r)
    rendered += meanCurvature(&out.points[r * 400 * 3], 400);
  rendered /= hi.strandCount();
  const double c = 0.005 / (2 * M_PI), guide = 0.006 / (0.006 * 0.006 + c * c);
  RecordProperty("rendered_mean_curvature", std::to_string(rendered));
  EXPECT_NEAR(rendered / guide, 1, 0.10) << rendered << " against " << guide;
}

TEST(HairInterpolation, PointsInsideTheBodyArePushedOut)
{
  // A sphere of 5 cm about (0, −0.1, 0) under the strip: guides falling straight through
  // it; every rendered point that enters it is moved to its surface.
  const hairtest::Ellipsoid sphere(Eigen::Vector3d(0, -0.12, 0), Eigen::Vector3d(0.05, 0.05, 0.05));
  TableSpec spec;
  spec.projection = Projection::Spherical;
  spec.frame.origin = sphere.centre;
  CollisionTable table;
  ASSERT_TRUE(table.build(spec, sphere).ok());
  std::vector<PosedPart> parts{PosedPart::still(table)};
  const std::vector<GuideStrand> guides = row(9, 0.01, Eigen::Vector3d(0, -1, 0));
  InterpolationOptions o;
  o.strands = 1000;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o).ok());
  RenderedHair out;
  ASSERT_TRUE(hi.evaluate(curvesOf(guides, 0, 0.005, 31), parts, out).ok());
  EXPECT_GT(out.pushedOut, 1000);
  EXPECT_GT(out.deepest, 0.02);
  EXPECT_EQ(out.stillInside, 0);
  for (std::size_t k = 0; k < out.points.size() / 3; ++k)
  {
    const Eigen::Vector3d x(out.points[3 * k], out.points[3 * k + 1], out.points[3 * k + 2]);
    double depth = 0;
    EXPECT_FALSE(insideDepth(parts, x, depth) && depth > 1e-6) << k;
  }
}

TEST(HairInterpolation, TheSameHairOnAnyNumberOfThreads)
{
  const std::vector<GuideStrand> guides = row(9, 0.01, Eigen::Vector3d(0, -1, 0));
  const GuideCurves curves = curvesOf(guides, 0.01, 0.005, 41);
  RenderedHair out[2];
  for (int t = 0; t < 2; ++t)
  {
    InterpolationOptions o;
    o.strands = 20000;
    o.threads = t + 1;
    HairInterpolation hi;
    ASSERT_TRUE(hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o).ok());
    ASSERT_TRUE(hi.evaluate(curves, {}, out[t]).ok());
  }
  EXPECT_EQ(out[0].points, out[1].points);
  EXPECT_EQ(out[0].tangents, out[1].tangents);
}

TEST(HairInterpolation, BadOptionsAndMismatchedGuidesAreRefused)
{
  const std::vector<GuideStrand> guides = row(3, 0.01, Eigen::Vector3d(0, -1, 0));
  InterpolationOptions o;
  o.strands = 0;
  HairInterpolation hi;
  Status s = hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("rendered strands"), std::string::npos) << s.message();
  o = InterpolationOptions{};
  o.tipDistance = std::nan("");
  EXPECT_FALSE(hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o).ok());
  o = InterpolationOptions{};
  s = hi.bind(guides, strip(5, 6, 5, 6), o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("near the guides"), std::string::npos) << s.message();
  o.strands = 10;
  ASSERT_TRUE(hi.bind(guides, strip(-0.05, 0.05, -0.01, 0.01), o).ok());
  RenderedHair out;
  s = hi.evaluate(curvesOf(row(4, 0.01, Eigen::Vector3d(0, -1, 0)), 0, 0.005, 11), {}, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("bound to 3 guides"), std::string::npos) << s.message();
}

TEST(HairInterpolation, RenderedHairFollowsTheDemoGuidesWithoutJumps)
{
  // The demo's Super-Helix run (200 wavy guides on the bundled body, head shaking ±0.5 rad at
  // 1 Hz, wind, head and trunk tables; Testing/Fixtures/DemoScene), 5 s, 10 000 rendered
  // strands. Between two frames no rendered point may move farther than the guides it
  // follows can carry it: the largest motion of their points plus their largest offset
  // times the largest turn of their frames, plus the push-outs of both frames. Per frame,
  // the points pushed out and how deep they were, and whether any is left inside.
  BundledBody body;
  ASSERT_TRUE(loadBundledBody(HAIR_DATA_DIR, body).ok());
  std::vector<GuideStrand> guides;
  ASSERT_TRUE(demoGuides(body, 200, 10, guides).ok());
  const Scene scene = demoScene(body);
  Simulation sim;
  SimulationOptions options;
  options.threads = 2;
  ASSERT_TRUE(sim.initialize(guides, scene, options).ok());
  ASSERT_TRUE(sim.advanceTo(151).ok());

  InterpolationOptions o;
  o.strands = 10000;
  o.threads = 2;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, body.mesh, o).ok());
  auto curvesAt = [&](int f)
  {
    const StateFrame& frame = sim.frame(f);
    GuideCurves c;
    c.points = frame.positions;
    for (std::int64_t off : sim.header().offsets)
      c.offsets.push_back(std::size_t(off));
    return c; // tangents from the points, frames carried along them
  };
  RenderedHair previous;
  GuideCurves previousCurves;
  double worstRatio = 0, pushedMax = 0, deepestMax = 0, deepestAfter = 0, insideMax = 0;
  long leftInside = 0;
  std::vector<PosedPart> parts;
  for (int f = 1; f <= 150; ++f)
  {
    GuideCurves c = curvesAt(f);
    scene.posedParts(sim.frame(f).time, parts);
    RenderedHair now;
    ASSERT_TRUE(hi.evaluate(c, parts, now).ok());
    pushedMax = std::max(pushedMax, double(now.pushedOut) / (now.points.size() / 3));
    deepestMax = std::max(deepestMax, now.deepest);
    leftInside += now.stillInside;
    deepestAfter = std::max(deepestAfter, now.deepestAfter);
    insideMax = std::max(insideMax, double(now.stillInside) / (now.points.size() / 3));
    if (f > 1)
    {
      // Per guide: the largest motion of its points between the frames.
      std::vector<double> guideMotion(guides.size(), 0);
      for (std::size_t g = 0; g < guides.size(); ++g)
        for (std::size_t k = c.offsets[g]; k < c.offsets[g + 1]; ++k)
          guideMotion[g] =
              std::max(guideMotion[g], (c.points[k] - previousCurves.points[k]).norm());
      const double allowance = now.deepest + previous.deepest + 2e-5;
      for (std::size_t r = 0; r < hi.strandCount(); ++r)
      {
        const HairInterpolation::Binding& b = hi.bindings()[r];
        double bound = 0, offset = 0;
        for (int i = 0; i < b.count; ++i)
        {
          bound = std::max(bound, guideMotion[b.guides[i]]);
          offset = std::max(offset, b.offsets[i].norm());
        }
        // Frames turn by at most about (guide motion)/(distance between neighbour points)
        // per frame; 2 × offset is the most an offset can swing.
        bound += 2 * offset;
        for (int j = 0; j < o.pointsPerStrand; ++j)
        {
          const std::size_t k = (r * o.pointsPerStrand + j) * 3;
          const Eigen::Vector3f step(now.points[k] - previous.points[k],
                                     now.points[k + 1] - previous.points[k + 1],
                                     now.points[k + 2] - previous.points[k + 2]);
          worstRatio = std::max(worstRatio, step.norm() / (bound + allowance));
        }
      }
    }
    previous = std::move(now);
    previousCurves = std::move(c);
  }
  RecordProperty("worst_step_over_bound", std::to_string(worstRatio));
  RecordProperty("largest_share_pushed_out", std::to_string(pushedMax));
  RecordProperty("deepest_before_push_out_mm", std::to_string(1000 * deepestMax));
  RecordProperty("points_left_inside", std::to_string(leftInside));
  RecordProperty("deepest_after_push_out_mm", std::to_string(1000 * deepestAfter));
  std::cout << "worst step / bound " << worstRatio << "; before the push-out at most "
            << 100 * pushedMax << " % of the points inside, " << 1000 * deepestMax
            << " mm deep; after it at most " << 100 * insideMax << " %, " << 1000 * deepestAfter
            << " mm deep (" << leftInside << " points over 150 frames)\n";
  EXPECT_LE(worstRatio, 1.0);
  // What the push-out leaves: points moved from one table into the other where head and
  // trunk overlap at the neck, after eight passes. At most 0.1 % of the points, within the
  // tables' own error of the bundled body (head 4.7 mm, trunk 8.5 mm, docs/collision-tables.md).
  EXPECT_LE(insideMax, 1e-3);
  EXPECT_LE(deepestAfter, 0.0085);
}

TEST(HairInterpolation, CurlyHairKeepsItsCurlThroughTheShake)
{
  // The demo's curly run (curly Super-Helix guides combed on the bundled body, head shaking
  // ±0.5 rad at 1 Hz, wind, head and trunk tables), the guides drawn as Hair Simulation
  // draws them (16 points per element, material frames): at rest and through the shake,
  // the rendered strands' mean curvature stays within 10 % of their guides' (the issue's
  // criterion). The frame that carries the offsets once followed the curl within half a turn
  // of the root and the tip, where its averaging window was cut short: the ends were half as
  // curly again as their guides, the whole strand 8 % at rest and 13 % at 2.25 s.
  BundledBody body;
  ASSERT_TRUE(loadBundledBody(HAIR_DATA_DIR, body).ok());
  std::vector<GuideStrand> guides;
  ASSERT_TRUE(demoGuides(body, 60, 10, guides).ok());
  for (GuideStrand& g : guides)
    g.hair = HairParameters::preset(HairType::Curly);
  const Scene scene = demoScene(body);
  Simulation sim;
  SimulationOptions options;
  options.threads = 2;
  ASSERT_TRUE(sim.initialize(guides, scene, options).ok());
  ASSERT_TRUE(sim.advanceTo(68).ok());

  InterpolationOptions o;
  o.strands = 1000;
  o.pointsPerStrand = 161;
  o.variation = 0;
  o.threads = 2;
  HairInterpolation hi;
  ASSERT_TRUE(hi.bind(guides, body.mesh, o).ok());
  double worst = 0;
  for (const int f : {0, 15, 30, 38, 45, 53, 60, 67})
  {
    GuideCurves c;
    ASSERT_TRUE(drawnCurves(sim, f, 16, {}, c).ok());
    double guide = 0;
    std::vector<float> xyz;
    for (std::size_t g = 0; g + 1 < c.offsets.size(); ++g)
    {
      xyz.clear();
      for (std::size_t i = c.offsets[g]; i < c.offsets[g + 1]; ++i)
        for (int a = 0; a < 3; ++a)
          xyz.push_back(float(c.points[i][a]));
      guide += meanCurvature(xyz.data(), int(c.offsets[g + 1] - c.offsets[g]));
    }
    guide /= double(c.offsets.size() - 1);
    RenderedHair out;
    ASSERT_TRUE(hi.evaluate(c, {}, out).ok());
    double rendered = 0;
    for (std::size_t r = 0; r < hi.strandCount(); ++r)
      rendered += meanCurvature(&out.points[r * 161 * 3], 161);
    rendered /= double(hi.strandCount());
    std::printf("t = %.2f s: guides %.1f 1/m, rendered %.1f 1/m, ratio %.3f\n", sim.frame(f).time,
                guide, rendered, rendered / guide);
    worst = std::max(worst, std::abs(rendered / guide - 1));
  }
  RecordProperty("worst_curvature_ratio_error", std::to_string(worst));
  EXPECT_LT(worst, 0.10);
}
