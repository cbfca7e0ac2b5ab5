// Hair–hair contacts between Super-Helix guide strands (docs/hair-hair-contacts.md), driven
// through the strands' contact hook at dt = 1/30 s.
// References: brute-force O(n²) search for the broad phase; Newton's third law for the pair
// forces; the strands' own energy budget (docs/super-helix.md) for the contact work; the
// static penetration of a penalty, load / stiffness.
#include "ClumpScene.h"
#include "HeadShake.h"
#include "contact/HairHairContacts.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace hair;

namespace
{
constexpr double Dt = 1.0 / 30;

// A right-handed frame whose first column is `tangent`.
Eigen::Matrix3d frameWithTangent(const Eigen::Vector3d& tangent)
{
  Eigen::Matrix3d f;
  f.col(0) = tangent.normalized();
  f.col(1) = f.col(0).unitOrthogonal();
  f.col(2) = f.col(0).cross(f.col(1));
  return f;
}

// Smallest distance between the centrelines of two strands (8 points per element).
double centrelineDistance(const SuperHelix& a, const SuperHelix& b)
{
  std::vector<Eigen::Vector3d> pa, pb;
  a.polyline(8, pa);
  b.polyline(8, pb);
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i + 1 < pa.size(); ++i)
    for (size_t j = 0; j + 1 < pb.size(); ++j)
    {
      double u, v;
      best = std::min(best, closestPointsOfSegments(pa[i], pa[i + 1], pb[j], pb[j + 1], u, v));
    }
  return std::sqrt(best);
}

// Steps every strand once, the contacts (if any) updated from all strands first.
Status stepAll(std::vector<SuperHelix>& strands, HairHairContacts* contacts, int threads = 2)
{
  if (contacts)
  {
    Status st = findHairHairContacts(strands, *contacts);
    if (!st)
      return st;
  }
  return stepStrands(strands, Dt, threads);
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

TEST(HairHairContacts, BadParametersAreRefusedWithTheirName)
{
  struct Case
  {
    const char* name;
    void (*set)(HairHairParameters&);
  };
  const Case cases[] = {
      {"thickness", [](HairHairParameters& p) { p.thickness = 0; }},
      {"thickness", [](HairHairParameters& p) { p.thickness = std::nan(""); }},
      {"thickness", [](HairHairParameters& p) { p.thickness = 2.5; }},
      {"stiffness", [](HairHairParameters& p) { p.stiffness = -1; }},
      {"stiffness", [](HairHairParameters& p) { p.stiffness = INFINITY; }},
      {"damping", [](HairHairParameters& p) { p.damping = -1e-4; }},
      {"friction", [](HairHairParameters& p) { p.friction = std::nan(""); }},
      {"margin", [](HairHairParameters& p) { p.margin = -1; }},
      {"margin", [](HairHairParameters& p) { p.margin = 3; }},
      {"cellSize", [](HairHairParameters& p) { p.cellSize = -0.1; }},
      {"maxForce", [](HairHairParameters& p) { p.maxForce = 0; }},
      {"threads", [](HairHairParameters& p) { p.threads = 0; }},
      {"allowedDepth", [](HairHairParameters& p) { p.allowedDepth = 1; }},
      {"maxForce", [](HairHairParameters& p) { p.maxForce = INFINITY; }},
      {"referenceLength", [](HairHairParameters& p) { p.referenceLength = 0; }},
      {"referenceLength", [](HairHairParameters& p) { p.referenceLength = std::nan(""); }},
  };
  for (const Case& c : cases)
  {
    HairHairParameters p;
    c.set(p);
    HairHairContacts h;
    const Status st = h.setParameters(p);
    ASSERT_FALSE(st.ok()) << c.name;
    EXPECT_NE(st.message().find(c.name), std::string::npos) << st.message();
  }
  EXPECT_TRUE(HairHairParameters().validate().ok());
  // Bad input to update: duplicate ids, non-finite samples.
  HairHairContacts h;
  std::vector<std::vector<StrandSample>> s(2, std::vector<StrandSample>(3));
  for (auto& strand : s)
    for (int k = 0; k < 3; ++k)
    {
      strand[k].s = 0.01 * (k + 1);
      strand[k].weight = 0.01;
    }
  Status st = h.update(s, {4, 4});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("same id"), std::string::npos) << st.message();
  s[1][2].position.x() = std::nan("");
  st = h.update(s);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("non-finite"), std::string::npos) << st.message();
}

