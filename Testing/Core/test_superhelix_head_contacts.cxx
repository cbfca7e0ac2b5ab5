// Super-Helix strands on the bundled head (Data/body.vtk, Data/body_parts.txt) with hair–body
// contacts at dt = 1/30 s: one strand draped over the head, measured with the tables and with
// the exact mesh (CGAL); and the demo's head-shake scene (Scripts/demo_simulation.py: 200
// wavy guides of 30 cm, 10 elements, combed, head shaking ±0.5 rad at 1 Hz, wind 0.5 m/s
// from the front, 5 s), whose penetration statistics per frame docs/superhelix-contacts.md
// records (this test prints them).
#include "DemoScene.h"
#include "ProjectiveScenes.h"
#include "contact/BodyContacts.h"
#include "geometry/TriangleMesh.h"
#include "simulation/Simulation.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

using namespace hair;

namespace
{
const BundledBody& body()
{
  static BundledBody b;
  static Status st = loadBundledBody(HAIR_DATA_DIR, b);
  EXPECT_TRUE(st.ok()) << st.message();
  return b;
}

/// Signed distance to the exact mesh (> 0 inside), by CGAL.
double meshDepth(const MeshQueries& mesh, const Eigen::Vector3d& p)
{
  const double d = (mesh.closestPoint(p) - p).norm();
  return mesh.isInside(p) ? d : -d;
}
} // namespace

namespace
{
void drapeOverHead(Integrator integrator, long& firstOrder)
{
  firstOrder = 0;
  // A smooth strand of 25 cm rooted 2 mm above the crown, growing sideways (+x) over the
  // head, left 5 s under gravity: it drapes over the side of the head and rests.
  const BundledBody& b = body();
  const PosedPart head = PosedPart::still(b.parts[b.head].table);
  const TableQuery top = head.query(b.headCentre + Eigen::Vector3d(0, 0.2, 0));
  ASSERT_TRUE(top.covered);
  HairParameters hp = HairParameters::preset(HairType::Smooth);
  StrandSpec s = StrandSpec::uniform(0.25, 10, hp);
  s.integrator = integrator;
  const Eigen::Vector3d root = top.surfacePoint + 0.002 * top.normal;
  s.root = [root](double)
  {
    RootState r;
    r.position = root;
    r.orientation.col(0) = Eigen::Vector3d::UnitX();
    r.orientation.col(1) = Eigen::Vector3d::UnitY();
    r.orientation.col(2) = Eigen::Vector3d::UnitZ();
    return r;
  };
  SuperHelix h;
  ASSERT_TRUE(h.initialize(s).ok());
  BodyContacts contacts;
  ASSERT_TRUE(contacts.setParameters(BodyContactParameters()).ok());
  const std::vector<PosedPart> bodies = {PosedPart::still(b.parts[b.head].table),
                                         PosedPart::still(b.parts[b.trunk].table)};
  const double rhoS = hp.linearDensity();
  h.setContactForces(
      [&](int, double, const std::vector<StrandSample>& smp, std::vector<ContactResponse>& r)
      { contacts.respond(smp, rhoS, bodies.data(), 2, r); });
  // 10 s: long enough to be at rest (speed below, within 3 ε).
  for (int i = 0; i < 300; ++i)
  {
    const Status st = h.step(1.0 / 30);
    ASSERT_TRUE(st.ok()) << st.message();
    firstOrder += h.lastFirstOrder();
  }
  const MeshQueries mesh(b.mesh);
  // Table depths: near the clamp (the first three elements, s < 7.5 cm) the clamp's moment
  // presses the strand onto the crown with a cantilever's reaction, which the load bound
  // below does not cover (measured: the deepest samples, 0.24 mm into the layer, are at
  // s = 4.8 and 5.2 cm); they are checked against the exact mesh with the rest.
  double tableDepth = -1, tableDepthClamp = -1, exactDepth = -1, speed = 0;
  for (const StrandSample& q : h.samples())
  {
    speed = std::max(speed, q.velocity.norm());
    for (const PosedPart& p : bodies)
    {
      const TableQuery t = p.query(q.position);
      if (t.covered)
      {
        const double dd = t.inside ? std::max(t.depth, 0.0) : std::min(t.depth, 0.0);
        (q.s < 0.075 ? tableDepthClamp : tableDepth) =
            std::max(q.s < 0.075 ? tableDepthClamp : tableDepth, dd);
      }
    }
  }
  for (int i = 0; i <= 250; ++i)
    exactDepth = std::max(exactDepth, meshDepth(mesh, h.position(0.25 * i / 250)));
  const Eigen::Vector3d tip = h.position(0.25);
  std::printf("draped strand: tip (%.3f, %.3f, %.3f), max speed %.2g m/s, deepest: table %.3g "
              "m (%.3g m near the clamp), exact mesh %.3g m\n",
              tip.x(), tip.y(), tip.z(), speed, tableDepth, tableDepthClamp, exactDepth);
  // It fell over the side: the tip is below the root.
  EXPECT_LT(tip.y(), root.y() - 0.1);
  // The table's penetration of the clump's layer is λ/k, λ ≤ ρS g (1 + L/R) + EI/(R ℓ w_min)
  // as in the sphere test (R = 0.1 m, the head's radius): 1.2e-4 m; so the table depth is at
  // most that less the 1 mm thickness.
  const BodyContactParameters prm;
  const double w = rhoS * 9.81, R = 0.1, l = 0.025, EI = hp.stiffness()[1];
  double wMin = 1;
  for (const StrandSample& q : h.samples())
    wMin = std::min(wMin, q.weight);
  const double sink = (w * (1 + 0.25 / R) + EI / (R * l * wMin)) / prm.stiffness;
  EXPECT_LE(tableDepth, sink - prm.thickness);
  // The exact mesh: add the head table's error along the strand's path, 1.23 mm at the
  // 95th percentile of the whole head (docs/study-table-error.md); the path over the crown
  // and the side avoids the face and ears where the error reaches 10 mm.
  EXPECT_LE(exactDepth, sink - prm.thickness + 1.23e-3);
  EXPECT_LT(speed, 3 * prm.slipVelocity); // at rest, as in the sphere test
}
} // namespace

