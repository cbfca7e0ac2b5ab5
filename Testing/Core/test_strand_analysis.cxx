// The measurements of Hair Analysis on hand-built strands whose answers are known exactly
// from geometry (docs/hair-analysis.md gives the definitions). Tolerances: values of order
// 1 m that go through a projection and a square root carry a few rounding errors of
// 2.2e-16 each; 1e-14 allows for them and nothing more.
#include "analysis/StrandAnalysis.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace hair;

namespace
{
constexpr double Rounding = 1e-14; // see the header comment

/// Appends a straight strand of `n` points from `root` to `tip`, with the given curvature,
/// twist and contact depth at every point.
void addStrand(StrandsFrame& f, const Eigen::Vector3d& root, const Eigen::Vector3d& tip, int n,
               double curvature = 0, double twist = 0, double depth = 0)
{
  if (f.offsets.empty())
  {
    f.offsets.push_back(0);
  }
  for (int i = 0; i < n; ++i)
  {
    f.positions.push_back(root + (tip - root) * (double(i) / (n - 1)));
    f.curvature.push_back(curvature);
    f.twist.push_back(twist);
    f.contactDepth.push_back(depth);
  }
  f.offsets.push_back(f.offsets.back() + n);
}

/// The definition, pair by pair: the reference for the convex-hull version.
double bruteForceDiameter(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& vertical)
{
  const Eigen::Vector3d up = vertical.normalized();
  double widest = 0;
  for (std::size_t a = 0; a < p.size(); ++a)
  {
    for (std::size_t b = a + 1; b < p.size(); ++b)
    {
      const Eigen::Vector3d d = (p[a] - p[a].dot(up) * up) - (p[b] - p[b].dot(up) * up);
      widest = std::max(widest, d.norm());
    }
  }
  return widest;
}
} // namespace

TEST(HorizontalDiameter, SquareSeenFromAboveIsItsDiagonal)
{
  // Corners of a 1 m square in the x-z plane at different heights (y): the heights do not
  // count, the diagonal is √2 m.
  const std::vector<Eigen::Vector3d> tips = {
      {0.5, 0.1, 0.5}, {-0.5, -0.7, 0.5}, {-0.5, 0.3, -0.5}, {0.5, 2.0, -0.5}};
  EXPECT_DOUBLE_EQ(horizontalDiameter(tips, {0, 1, 0}), std::sqrt(2.0));
  // Seen along x instead, the same points span 2.7 m in y by 1 m in z.
  EXPECT_NEAR(horizontalDiameter(tips, {1, 0, 0}), std::hypot(2.7, 1.0), Rounding);
}

TEST(HorizontalDiameter, RegularHexagonUnderATiltedVerticalIsTwiceItsRadius)
{
  // A hexagon of radius 0.2 m in the plane perpendicular to a tilted vertical, each vertex
  // lifted along the vertical by a different amount, plus points inside it.
  const Eigen::Vector3d up = Eigen::Vector3d(0.3, 1.0, -0.4).normalized();
  const Eigen::Vector3d e1 = up.unitOrthogonal(), e2 = up.cross(e1);
  const double r = 0.2;
  std::vector<Eigen::Vector3d> tips;
  for (int i = 0; i < 6; ++i)
  {
    const double a = M_PI / 3 * i;
    tips.push_back(r * (std::cos(a) * e1 + std::sin(a) * e2) + 0.1 * i * up);
  }
  tips.push_back(0.5 * r * e1 - 3.0 * up);
  tips.push_back(0.3 * r * e2 + 1.0 * up);
  EXPECT_NEAR(horizontalDiameter(tips, 5.0 * up), 2 * r, Rounding);
}

