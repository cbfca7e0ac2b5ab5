// Hair–hair contacts between Super-Helix guide strands (docs/hair-hair-contacts.md), solved
// together with the strands' implicit steps at dt = 1/30 s (stepStrandsWithContacts).
// References: a brute-force O(n²) search for the broad phase; the strand's own step with the
// same point forces added through its contact hook; Coulomb's law on two point masses in
// closed form; Newton's third law; the static overlap of a penalty, load / stiffness; the
// pass-through count of contact/PassThrough.h, which knows nothing of the contacts.
#include "ClumpScene.h"
#include "HeadShake.h"
#include "StrandPairs.h"
#include "contact/HairHairContacts.h"
#include "contact/PassThrough.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace hair;

namespace
{
constexpr double Dt = 1.0 / 30;

// The strands' drawn points (4 per element), for the pass-through count.
std::vector<std::vector<Eigen::Vector3d>> drawn(const std::vector<SuperHelix>& strands)
{
  return drawnStrands(strands, 4);
}

// A straight strand of samples every `spacing` from `start` along `direction`, all moving at
// `velocity`, for the contact solve alone.
std::vector<StrandSample> line(const Eigen::Vector3d& start, const Eigen::Vector3d& direction,
                               int count, double spacing, const Eigen::Vector3d& velocity)
{
  std::vector<StrandSample> s(count);
  for (int k = 0; k < count; ++k)
  {
    s[k].s = spacing * (k + 0.5);
    s[k].weight = spacing;
    s[k].position = start + spacing * k * direction.normalized();
    s[k].velocity = velocity;
  }
  return s;
}

// The compliance of samples that are free point masses of `mass` each over a step of h: the
// coordinates are their velocities, three per coupling sample (J_k selects them, Y_k = h/m
// J_kᵀ), the free velocity is the samples'.
StrandCompliance pointMasses(const std::vector<StrandSample>& s, const std::vector<int>& coupling,
                             double mass, double h)
{
  StrandCompliance c;
  const int n = static_cast<int>(coupling.size());
  c.samples = coupling;
  c.Jt = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int k = 0; k < n; ++k)
  {
    c.Jt.block<3, 3>(3 * k, 3 * k).setIdentity();
    c.columns.push_back(3 * (k + 1));
    c.freeVelocity.push_back(s[coupling[k]].velocity);
  }
  c.Y = (h / mass) * c.Jt;
  return c;
}
} // namespace

TEST(HairHairContacts, ClosestPointsOfSegments)
{
  // Crossing at right angles 0.3 apart; parallel overlapping; an end against an interior.
  double u, v;
  double d2 = closestPointsOfSegments({0, 0, 0}, {1, 0, 0}, {0.25, -1, 0.3}, {0.25, 1, 0.3}, u, v);
  EXPECT_NEAR(std::sqrt(d2), 0.3, 1e-15);
  EXPECT_NEAR(u, 0.25, 1e-15);
  EXPECT_NEAR(v, 0.5, 1e-15);
  d2 = closestPointsOfSegments({0, 0, 0}, {1, 0, 0}, {0.5, 0.2, 0}, {2, 0.2, 0}, u, v);
  EXPECT_NEAR(std::sqrt(d2), 0.2, 1e-15);
  EXPECT_NEAR(u, 0.75, 1e-15); // middle of the overlap [0.5, 1]
  d2 = closestPointsOfSegments({0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}, {3, 2, 0}, u, v);
  EXPECT_NEAR(std::sqrt(d2), std::sqrt(1 + 0.25), 1e-15);
  EXPECT_EQ(u, 1);
  EXPECT_EQ(v, 0);
}

TEST(HairHairContacts, BadParametersAndInputAreRefusedWithTheirName)
{
  struct Case
  {
    const char* name;
    void (*set)(HairHairParameters&);
  };
  const Case cases[] = {
      {"thickness", [](HairHairParameters& p) { p.thickness = -1e-3; }},
      {"thickness", [](HairHairParameters& p) { p.thickness = std::nan(""); }},
      {"thickness", [](HairHairParameters& p) { p.thickness = 2.5; }},
      {"stiffness", [](HairHairParameters& p) { p.stiffness = -1; }},
      {"stiffness", [](HairHairParameters& p) { p.stiffness = INFINITY; }},
      {"damping", [](HairHairParameters& p) { p.damping = -1e-4; }},
      {"friction", [](HairHairParameters& p) { p.friction = std::nan(""); }},
      {"friction", [](HairHairParameters& p) { p.friction = -0.1; }},
      {"margin", [](HairHairParameters& p) { p.margin = -1; }},
      {"margin", [](HairHairParameters& p) { p.margin = 5; }},
      {"cellSize", [](HairHairParameters& p) { p.cellSize = -0.1; }},
      {"threads", [](HairHairParameters& p) { p.threads = 0; }},
      {"iterations", [](HairHairParameters& p) { p.iterations = 0; }},
      {"tolerance", [](HairHairParameters& p) { p.tolerance = 1; }},
      {"referenceLength", [](HairHairParameters& p) { p.referenceLength = 0; }},
      {"referenceLength", [](HairHairParameters& p) { p.referenceLength = std::nan(""); }},
  };
  for (const Case& c : cases)
  {
    HairHairParameters p;
    p.thickness = 2.5e-3;
    c.set(p);
    HairHairContacts h;
    const Status st = h.setParameters(p);
    ASSERT_FALSE(st.ok()) << c.name;
    EXPECT_NE(st.message().find(c.name), std::string::npos) << st.message();
  }
  // The automatic thickness (0) validates, but the contacts need it resolved.
  EXPECT_TRUE(HairHairParameters().validate().ok());
  HairHairContacts h;
  Status st = h.setParameters(HairHairParameters());
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("automaticThickness"), std::string::npos) << st.message();
  // The automatic thickness: r √(120 000 / (guides × ½)), 1.21 mm for 200 guides of 35 µm.
  EXPECT_NEAR(HairHairParameters::automaticThickness(35e-6, 200), 35e-6 * std::sqrt(120000.0 / 100),
              1e-15);
  // Bad input to detect: duplicate ids, non-finite samples, no step.
  HairHairParameters p;
  p.thickness = 2.5e-3;
  ASSERT_TRUE(h.setParameters(p).ok());
  std::vector<std::vector<StrandSample>> s(2, line({0, 0, 0}, {1, 0, 0}, 3, 0.01, {0, 0, 0}));
  st = h.detect(s, {4, 4}, Dt);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("same id"), std::string::npos) << st.message();
  st = h.detect(s, {}, 0);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("step"), std::string::npos) << st.message();
  s[1][2].position.x() = std::nan("");
  st = h.detect(s, {}, Dt);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("non-finite"), std::string::npos) << st.message();
  // A compliance that does not describe the coupling samples.
  s[1][2].position.x() = 0.02;
  s[1] = line({0, 0.003, 0}, {1, 0, 0}, 3, 0.01, {0, 0, 0});
  ASSERT_TRUE(h.detect(s, {}, Dt).ok());
  ASSERT_FALSE(h.couplingSamples(0).empty());
  std::vector<StrandCompliance> wrong(2);
  st = h.solve(wrong);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("compliance"), std::string::npos) << st.message();
}

