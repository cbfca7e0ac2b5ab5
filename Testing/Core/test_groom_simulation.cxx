// Grooms through a whole run (simulation/Simulation.h): guide curves checked one by one
// (strands/GuideCurves.h), the projective model's chain along a curve, sag-free rest shapes
// of both models holding a groom on the bundled body, and the state file that records the
// groom and runs it again bit for bit.
#include "ProjectiveScenes.h"
#include "groom/CurveFit.h"
#include "io/StateFile.h"
#include "projective/ProjectiveGroom.h"
#include "simulation/GuidesFromState.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"
#include "strands/GuideCurves.h"
#include "strands/GuideGrowth.h"
#include "strands/RootSampling.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

using namespace hair;

namespace
{
std::string sci(double v)
{
  char b[32];
  std::snprintf(b, sizeof b, "%.3e", v);
  return b;
}

const double NaN = std::numeric_limits<double>::quiet_NaN();

const BundledBody& body()
{
  static BundledBody b;
  static Status st = loadBundledBody(HAIR_DATA_DIR, b);
  EXPECT_TRUE(st.ok()) << st.message();
  return b;
}

const MeshQueries& bodyMesh()
{
  static MeshQueries q(body().mesh);
  return q;
}

/// The head and trunk where their tables were built, still.
Scene stillScene()
{
  Scene s;
  s.parts = {body().parts[body().head], body().parts[body().trunk]};
  return s;
}

/// Straight horizontal (+x) guides of `length` from a root at the origin (no body).
GuideStrand horizontalGuide(double length, int n, HairType type)
{
  GuideStrand g;
  g.root = Eigen::Vector3d::Zero();
  g.growth = Eigen::Vector3d::UnitX();
  g.normal = Eigen::Vector3d::UnitY();
  g.length = length;
  g.elements = n;
  g.hair = HairParameters::preset(type);
  g.curve = {g.root, g.root + length * g.growth};
  g.restShape = RestShape::SagFree;
  return g;
}

/// Largest distance of each strand's points, over all frames, from where they are in frame 0.
std::vector<double> strandMotion(const Simulation& sim)
{
  const StateHeader& h = sim.header();
  std::vector<double> worst(h.numberOfStrands(), 0.0);
  StateFrame first, f;
  EXPECT_TRUE(sim.readFrame(0, first));
  for (int i = 1; i < sim.numberOfFrames(); ++i)
  {
    EXPECT_TRUE(sim.readFrame(i, f));
    for (std::size_t k = 0; k < worst.size(); ++k)
    {
      for (std::int64_t p = h.offsets[k]; p < h.offsets[k + 1]; ++p)
      {
        worst[k] = std::max(worst[k], (f.positions[p] - first.positions[p]).norm());
      }
    }
  }
  return worst;
}

/// Guides grown on the bundled scalp (seed 1), wavy, combed down, as the demo grows them.
std::vector<GuideStrand> scalpGuides(int count, int n, HairType type)
{
  std::vector<Root> roots;
  RootSamplingOptions ro;
  ro.count = count;
  EXPECT_TRUE(sampleRoots(body().mesh, bundled::scalp(body().mesh), ro, roots));
  if (body().mesh.signedVolume() < 0)
  {
    for (Root& r : roots)
    {
      r.normal = -r.normal;
    }
  }
  GrowthOptions grow;
  grow.length = 0.3;
  grow.elements = n;
  grow.combed = true;
  grow.combDirection = Eigen::Vector3d(0, -1, -0.3);
  grow.combWeight = 0.35;
  grow.hair = HairParameters::preset(type);
  std::vector<GuideStrand> guides;
  EXPECT_TRUE(growGuides(roots, grow, guides));
  return guides;
}

/// A groom a user would make: the guides shaken for 0.5 s (±0.5 rad at 1 Hz about the neck:
/// the head is back at rest at 0.5 s), that frame's strands as curves, roots on the scalp.
std::vector<std::vector<Eigen::Vector3d>> shakenGroom(const std::vector<GuideStrand>& guides,
                                                      ModelType model)
{
  Scene scene = stillScene();
  scene.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.5, 1.0);
  scene.parts[0].motion = scene.rootMotion;
  SimulationOptions o;
  o.model = model;
  o.threads = 2;
  Simulation sim;
  EXPECT_TRUE(sim.initialize(guides, scene, o));
  EXPECT_TRUE(sim.advanceTo(16));
  GuideDrawing drawn;
  EXPECT_TRUE(sim.drawFrame(15, 8, drawn));
  const StateFrame& f = drawn.frame;
  std::vector<std::vector<Eigen::Vector3d>> curves;
  const StateHeader& h = drawn.header;
  for (std::size_t k = 0; k < h.numberOfStrands(); ++k)
  {
    curves.emplace_back(f.positions.begin() + h.offsets[k], f.positions.begin() + h.offsets[k + 1]);
  }
  return curves;
}

} // namespace