TEST(HairHairContacts, CrossingPairGetsThePenaltyDampingAndFrictionOfTheEquations)
{
  // Two straight strands crossing at right angles, 4.5 mm apart (contact distance 5 mm), the
  // crossing in the middle of a piece of each; A moves towards B at 1 cm/s and along B at
  // 2 cm/s. The force on A must be (k δ − c_n w_n) n − c_t w_t (docs/hair-hair-contacts.md),
  // spread over A's two samples and written per unit length (Σ weight × f = F), B getting
  // the opposite; the implicit blocks summed over A's samples must be 2 k n nᵀ and
  // 2 (c_n n nᵀ + c_t (I − n nᵀ)) (the mirror model).
  HairHairParameters p;
  const double gap = 4.5e-3, delta = 2 * p.thickness - gap;
  std::vector<std::vector<StrandSample>> s(2);
  const Eigen::Vector3d vA(0, -0.01, 0.02);
  for (int k = 0; k < 4; ++k)
  {
    StrandSample a, b;
    a.s = b.s = 0.01 * k + 0.005;
    a.weight = b.weight = 0.01;
    a.position = Eigen::Vector3d(0.01 * k - 0.013, gap, 0); // A along x, above B
    a.velocity = vA;
    b.position = Eigen::Vector3d(0, 0, 0.01 * k - 0.017); // B along z
    s[0].push_back(a);
    s[1].push_back(b);
  }
  HairHairContacts h;
  ASSERT_TRUE(h.setParameters(p).ok());
  ASSERT_TRUE(h.update(s).ok());
  ASSERT_EQ(h.stats().contacts, 1);
  const Eigen::Vector3d n(0, 1, 0);
  const double wn = vA.dot(n);
  const Eigen::Vector3d wt = vA - wn * n;
  const Eigen::Vector3d expected = (p.stiffness * delta - p.damping * wn) * n - p.friction * wt;
  ASSERT_LT(expected.norm(), p.maxForce); // not capped
  for (int strand = 0; strand < 2; ++strand)
  {
    std::vector<ContactResponse> r(4);
    h.addResponses(strand, s[strand], r);
    Eigen::Vector3d F = Eigen::Vector3d::Zero();
    Eigen::Matrix3d K = Eigen::Matrix3d::Zero(), D = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 4; ++k)
    {
      F += s[strand][k].weight * r[k].force;
      K += s[strand][k].weight * r[k].stiffness;
      D += s[strand][k].weight * r[k].damping;
    }
    // Round-off: a few operations on numbers of order 1e-4 N.
    EXPECT_LT((F - (strand == 0 ? 1 : -1) * expected).norm(), 1e-15) << strand;
    const Eigen::Matrix3d nn = n * n.transpose();
    EXPECT_LT((K - 2 * p.stiffness * nn).norm(), 1e-15);
    EXPECT_LT((D - 2 * (p.damping * nn + p.friction * (Eigen::Matrix3d::Identity() - nn))).norm(),
              1e-15);
  }
  // The crossing is at u = 0.3 of A's piece 1 (samples 1 and 2): 0.7 and 0.3 of F.
  std::vector<ContactResponse> r(4);
  h.addResponses(0, s[0], r);
  EXPECT_LT((s[0][1].weight * r[1].force - 0.7 * expected).norm(), 1e-15);
  EXPECT_LT((s[0][2].weight * r[2].force - 0.3 * expected).norm(), 1e-15);
  EXPECT_TRUE(r[0].force.isZero(0) && r[3].force.isZero(0));
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