TEST(HairHairContacts, GridFindsTheSamePairsAsBruteForce)
{
  // Random polylines (random walks) in a 5 cm box, at rest (the swept boxes are the boxes),
  // thickness and margin such that many pieces are near: every pair of pieces of different
  // strands whose grown boxes overlap must come out of the grid once, and nothing else.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> box(0, 0.05), step(-0.006, 0.006);
  long contacts = 0;
  for (int trial = 0; trial < 20; ++trial)
  {
    const int strands = 5 + trial * 3;
    std::vector<std::vector<StrandSample>> s(strands);
    for (auto& strand : s)
    {
      Eigen::Vector3d x(box(gen), box(gen), box(gen));
      const int n = 2 + static_cast<int>(gen() % 30);
      for (int k = 0; k < n; ++k)
      {
        StrandSample smp;
        smp.s = 0.01 * (k + 1);
        smp.weight = 0.01;
        smp.position = x;
        strand.push_back(smp);
        x += Eigen::Vector3d(step(gen), step(gen), step(gen));
      }
    }
    HairHairParameters p;
    p.thickness = 1e-3 * (1 + trial % 4);
    p.margin = trial % 2 ? 0 : 0.5;
    p.cellSize = trial % 3 == 0 ? 0 : 0.004; // automatic, and smaller than the boxes
    HairHairContacts h;
    ASSERT_TRUE(h.setParameters(p).ok());
    ASSERT_TRUE(h.detect(s, {}, Dt).ok());
    const double grow = p.thickness * (1 + p.margin), reach = 2 * grow;
    std::vector<std::pair<std::int64_t, std::int64_t>> brute;
    long close = 0;
    for (int a = 0; a < strands; ++a)
      for (int b = a + 1; b < strands; ++b)
        for (size_t i = 0; i + 1 < s[a].size(); ++i)
          for (size_t j = 0; j + 1 < s[b].size(); ++j)
          {
            const Eigen::Vector3d loA =
                s[a][i].position.cwiseMin(s[a][i + 1].position).array() - grow;
            const Eigen::Vector3d hiA =
                s[a][i].position.cwiseMax(s[a][i + 1].position).array() + grow;
            const Eigen::Vector3d loB =
                s[b][j].position.cwiseMin(s[b][j + 1].position).array() - grow;
            const Eigen::Vector3d hiB =
                s[b][j].position.cwiseMax(s[b][j + 1].position).array() + grow;
            if ((loA.array() > hiB.array()).any() || (loB.array() > hiA.array()).any())
              continue;
            brute.emplace_back(HairHairContacts::pieceKey(a, static_cast<int>(i)),
                               HairHairContacts::pieceKey(b, static_cast<int>(j)));
            double u, v;
            if (closestPointsOfSegments(s[a][i].position, s[a][i + 1].position, s[b][j].position,
                                        s[b][j + 1].position, u, v) < reach * reach)
              ++close;
          }
    std::sort(brute.begin(), brute.end());
    EXPECT_EQ(h.candidatePairs(), brute) << "trial " << trial;
    // Contacts: the pairs within reach, less those that found the same closest points (at a
    // shared sample) as another pair and are merged into it; never more.
    EXPECT_LE(h.stats().contacts, close);
    EXPECT_GT(h.stats().contacts, close / 4);
    contacts += h.stats().contacts;
  }
  EXPECT_GT(contacts, 100) << "the configurations must have contacts to test";
}

TEST(HairHairContacts, ThreadsFindTheSameContacts)
{
  // 300 random walks in a 3 cm box, moving (≤ 1 cm/s): tens of thousands of candidate pairs,
  // split over
  // 1, 2 and 3 threads; the pairs and the coupling samples must be the same (the solve that
  // follows runs on one thread, in the pairs' order).
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> box(0, 0.03), step(-0.004, 0.004), vel(-0.01, 0.01);
  std::vector<std::vector<StrandSample>> s(300);
  for (auto& strand : s)
  {
    Eigen::Vector3d x(box(gen), box(gen), box(gen));
    for (int k = 0; k < 30; ++k)
    {
      StrandSample smp;
      smp.s = 0.004 * (k + 1);
      smp.weight = 0.004;
      smp.position = x;
      smp.velocity = Eigen::Vector3d(vel(gen), vel(gen), vel(gen));
      strand.push_back(smp);
      x += Eigen::Vector3d(step(gen), step(gen), step(gen));
    }
  }
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  std::vector<std::vector<int>> coupling;
  long contacts = 0;
  for (int threads : {1, 2, 3})
  {
    HairHairParameters p;
    p.thickness = 1e-3;
    p.threads = threads;
    HairHairContacts h;
    ASSERT_TRUE(h.setParameters(p).ok());
    ASSERT_TRUE(h.detect(s, {}, Dt).ok());
    ASSERT_GT(h.stats().candidatePairs, 3 * 4096) << "too few candidates to split";
    std::vector<std::vector<int>> c;
    for (size_t i = 0; i < s.size(); ++i)
      c.push_back(h.couplingSamples(int(i)));
    if (threads == 1)
    {
      pairs = h.candidatePairs();
      coupling = c;
      contacts = h.stats().contacts;
      continue;
    }
    EXPECT_EQ(h.candidatePairs(), pairs);
    EXPECT_EQ(c, coupling);
    EXPECT_EQ(h.stats().contacts, contacts);
  }
}

