// The guides as the filters draw them (simulation/GuideDrawing.h): the Super-Helix drawn from
// q and its root at any number of points per element lies on the rod SuperHelix reconstructs
// (positions, velocities, frames); the material frame at every strand's root is the guide's
// rest root frame turned by the head's motion, for both models, at rest and during a shake;
// a version 3 state file (states and nodes) redraws its frames at any resolution as the run
// draws them, for both models, and a file without root poses reads at its stored points.
#include "helix/Centerline.h"
#include "io/StateFormat.h"
#include "model/StrandPoints.h"
#include "simulation/GuideDrawing.h"
#include "simulation/Simulation.h"
#include "strands/StrandParameters.h"

#include "HeadShake.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

using namespace hair;

namespace
{
std::string figure(double x)
{
  std::ostringstream s;
  s << std::setprecision(3) << x;
  return s.str();
}

std::string temp(const char* name)
{
  return ::testing::TempDir() + "/" + name;
}

/// Guides of the curly preset on a ring of roots, growing outwards and down, their scalp
/// normals not perpendicular to the growth (so that rootFrame() makes n1 from them).
std::vector<GuideStrand> ringGuides(int count, int elements)
{
  std::vector<GuideStrand> g(count);
  for (int k = 0; k < count; ++k)
  {
    const double a = 2 * M_PI * k / count;
    const Eigen::Vector3d out(std::cos(a), 0, std::sin(a));
    g[k].root = Eigen::Vector3d(0, 1.6, 0.02) + 0.09 * out;
    g[k].growth = (out - 0.4 * Eigen::Vector3d::UnitY()).normalized();
    g[k].normal = (out + 0.3 * Eigen::Vector3d::UnitY()).normalized();
    g[k].length = 0.3;
    g[k].elements = elements;
    g[k].hair = HairParameters::preset(HairType::Curly);
    g[k].seed = 7;
  }
  return g;
}

Scene shakeScene(bool moving)
{
  Scene scene;
  if (moving)
  {
    // The filter's default shake (0.5 rad at 1 Hz about the neck), with a fade-in.
    scene.rootMotion =
        RigidMotion::shake(Eigen::Vector3d(0, 1.45, 0.02), Eigen::Vector3d::UnitY(), 0.5, 1.0);
    scene.rootMotion.during(0).fading(0.2);
  }
  return scene;
}

/// max over strands of |(Tangent, Director1, Tangent × Director1) at the root − R(t)
/// rootFrame()|, largest matrix entry.
double rootFrameDeviation(const GuideDrawing& d, const std::vector<GuideStrand>& guides,
                          const RigidMotion& motion, double t)
{
  double worst = 0;
  const Eigen::Matrix3d rotation = motion.pose(t).linear();
  for (std::size_t k = 0; k < guides.size(); ++k)
  {
    const std::size_t i = d.header.offsets[k];
    Eigen::Matrix3d m;
    m << d.tangents[i], d.directors[i], d.tangents[i].cross(d.directors[i]);
    worst = std::max(worst, (m - rotation * guides[k].rootFrame()).cwiseAbs().maxCoeff());
  }
  return worst;
}

/// Every point's tangent and director unit and orthogonal, to `tol`.
void expectOrthonormal(const GuideDrawing& d, double tol)
{
  ASSERT_EQ(d.tangents.size(), d.frame.positions.size());
  ASSERT_EQ(d.directors.size(), d.frame.positions.size());
  for (std::size_t i = 0; i < d.tangents.size(); ++i)
  {
    EXPECT_NEAR(d.tangents[i].norm(), 1, tol);
    EXPECT_NEAR(d.directors[i].norm(), 1, tol);
    EXPECT_NEAR(d.tangents[i].dot(d.directors[i]), 0, tol);
  }
}

class FrameContract : public ::testing::TestWithParam<ModelType>
{
};
} // namespace