TEST(HairHairContacts, PerLengthPenaltyDoesNotDependOnTheSampleSpacing)
{
  // Two straight parallel strands 4.5 mm apart (contact distance 5 mm, δ = 0.5 mm, below
  // the cap), 10 cm side by side, sampled every 1 cm or every 2.5 mm (a straight and a
  // curly element's spacing). With the per-length penalty the total normal force must be
  // k δ L / ℓ_ref whatever the spacing: the lengths in contact of the pairs of pieces add up
  // to L on each strand (round-off bound 1e-12 relative). Per contact point it grows with
  // the number of pairs: the finer spacing must push at least twice as hard (the defect the
  // option removes, docs/hair-hair-contacts.md).
  auto totalForce = [](bool perLength, double hA, double hB)
  {
    HairHairParameters p;
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
    EXPECT_TRUE(h.update(s).ok());
    std::vector<ContactResponse> r(s[0].size());
    h.addResponses(0, s[0], r);
    double F = 0;
    for (size_t k = 0; k < r.size(); ++k)
      F += s[0][k].weight * r[k].force.y();
    return F;
  };
  const double k = HairHairParameters().stiffness, delta = 0.5e-3, L = 0.1, ref = 0.01;
  const double expected = k * delta * L / ref;
  for (const auto& [hA, hB] : {std::pair{0.01, 0.01}, {2.5e-3, 2.5e-3}, {0.01, 2.5e-3}})
  {
    EXPECT_NEAR(totalForce(true, hA, hB), expected, 1e-12 * expected) << hA << " " << hB;
  }
  const double coarse = totalForce(false, 0.01, 0.01), fine = totalForce(false, 2.5e-3, 2.5e-3);
  EXPECT_GT(fine, 2 * coarse);
  std::printf("10 cm of parallel contact, in units of k δ: per length %.3f; per point %.3f "
              "(1 cm spacing), %.3f (2.5 mm)\n",
              totalForce(true, 0.01, 0.01) / (k * delta), coarse / (k * delta), fine / (k * delta));
}

TEST(HairHairContacts, GridFindsTheSamePairsAsBruteForce)
{
  // Random polylines (random walks) in a 5 cm box, thickness and margin such that many
  // pieces are near: every pair of pieces of different strands whose grown boxes overlap
  // must come out of the grid once, and nothing else; and every pair closer than
  // 2 × thickness must be a contact.
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
    p.margin = trial % 2 ? 0 : 2e-3;
    p.cellSize = trial % 3 == 0 ? 0 : 0.004; // automatic, and smaller than the boxes
    HairHairContacts h;
    ASSERT_TRUE(h.setParameters(p).ok());
    ASSERT_TRUE(h.update(s).ok());
    const double grow = p.thickness + 0.5 * p.margin;
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
                                        s[b][j + 1].position, u, v) < 4 * p.thickness * p.thickness)
              ++close;
          }
    std::sort(brute.begin(), brute.end());
    EXPECT_EQ(h.candidatePairs(), brute) << "trial " << trial;
    // Contacts: the close pairs, less those whose closest point is a shared vertex reported
    // by the neighbouring piece as well (counted once there); never more.
    EXPECT_LE(h.stats().contacts, close);
    contacts += h.stats().contacts;
  }
  EXPECT_GT(contacts, 100) << "the configurations must have contacts to test";
}

TEST(HairHairContacts, ThreadsFindTheSameContactsInTheSameOrder)
{
  // 300 random walks in a 3 cm box: tens of thousands of candidate pairs, split over 1, 2
  // and 3 threads; the merged result must be the same to the bit.
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> box(0, 0.03), step(-0.004, 0.004), vel(-0.1, 0.1);
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
  std::vector<HairHairContact> reference;
  for (int threads : {1, 2, 3})
  {
    HairHairParameters p;
    p.threads = threads;
    HairHairContacts h;
    ASSERT_TRUE(h.setParameters(p).ok());
    ASSERT_TRUE(h.update(s).ok());
    ASSERT_GT(h.stats().candidatePairs, 3 * 4096) << "too few candidates to split";
    if (threads == 1)
    {
      reference = h.contacts();
      continue;
    }
    ASSERT_EQ(h.contacts().size(), reference.size());
    for (size_t c = 0; c < reference.size(); ++c)
    {
      EXPECT_EQ(h.contacts()[c].sA, reference[c].sA);
      EXPECT_EQ(h.contacts()[c].sB, reference[c].sB);
      EXPECT_EQ(h.contacts()[c].forceOnA, reference[c].forceOnA);
    }
    std::vector<ContactResponse> r1(30), r2(30);
    h.addResponses(7, s[7], r2);
    HairHairContacts one;
    ASSERT_TRUE(one.update(s).ok());
    one.addResponses(7, s[7], r1);
    for (int k = 0; k < 30; ++k)
      EXPECT_EQ(r1[k].force, r2[k].force);
  }
}