TEST(HairHairContacts, CoulombFrictionOfTwoPointMassesSticksBelowTheThresholdAndSlidesAbove)
{
  // Two pieces crossing at right angles, their samples free point masses m (so the pair's
  // compliance is (h/m) I, isotropic): A along x, 4.5 mm above B along z (contact distance
  // 5 mm), A approaching B at 1 cm/s and sliding along x at speed u. The contact's law
  // (docs/hair-hair-contacts.md) in closed form: λ = (k (R − d0) − (k h + c_n) w_n) / (1 +
  // (k h + c_n) h/m), and the tangential force that stops the sliding within the step is
  // m u / h: Coulomb sticks (end sliding 0) while m u / h ≤ μ λ, and slides otherwise with
  // the force μ λ against the sliding (end sliding u − μ λ h / m). The threshold is
  // u* = μ λ h / m; the test runs 0.9 u* and 1.1 u*.
  HairHairParameters p;
  p.thickness = 2.5e-3;
  p.friction = 0.3;
  const double m = 1e-7, R = 5e-3, d0 = 4.5e-3, vn = -0.01;
  const double a = p.stiffness * Dt + p.damping;
  const double lambda = (p.stiffness * (R - d0) - a * vn) / (1 + a * Dt / m);
  const double threshold = p.friction * lambda * Dt / m;
  for (double ratio : {0.9, 1.1})
  {
    const double u = ratio * threshold;
    std::vector<std::vector<StrandSample>> s = {
        line({-0.005, d0, 0}, {1, 0, 0}, 2, 0.01, {u, vn, 0}),
        line({0, 0, -0.005}, {0, 0, 1}, 2, 0.01, {0, 0, 0})};
    HairHairContacts h;
    ASSERT_TRUE(h.setParameters(p).ok());
    ASSERT_TRUE(h.detect(s, {}, Dt).ok());
    ASSERT_EQ(h.stats().contacts, 1);
    std::vector<StrandCompliance> c = {pointMasses(s[0], h.couplingSamples(0), m, Dt),
                                       pointMasses(s[1], h.couplingSamples(1), m, Dt)};
    ASSERT_TRUE(h.solve(c).ok());
    ASSERT_EQ(h.contacts().size(), 1u);
    const HairHairContact& k = h.contacts()[0];
    const Eigen::Vector3d n(0, 1, 0);
    EXPECT_LT((k.normal - n).norm(), 1e-12);
    // Round-off: a few dozen operations on forces of ~1e-5 N.
    EXPECT_NEAR(k.forceOnA.dot(n), lambda, 1e-12 * lambda) << ratio;
    const double tangential = k.forceOnA.x();
    const double endSliding = k.relativeVelocity.x();
    if (ratio < 1)
    {
      EXPECT_NEAR(tangential, -m * u / Dt, 1e-12 * lambda);
      EXPECT_NEAR(endSliding, 0, 1e-12 * u);
      EXPECT_EQ(h.stats().sticking, 1);
    }
    else
    {
      EXPECT_NEAR(tangential, -p.friction * lambda, 1e-12 * lambda);
      EXPECT_NEAR(endSliding, u - p.friction * lambda * Dt / m, 1e-12 * u);
      EXPECT_EQ(h.stats().sticking, 0);
    }
    // Newton's third law: the forces on A's samples and B's add up to zero.
    Eigen::Vector3d net = Eigen::Vector3d::Zero();
    for (int i = 0; i < 2; ++i)
      for (const Eigen::Vector3d& f : h.forces(i))
        net += f;
    EXPECT_LT(net.norm(), 1e-15 * lambda);
    std::printf("u = %.2f u* = %.4g m/s: normal force %.4g N, tangential %.4g N (mu lambda "
                "%.4g N), sliding at the end %.4g m/s\n",
                ratio, u, lambda, tangential, p.friction * lambda, endSliding);
  }
}

TEST(HairHairContacts, LengthInCylinderIsTheChordOfTheGeometry)
{
  // Exact geometry (round-off bound 1e-15 m on centimetre segments): a segment crossing the
  // axis at right angles d = 3 mm from it cuts a chord 2 √(R² − d²) = 8 mm of the R = 5 mm
  // cylinder; at 30° to it the chord is 2 √(R² − d²) / sin 30° = 16 mm; a parallel segment
  // inside the cylinder counts only its part over the axis' extent; one outside counts 0.
  const double R = 5e-3, d = 3e-3;
  const Eigen::Vector3d q0(0, 0, -0.05), q1(0, 0, 0.05); // the axis: z from −5 to 5 cm
  EXPECT_NEAR(lengthInCylinder({-0.02, d, 0}, {0.02, d, 0}, q0, q1, R), 8e-3, 1e-15);
  const double c = std::cos(M_PI / 6), sn = std::sin(M_PI / 6);
  EXPECT_NEAR(lengthInCylinder({-0.04 * sn, d, -0.04 * c}, {0.04 * sn, d, 0.04 * c}, q0, q1, R),
              16e-3, 1e-15);
  EXPECT_NEAR(lengthInCylinder({0, d, 0.02}, {0, d, 0.09}, q0, q1, R), 0.03, 1e-15);
  EXPECT_NEAR(lengthInCylinder({0, d, 0.09}, {0, d, 0.02}, q0, q1, R), 0.03, 1e-15);
  EXPECT_EQ(lengthInCylinder({0, 6e-3, -0.02}, {0, 6e-3, 0.02}, q0, q1, R), 0);
  EXPECT_EQ(lengthInCylinder({0, d, 0.06}, {0, d, 0.08}, q0, q1, R), 0);  // beyond the extent
  EXPECT_EQ(lengthInCylinder({-0.02, d, 0}, {0.02, d, 0}, q0, q0, R), 0); // degenerate axis
}

