// The Super-Helix's released strand against Discrete Elastic Rods: two discretizations of the
// same Kirchhoff rod (docs/super-helix.md, docs/discrete-elastic-rods.md) written apart, so
// that each is a reference for the other's dynamics. A straight round strand clamped
// horizontally at the origin, at rest, is released under gravity and swings down; its tip is
// compared over time. Each model is run at two resolutions in space and time: for a method
// in its asymptotic range the finer run's error is at most its distance from the coarser
// run's (order p ≥ 1: error(fine) ≈ |coarse − fine| / (2^p − 1)), so the two finer runs may
// differ by at most the sum of those two distances, and that is the tolerance.
#include "der/DerRod.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

using namespace hair;

namespace
{
constexpr double Length = 0.1;   ///< m: wL³/EI ≈ 20, a large swing
constexpr double Duration = 0.3; ///< s: the swing down and back up (period ≈ 0.2 s)
constexpr double Every = 0.005;  ///< s between compared samples

HairParameters hair()
{
  // The round straight fibre without internal friction or air drag: the two models define
  // their dissipations on different strains, so the comparison is of the conservative rod.
  HairParameters p = HairParameters::roundStraight();
  p.internalFriction = 0;
  p.airFriction = 0;
  return p;
}

using Tips = std::vector<Eigen::Vector3d>;

/// The Super-Helix of n elements, midpoint steps of h (second order).
Tips superHelix(int n, double h)
{
  StrandSpec spec = StrandSpec::uniform(Length, n, hair());
  spec.integrator = Integrator::Midpoint;
  SuperHelix strand;
  EXPECT_TRUE(strand.initialize(spec).ok());
  Tips tips{strand.position(Length)};
  const int per = static_cast<int>(std::lround(Every / h));
  for (int i = 1; i <= static_cast<int>(std::lround(Duration / Every)); ++i)
  {
    for (int k = 0; k < per; ++k)
    {
      const Status s = strand.step(h);
      EXPECT_TRUE(s.ok()) << s.message();
    }
    tips.push_back(strand.position(Length));
  }
  return tips;
}

/// The rod of n edges clamped as DerModel clamps a guide (the root at the first edge's
/// middle, the strand L long from it), backward Euler steps of h and of h/2 extrapolated
/// (Richardson: 2 x(h/2) − x(h), second order from a first-order method).
Tips rod(int n, double h)
{
  auto run = [n](double step)
  {
    const double edge = Length / (n - 0.5);
    DerSpec spec = DerSpec::uniform(edge * n, n, hair());
    RootState root;
    root.position = Eigen::Vector3d(-0.5 * edge, 0, 0);
    spec.root = [root](double) { return root; };
    DerRod strand;
    EXPECT_TRUE(strand.initialize(spec).ok());
    Tips tips{strand.position(n)};
    const int per = static_cast<int>(std::lround(Every / step));
    for (int i = 1; i <= static_cast<int>(std::lround(Duration / Every)); ++i)
    {
      for (int k = 0; k < per; ++k)
      {
        const Status s = strand.step(step);
        EXPECT_TRUE(s.ok()) << s.message();
      }
      tips.push_back(strand.position(n));
    }
    return tips;
  };
  const Tips coarse = run(h), fine = run(0.5 * h);
  Tips tips(coarse.size());
  for (std::size_t i = 0; i < tips.size(); ++i)
  {
    tips[i] = 2 * fine[i] - coarse[i];
  }
  return tips;
}

double largestDistance(const Tips& a, const Tips& b)
{
  double d = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
  {
    d = std::max(d, (a[i] - b[i]).norm());
  }
  return d;
}
} // namespace