namespace
{
// Two strands whose roots move towards each other; the closest approach of their centrelines
// over the run. Strand A is clamped horizontally (tangent +z) and droops; strand B is its
// mirror image, clamped at z = 2D facing −z, D being how far A's free part hangs out in z,
// so that their hanging parts meet. Their roots move to x = 0 (they stay 2D apart).
struct PairEnergy
{
  double contactWork = 0, residual = 0, dissipated = 0, penalty = 0, arrival = 0;
  double netForce = 0, pairForce = 0; ///< |Σ forces| and Σ |forces| at the last update
};

Status pushTogether(bool withContacts, double& closest, double& depthAtRest, double thickness,
                    PairEnergy* energy = nullptr, bool perLength = false)
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
  if (withContacts)
    for (SuperHelix& h : strands)
      h.setContactForces(contacts.hook());
  closest = std::numeric_limits<double>::infinity();
  depthAtRest = 0;
  if (energy)
    *energy = PairEnergy{};
  for (int i = 0; i < 180; ++i) // 6 s: 2 s settling, 2 s moving, 2 s still
  {
    if (!(st = stepAll(strands, withContacts ? &contacts : nullptr)))
      return st;
    if (energy)
      energy->arrival += contacts.stats().arrivalEnergy;
    closest = std::min(closest, centrelineDistance(strands[0], strands[1]));
  }
  depthAtRest = 2 * thickness - centrelineDistance(strands[0], strands[1]);
  if (energy)
  {
    for (const SuperHelix& h : strands)
    {
      energy->contactWork += h.energy().total.contactWork;
      energy->residual += h.energy().total.residual;
      energy->dissipated += h.energy().total.frictionDissipated + h.energy().total.airDissipated;
    }
    // Momentum: the responses the hook gives every strand at the update's configuration,
    // integrated along the strands (Σ weight × force per unit length), must cancel.
    if (!(st = findHairHairContacts(strands, contacts)))
      return st;
    energy->penalty = contacts.stats().potentialEnergy;
    Eigen::Vector3d net = Eigen::Vector3d::Zero();
    for (const SuperHelix& h : strands)
    {
      const std::vector<StrandSample>& smp = h.samples();
      std::vector<ContactResponse> r(smp.size());
      contacts.addResponses(h.spec().id, smp, r);
      for (size_t i = 0; i < smp.size(); ++i)
      {
        net += smp[i].weight * r[i].force;
        energy->pairForce += smp[i].weight * r[i].force.norm();
      }
    }
    energy->netForce = net.norm();
  }
  return Status::Ok();
}
} // namespace

TEST(HairHairContacts, StrandsPushedTogetherDoNotPassThrough)
{
  // The load pressing the two hanging parts together is the lateral pull of gravity on a
  // strand pushed aside by about a thickness: ~ ρS g L × (thickness / L) ≈ 2.5e-7 N, which
  // the default penalty (0.1 N/m) holds at a static penetration of ~ 3 µm per contact,
  // 0.05 % of 2 × thickness. Contacts are found at the start of a step, so a pair first
  // seen in contact can already be in by its relative motion over one step: the roots close
  // at ≤ 2 × 2.25 cm/s, ≤ 1.5 mm per step (30 % of 2 × thickness) and the overdamped
  // hanging parts follow them no faster. Hence the bound: above 70 % of 2 × thickness.
  const double thickness = 2.5e-3;
  double closest = 0, depth = 0;
  Status st = pushTogether(true, closest, depth, thickness);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_GT(closest, 0.7 * 2 * thickness);
  // At rest, pressed together: the static penetration, well under the 30 % transient.
  EXPECT_LT(depth, 0.1 * 2 * thickness);
  // Without contacts the hanging parts, mirror images of each other, go into each other by
  // more than half the contact distance.
  double closestFree = 0, depthFree = 0;
  st = pushTogether(false, closestFree, depthFree, thickness);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_LT(closestFree, 0.5 * 2 * thickness);
  PairEnergy e;
  st = pushTogether(true, closest, depth, thickness, &e);
  ASSERT_TRUE(st.ok()) << st.message();
  // Newton's third law: the forces on the two strands cancel to round-off (1e-12 of their
  // magnitude: a few dozen double-precision operations each).
  EXPECT_GT(e.pairForce, 0) << "the strands must be in contact at the end";
  EXPECT_LT(e.netForce, 1e-12 * e.pairForce);
  // Energy: the contact forces are a convex penalty plus dissipation, stepped implicitly
  // (backward Euler dissipates on a convex potential), so their total work cannot exceed
  // minus the penalty energy stored at the end (0 at the start), except for what a contact
  // found at the start of a step already in gives back without having taken it: the
  // arrival energy Σ ½ k δ² of new contacts.
  EXPECT_LE(e.contactWork, -e.penalty + e.arrival);
  std::printf("contact work %.3g J, penalty energy at the end %.3g J, arrival energy %.3g J, "
              "residual %.3g J, friction + air %.3g J; |Σ F| = %.3g N of Σ |F| = %.3g N\n",
              e.contactWork, e.penalty, e.arrival, e.residual, e.dissipated, e.netForce,
              e.pairForce);
  std::printf("closest approach: %.3g mm with contacts, %.3g mm without (2 × thickness = %.3g "
              "mm)\n",
              1e3 * closest, 1e3 * closestFree, 2e3 * thickness);
}