TEST(HairHairContacts, CoupledStepIsTheStepWithTheSameForcesInItsHook)
{
  // A wavy strand bent out of its natural shape, at rest, let go (gravity off, root still),
  // with a contact hook of its own (a stiff implicit spring and damper on two samples, as
  // the body's contacts would be): beginStep, compliance at three samples and endStep with
  // point forces F_k there and their response Σ Y_k F_k must give the step that step()
  // gives with F_k / weight_k added to the hook's force at those samples: the same q, q̇ and
  // energy flows, to round-off (1e-10 relative: the same system, the forces in its
  // right-hand side or through its factors). At rest without gravity the step's only loads
  // are these forces (≤ 3e-8 N), below the tension it leaves explicit (ρS ℓ² / (64 h²) =
  // 6e-8 N, docs/super-helix.md), so its tension stiffness K_T is zero both ways: larger
  // loads make K_T depend on them, and the coupled step leaves the coupling forces out of
  // K_T (docs/hair-hair-contacts.md).
  StrandSpec spec = StrandSpec::uniform(0.3, 10, HairParameters::preset(HairType::Wavy));
  spec.gravity.setZero();
  const ContactForces own =
      [](int, double, const std::vector<StrandSample>&, std::vector<ContactResponse>& r)
  {
    for (int j : {4, 11})
    {
      r[j].stiffness += 50 * Eigen::Matrix3d::Identity();
      r[j].damping += 0.01 * Eigen::Matrix3d::Identity();
    }
  };
  SuperHelix a, b;
  ASSERT_TRUE(a.initialize(spec).ok());
  ASSERT_TRUE(a.setState(1.3 * a.restCurvature(), Eigen::VectorXd::Zero(a.q().size())).ok());
  a.setContactForces(own);
  b = a;
  const std::vector<int> coupling = {3, 7, 20};
  const std::vector<Eigen::Vector3d> forces = {
      {2e-8, -1e-8, 5e-9}, {-3e-9, 2e-8, 1e-8}, {1e-8, 1e-8, -2e-8}};
  ASSERT_TRUE(a.beginStep(Dt).ok());
  StrandCompliance c;
  ASSERT_TRUE(a.compliance(coupling, c).ok());
  Eigen::VectorXd response = Eigen::VectorXd::Zero(a.q().size());
  for (size_t k = 0; k < coupling.size(); ++k)
    response += c.Y.middleCols<3>(3 * k) * forces[k];
  ASSERT_TRUE(a.endStep(coupling, forces, response).ok());
  b.setContactForces(
      [&](int id, double t, const std::vector<StrandSample>& s, std::vector<ContactResponse>& r)
      {
        own(id, t, s, r);
        for (size_t k = 0; k < coupling.size(); ++k)
          r[coupling[k]].force += forces[k] / s[coupling[k]].weight;
      });
  ASSERT_TRUE(b.step(Dt).ok());
  EXPECT_LT((a.q() - b.q()).norm(), 1e-10 * b.q().norm());
  EXPECT_LT((a.qdot() - b.qdot()).norm(), 1e-10 * b.qdot().norm());
  const EnergyTerms &ea = a.energy().lastStep, &eb = b.energy().lastStep;
  const double scale = std::abs(eb.contactWork) + std::abs(eb.frictionDissipated);
  EXPECT_NEAR(ea.contactWork, eb.contactWork, 1e-10 * scale);
  EXPECT_NEAR(ea.residual, eb.residual, 1e-10 * scale);
  // The velocities the free step gives the samples (x + h v predicts where they end):
  // the coupling samples' are the compliance's free velocities.
  SuperHelix d = b, e = b;
  ASSERT_TRUE(d.beginStep(Dt).ok());
  ASSERT_TRUE(d.compliance(coupling, c).ok());
  for (size_t k = 0; k < coupling.size(); ++k)
    EXPECT_EQ(c.freeVelocity[k], d.freeSamples()[coupling[k]].velocity);
  // With no forces, endStep is step() to the bit.
  ASSERT_TRUE(d.endStep({}, {}, Eigen::VectorXd()).ok());
  ASSERT_TRUE(e.step(Dt).ok());
  EXPECT_EQ(d.q(), e.q());
  EXPECT_EQ(d.qdot(), e.qdot());
  // Misuse is refused: endStep without beginStep, samples out of order or range.
  EXPECT_FALSE(d.endStep({}, {}, Eigen::VectorXd()).ok());
  ASSERT_TRUE(d.beginStep(Dt).ok());
  EXPECT_FALSE(d.compliance({5, 3}, c).ok());
  EXPECT_FALSE(d.compliance({1000}, c).ok());
}

TEST(HairHairContacts, PassThroughsAreCrossingsBetweenFrames)
{
  // Two straight strands of 4 pieces crossing at right angles in projection: A along x, B
  // along z. A going from 2 mm above B to 2 mm below is a pass-through (within 5 mm); going
  // from 2 mm to 4 mm above is not; from 20 mm above to 20 mm below neither (never within
  // 5 mm: not a contact's business); A sliding along a parallel B, 3 mm beside it, by a
  // piece and a half is not (the closest points' direction turns at the pieces' ends).
  auto strand = [](const Eigen::Vector3d& start, const Eigen::Vector3d& step)
  {
    std::vector<Eigen::Vector3d> p;
    for (int k = 0; k <= 4; ++k)
      p.push_back(start + k * step);
    return p;
  };
  const Eigen::Vector3d x(0.01, 0, 0), z(0, 0, 0.01);
  auto crossing = [&](double before, double after)
  {
    const std::vector<std::vector<Eigen::Vector3d>> b = {strand({-0.02, before, 0.001}, x),
                                                         strand({0.001, 0, -0.02}, z)};
    const std::vector<std::vector<Eigen::Vector3d>> a = {strand({-0.02, after, 0.001}, x),
                                                         strand({0.001, 0, -0.02}, z)};
    return findPassThroughs(b, a, 5e-3);
  };
  const std::vector<PassThrough> through = crossing(2e-3, -2e-3);
  ASSERT_EQ(through.size(), 1u);
  EXPECT_EQ(through[0].strandA, 0);
  EXPECT_EQ(through[0].pieceA, 2);
  EXPECT_EQ(through[0].strandB, 1);
  EXPECT_EQ(through[0].pieceB, 2);
  EXPECT_NEAR(through[0].distanceBefore, 2e-3, 1e-15);
  EXPECT_TRUE(crossing(2e-3, 4e-3).empty());
  EXPECT_TRUE(crossing(20e-3, 30e-3).empty());
  // Faster than a contact distance per frame: 20 mm above, then 20 mm below, crossed.
  EXPECT_EQ(crossing(20e-3, -20e-3).size(), 1u);
  const std::vector<std::vector<Eigen::Vector3d>> before = {strand({0, 3e-3, 0}, x),
                                                            strand({0, 0, 0}, x)};
  const std::vector<std::vector<Eigen::Vector3d>> after = {strand({0.015, 3e-3, 0}, x),
                                                           strand({0, 0, 0}, x)};
  EXPECT_TRUE(findPassThroughs(before, after, 5e-3).empty());
}