TEST(GrownGuides, ProjectiveStrandsStartDrapedOverTheBody)
{
  // Guides grown straight from the scalp, combed down and back, go through the neck and the
  // shoulders as grown. The projective model starts a strand that enters the head or trunk
  // tables draped over them (collision/PosedPart.h, drapeOutside), its rest shape the grown
  // one: at t = 0 no node is inside a table, the strands that needed it say how far they
  // were moved, the segments keep their length exactly, and the run holds them out.
  std::vector<GuideStrand> guides = scalpGuides(200, 10, HairType::Smooth);
  for (GuideStrand& g : guides)
  {
    g.growth = (g.normal + 1.5 * Eigen::Vector3d(0, -1, -0.3).normalized()).normalized();
  }
  const Scene scene = stillScene();
  std::vector<PosedPart> parts;
  scene.posedParts(0, parts);
  int grownInside = 0;
  for (const GuideStrand& g : guides)
  {
    const std::vector<Eigen::Vector3d> grown = grownPolyline(g);
    grownInside += std::any_of(grown.begin() + 1, grown.end(),
                               [&](const Eigen::Vector3d& p) { return insideAny(parts, p); });
  }
  ASSERT_GT(grownInside, 20) << "the check needs guides grown into the body";
  SimulationOptions o;
  o.model = ModelType::Projective;
  o.threads = 2;
  Simulation sim;
  ASSERT_TRUE(sim.initialize(guides, scene, o));
  GuideDrawing drawn;
  ASSERT_TRUE(sim.drawFrame(0, 1, drawn));
  const StateHeader& h = drawn.header;
  int inside = 0, draped = 0;
  double moved = 0, worstLength = 0;
  for (std::size_t k = 0; k < h.numberOfStrands(); ++k)
  {
    for (std::int64_t i = h.offsets[k] + 1; i < h.offsets[k + 1]; ++i)
    {
      inside += insideAny(parts, drawn.frame.positions[i]);
      const double segment = (drawn.frame.positions[i] - drawn.frame.positions[i - 1]).norm();
      worstLength =
          std::max(worstLength, std::abs(segment * guides[k].elements / guides[k].length - 1));
    }
    const double drape = sim.groomReports()[k].drape;
    draped += drape > 0;
    moved = std::max(moved, drape);
  }
  // One second at rest on the body: the constraint and the projection hold the nodes out.
  ASSERT_TRUE(sim.advanceTo(31));
  double deepest = 0;
  for (int f = 1; f < sim.numberOfFrames(); ++f)
  {
    deepest = std::max(deepest, sim.maxDepth()[f]);
  }
  std::printf("%d of %zu guides grown into the body, %d draped (largest move %.1f mm); nodes "
              "inside at t = 0: %d; segment lengths kept within %.2g; deepest over 1 s %.3f mm\n",
              grownInside, guides.size(), draped, 1e3 * moved, inside, worstLength, 1e3 * deepest);
  EXPECT_EQ(inside, 0);
  EXPECT_EQ(draped, grownInside);
  EXPECT_LT(worstLength, 1e-12);
}