TEST(HairHairContacts, StrandsPushedTogetherDoNotPassThroughWithThePerLengthPenalty)
{
  // The same pair with the per-length penalty (ℓ_ref = 1 cm, these straight strands' samples
  // are 7–12 mm apart, so about the per-point force): the same bounds, the same third law
  // and the same energy inequality (the penalty energy is ½ k δ² ℓ_c / ℓ_ref per contact).
  const double thickness = 2.5e-3;
  double closest = 0, depth = 0;
  PairEnergy e;
  const Status st = pushTogether(true, closest, depth, thickness, &e, true);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_GT(closest, 0.7 * 2 * thickness);
  EXPECT_LT(depth, 0.1 * 2 * thickness);
  EXPECT_GT(e.pairForce, 0) << "the strands must be in contact at the end";
  EXPECT_LT(e.netForce, 1e-12 * e.pairForce);
  EXPECT_LE(e.contactWork, -e.penalty + e.arrival);
  std::printf("per length: closest approach %.3g mm, depth at rest %.3g mm; contact work %.3g J, "
              "penalty %.3g J, arrival %.3g J\n",
              1e3 * closest, 1e3 * depth, e.contactWork, e.penalty, e.arrival);
}

namespace
{
// The benchmark's head of hair (bench_hair_hair.cxx): `count` smooth guides rooted evenly on
// the cap y > 0.3 r of a 10 cm sphere, clamped pointing down, the head turning ±10° at
// 0.5 Hz, clumps of thickness 0.4 √(cap area / count). Near the cap's rim the roots are
// closer in projection than 2 × thickness, so clumps start overlapping by up to 11 mm.
Status headOfHair(int count, double maxForce, int frames)
{
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
    Status st = strands[i].initialize(s);
    if (!st)
      return st;
  }
  HairHairContacts contacts;
  HairHairParameters p;
  p.thickness = 0.4 * std::sqrt(2 * M_PI * 0.1 * 0.1 * 0.7 / count);
  p.maxForce = maxForce;
  Status st = contacts.setParameters(p);
  if (!st)
    return st;
  for (SuperHelix& h : strands)
    h.setContactForces(contacts.hook());
  for (int i = 0; i < frames; ++i)
    if (!(st = stepAll(strands, &contacts)))
      return st;
  return Status::Ok();
}
} // namespace

TEST(HairHairContacts, AHeadOfOverlappingGuidesRunsCappedAndUncapped)
{
  // The deep initial overlaps of this head push with k δ ≈ 1e-3 N per contact point (30 ×
  // a strand's weight), ten times the default cap (1e-4 N); the single step with implicit
  // tension stiffness (docs/super-helix.md) must run both, capped and uncapped, for 3 s.
  Status st = headOfHair(200, HairHairParameters().maxForce, 90);
  EXPECT_TRUE(st.ok()) << st.message();
  st = headOfHair(200, 1e3, 90);
  EXPECT_TRUE(st.ok()) << "uncapped: " << st.message();
}