namespace
{
// Strand B lies straight along z (root fixed at the origin); strand A, straight along x,
// 10 mm above B's middle (the crossing inside pieces of both, not at their drawn points),
// is driven down through it by its root at `speed` (gravity
// off: both stay straight until they meet). Returns the pass-throughs counted frame by frame
// and the closest approach of the centrelines over `frames` frames.
Status driveThrough(bool withContacts, double speed, int frames, long& passes, double& closest)
{
  std::vector<SuperHelix> strands;
  if (Status st = drivenPair(speed, -0.1025, 0.1025, strands); !st)
    return st;
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = 2.5e-3;
  if (Status st = contacts.setParameters(p); !st)
    return st;
  return runPair(
      strands, frames, 4, 2 * p.thickness,
      [&](std::vector<SuperHelix>& s) {
        return withContacts ? stepStrandsWithContacts(s, contacts, Dt, 1) : stepStrands(s, Dt, 1);
      },
      passes, closest);
}
} // namespace

TEST(HairHairContacts, AStrandDrivenThroughAnotherIsStoppedWithinTheStep)
{
  // A at 0.6 m/s covers 20 mm per 1/30 s step, four contact distances (5 mm): starting 10 mm
  // above B, it would be 10 mm below after one step. Found before the step from where the
  // step takes it, the pair's force acts from the start of that step, and the gap it sees
  // is the one at the end: A stops on B (and bends around it as its root goes on) instead of
  // crossing. Without contacts it crosses within the first step.
  long passes = 0, passesFree = 0;
  double closest = 0, closestFree = 0;
  Status st = driveThrough(true, 0.6, 6, passes, closest);
  ASSERT_TRUE(st.ok()) << st.message();
  st = driveThrough(false, 0.6, 6, passesFree, closestFree);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(passes, 0);
  EXPECT_GE(passesFree, 1);
  // The pair ends at the contact distance less what the step's first order and the
  // penalty's overlap let through (the force stopping A within one step, m v / h ≈ 1e-4 N
  // for the 3 cm of A nearest B, holds at 0.1 mm with k = 1 N/m): required above 80 % of R.
  EXPECT_GT(closest, 0.8 * 5e-3);
  std::printf("driven at 0.6 m/s: closest approach %.3g mm with contacts (%ld pass-throughs), "
              "%.3g mm without (%ld)\n",
              1e3 * closest, passes, 1e3 * closestFree, passesFree);
}

TEST(HairHairContacts, WithTheMidpointIntegratorStrandsInContactStepSemiImplicitly)
{
  // Integrator::Midpoint (docs/super-helix.md, "The second-order step") leaves a stiff
  // penalty mode ringing, so a strand touching anything takes the semi-implicit step; the
  // coupled solve is that step's (docs/hair-hair-contacts.md, "With the second-order step").
  // The drive-through pair with the midpoint integrator, and a third strand far from both:
  // the pair is stopped as with the semi-implicit step, each step of A and B that carries a
  // hair–hair force is taken first order, and the far strand takes the second-order step,
  // the same as stepped alone (to round-off).
  HairParameters hair = HairParameters::roundStraight();
  auto make = [&](int id, const RootState& r0, const Eigen::Vector3d& velocity, SuperHelix& h)
  {
    StrandSpec s = StrandSpec::uniform(0.2, 10, hair);
    s.id = id;
    s.integrator = Integrator::Midpoint;
    s.root = [r0, velocity](double t)
    {
      RootState r = r0;
      r.position += velocity * t;
      r.velocity = velocity;
      return r;
    };
    return h.initialize(s);
  };
  RootState ra, rb, rc;
  ra.position = Eigen::Vector3d(-0.1025, 0.01, 0.1025);
  ra.orientation = frameWithTangent({1, 0, 0});
  rb.orientation = frameWithTangent({0, 0, 1});
  // C hangs (gravity on) 1 m away, so that its step is not trivial.
  rc.position = Eigen::Vector3d(1, 0, 0);
  rc.orientation = frameWithTangent({1, 0, 0.2});
  std::vector<SuperHelix> strands(3);
  SuperHelix alone;
  const Eigen::Vector3d down(0, -0.6, 0);
  ASSERT_TRUE(make(0, ra, down, strands[0]).ok());
  ASSERT_TRUE(make(1, rb, Eigen::Vector3d::Zero(), strands[1]).ok());
  ASSERT_TRUE(make(2, rc, Eigen::Vector3d::Zero(), strands[2]).ok());
  ASSERT_TRUE(make(2, rc, Eigen::Vector3d::Zero(), alone).ok());
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = 2.5e-3;
  ASSERT_TRUE(contacts.setParameters(p).ok());
  long passes = 0;
  int coupledSteps = 0, coupledFirstOrder = 0, farSecondOrder = 0, aloneSecondOrder = 0;
  double closest = std::numeric_limits<double>::infinity();
  std::vector<std::vector<Eigen::Vector3d>> before = drawn(strands);
  const int frames = 6;
  for (int f = 0; f < frames; ++f)
  {
    Status st = stepStrandsWithContacts(strands, contacts, Dt, 1);
    ASSERT_TRUE(st.ok()) << st.message();
    ASSERT_TRUE((st = alone.step(Dt)).ok()) << st.message();
    for (int i = 0; i < 2; ++i)
      if (!contacts.couplingSamples(i).empty())
      {
        ++coupledSteps;
        coupledFirstOrder += strands[i].lastFirstOrder();
      }
    EXPECT_TRUE(contacts.couplingSamples(2).empty());
    farSecondOrder += strands[2].lastFirstOrder() == 0 ? 1 : 0;
    aloneSecondOrder += alone.lastFirstOrder() == 0 ? 1 : 0;
    const std::vector<std::vector<Eigen::Vector3d>> after = drawn(strands);
    passes += static_cast<long>(findPassThroughs(before, after, 2 * p.thickness).size());
    closest = std::min(closest, centrelineDistance(strands[0], strands[1]));
    before = after;
  }
  EXPECT_EQ(passes, 0);
  // As AStrandDrivenThroughAnotherIsStoppedWithinTheStep (semi-implicit): above 80 % of R.
  EXPECT_GT(closest, 0.8 * 5e-3);
  EXPECT_GT(coupledSteps, 0);
  EXPECT_EQ(coupledFirstOrder, coupledSteps);
  // (The midpoint step's own energy guard may decline a step of C: alone as well.)
  EXPECT_GT(farSecondOrder, 0);
  EXPECT_EQ(farSecondOrder, aloneSecondOrder);
  EXPECT_LT((strands[2].q() - alone.q()).norm(), 1e-12 * alone.q().norm());
  std::printf("midpoint integrator: closest approach %.3g mm, %d coupled steps (all first "
              "order), the far strand second order in %d of %d steps\n",
              1e3 * closest, coupledSteps, farSecondOrder, frames);
}

