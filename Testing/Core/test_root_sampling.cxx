// Roots of guide strands: on the surface, in the region, evenly spread (against the
// spacing of a hexagonal packing, the densest arrangement of equal discs: Thue), seeded.
#include "AnalyticBodies.h"
#include "geometry/MeshIO.h"
#include "strands/BundledBody.h"
#include "strands/RootSampling.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace hair;

namespace
{
double minNeighbourDistance(const std::vector<Root>& roots)
{
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < roots.size(); ++i)
  {
    for (std::size_t j = i + 1; j < roots.size(); ++j)
    {
      best = std::min(best, (roots[i].position - roots[j].position).norm());
    }
  }
  return best;
}
} // namespace

TEST(RootSampling, OnTheSurfaceOutwardSeededAndEven)
{
  const double R = 0.1;
  const TriangleMesh sphere = hairtest::triangulatedSphere(Eigen::Vector3d(0, 1.5, 0), R, 5);
  RootSamplingOptions o;
  o.count = 300;
  o.seed = 42;
  std::vector<Root> roots, again, other;
  ASSERT_TRUE(sampleRoots(sphere, {}, o, roots).ok());
  ASSERT_TRUE(sampleRoots(sphere, {}, o, again).ok());
  o.seed = 43;
  ASSERT_TRUE(sampleRoots(sphere, {}, o, other).ok());
  ASSERT_EQ(roots.size(), 300u);
  for (std::size_t i = 0; i < roots.size(); ++i)
  {
    const Eigen::Vector3d radial = roots[i].position - Eigen::Vector3d(0, 1.5, 0);
    // On the faceted sphere: between the inscribed faces (gap < 1e-4 m here) and R.
    EXPECT_LE(radial.norm(), R + 1e-12);
    EXPECT_GE(radial.norm(), R - 1e-4);
    EXPECT_GT(roots[i].normal.dot(radial.normalized()), 0.999);
    EXPECT_EQ(roots[i].position, again[i].position); // same seed, same roots
  }
  EXPECT_NE(roots[5].position, other[5].position);

  // Hexagonal packing of N discs on an area A has spacing d = sqrt(2A / (√3 N)); no
  // arrangement does much better. Farthest-point selection must reach half of it (uniform
  // random roots get about a tenth: the nearest pair of N random points is O(1/N) apart).
  const double area = 4 * M_PI * R * R;
  const double hex = std::sqrt(2 * area / (std::sqrt(3.0) * o.count));
  const double d = minNeighbourDistance(roots);
  std::printf("300 roots on a sphere: nearest pair %.4f m = %.2f of the hexagonal spacing\n", d,
              d / hex);
  EXPECT_GE(d, 0.5 * hex);
  EXPECT_LE(d, 1.1 * hex);
  o.candidatesPerRoot = 1; // no selection: uniform random roots
  std::vector<Root> random;
  ASSERT_TRUE(sampleRoots(sphere, {}, o, random).ok());
  EXPECT_LT(minNeighbourDistance(random), 0.5 * hex);
}

TEST(RootSampling, BundledScalpIsAboveTheEarsAndBehindTheHairline)
{
  TriangleMesh body;
  ASSERT_TRUE(readVtkPolyData(std::string(HAIR_DATA_DIR) + "/body.vtk", body).ok());
  const auto scalp = bundled::scalp(body);
  RootSamplingOptions o;
  o.count = 500;
  std::vector<Root> roots;
  ASSERT_TRUE(sampleRoots(body, scalp, o, roots).ok());
  for (const Root& r : roots)
  {
    EXPECT_TRUE(scalp[r.triangle]);
    EXPECT_GT(r.position.y(), 1.47); // the nape's hairline is at about 1.49 m
    // The face (front of the head below the hairline, y < 1.6) has no roots.
    EXPECT_FALSE(r.position.z() > 0.12 && r.position.y() < 1.60) << r.position.transpose();
    // Normals point away from the head's centre.
    EXPECT_GT(r.normal.dot(r.position - Eigen::Vector3d(0, 1.555, 0.055)), 0);
  }
}

TEST(RootSampling, BadInputIsRefused)
{
  const TriangleMesh sphere = hairtest::triangulatedSphere(Eigen::Vector3d::Zero(), 1, 2);
  std::vector<Root> roots;
  RootSamplingOptions o;
  o.count = 0;
  EXPECT_NE(sampleRoots(sphere, {}, o, roots).message().find("give 1 to 100000"),
            std::string::npos);
  // More than the quadratic spreading can do in reasonable time: refused at once.
  o.count = 10000000;
  EXPECT_NE(sampleRoots(sphere, {}, o, roots).message().find("give 1 to 100000"),
            std::string::npos);
  o.count = 10;
  std::vector<std::uint8_t> none(sphere.triangles.size(), 0);
  EXPECT_NE(sampleRoots(sphere, none, o, roots).message().find("region is empty"),
            std::string::npos);
  std::vector<std::uint8_t> wrongSize(3, 1);
  EXPECT_FALSE(sampleRoots(sphere, wrongSize, o, roots).ok());
  TriangleMesh empty;
  EXPECT_FALSE(sampleRoots(empty, {}, o, roots).ok());
  EXPECT_TRUE(roots.empty());
}