TEST(DrawSuperHelix, PointsVelocitiesAndFramesLieOnTheRodAtAnyResolution)
{
  // A curly strand shaken at 3 Hz for 10 steps: q̇ and the root's rates are far from zero.
  SuperHelix h;
  ASSERT_TRUE(h.initialize(shakenStrand(HairType::Curly, 10)).ok());
  for (int i = 0; i < 10; ++i)
  {
    ASSERT_TRUE(h.step(1.0 / 30).ok());
  }
  ASSERT_GT(h.qdot().norm(), 1.0);
  const RootState root = h.rootState(h.time());
  double dx = 0, dv = 0, df = 0;
  for (int per : {1, 3, 4, 8, 16, 33})
  {
    StrandPoints p;
    drawSuperHelix(h.spec().elementLengths, h.q().data(), h.qdot().data(), root, per, p);
    ASSERT_EQ(p.positions.size(), std::size_t(10 * per + 1));
    double s0 = 0;
    for (int e = 0; e < 10; ++e)
    {
      const double l = h.spec().elementLengths[e];
      for (int j = 0; j <= per; ++j)
      {
        if (j == per && e + 1 < 10)
        {
          break; // the next element's first point
        }
        const std::size_t i = std::size_t(e) * per + j;
        const double s = s0 + l * j / per;
        const Eigen::Matrix3d frame = h.frame(s);
        dx = std::max(dx, (p.positions[i] - h.position(s)).norm());
        dv = std::max(dv, (p.velocities[i] - h.velocity(s)).norm() / h.velocity(s).norm());
        df = std::max(df, (p.tangents[i] - frame.col(0)).norm());
        df = std::max(df, (p.directors[i] - frame.col(1)).norm());
        EXPECT_EQ(p.curvature[i], std::hypot(h.q()[3 * e + 1], h.q()[3 * e + 2]));
        EXPECT_EQ(p.twist[i], h.q()[3 * e]);
      }
      s0 += l;
    }
  }
  // Round-off of a 30 cm strand chained over 10 elements (2⁻⁵² ≈ 2.2e-16).
  EXPECT_LT(dx, 1e-14);
  EXPECT_LT(dv, 1e-13);
  EXPECT_LT(df, 1e-13);
  RecordProperty("largest_position_difference_m", figure(dx));
  RecordProperty("largest_relative_velocity_difference", figure(dv));
  RecordProperty("largest_frame_difference", figure(df));
}

TEST_P(FrameContract, RootFrameIsTheRestFrameTurnedByTheHead)
{
  for (bool moving : {false, true})
  {
    const std::vector<GuideStrand> g = ringGuides(8, 10);
    const Scene scene = shakeScene(moving);
    SimulationOptions o;
    o.model = GetParam();
    Simulation sim;
    ASSERT_TRUE(sim.initialize(g, scene, o).ok());
    ASSERT_TRUE(sim.advanceTo(16).ok()); // 0.5 s: the head turns by up to 0.5 rad
    double worst = 0, worstAtRest = 0;
    for (int f = 0; f < sim.numberOfFrames(); ++f)
    {
      GuideDrawing d;
      ASSERT_TRUE(drawGuides(sim.header(), sim.frame(f), 0, 1, d).ok());
      ASSERT_TRUE(d.warning.empty()) << d.warning;
      expectOrthonormal(d, 1e-13);
      const double dev = rootFrameDeviation(d, g, scene.rootMotion, sim.frame(f).time);
      worst = std::max(worst, dev);
      if (f == 0)
      {
        worstAtRest = dev;
      }
    }
    // Round-off: the projective root frame is made from the first segment's end point minus
    // the root, 3 cm against 1.6 m (2⁻⁵² · 1.6 / 0.03 ≈ 1.2e-14).
    EXPECT_LT(worst, 5e-14) << (moving ? "shake" : "still");
    EXPECT_LT(worstAtRest, 5e-14);
    RecordProperty(std::string(moving ? "shake" : "still") + "_largest_root_frame_deviation",
                   figure(worst));
    if (moving)
    {
      // The shake turns the roots: the contract is not met by the rest frame alone.
      GuideDrawing d;
      ASSERT_TRUE(drawGuides(sim.header(), sim.frame(8), 0, 1, d).ok());
      EXPECT_GT(rootFrameDeviation(d, g, RigidMotion::still(), 0), 0.1);
    }
  }
}