TEST(GroomSimulation, SettledStraightHairRunsAgainAsItsGroom)
{
  // Straight hair (the smooth preset) grown along the scalp normal, settled 3 s at rest on
  // the head and shoulders, and that frame given back as a sag-free groom: the Super-Helix
  // fits each strand's curve. Where an element hardly bends, the positions leave its twist
  // free; fitted free, one strand of these took a twist that blew the first step up
  // ("element 9 reached curvature 36153 1/m"). The fit now holds the twist towards the
  // hair's natural twist there (SuperHelixModel: a radian an element costs as much as 1 µm
  // at one point): the groom runs. Within 1 mm for its first second: at least the 140 of 200
  // that groom_study (groom=settled, docs/study-groom.md) finds within 1 mm for 10 s.
  std::vector<Root> roots;
  RootSamplingOptions ro;
  ro.count = 200;
  ASSERT_TRUE(sampleRoots(body().mesh, bundled::scalp(body().mesh), ro, roots));
  if (body().mesh.signedVolume() < 0)
  {
    for (Root& r : roots)
    {
      r.normal = -r.normal;
    }
  }
  GrowthOptions grow;
  grow.hair = HairParameters::preset(HairType::Smooth);
  std::vector<GuideStrand> grown;
  ASSERT_TRUE(growGuides(roots, grow, grown));
  SimulationOptions o;
  o.threads = 2;
  o.hairHair.enabled = false;
  Simulation settle;
  ASSERT_TRUE(settle.initialize(grown, stillScene(), o));
  ASSERT_TRUE(settle.advanceTo(91));
  GuideDrawing drawn;
  ASSERT_TRUE(settle.drawFrame(90, 16, drawn));
  std::vector<std::vector<Eigen::Vector3d>> curves;
  std::vector<Eigen::Vector3d> normals;
  const StateHeader& h = drawn.header;
  for (std::size_t k = 0; k < h.numberOfStrands(); ++k)
  {
    curves.emplace_back(drawn.frame.positions.begin() + h.offsets[k],
                        drawn.frame.positions.begin() + h.offsets[k + 1]);
    normals.push_back(grown[k].normal);
  }
  CurveGuideOptions co;
  co.hair = grow.hair;
  co.restShape = RestShape::SagFree;
  std::vector<GuideStrand> groom;
  std::vector<int> source;
  std::vector<CurveRefusal> refused;
  ASSERT_TRUE(guidesFromCurves(curves, normals, &bodyMesh(), co, groom, source, refused));
  ASSERT_EQ(groom.size(), curves.size());
  Simulation sim;
  ASSERT_TRUE(sim.initialize(groom, stillScene(), o));
  const Status ran = sim.advanceTo(31);
  ASSERT_TRUE(ran) << ran.message();
  const std::vector<double> moved = strandMotion(sim);
  const long within = std::count_if(moved.begin(), moved.end(), [](double d) { return d <= 1e-3; });
  std::printf("settled smooth groom: %ld of %zu strands within 1 mm over 1 s\n", within,
              moved.size());
  EXPECT_GE(within, 140);
}