TEST(DerAgainstSuperHelix, AReleasedStrandsTipFollowsTheSamePath)
{
  // Super-Helix: 10 and 20 elements at 1e-4 s, and 20 elements at 5e-5 s; rods: 20 and 40
  // edges at 5e-4 s (extrapolated with 2.5e-4 s), and 40 edges at 2.5e-4 s. (Measured: the
  // time steps' errors are 1e-6 and 1e-4 m, the elements' and edges' 1e-3 m.)
  const Tips sh10 = superHelix(10, 1e-4), sh20 = superHelix(20, 1e-4);
  const Tips sh20fine = superHelix(20, 5e-5);
  const Tips der20 = rod(20, 5e-4), der40 = rod(40, 5e-4), der40fine = rod(40, 2.5e-4);
  ASSERT_EQ(sh20.size(), der40.size());
  double travel = 0;
  for (const Eigen::Vector3d& tip : sh20)
  {
    travel = std::max(travel, (tip - sh20[0]).norm());
  }
  const double shError = largestDistance(sh10, sh20) + largestDistance(sh20, sh20fine);
  const double derError = largestDistance(der20, der40) + largestDistance(der40, der40fine);
  const double apart = largestDistance(sh20, der40);
  std::cout << "tip travel " << travel << " m; Super-Helix 10→20 elements "
            << largestDistance(sh10, sh20) << " m, dt halved " << largestDistance(sh20, sh20fine)
            << " m; rods 20→40 edges " << largestDistance(der20, der40) << " m, dt halved "
            << largestDistance(der40, der40fine) << " m; the two models apart " << apart << " m\n";
  RecordProperty("tip_travel_m", std::to_string(travel));
  RecordProperty("models_apart_m", std::to_string(apart));
  RecordProperty("superhelix_error_m", std::to_string(shError));
  RecordProperty("der_error_m", std::to_string(derError));
  // The swing is large: the tip travels more than a third of the strand.
  EXPECT_GT(travel, Length / 3);
  EXPECT_LE(apart, shError + derError);
}

TEST(DerAgainstSuperHelix, TheNaturalShapeIsTheSuperHelixsHelixAtSecondOrder)
{
  // A curly strand (no variation) grown in its natural shape by both models from the same
  // clamp: the Super-Helix's is the exact helix of its natural curvatures and twist (one
  // element, closed form); the rod's nodes, built by DerRod::naturalShape from its rest
  // strains, must lie on it up to the discretization's O(N⁻²), and the rod must start at rest
  // (its elastic energy a vanishing share of the helix's bending energy scale EI κ² L).
  HairParameters curly = HairParameters::preset(HairType::Curly);
  curly.curvatureVariation = 0;
  StrandSpec spec = StrandSpec::uniform(Length, 1, curly);
  SuperHelix helix;
  ASSERT_TRUE(helix.initialize(spec).ok());
  const double kappa = curly.naturalCurvature().tail<2>().norm();
  const double scale = curly.stiffness()[1] * kappa * kappa * Length;
  std::vector<double> errors;
  for (int n : {20, 40, 80})
  {
    const double edge = Length / (n - 0.5);
    DerSpec straight = DerSpec::uniform(edge * n, n, curly);
    RootState root;
    root.position = Eigen::Vector3d(-0.5 * edge, 0, 0);
    straight.root = [root](double) { return root; };
    DerRod rod;
    ASSERT_TRUE(rod.initialize(straight).ok());
    DerSpec natural = straight;
    rod.naturalShape(natural.initialNodes, natural.initialTwists);
    for (int i = 1; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        natural.restStrains.push_back(rod.restStrains(i)[c] / edge);
      }
    }
    ASSERT_TRUE(rod.initialize(natural).ok());
    double error = 0;
    for (int k = 1; k <= n; ++k)
    {
      error = std::max(error, (rod.position(k) - helix.position((k - 0.5) * edge)).norm());
    }
    errors.push_back(error);
    std::cout << "N = " << n << ": largest node distance from the helix " << error
              << " m, elastic energy " << rod.energy().elastic / scale << " EI κ² L\n";
    EXPECT_LT(rod.energy().elastic, 1e-3 * scale) << n;
  }
  const double order = std::log2(errors[1] / errors[2]);
  RecordProperty("natural_shape_order", std::to_string(order));
  EXPECT_GT(order, 1.8);
}