namespace
{
// A clump of `count` guides rooted on a horizontal disc of radius rho0 (sunflower pattern),
// clamped pointing down, in an air flow converging on the clump's axis, v = −β(t) (x, 0, z),
// β ramped from 0 to betaMax over rampTime: it squeezes the clump as a hand gathering hair
// would, so that without hair–hair contacts every strand drifts onto the axis. From
// startOscillation on, the root disc oscillates vertically (amplitude, frequency), as in the
// Super-Helices paper's clump experiment. Every frame of Dt, the contacts are updated and the
// strands stepped `updatesPerFrame` times by Dt / updatesPerFrame. Records per frame the mean
// distance to the clump's axis of the points at arc length sProbe and their span ℓ_A
// (largest horizontal distance between two of them).
struct ClumpSetup
{
  /// The clump (ClumpScene's defaults: 50 guides on a 12 mm disc, 30 cm, β = 25 1/s over
  /// 3 s, 1 cm at 3 Hz from 3 s) with ν = 2e-4: 20 × the smooth preset's, the flow's grip.
  ClumpSpec scene = []
  {
    ClumpSpec c;
    c.hair.airFriction = 2e-4;
    return c;
  }();
  double sProbe = 0.2, duration = 6;
  bool contacts = true;
  int updatesPerFrame = 1;     ///< 0: as many as HairHairContacts::updatesPerStep asks (≤ 16)
  bool checkCoherence = false; ///< compare every update with a grid rebuilt from scratch
  HairHairParameters parameters;
};

struct ClumpRun
{
  std::vector<double> time, meanRadius, span, maxPenetration;
  double contactWork = 0, residual = 0, penaltyEnergy = 0, arrivalEnergy = 0;
  long coherenceMismatches = 0, updates = 0, rebuilds = 0, frames = 0;
};

Status runClump(const ClumpSetup& c, ClumpRun& out)
{
  std::vector<SuperHelix> strands;
  if (Status st = initializeClump(c.scene, strands); !st)
    return st;
  HairHairContacts contacts, fresh;
  Status st = contacts.setParameters(c.parameters);
  if (!st)
    return st;
  HairHairParameters noCoherence = c.parameters;
  noCoherence.margin = 0;
  if (!(st = fresh.setParameters(noCoherence)))
    return st;
  if (c.contacts)
    for (SuperHelix& h : strands)
      h.setContactForces(contacts.hook());
  out = ClumpRun{};
  double deepest = 0;
  auto record = [&]()
  {
    std::vector<Eigen::Vector3d> p;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const SuperHelix& h : strands)
    {
      p.push_back(h.position(c.sProbe));
      centre += p.back();
    }
    centre /= c.scene.count;
    double mean = 0, span = 0;
    for (size_t i = 0; i < p.size(); ++i)
    {
      mean += Eigen::Vector2d(p[i].x() - centre.x(), p[i].z() - centre.z()).norm();
      for (size_t j = 0; j < i; ++j)
        span = std::max(span, Eigen::Vector2d(p[i].x() - p[j].x(), p[i].z() - p[j].z()).norm());
    }
    out.time.push_back(strands[0].time());
    out.meanRadius.push_back(mean / c.scene.count);
    out.span.push_back(span);
    out.maxPenetration.push_back(deepest);
    deepest = 0;
  };
  record();
  const int frames = static_cast<int>(std::lround(c.duration / Dt));
  for (int f = 0; f < frames; ++f)
  {
    // Fixed: updatesPerFrame equal steps. Adaptive: after every update, the rest of the frame
    // is cut into as many steps as updatesPerStep asks, and one of them is taken.
    double remaining = Dt;
    for (int u = 0; remaining > 1e-12 * Dt; ++u)
    {
      double h = c.updatesPerFrame > 0 ? Dt / c.updatesPerFrame : remaining;
      if (c.contacts)
      {
        if (!(st = findHairHairContacts(strands, contacts)))
          return st;
        if (c.updatesPerFrame <= 0)
          h = remaining / contacts.updatesPerStep(remaining);
        ++out.updates;
        out.rebuilds += contacts.stats().rebuilt;
        out.arrivalEnergy += contacts.stats().arrivalEnergy;
        deepest = std::max(deepest, contacts.stats().maxPenetration);
        if (c.checkCoherence)
        {
          if (!(st = findHairHairContacts(strands, fresh)))
            return st;
          const HairHairStats &a = contacts.stats(), &b = fresh.stats();
          if (a.contacts != b.contacts ||
              std::abs(a.potentialEnergy - b.potentialEnergy) > 1e-12 * b.potentialEnergy)
            ++out.coherenceMismatches;
        }
      }
      if (c.updatesPerFrame > 0 && u + 1 == c.updatesPerFrame)
        h = remaining; // the last step ends exactly at the frame
      if (!(st = stepStrands(strands, h, 2)))
        return st;
      remaining -= h;
    }
    ++out.frames;
    record();
  }
  for (const SuperHelix& h : strands)
  {
    out.contactWork += h.energy().total.contactWork;
    out.residual += h.energy().total.residual;
  }
  if (c.contacts)
  {
    if (!(st = findHairHairContacts(strands, contacts)))
      return st;
    out.penaltyEnergy = contacts.stats().potentialEnergy;
  }
  return Status::Ok();
}