TEST(GroomCurves, EachBadCurveIsRefusedWithItsReasonAndTheOthersKept)
{
  const Eigen::Vector3d top = bodyMesh().closestPoint(Eigen::Vector3d(0, 1.8, 0.03));
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  auto line = [&](const Eigen::Vector3d& root) {
    return std::vector<Eigen::Vector3d>{root, root + 0.1 * up, root + 0.2 * up};
  };
  std::vector<std::vector<Eigen::Vector3d>> curves = {
      line(top + Eigen::Vector3d(0, 0.003, 0)), // good: 3 mm off the scalp, moved onto it
      {top},                                    // one point
      {top, top + 0.1 * up, Eigen::Vector3d(0, NaN, 0)},
      {top, top + 0.1 * up, top + 0.1 * up, top + 0.2 * up}, // repeated point
      {top, top + 0.1 * up, top},                            // folds back
      line(top + Eigen::Vector3d(0, 0.05, 0)),               // root 5 cm off the scalp
      {top, top + 5 * up},                                   // 5 m long
      line(top + Eigen::Vector3d(0.001, 0, 0)),              // good
  };
  CurveGuideOptions o;
  o.hair = HairParameters::preset(HairType::Curly);
  o.restShape = RestShape::SagFree;
  std::vector<GuideStrand> guides;
  std::vector<int> source;
  std::vector<CurveRefusal> refused;
  ASSERT_TRUE(guidesFromCurves(curves, {}, &bodyMesh(), o, guides, source, refused));
  ASSERT_EQ(guides.size(), 2u);
  EXPECT_EQ(source, (std::vector<int>{0, 7}));
  ASSERT_EQ(refused.size(), 6u);
  const char* says[] = {"one point",      "NaN",   "same point", "back on itself",
                        "from the scalp", "m long"};
  for (int i = 0; i < 6; ++i)
  {
    EXPECT_EQ(refused[i].curve, i + 1);
    EXPECT_NE(refused[i].reason.find("curve " + std::to_string(i + 1)), std::string::npos)
        << refused[i].reason;
    EXPECT_NE(refused[i].reason.find(says[i]), std::string::npos) << refused[i].reason;
  }
  // The kept curve's root is on the scalp, the curve moved with it, the normal the scalp's.
  const Eigen::Vector3d onScalp = bodyMesh().closestPoint(curves[0][0]);
  EXPECT_LT((guides[0].root - onScalp).norm(), 1e-12);
  EXPECT_LT((guides[0].curve[2] - (curves[0][2] + onScalp - curves[0][0])).norm(), 1e-12);
  EXPECT_GT(guides[0].normal.dot(up), 0.9);
  EXPECT_EQ(guides[0].restShape, RestShape::SagFree);
  EXPECT_NEAR(guides[0].length, 0.2, 1e-12);
  // Every curve bad: an error naming the first ones.
  const std::vector<std::vector<Eigen::Vector3d>> bad(curves.begin() + 1, curves.begin() + 4);
  const Status st = guidesFromCurves(bad, {}, &bodyMesh(), o, guides, source, refused);
  EXPECT_FALSE(st);
  EXPECT_NE(st.message().find("curve 0 has one point"), std::string::npos) << st.message();
}

TEST(GroomCurves, ProjectiveChainIsInscribedInTheCurve)
{
  // A chain of 12 equal segments is its own chain, to round-off.
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> chain = {Eigen::Vector3d::Zero()};
  Eigen::Vector3d d = Eigen::Vector3d::UnitX();
  for (int i = 0; i < 12; ++i)
  {
    d = (d + 0.6 * Eigen::Vector3d(u(gen), u(gen), u(gen))).normalized();
    chain.push_back(chain.back() + 0.025 * d);
  }
  std::vector<Eigen::Vector3d> nodes;
  double error = 1;
  ASSERT_TRUE(segmentsAlongCurve(chain, 12, nodes, error));
  EXPECT_LT(error, 1e-13);
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    EXPECT_LT((nodes[i] - chain[i]).norm(), 1e-13);
  }
  // A circle of radius R cut in n equal chords: the chain's largest distance from the
  // circle is the sagitta R (1 − cos(π/2n)) for a quarter circle, which falls as n⁻².
  const double R = 0.1;
  std::vector<Eigen::Vector3d> arc;
  for (int j = 0; j <= 2000; ++j)
  {
    const double a = 0.5 * M_PI * j / 2000;
    arc.push_back(R * Eigen::Vector3d(std::sin(a), 1 - std::cos(a), 0));
  }
  for (int n : {2, 5, 10, 20})
  {
    ASSERT_TRUE(segmentsAlongCurve(arc, n, nodes, error));
    const double sagitta = R * (1 - std::cos(0.25 * M_PI / n));
    // The polyline of 2000 chords is itself R (1 − cos(π/8000)) = 7.7e-9 m off the circle.
    EXPECT_NEAR(error, sagitta, 1e-8) << "n = " << n;
    for (std::size_t i = 1; i < nodes.size(); ++i)
    {
      EXPECT_NEAR((nodes[i] - nodes[i - 1]).norm(), 2 * R * std::sin(0.25 * M_PI / n), 1e-8);
    }
  }
}