TEST(SuperHelixHeadContacts, StrandDrapedOverTheHeadRestsOutside)
{
  // Every time step (the midpoint one takes the semi-implicit step wherever the strand
  // touches; BDF2 keeps its own step in contact: the bounds are the same).
  for (Integrator integrator : {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2})
  {
    SCOPED_TRACE(toString(integrator));
    long firstOrder = 0;
    drapeOverHead(integrator, firstOrder);
    RecordProperty(std::string(toString(integrator)) + "_first_order_steps",
                   std::to_string(firstOrder));
    // BDF2 lying on the head: its own step but for the first one and those the energy guard
    // declines (measured: see the property); at most a tenth of the 300.
    if (integrator == Integrator::Bdf2)
      EXPECT_LE(firstOrder, 30);
  }
}

namespace
{
struct FrameStats
{
  double time = 0, max = 0, mean = 0, p95 = 0;
  long inside = 0, points = 0;
  long insideRootElement = 0; ///< of `inside`, nodes on the first element (s ≤ ℓ)
  double maxFree = 0;         ///< deepest point beyond the first element
};

/// The demo scene, headless: guides as Hair Strands grows them on the automatic scalp
/// (200, seed 1, 30 cm, 10 elements, wavy, combed towards (0, −1, −0.3) with weight 0.35).
Status demoScene(bool contacts, std::vector<FrameStats>& stats, double& seconds)
{
  const BundledBody& b = body();
  std::vector<GuideStrand> guides;
  if (Status s = demoGuides(b, 200, 10, guides); !s)
    return s;
  const Scene scene = demoScene(b);
  SimulationOptions o;
  o.threads = 2;
  o.contacts.enabled = contacts;
  Simulation sim;
  if (Status s = sim.initialize(guides, scene, o); !s)
    return s;
  const auto t0 = std::chrono::steady_clock::now();
  if (Status s = sim.advanceTo(151); !s)
    return s;
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stats.clear();
  for (int f = 0; f < sim.numberOfFrames(); ++f)
  {
    const StateFrame& fr = sim.frame(f);
    std::vector<double> d;
    FrameStats st;
    const std::vector<double>& depth = fr.pointData.at("contact_depth");
    // The frame's points are the strands' nodes: 11 per guide, nodes 0 and 1 on the root
    // element.
    const int perStrand = 10 + 1;
    for (std::size_t i = 0; i < depth.size(); ++i)
      if (depth[i] > 0)
      {
        d.push_back(depth[i]);
        if (static_cast<int>(i % perStrand) <= 1)
          ++st.insideRootElement;
        else
          st.maxFree = std::max(st.maxFree, depth[i]);
      }
    st.time = fr.time;
    st.points = static_cast<long>(fr.positions.size());
    st.inside = sim.contacts()[f];
    if (!d.empty())
    {
      std::sort(d.begin(), d.end());
      st.max = d.back();
      for (double x : d)
        st.mean += x / d.size();
      st.p95 = d[std::min(d.size() - 1, static_cast<std::size_t>(0.95 * d.size()))];
    }
    stats.push_back(st);
  }
  return Status::Ok();
}
} // namespace