// Smallest value of `series` over the frames with time in [from, to].
double smallest(const ClumpRun& r, const std::vector<double>& series, double from, double to)
{
  double m = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < r.time.size(); ++i)
    if (r.time[i] >= from - 1e-9 && r.time[i] <= to + 1e-9)
      m = std::min(m, series[i]);
  return m;
}

double largest(const ClumpRun& r, const std::vector<double>& series, double from, double to)
{
  double m = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < r.time.size(); ++i)
    if (r.time[i] >= from - 1e-9 && r.time[i] <= to + 1e-9)
      m = std::max(m, series[i]);
  return m;
}
} // namespace

TEST(HairHairContacts, ClumpKeepsItsVolume)
{
  // 50 disks of radius `thickness` that do not overlap cannot have a mean distance to their
  // centroid below that of their densest packing, (2/3) · thickness · √(50 / 0.9069) (a
  // disc of the hexagonal packing's density) = 0.74 × the initial mean, (2/3) ρ0. We require
  // 0.5 × the initial mean: the packing of disks overlapping by up to 30 % (0.7 × 0.74),
  // the first-contact bound of the two-strand test. Without contacts the flow gathers every
  // strand onto the axis: "collapsed into a line" is a mean distance to the axis below one
  // clump thickness.
  const double thickness = 1.2e-3;
  ClumpSetup c;
  c.parameters.thickness = thickness;
  c.checkCoherence = true;
  ClumpRun with, without;
  Status st = runClump(c, with);
  ASSERT_TRUE(st.ok()) << st.message();
  c.contacts = false;
  st = runClump(c, without);
  ASSERT_TRUE(st.ok()) << st.message();
  const double initial = with.meanRadius[0];
  EXPECT_NEAR(initial, 2.0 / 3 * c.scene.discRadius,
              0.02 * initial); // the sunflower fills the disc
  // Squeezed (t in [1, 3] s: the flow at a third of its strength and more).
  EXPECT_GT(smallest(with, with.meanRadius, 1, 3), 0.5 * initial);
  EXPECT_LT(largest(without, without.meanRadius, 2, 3), thickness);
  // Temporal coherence changes nothing: every update found the contacts a rebuilt grid finds.
  EXPECT_EQ(with.coherenceMismatches, 0);
  // Energy, as for the pair: the contacts' total work is at most minus the penalty energy
  // left at the end plus the arrival energy of contacts found already in.
  EXPECT_LE(with.contactWork, -with.penaltyEnergy + with.arrivalEnergy);
  std::printf("mean radius at s = %.2f m: initial %.3g mm; squeezed min %.3g mm with contacts, "
              "max %.3g mm without; oscillating (3-6 s) min %.3g mm with, max %.3g mm without\n",
              c.sProbe, 1e3 * initial, 1e3 * smallest(with, with.meanRadius, 1, 3),
              1e3 * largest(without, without.meanRadius, 2, 3),
              1e3 * smallest(with, with.meanRadius, 3, 6),
              1e3 * largest(without, without.meanRadius, 3, 6));
  std::printf("deepest penetration %.3g mm (2 × thickness = %.3g mm); updates %ld, grid rebuilt "
              "%ld; contact work %.3g J, penalty left %.3g J, arrival %.3g J, residual %.3g J\n",
              1e3 * largest(with, with.maxPenetration, 0, 6), 2e3 * thickness, with.updates,
              with.rebuilds, with.contactWork, with.penaltyEnergy, with.arrivalEnergy,
              with.residual);
}

namespace
{
// The bounds of a shaken clump (derived in ClumpKeepsItsVolume): mean distance to the
// axis above half its initial value from 1 s on, no pair in by 30 % of 2 × thickness.
void expectShakenClumpHolds(const ClumpRun& run, double thickness)
{
  EXPECT_GT(smallest(run, run.meanRadius, 1, 6), 0.5 * run.meanRadius[0]);
  EXPECT_LT(largest(run, run.maxPenetration, 0, 6), 0.3 * 2 * thickness);
}
} // namespace