TEST_P(FrameContract, TangentsFollowThePoints)
{
  // The tangent at a point is the strand's direction there: for the projective model exactly
  // its segment's (node i + 1: the segment from i to i + 1), for the Super-Helix the chord's
  // direction to within the chord's turning (16 points per element: ≤ 0.1 rad here).
  const std::vector<GuideStrand> g = ringGuides(4, 10);
  SimulationOptions o;
  o.model = GetParam();
  Simulation sim;
  ASSERT_TRUE(sim.initialize(g, shakeScene(true), o).ok());
  ASSERT_TRUE(sim.advanceTo(10).ok());
  GuideDrawing d;
  ASSERT_TRUE(sim.drawFrame(9, 16, d).ok());
  const double tol = GetParam() == ModelType::Projective ? 1e-12 : 0.1;
  for (std::size_t k = 0; k < g.size(); ++k)
  {
    for (std::int64_t i = d.header.offsets[k]; i + 1 < d.header.offsets[k + 1]; ++i)
    {
      const Eigen::Vector3d chord = (d.frame.positions[i + 1] - d.frame.positions[i]).normalized();
      const Eigen::Vector3d mid = (d.tangents[i] + d.tangents[i + 1]).normalized();
      const Eigen::Vector3d t = GetParam() == ModelType::Projective ? d.tangents[i + 1] : mid;
      EXPECT_LT((chord - t).norm(), tol) << "strand " << k << " point " << i;
    }
  }
}