namespace
{
// Two strands whose roots move towards each other; the closest approach of their centrelines
// over the run. Strand A is clamped horizontally (tangent +z) and droops; strand B is its
// mirror image, clamped at z = 2D facing −z, D being how far A's free part hangs out in z,
// so that their hanging parts meet. Their roots move to x = 0 (they stay 2D apart).
struct PairRun
{
  double closest = 0, depthAtRest = 0;
  long passes = 0;
  double work = 0, dissipated = 0, residual = 0, rootWork = 0;
  double netForce = 0, pairForce = 0; ///< |Σ forces| and Σ |forces| of the last solve
};

Status pushTogether(bool withContacts, double thickness, PairRun& out, bool perLength = false)
{
  // Air drag 20 times the smooth preset's, so that the drooping strands settle within 2 s.
  HairParameters hair = HairParameters::roundStraight();
  hair.airFriction = 2e-4;
  const double L = 0.3;
  // A alone, settled, for D.
  double D = 0;
  {
    StrandSpec s = StrandSpec::uniform(L, 10, hair);
    RootState r;
    r.orientation = frameWithTangent({0, 0, 1});
    s.root = [r](double) { return r; };
    SuperHelix a;
    Status st = a.initialize(s);
    if (!st)
      return st;
    for (int i = 0; i < 60; ++i)
      if (!(st = a.step(Dt)))
        return st;
    D = a.position(0.5 * L).z();
  }
  auto rootOf = [D](int side)
  {
    return [D, side](double t)
    {
      // Roots at x = ∓3 cm, moving to 0 between t = 2 s and 4 s (smoothstep, speed ≤ 2.25
      // cm/s).
      const double x0 = side == 0 ? -0.03 : 0.03;
      const double u = std::clamp(0.5 * (t - 2.0), 0.0, 1.0);
      const double sm = u * u * (3 - 2 * u), dsm = 3 * u * (1 - u), ddsm = 1.5 - 3 * u;
      const bool moving = t > 2 && t < 4;
      RootState r;
      r.position = Eigen::Vector3d(x0 * (1 - sm), 0, side == 0 ? 0 : 2 * D);
      r.velocity = Eigen::Vector3d(moving ? -x0 * dsm : 0, 0, 0);
      r.acceleration = Eigen::Vector3d(moving ? -x0 * ddsm : 0, 0, 0);
      r.orientation = frameWithTangent({0, 0, side == 0 ? 1.0 : -1.0});
      return r;
    };
  };
  std::vector<SuperHelix> strands(2);
  for (int i = 0; i < 2; ++i)
  {
    StrandSpec s = StrandSpec::uniform(L, 10, hair);
    s.id = i;
    s.root = rootOf(i);
    Status st = strands[i].initialize(s);
    if (!st)
      return st;
  }
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = thickness;
  p.perLength = perLength;
  Status st = contacts.setParameters(p);
  if (!st)
    return st;
  out = PairRun{};
  out.closest = std::numeric_limits<double>::infinity();
  std::vector<std::vector<Eigen::Vector3d>> before = drawn(strands);
  for (int i = 0; i < 180; ++i) // 6 s: 2 s settling, 2 s moving, 2 s still
  {
    st = withContacts ? stepStrandsWithContacts(strands, contacts, Dt, 2)
                      : stepStrands(strands, Dt, 2);
    if (!st)
      return st;
    if (withContacts)
    {
      out.work += contacts.stats().work;
      out.dissipated += contacts.stats().dissipated;
    }
    const std::vector<std::vector<Eigen::Vector3d>> after = drawn(strands);
    out.passes += static_cast<long>(findPassThroughs(before, after, 2 * thickness).size());
    before = after;
    out.closest = std::min(out.closest, centrelineDistance(strands[0], strands[1]));
  }
  out.depthAtRest = 2 * thickness - centrelineDistance(strands[0], strands[1]);
  for (const SuperHelix& h : strands)
  {
    out.residual += h.energy().total.residual;
    out.rootWork += std::abs(h.energy().total.rootWork);
  }
  if (withContacts)
  {
    // Momentum: the forces the last solve put on the two strands cancel.
    Eigen::Vector3d net = Eigen::Vector3d::Zero();
    for (int i = 0; i < 2; ++i)
      for (const Eigen::Vector3d& f : contacts.forces(i))
      {
        net += f;
        out.pairForce += f.norm();
      }
    out.netForce = net.norm();
  }
  return Status::Ok();
}
} // namespace

TEST(HairHairContacts, StrandsPushedTogetherDoNotPassThrough)
{
  // The hanging parts, mirror images, are pushed into each other by their roots (≤ 2.25
  // cm/s each). The load pressing them together is the lateral pull of gravity on a strand
  // pushed aside by about a thickness, ~ ρS g L × (thickness / L) ≈ 2.5e-7 N, which the
  // penalty (1 N/m) holds at ~0.25 µm; the solve stops the approach within the step at
  // the predicted end gap. So the closest approach of the centrelines must stay within the
  // contact distance R = 5 mm less 5 %: the solve's tolerance (1 % of R per sweep) and the
  // chords between quadrature samples against the centreline (measured below).
  const double thickness = 2.5e-3, R = 2 * thickness;
  PairRun with, without;
  Status st = pushTogether(true, thickness, with);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_GT(with.closest, 0.95 * R);
  EXPECT_LT(with.depthAtRest, 0.05 * R);
  EXPECT_EQ(with.passes, 0);
  // Without contacts the hanging parts go into each other by more than half of R.
  st = pushTogether(false, thickness, without);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_LT(without.closest, 0.5 * R);
  // Newton's third law: the forces on the two strands cancel to round-off.
  EXPECT_GT(with.pairForce, 0) << "the strands must be in contact at the end";
  EXPECT_LT(with.netForce, 1e-12 * with.pairForce);
  // Energy: damping and friction dissipate (≥ 0), and the contacts' work is what their
  // penalty stored and what was dissipated: it cannot exceed the penalty's energy at the
  // end, which is ½ k δ² ≤ ½ × 1 N/m × (0.05 R)² per contact (tiny), so it must be ≤ 0 up to
  // that; the strands' budget closes with their own residual (reported).
  EXPECT_GE(with.dissipated, 0);
  EXPECT_LE(with.work, 1e-12);
  std::printf("closest approach %.4g mm with contacts, %.3g mm without (R = %.3g mm); at rest "
              "%.3g um in; contact work %.3g J, dissipated %.3g J; residual %.3g J with, %.3g J "
              "without, of root work %.3g J\n",
              1e3 * with.closest, 1e3 * without.closest, 1e3 * R, 1e6 * with.depthAtRest, with.work,
              with.dissipated, with.residual, without.residual, with.rootWork);
}