TEST(GroomSimulation, HorizontalStrandStaysHorizontalInBothModels)
{
  // Through the whole run (Simulation, 10 s, frames of 1/30 s): the Super-Helix at
  // dt = 1/30 s, the projective model in its own steps of 1 ms. 5 cm, smooth, N = 1 … 20.
  for (ModelType model : {ModelType::SuperHelix, ModelType::Projective})
  {
    double worst = 0, grown = 0;
    for (int n = 1; n <= 20; ++n)
    {
      for (RestShape rest : {RestShape::SagFree, RestShape::AsGrown})
      {
        GuideStrand g = horizontalGuide(0.05, n, HairType::Smooth);
        g.restShape = rest;
        SimulationOptions o;
        o.model = model;
        Simulation sim;
        ASSERT_TRUE(sim.initialize({g}, Scene(), o));
        ASSERT_TRUE(sim.advanceTo(301));
        const double moved = strandMotion(sim)[0];
        if (rest == RestShape::SagFree)
        {
          ASSERT_EQ(sim.groomReports()[0].outcome, RestOutcome::Held);
          EXPECT_LT(moved, 1e-3) << (model == ModelType::Projective ? "projective" : "super-helix")
                                 << " N = " << n;
          worst = std::max(worst, moved);
        }
        else
        {
          grown = std::max(grown, moved);
        }
      }
    }
    const std::string name = model == ModelType::Projective ? "projective" : "super_helix";
    RecordProperty(name + "_sag_free_largest_motion_m", sci(worst));
    RecordProperty(name + "_as_grown_largest_motion_m", sci(grown));
    EXPECT_GT(grown, 0.01); // as grown it falls
  }
}

TEST(GroomSimulation, ShakenGroomIsHeldOnTheBodyAndTheFileRunsItAgain)
{
  // Eight wavy guides on the bundled scalp, shaken 0.5 s, that frame given back as the
  // groom (roots moved onto the scalp), made sag-free against the head and trunk tables and
  // left 2 s with the body still: every strand that is held stays within 1 mm of the groom
  // (the balance is exact: what moves it is round-off and the contacts' look-up).
  const std::vector<GuideStrand> grown = scalpGuides(8, 10, HairType::Wavy);
  for (ModelType model : {ModelType::SuperHelix, ModelType::Projective})
  {
    const std::string name = model == ModelType::Projective ? "projective" : "super_helix";
    const auto curves = shakenGroom(grown, model);
    CurveGuideOptions co;
    co.hair = HairParameters::preset(HairType::Wavy);
    co.restShape = RestShape::SagFree;
    std::vector<GuideStrand> guides;
    std::vector<int> source;
    std::vector<CurveRefusal> refused;
    std::vector<Eigen::Vector3d> normals;
    for (const GuideStrand& g : grown)
    {
      normals.push_back(g.normal);
    }
    ASSERT_TRUE(guidesFromCurves(curves, normals, &bodyMesh(), co, guides, source, refused));
    ASSERT_EQ(guides.size(), grown.size());
    char path[] = "/tmp/hair_groom_XXXXXX";
    const int fd = mkstemp(path);
    ASSERT_GE(fd, 0);
    close(fd);
    unlink(path);
    SimulationOptions o;
    o.model = model;
    o.threads = 2;
    StorageOptions storage;
    storage.stateFile = std::string(path) + ".h5";
    storage.frames = 61;
    Simulation sim;
    ASSERT_TRUE(sim.initialize(guides, stillScene(), o, storage));
    ASSERT_TRUE(sim.advanceTo(61));
    const std::vector<double> moved = strandMotion(sim);
    int held = 0;
    for (std::size_t k = 0; k < moved.size(); ++k)
    {
      const GroomReport& r = sim.groomReports()[k];
      EXPECT_LT(r.fitError, model == ModelType::SuperHelix ? 1e-9 : 1e-2) << name << " " << k;
      if (r.outcome == RestOutcome::Held)
      {
        ++held;
        EXPECT_LT(moved[k], 1e-3) << name << " strand " << k;
      }
      else
      {
        EXPECT_FALSE(r.reason.empty());
      }
    }
    RecordProperty(name + "_held", held);
    RecordProperty(name + "_largest_motion_m", sci(*std::max_element(moved.begin(), moved.end())));

    // The file keeps the groom: the same guides come back from it, and run again they give
    // the same frames bit for bit.
    StateFileReader reader;
    ASSERT_TRUE(reader.open(storage.stateFile));
    const StateGroom& g = reader.header().groom;
    ASSERT_EQ(g.curveOffsets.size(), guides.size() + 1);
    ASSERT_EQ(g.restCoordinates.size(),
              guides.size() * std::size_t(reader.header().coordinatesPerStrand));
    ASSERT_EQ(g.strandValues.count("rest_status"), 1u);
    std::vector<GuideStrand> again;
    ASSERT_TRUE(guidesFromState(reader.header(), again));
    for (std::size_t k = 0; k < guides.size(); ++k)
    {
      EXPECT_EQ(again[k].curve, guides[k].curve);
      EXPECT_EQ(again[k].restShape, RestShape::SagFree);
    }
    Simulation rerun;
    ASSERT_TRUE(rerun.initialize(again, stillScene(), o));
    ASSERT_TRUE(rerun.advanceTo(11));
    std::vector<double> rest;
    rerun.model().restCoordinates(rest);
    EXPECT_EQ(rest, g.restCoordinates);
    StateFrame a, b;
    for (int i : {0, 10})
    {
      ASSERT_TRUE(sim.readFrame(i, a));
      ASSERT_TRUE(rerun.readFrame(i, b));
      EXPECT_EQ(a.positions, b.positions) << name << " frame " << i;
    }
    reader.close();
    unlink(storage.stateFile.c_str());
  }
}