TEST_P(FrameContract, AVersion3FileDrawsAsTheRunDraws)
{
  // The file keeps states (q, q̇, the roots) and the nodes; read back and drawn at any
  // resolution it gives the run's own drawing bit for bit (the same numbers through the
  // same code), and its nodes are the run's to single precision (the Super-Helix's are a
  // view in float32: 2⁻²⁴ relative, 0.1 µm at 2 m) or exactly (the projective model's).
  const ModelType model = GetParam();
  const bool superHelix = model == ModelType::SuperHelix;
  const std::vector<GuideStrand> g = ringGuides(6, 10);
  const std::string path = temp(superHelix ? "v3-super-helix.h5" : "v3-projective.h5");
  SimulationOptions o;
  o.model = model;
  StorageOptions storage;
  storage.stateFile = path;
  storage.replaceStateFile = true;
  Simulation run;
  ASSERT_TRUE(run.initialize(g, shakeScene(true), o, storage).ok());
  ASSERT_TRUE(run.advanceTo(12).ok());

  StateFileReader file;
  ASSERT_TRUE(file.open(path).ok());
  EXPECT_EQ(file.version(), stateformat::Version);
  const StateHeader& h = file.header();
  EXPECT_TRUE(h.rootFrames);
  EXPECT_EQ(h.singlePrecisionPoints, superHelix);
  EXPECT_EQ(h.offsets, run.header().offsets);
  EXPECT_EQ(h.pointData, std::vector<std::string>{"contact_depth"});
  // The model's nodes, not display points: element ends, segment ends.
  const std::int64_t nodes = superHelix ? 11 : h.coordinatesPerStrand / 2 + 1;
  EXPECT_EQ(h.offsets[1], nodes);
  // The guides as grown, so that a study can run them again from the file.
  for (const StrandVector& v : strandVectors())
  {
    ASSERT_TRUE(h.strandVectors.count(v.file)) << v.file;
    for (std::size_t k = 0; k < g.size(); ++k)
    {
      EXPECT_EQ(h.strandVectors.at(v.file)[k], v.get(g[k])) << v.file;
    }
  }
  double nodeError = 0;
  for (int f = 0; f < 12; ++f)
  {
    StateFrame stored;
    ASSERT_TRUE(file.readFrame(f, stored).ok());
    const StateFrame& own = run.frame(f);
    EXPECT_EQ(stored.q, own.q);
    EXPECT_EQ(stored.qdot, own.qdot);
    EXPECT_EQ(stored.rootFrames, own.rootFrames);
    EXPECT_EQ(stored.pointData.at("contact_depth"), own.pointData.at("contact_depth"));
    for (std::size_t i = 0; i < own.positions.size(); ++i)
    {
      const double scale = std::max(1.0, own.positions[i].norm());
      nodeError = std::max(nodeError, (stored.positions[i] - own.positions[i]).norm() / scale);
    }
    for (int per : {1, 4, 16})
    {
      GuideDrawing fromFile, fromRun;
      ASSERT_TRUE(drawGuides(h, stored, per, 2, fromFile).ok());
      ASSERT_TRUE(run.drawFrame(f, per, fromRun).ok());
      EXPECT_TRUE(fromFile.warning.empty()) << fromFile.warning;
      const std::size_t points = g.size() * std::size_t(superHelix ? 10 * per + 1 : nodes);
      ASSERT_EQ(fromFile.frame.positions.size(), points);
      ASSERT_EQ(fromFile.header.offsets, fromRun.header.offsets);
      if (superHelix)
      {
        ASSERT_EQ(fromFile.frame.positions, fromRun.frame.positions) << "frame " << f;
        ASSERT_EQ(fromFile.frame.velocities, fromRun.frame.velocities) << "frame " << f;
      }
      else
      {
        // Drawn at the stored nodes: float64 in the file.
        ASSERT_EQ(fromFile.frame.positions, own.positions);
        ASSERT_EQ(fromFile.frame.velocities, own.velocities);
      }
      ASSERT_EQ(fromFile.tangents, fromRun.tangents);
      ASSERT_EQ(fromFile.directors, fromRun.directors);
      for (const char* name : {"curvature", "twist", "contact_depth"})
      {
        ASSERT_EQ(fromFile.frame.pointData.at(name), fromRun.frame.pointData.at(name)) << name;
      }
    }
  }
  EXPECT_LE(nodeError, superHelix ? std::ldexp(1.0, -24) : 0.0);
  RecordProperty("largest_node_difference_file_run_relative", figure(nodeError));
  std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(BothModels, FrameContract,
                         ::testing::Values(ModelType::SuperHelix, ModelType::Projective),
                         [](const auto& info) {
                           return info.param == ModelType::SuperHelix ? "SuperHelix" : "Projective";
                         });

TEST(GuideDrawing, AFileWithoutRootPosesReadsAtItsStoredPoints)
{
  // A file as written before the root poses: header and frames without them.
  const std::vector<GuideStrand> g = ringGuides(3, 5);
  Simulation sim;
  ASSERT_TRUE(sim.initialize(g, shakeScene(true), SimulationOptions{}).ok());
  ASSERT_TRUE(sim.advanceTo(3).ok());
  StateHeader old = sim.header();
  old.rootFrames = false;
  old.singlePrecisionPoints = false;
  old.strandVectors.clear();
  const std::string path = temp("old.h5");
  {
    StateFileWriter w;
    ASSERT_TRUE(w.create(path, old, sim.extraEnergyTerms()).ok());
    for (int f = 0; f < 3; ++f)
    {
      StateFrame fr = sim.frame(f);
      fr.rootFrames.clear();
      fr.rootVelocities.clear();
      ASSERT_TRUE(w.append(fr).ok());
    }
  }
  StateFileReader file;
  ASSERT_TRUE(file.open(path).ok());
  EXPECT_FALSE(file.header().rootFrames);
  EXPECT_TRUE(file.header().strandVectors.empty());
  for (int f = 0; f < 3; ++f)
  {
    StateFrame stored;
    ASSERT_TRUE(file.readFrame(f, stored).ok());
    EXPECT_TRUE(stored.rootFrames.empty());
    GuideDrawing d;
    ASSERT_TRUE(drawGuides(file.header(), stored, 16, 1, d).ok());
    EXPECT_NE(d.warning.find("no root poses"), std::string::npos) << d.warning;
    EXPECT_EQ(d.frame.positions, sim.frame(f).positions); // 5 + 1 per strand, as stored
    EXPECT_EQ(d.header.offsets, sim.header().offsets);
    EXPECT_TRUE(d.tangents.empty());
  }
  std::remove(path.c_str());
}