TEST(HairHairContacts, StrandsPushedTogetherDoNotPassThroughWithThePerLengthPenalty)
{
  // The same pair with the per-length penalty (ℓ_ref = 1 cm; these straight strands' samples
  // are 7–12 mm apart, so about the per-point force): the same bounds and third law.
  const double thickness = 2.5e-3, R = 2 * thickness;
  PairRun with;
  const Status st = pushTogether(true, thickness, with, true);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_GT(with.closest, 0.95 * R);
  EXPECT_LT(with.depthAtRest, 0.05 * R);
  EXPECT_EQ(with.passes, 0);
  EXPECT_GT(with.pairForce, 0);
  EXPECT_LT(with.netForce, 1e-12 * with.pairForce);
  std::printf("per length: closest approach %.4g mm, depth at rest %.3g um\n", 1e3 * with.closest,
              1e6 * with.depthAtRest);
}

TEST(HairHairContacts, PerLengthPenaltyDoesNotDependOnTheSampleSpacing)
{
  // Two straight parallel strands 4.5 mm apart (contact distance 5 mm, δ = 0.5 mm), 10 cm
  // side by side, sampled every 1 cm or every 2.5 mm (a straight and a curly element's
  // spacing), at rest and so heavy (point masses of 1 kg) that the step moves them by
  // nothing: the law gives each contact k_c δ, and with the per-length penalty the total
  // normal force must be k δ L / ℓ_ref whatever the spacing (the lengths in contact of the
  // pairs of pieces add up to L on each strand; round-off 1e-9 relative). Per contact point
  // the total grows with the number of closest points.
  auto totalForce = [](bool perLength, double hA, double hB)
  {
    HairHairParameters p;
    p.thickness = 2.5e-3;
    p.perLength = perLength;
    std::vector<std::vector<StrandSample>> s(2);
    auto sample = [](double x, double y, double h)
    {
      StrandSample q;
      q.s = x;
      q.weight = h;
      q.position = Eigen::Vector3d(x, y, 0);
      q.velocity.setZero();
      return q;
    };
    for (int k = 0; k * hA <= 0.1 + 1e-12; ++k)
      s[0].push_back(sample(k * hA, 4.5e-3, hA));
    for (int k = 0; k * hB <= 0.1 + 1e-12; ++k)
      s[1].push_back(sample(k * hB, 0, hB));
    HairHairContacts h;
    EXPECT_TRUE(h.setParameters(p).ok());
    EXPECT_TRUE(h.detect(s, {}, Dt).ok());
    std::vector<StrandCompliance> c = {pointMasses(s[0], h.couplingSamples(0), 1, Dt),
                                       pointMasses(s[1], h.couplingSamples(1), 1, Dt)};
    EXPECT_TRUE(h.solve(c).ok());
    double F = 0;
    for (const Eigen::Vector3d& f : h.forces(0))
      F += f.y();
    return F;
  };
  const double k = HairHairParameters().stiffness, delta = 0.5e-3, L = 0.1, ref = 0.01;
  const double expected = k * delta * L / ref;
  for (const auto& [hA, hB] : {std::pair{0.01, 0.01}, {2.5e-3, 2.5e-3}, {0.01, 2.5e-3}})
  {
    // The penalty's own step compliance, 1 + (k h + c) h/m ≈ 1 + 1e-3, slightly softens it.
    EXPECT_NEAR(totalForce(true, hA, hB), expected, 2e-3 * expected) << hA << " " << hB;
  }
  const double coarse = totalForce(false, 0.01, 0.01), fine = totalForce(false, 2.5e-3, 2.5e-3);
  EXPECT_GT(fine, 2 * coarse);
  std::printf("10 cm of parallel contact, in units of k δ: per length %.3f; per point %.3f "
              "(1 cm spacing), %.3f (2.5 mm)\n",
              totalForce(true, 0.01, 0.01) / (k * delta), coarse / (k * delta), fine / (k * delta));
}

namespace
{
// The clump of ClumpScene (50 guides rooted on a 12 mm disc, smooth hair, in an air flow
// converging on the clump's axis, v = −β(t) (x, 0, z)), with ν = 2e-4 (20 × the smooth
// preset's, the flow's grip), β ramped to 25 1/s over `ramp`, then the root disc shaken
// vertically (1 cm, 3 Hz): one step per 1/30 s frame. Per frame: the mean distance to the
// clump's axis of the points at s = 0.2 m, the deepest pair (at the start of the step) and
// the pass-throughs since the previous frame.
struct ClumpRun
{
  std::vector<double> time, meanRadius, deepest;
  long passes = 0;
  double residual = 0, rootWork = 0;
};

Status runClump(bool withContacts, double ramp, double duration, double thickness, ClumpRun& out)
{
  ClumpSpec spec;
  spec.hair.airFriction = 2e-4;
  spec.rampTime = ramp;
  spec.startOscillation = ramp;
  std::vector<SuperHelix> strands;
  if (Status st = initializeClump(spec, strands); !st)
    return st;
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = thickness;
  if (Status st = contacts.setParameters(p); !st)
    return st;
  out = ClumpRun{};
  auto record = [&](double deepest)
  {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> x;
    for (const SuperHelix& h : strands)
    {
      x.push_back(h.position(0.2));
      centre += x.back() / spec.count;
    }
    double mean = 0;
    for (const Eigen::Vector3d& q : x)
      mean += Eigen::Vector2d(q.x() - centre.x(), q.z() - centre.z()).norm() / spec.count;
    out.time.push_back(strands[0].time());
    out.meanRadius.push_back(mean);
    out.deepest.push_back(deepest);
  };
  record(0);
  std::vector<std::vector<Eigen::Vector3d>> before = drawn(strands);
  const int frames = static_cast<int>(std::lround(duration / Dt));
  for (int f = 0; f < frames; ++f)
  {
    const Status st = withContacts ? stepStrandsWithContacts(strands, contacts, Dt, 2)
                                   : stepStrands(strands, Dt, 2);
    if (!st)
      return st;
    const std::vector<std::vector<Eigen::Vector3d>> after = drawn(strands);
    out.passes += static_cast<long>(findPassThroughs(before, after, 2 * thickness).size());
    before = after;
    record(withContacts ? contacts.stats().maxPenetration : 0);
  }
  for (const SuperHelix& h : strands)
  {
    out.residual += h.energy().total.residual;
    out.rootWork += std::abs(h.energy().total.rootWork) + std::abs(h.energy().total.windWork);
  }
  return Status::Ok();
}

double extreme(const ClumpRun& r, const std::vector<double>& series, double from, double to,
               bool largest)
{
  double m =
      largest ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < r.time.size(); ++i)
    if (r.time[i] >= from - 1e-9 && r.time[i] <= to + 1e-9)
      m = largest ? std::max(m, series[i]) : std::min(m, series[i]);
  return m;
}
} // namespace