TEST(GroomSimulation, ShortShakeAndReleaseReturnsToTheGroom)
{
  // A stable equilibrium, not just a balanced one: the 5 cm horizontal strand made sag-free,
  // its root shaken ±0.2 rad at 2 Hz for one cycle (faded in and out over 0.1 s) from 0.1 s,
  // then left: at 10 s it is back within 1 mm of where it started (both models, N = 10; the
  // bound is the issue's). Measured: swung 5.5 mm at 0.4 s, back to 5e-19 m (Super-Helix) and
  // 1.3e-13 m (projective).
  for (ModelType model : {ModelType::SuperHelix, ModelType::Projective})
  {
    GuideStrand g = horizontalGuide(0.05, 10, HairType::Smooth);
    Scene scene;
    scene.rootMotion =
        RigidMotion::shake(Eigen::Vector3d(0, -0.1, 0), Eigen::Vector3d::UnitY(), 0.2, 2.0);
    scene.rootMotion.during(0.1, 1).fading(0.1);
    SimulationOptions o;
    o.model = model;
    Simulation sim;
    ASSERT_TRUE(sim.initialize({g}, scene, o));
    ASSERT_TRUE(sim.advanceTo(301));
    StateFrame first, last, mid;
    ASSERT_TRUE(sim.readFrame(0, first));
    ASSERT_TRUE(sim.readFrame(12, mid));
    ASSERT_TRUE(sim.readFrame(300, last));
    double away = 0, swung = 0;
    for (std::size_t i = 0; i < first.positions.size(); ++i)
    {
      away = std::max(away, (last.positions[i] - first.positions[i]).norm());
      swung = std::max(swung, (mid.positions[i] - first.positions[i]).norm());
    }
    const std::string name = model == ModelType::Projective ? "projective" : "super_helix";
    RecordProperty(name + "_swing_m", sci(swung));
    RecordProperty(name + "_back_m", sci(away));
    EXPECT_GT(swung, 1e-3) << name; // the shake moved it
    EXPECT_LT(away, 1e-3) << name;  // and it came back
  }
}