TEST(SuperHelixHeadContacts, DemoHeadShakeScene)
{
  // Penetration statistics of the nodes (11 per guide) inside the head or trunk table, per
  // frame, with contacts and without.
  std::vector<FrameStats> on, off;
  double secondsOn = 0, secondsOff = 0;
  Status st = demoScene(true, on, secondsOn);
  ASSERT_TRUE(st.ok()) << st.message();
  st = demoScene(false, off, secondsOff);
  ASSERT_TRUE(st.ok()) << st.message();
  std::printf("| t (s) | inside, on | of them on the root element | max (mm) | max beyond the "
              "root element (mm) | mean (mm) | 95th pct (mm) | inside, off | max off (mm) "
              "|\n|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t f = 0; f < on.size(); f += 15)
    std::printf("| %.1f | %ld | %ld | %.2f | %.2f | %.3f | %.2f | %ld | %.1f |\n", on[f].time,
                on[f].inside, on[f].insideRootElement, 1e3 * on[f].max, 1e3 * on[f].maxFree,
                1e3 * on[f].mean, 1e3 * on[f].p95, off[f].inside, 1e3 * off[f].max);
  // Over the whole run (frames 1…150).
  double worst = 0, worstFree = 0, p95max = 0, meanInside = 0, meanFree = 0, meanFreeOff = 0;
  for (std::size_t f = 1; f < on.size(); ++f)
  {
    const double n = double(on.size() - 1);
    worst = std::max(worst, on[f].max);
    worstFree = std::max(worstFree, on[f].maxFree);
    p95max = std::max(p95max, on[f].p95);
    meanInside += on[f].inside / n;
    meanFree += (on[f].inside - on[f].insideRootElement) / n;
    meanFreeOff += (off[f].inside - off[f].insideRootElement) / n;
  }
  std::printf("frames 1-150, %ld points: contacts on: mean %.1f inside (%.1f beyond the root "
              "element), worst %.2f mm (%.2f mm beyond the root element), worst 95th pct %.2f "
              "mm, %.1f s; off: mean %.1f inside beyond the root element, %.1f s\n",
              on[0].points, meanInside, meanFree, 1e3 * worst, 1e3 * worstFree, 1e3 * p95max,
              secondsOn, meanFreeOff, secondsOff);
  // What contacts leave inside: the root elements (clamped on the mesh, which the head
  // table misses by its error, 1.2 mm at the 95th percentile and up to 10 mm), and, while
  // the head shakes, points driven into the 1 mm layer and past it within a step (with the
  // head still, no point beyond the root element is inside once the guides have settled;
  // docs/superhelix-contacts.md). Without contacts the hanging strands cross the trunk and
  // head (a third of all points). Beyond the root element, the share left inside was
  // measured 0.095 of the no-contact count with the sub-stepped step and 0.101 with the
  // single step at 1/30 s (docs/superhelix-contacts.md): required below 0.15, a guard
  // against regressions rather than a physical bound.
  EXPECT_LT(meanFree, 0.15 * meanFreeOff);
  // The physical bound on depth: a point reached by the surface within one step is pushed
  // out only from the next, so it can be as deep as the surface's speed times dt — the
  // crown, 0.3 m from the neck's pivot, moves at up to 0.5 rad · 2π · 1 Hz · 0.3 m =
  // 0.94 m/s, 31 mm in 1/30 s — plus the table's own error, up to 10 mm on the head
  // (docs/study-table-error.md).
  EXPECT_LT(worstFree, 0.5 * 2 * 3.141592653589793 * 0.3 / 30 + 10e-3);
}