TEST(HairHairContacts, ClumpKeepsItsVolumeWithoutPairsPassingThrough)
{
  // 50 disks of radius `thickness` that do not overlap cannot have a mean distance to their
  // centroid below that of their densest packing, (2/3) · thickness · √(50 / 0.9069) (a
  // disc of the hexagonal packing's density) = 0.74 × the initial mean, (2/3) ρ0. We require
  // 0.5 × the initial mean while squeezed and while shaken: the packing of disks overlapping
  // by up to 30 % (0.7 × 0.74), and no pair in by 30 % of 2 × thickness, and no pair
  // passing through another (the shaken clump needed up to 16 steps per frame with the
  // mirror model: docs/hair-hair-contacts.md). Without contacts the flow gathers every strand
  // onto the axis: "collapsed into a line" is a mean distance to the axis below one
  // thickness. (The ramp is 1.5 s here, the shaking 1.5 s: the study runs 3 s of each.)
  const double thickness = 1.2e-3, ramp = 1.5, duration = 3;
  ClumpRun with, without;
  Status st = runClump(true, ramp, duration, thickness, with);
  ASSERT_TRUE(st.ok()) << st.message();
  st = runClump(false, ramp, duration, thickness, without);
  ASSERT_TRUE(st.ok()) << st.message();
  const double initial = with.meanRadius[0];
  EXPECT_NEAR(initial, 2.0 / 3 * 0.012, 0.02 * initial); // the sunflower fills the disc
  EXPECT_GT(extreme(with, with.meanRadius, 0.5, duration, false), 0.5 * initial);
  EXPECT_LT(extreme(without, without.meanRadius, 1.2, ramp, true), thickness);
  EXPECT_LT(extreme(with, with.deepest, 0, duration, true), 0.3 * 2 * thickness);
  EXPECT_EQ(with.passes, 0);
  std::printf("mean radius at s = 0.2 m: initial %.3g mm; with contacts min %.3g mm squeezed, "
              "%.3g mm shaken; without, max %.3g mm at the end of the ramp; deepest pair %.3g mm "
              "(R = %.3g mm); pass-throughs %ld with, %ld without; residual %.3g J with, %.3g J "
              "without (|root| + |wind| work %.3g J)\n",
              1e3 * initial, 1e3 * extreme(with, with.meanRadius, 0.5, ramp, false),
              1e3 * extreme(with, with.meanRadius, ramp, duration, false),
              1e3 * extreme(without, without.meanRadius, 1.2, ramp, true),
              1e3 * extreme(with, with.deepest, 0, duration, true), 2e3 * thickness, with.passes,
              without.passes, with.residual, without.residual, with.rootWork);
}

TEST(HairHairContacts, AHeadOfOverlappingGuidesRuns)
{
  // 200 smooth guides rooted evenly on the cap y > 0.3 r of a 10 cm sphere, clamped pointing
  // down, the head turning ±10° at 0.5 Hz, clumps of thickness 0.4 √(cap area / count): near
  // the cap's rim the roots are closer in projection than 2 × thickness, so clumps start
  // overlapping by up to 11 mm (pushed with k δ ≈ 1e-2 N, 300 × a strand's weight). The
  // coupled step must run 1 s of it.
  const int count = 200;
  std::vector<SuperHelix> strands(count);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i)
  {
    const double y = 1 - 0.7 * (i + 0.5) / count;
    const double r = std::sqrt(1 - y * y), phi = i * golden;
    HeadShake shake;
    shake.amplitude = M_PI / 18;
    shake.frequency = 0.5;
    shake.attachment = 0.1 * Eigen::Vector3d(r * std::cos(phi), y, r * std::sin(phi));
    shake.attachmentFrame = frameWithTangent({0, -1, 0});
    StrandSpec s = StrandSpec::uniform(0.3, 10, HairParameters::roundStraight());
    s.id = i;
    s.root = shake;
    ASSERT_TRUE(strands[i].initialize(s).ok());
  }
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = 0.4 * std::sqrt(2 * M_PI * 0.1 * 0.1 * 0.7 / count);
  ASSERT_TRUE(contacts.setParameters(p).ok());
  for (int i = 0; i < 30; ++i)
  {
    const Status st = stepStrandsWithContacts(strands, contacts, Dt, 2);
    ASSERT_TRUE(st.ok()) << st.message();
  }
}

TEST(ClumpScene, RootsOnTheDiscAndBadSpecsRefused)
{
  // The sunflower pattern puts root i at radius R √((i + ½)/n): all inside the disc, the
  // outermost at R √(1 − 1/(2n)); every strand hangs along −y at rest.
  ClumpSpec spec;
  spec.count = 20;
  std::vector<SuperHelix> strands;
  ASSERT_TRUE(initializeClump(spec, strands).ok());
  ASSERT_EQ(strands.size(), 20u);
  double outer = 0;
  for (const SuperHelix& h : strands)
  {
    const Eigen::Vector3d r = h.position(0), tip = h.position(spec.length);
    outer = std::max(outer, std::hypot(r.x(), r.z()));
    EXPECT_NEAR((tip - r).normalized().y(), -1, 1e-12);
  }
  EXPECT_NEAR(outer, spec.discRadius * std::sqrt(1 - 0.5 / 20), 1e-15);
  EXPECT_EQ(clumpRootOffset(spec, 0.5 * spec.startOscillation), 0.0);
  spec.count = 0;
  const Status st = initializeClump(spec, strands);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("count"), std::string::npos) << st.message();
  EXPECT_EQ(strands.size(), 20u); // left as it was
}