TEST(HairHairContacts, ClumpKeepsItsVolumeWhenShakenWithFourUpdatesPerFrame)
{
  // Through the vertical oscillation (3 Hz, 1 cm), with the contacts updated and the strands
  // stepped 4 times per 1/30 s frame: the same bounds as above, and no pair in by more than
  // 30 % of 2 × thickness (the bound the 0.5 is derived from). At one update per frame the
  // shaken clump has pairs that go through each other (docs/hair-hair-contacts.md).
  const double thickness = 1.2e-3;
  ClumpSetup c;
  c.parameters.thickness = thickness;
  c.updatesPerFrame = 4;
  ClumpRun with;
  const Status st = runClump(c, with);
  ASSERT_TRUE(st.ok()) << st.message();
  const double initial = with.meanRadius[0];
  expectShakenClumpHolds(with, thickness);
  EXPECT_LE(with.contactWork, -with.penaltyEnergy + with.arrivalEnergy);
  std::printf("4 updates per frame: mean radius min %.3g mm (initial %.3g mm), deepest "
              "penetration %.3g mm\n",
              1e3 * smallest(with, with.meanRadius, 1, 6), 1e3 * initial,
              1e3 * largest(with, with.maxPenetration, 0, 6));
}

TEST(HairHairContacts, ClumpShakenWithAdaptiveUpdatesKeepsItsPairsApart)
{
  // As above, the updates chosen by updatesPerStep from the closing speeds (after each
  // update, the rest of the frame is cut into as many steps as it asks, ≤ 16). It aims at
  // allowedDepth = 15 % of 2 × thickness at the current speeds; speeds change within a step
  // and pairs beyond the boxes' reach are not seen, so we hold it to 30 %, the bound the
  // volume's 0.5 is derived from.
  const double thickness = 1.2e-3;
  ClumpSetup c;
  c.parameters.thickness = thickness;
  c.parameters.allowedDepth = 0.15;
  c.updatesPerFrame = 0;
  ClumpRun with;
  const Status st = runClump(c, with);
  ASSERT_TRUE(st.ok()) << st.message();
  const double initial = with.meanRadius[0];
  expectShakenClumpHolds(with, thickness);
  std::printf("adaptive: %.2f updates per frame on average; mean radius min %.3g mm (initial "
              "%.3g mm), deepest penetration %.3g mm\n",
              static_cast<double>(with.updates) / with.frames,
              1e3 * smallest(with, with.meanRadius, 1, 6), 1e3 * initial,
              1e3 * largest(with, with.maxPenetration, 0, 6));
}

// For the studies (the paper's clump under vertical oscillation, figures 6–7): the span ℓ_A
// of the clump at s = 0.2 m over time for several internal frictions γ, as CSV on stdout.
// Run: test_hair_hair_contacts --gtest_also_run_disabled_tests
//        --gtest_filter='*DISABLED_ClumpSpanCsv*'
// Environment: HAIR_CLUMP_UPDATES (updates per frame, default 4; 0: as updatesPerStep asks),
// HAIR_CLUMP_DURATION (s, default 6).
TEST(HairHairContacts, DISABLED_ClumpSpanCsv)
{
  ClumpSetup c;
  c.parameters.thickness = 1.2e-3;
  c.updatesPerFrame =
      std::getenv("HAIR_CLUMP_UPDATES") ? std::atoi(std::getenv("HAIR_CLUMP_UPDATES")) : 4;
  if (std::getenv("HAIR_CLUMP_DURATION"))
    c.duration = std::atof(std::getenv("HAIR_CLUMP_DURATION"));
  const double gammas[] = {5e-11, 1e-10, 2e-10, 5e-10}; // the paper's range (design note)
  std::vector<ClumpRun> runs;
  for (double g : gammas)
  {
    c.scene.hair.internalFriction = g;
    runs.emplace_back();
    const Status st = runClump(c, runs.back());
    ASSERT_TRUE(st.ok()) << st.message();
  }
  std::printf("time_s");
  for (double g : gammas)
    std::printf(",span_m_gamma_%g,mean_radius_m_gamma_%g", g, g);
  std::printf("\n");
  for (size_t i = 0; i < runs[0].time.size(); ++i)
  {
    std::printf("%.6f", runs[0].time[i]);
    for (const ClumpRun& r : runs)
      std::printf(",%.6g,%.6g", r.span[i], r.meanRadius[i]);
    std::printf("\n");
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