TEST(HorizontalDiameter, DegenerateGroups)
{
  EXPECT_EQ(horizontalDiameter({}, {0, 1, 0}), 0.0);
  EXPECT_EQ(horizontalDiameter({{1, 2, 3}}, {0, 1, 0}), 0.0);
  // Tips on one vertical: no width.
  EXPECT_EQ(horizontalDiameter({{1, 2, 3}, {1, -5, 3}, {1, 0, 3}}, {0, 1, 0}), 0.0);
  // Collinear tips: the two ends.
  EXPECT_DOUBLE_EQ(
      horizontalDiameter({{0, 0, 0}, {3, 1, 4}, {1.5, 9, 2}, {0.6, 0, 0.8}}, {0, 1, 0}), 5.0);
  // Repeated tips.
  EXPECT_DOUBLE_EQ(horizontalDiameter({{0, 0, 0}, {0, 0, 0}, {3, 0, 4}, {3, 1, 4}}, {0, 1, 0}),
                   5.0);
}

TEST(HorizontalDiameter, EqualsThePairByPairDefinitionOnRandomClouds)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 0.1);
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<Eigen::Vector3d> tips(2 + trial % 40);
    for (auto& p : tips)
    {
      p = {g(rng), g(rng), g(rng)};
    }
    if (trial % 3 == 0) // some on a grid, with repeated and collinear projections
    {
      for (auto& p : tips)
      {
        p = {std::round(p.x() * 20) / 20, p.y(), std::round(p.z() * 20) / 20};
      }
    }
    const Eigen::Vector3d up =
        trial % 2 ? Eigen::Vector3d(0, 1, 0) : Eigen::Vector3d(g(rng), 1, g(rng));
    // Both take the same projections' distances: equal to the last bits.
    EXPECT_DOUBLE_EQ(horizontalDiameter(tips, up), bruteForceDiameter(tips, up)) << trial;
  }
}

TEST(LateralDeflection, DistanceFromTheVerticalThroughTheRoot)
{
  const Eigen::Vector3d root(1, 2, 3);
  EXPECT_DOUBLE_EQ(lateralDeflection(root, root + Eigen::Vector3d(3, -7, 4), {0, 1, 0}), 5.0);
  EXPECT_DOUBLE_EQ(lateralDeflection(root, root + Eigen::Vector3d(3, -7, 4), {0, 0, -2}),
                   std::sqrt(58.0));
  EXPECT_EQ(lateralDeflection(root, root + Eigen::Vector3d(0, -0.3, 0), {0, 1, 0}), 0.0);
}

TEST(StrandAnalysis, MeasuresHandBuiltStrands)
{
  // Strand 0 hangs straight down 0.3 m; strand 1 sticks out horizontally 0.2 m along +x
  // with curvature 4 /m, twist −9 /m and two points 1 mm inside a body; strand 2 goes
  // down-and-sideways to (0, 1.2, 0.4) from (0, 1.5, 0).
  StrandsFrame f;
  addStrand(f, {0, 1.5, 0}, {0, 1.2, 0}, 5);
  addStrand(f, {0.1, 1.5, 0}, {0.3, 1.5, 0}, 4, 4.0, -9.0);
  f.contactDepth[f.offsets[1] + 1] = 1e-3;
  f.contactDepth[f.offsets[1] + 2] = 2e-3;
  addStrand(f, {0, 1.5, 0}, {0, 1.2, 0.4}, 6, 2.5, 3.0);
  StrandAnalysis analysis;
  StrandAnalysisOptions o;
  o.tracked = {2, 0};
  ASSERT_TRUE(analysis.configure(o));
  StrandMeasures m;
  const Status s = analysis.measure(f, m);
  ASSERT_TRUE(s) << s.message();
  EXPECT_NEAR(m.meanTip.x(), 0.3 / 3, Rounding);
  EXPECT_NEAR(m.meanTip.y(), (1.2 + 1.5 + 1.2) / 3, Rounding);
  EXPECT_NEAR(m.meanTip.z(), 0.4 / 3, Rounding);
  ASSERT_EQ(m.trackedTips.size(), 2u);
  EXPECT_EQ(m.trackedTips[0], Eigen::Vector3d(0, 1.2, 0.4));
  EXPECT_EQ(m.trackedTips[1], Eigen::Vector3d(0, 1.2, 0));
  // Tips seen from above: (0, 0), (0.3, 0), (0, 0.4): the widest pair is 0.5 m apart.
  EXPECT_NEAR(m.span, 0.5, Rounding);
  EXPECT_EQ(m.maxCurvature, 4.0);
  EXPECT_EQ(m.maxTwist, 9.0);
  // Deflections 0, 0.2 and 0.4 m.
  EXPECT_NEAR(m.maxDeflection, 0.4, Rounding);
  EXPECT_NEAR(m.meanDeflection, 0.6 / 3, Rounding);
  EXPECT_EQ(m.contacts, 2);
  EXPECT_EQ(m.maxContactDepth, 2e-3);
  // The first frame is the reference: nothing has moved yet.
  EXPECT_EQ(m.maxTipDisplacement, 0.0);
  EXPECT_EQ(m.meanTipDisplacement, 0.0);

  // Next frame: strand 0's tip moves by (0.03, 0, 0.04), 5 cm; the others stay.
  f.positions[f.offsets[1] - 1] += Eigen::Vector3d(0.03, 0, 0.04);
  ASSERT_TRUE(analysis.measure(f, m));
  EXPECT_NEAR(m.maxTipDisplacement, 0.05, Rounding);
  EXPECT_NEAR(m.meanTipDisplacement, 0.05 / 3, Rounding);
  EXPECT_NEAR(m.maxDeflection, 0.4, Rounding);
  EXPECT_NEAR(m.meanDeflection, (0.05 + 0.2 + 0.4) / 3, Rounding);

  // A group: strands 0 and 1 only, tips (0.03, ·, 0.04) and (0.3, ·, 0) from above.
  o.group = {0, 1};
  ASSERT_TRUE(analysis.configure(o));
  ASSERT_TRUE(analysis.measure(f, m));
  EXPECT_NEAR(m.span, std::hypot(0.27, 0.04), Rounding);
  // configure() forgot the reference: this frame is the new one.
  EXPECT_EQ(m.maxTipDisplacement, 0.0);
}

TEST(StrandAnalysis, RefusesWhatItCannotMeasure)
{
  StrandsFrame f;
  addStrand(f, {0, 0, 0}, {0, -1, 0}, 3);
  addStrand(f, {1, 0, 0}, {1, -1, 0}, 3);
  StrandAnalysis analysis;
  StrandMeasures m;
  StrandAnalysisOptions o;
  o.vertical = Eigen::Vector3d::Zero();
  Status s = analysis.configure(o);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message().find("vertical"), std::string::npos) << s.message();

  o = StrandAnalysisOptions();
  o.tracked = {-1};
  EXPECT_FALSE(analysis.configure(o));

  o.tracked = {5};
  ASSERT_TRUE(analysis.configure(o));
  s = analysis.measure(f, m);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message().find("strand 5 does not exist"), std::string::npos) << s.message();

  o.tracked = {};
  o.group = {0, 2};
  ASSERT_TRUE(analysis.configure(o));
  EXPECT_FALSE(analysis.measure(f, m));

  ASSERT_TRUE(analysis.configure(StrandAnalysisOptions()));
  StrandsFrame bad = f;
  bad.twist.pop_back();
  s = analysis.measure(bad, m);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message().find("twist"), std::string::npos) << s.message();

  bad = f;
  bad.positions[1].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(analysis.measure(bad, m));

  bad = f;
  bad.offsets = {0, 1, 6};
  s = analysis.measure(bad, m);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message().find("strand 0 has 1 points"), std::string::npos) << s.message();

  EXPECT_FALSE(analysis.measure(StrandsFrame(), m));

  // The strands must stay the same over time.
  ASSERT_TRUE(analysis.measure(f, m));
  StrandsFrame more = f;
  addStrand(more, {2, 0, 0}, {2, -1, 0}, 3);
  s = analysis.measure(more, m);
  EXPECT_FALSE(s);
  EXPECT_NE(s.message().find("the first frame had 2"), std::string::npos) << s.message();
  analysis.restart();
  EXPECT_TRUE(analysis.measure(more, m));
}
