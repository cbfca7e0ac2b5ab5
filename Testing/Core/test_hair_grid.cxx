// The far field of hair–hair interaction (contact/HairGrid.h, docs/hair-hair-interaction.md):
// the splat against the volume it must hold, the continuum's volume fraction and mean
// velocity on a lattice of strands worked out by hand, the drag and push against their law,
// and the squeezed, shaken clump of the hair–hair experiments (ClumpScene) against the
// pressure balance of a continuum and against the same clump without the grid.
#include "ClumpScene.h"
#include "contact/HairGrid.h"
#include "superhelix/SuperHelix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using namespace hair;

namespace
{
constexpr double Dt = 1.0 / 30;

// A straight polyline from `a` to `b` of `count` points, all moving at `v`.
struct Line
{
  std::vector<Eigen::Vector3d> x, v;
  Line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int count,
       const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero())
  {
    for (int i = 0; i < count; ++i)
    {
      x.push_back(a + (b - a) * (double(i) / (count - 1)));
      v.push_back(velocity);
    }
  }
  HairGrid::Strand strand(double area) const
  {
    return {x.data(), v.data(), int(x.size()), area, (x.back() - x.front()).norm()};
  }
};

HairGrid gridWith(double cell, double volume = 1, double friction = 10, int iterations = 30)
{
  HairGrid g;
  HairGridParameters p;
  p.cellSize = cell;
  p.volume = volume;
  p.friction = friction;
  p.iterations = iterations;
  EXPECT_TRUE(g.setParameters(p).ok());
  return g;
}
} // namespace

TEST(HairGrid, BadParametersAreRefusedWithTheirName)
{
  HairGridParameters p;
  p.volumeFraction = 0;
  Status s = p.validate();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("rest volume fraction"), std::string::npos) << s.message();
  p = HairGridParameters();
  p.volume = std::nan("");
  EXPECT_NE(p.validate().message().find("volume"), std::string::npos);
  p = HairGridParameters();
  p.iterations = 0;
  EXPECT_NE(p.validate().message().find("iterations"), std::string::npos);
  p = HairGridParameters();
  p.friction = -1;
  EXPECT_NE(p.validate().message().find("friction"), std::string::npos);
  p = HairGridParameters();
  p.cellSize = 2;
  EXPECT_NE(p.validate().message().find("cell size"), std::string::npos);
}

TEST(HairGrid, TheSplatHoldsEachStrandsVolumeOnAnyNumberOfThreads)
{
  // Curved strands (coarse polylines of helices, which cut corners): the volume on the grid,
  // Σ φ cell³, is Σ area × length whatever the polyline, and the grid is the same, bit for
  // bit, when the strands are splatted on one thread or two.
  std::vector<Line> lines;
  std::vector<double> areas, lengths;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(0, 0.2);
  for (int k = 0; k < 30; ++k)
  {
    Line l({0, 0, 0}, {0, 0, 0}, 2);
    l.x.clear();
    l.v.clear();
    const Eigen::Vector3d start(u(random), u(random), u(random));
    for (int i = 0; i <= 12; ++i)
    {
      const double t = 0.5 * i;
      l.x.push_back(start + Eigen::Vector3d(0.01 * std::cos(t), 0.01 * std::sin(t), 0.02 * t));
      l.v.push_back(Eigen::Vector3d(0.1 * k, 0, 0));
    }
    lines.push_back(l);
    areas.push_back(1e-7 * (1 + k % 3));
    lengths.push_back(6 * std::sqrt(0.01 * 0.01 + 0.02 * 0.02)); // the helix's arc length
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const Line& l : lines)
    for (const Eigen::Vector3d& x : l.x)
    {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  double expected = 0;
  std::vector<HairGrid::Strand> strands;
  for (size_t k = 0; k < lines.size(); ++k)
  {
    HairGrid::Strand s = lines[k].strand(areas[k]);
    s.length = lengths[k];
    strands.push_back(s);
    expected += areas[k] * lengths[k];
  }
  HairGrid one = gridWith(0.007), two = gridWith(0.007);
  one.begin(lo, hi, 0.01, Dt);
  one.add(strands, 1);
  one.finish();
  two.begin(lo, hi, 0.01, Dt);
  two.add(strands, 2);
  two.finish();
  EXPECT_NEAR(one.stats().volume, expected, 1e-7 * expected);
  EXPECT_EQ(two.stats().volume, one.stats().volume); // integers: in any order the same
  std::uniform_real_distribution<double> w(-0.01, 0.21);
  for (int i = 0; i < 1000; ++i)
  {
    const Eigen::Vector3d x(w(random), w(random), w(random));
    Eigen::Vector3d v1, v2;
    ASSERT_EQ(one.fraction(x, &v1), two.fraction(x, &v2));
    ASSERT_EQ(v1, v2);
  }
}

TEST(HairGrid, TheContinuumOfALatticeOfStrandsAndItsDragOnAStrandCrossingIt)
{
  // Strands along x through the grid's node lines y = j h, z = k h (h the cell), each of
  // cross-section a, at rest: the hair's volume fraction on those lines is a / h² (each
  // strand's share of the yz plane), exactly, as the splat's points are a cell apart and the
  // trilinear weights sum to one along a line. A strand along y through the node lines
  // x = i h, z = k h, moving at u, adds a / h² at the nodes where it crosses the bed: there
  // φ = 2a / h² and the hair's mean velocity is ū = u / 2. The law of the drag on it
  // (HairGrid.h): per unit length c (ū − v) with c = ρS β (φ − φ_own) / φ0 and
  // φ_own = a / h², so the crossing strand is pulled back by ρS β (a / h²)/φ0 × u / 2; a bed
  // strand between crossings, alone on its line, feels no drag.
  const double h = 0.01, a = 0.02 * h * h; // the bed at φ = 0.02: with the crossing strand
                                           // 0.04, below φ0 = 0.05, so no push
  const Eigen::Vector3d u(0, 0, 0.3);
  std::vector<Line> lines;
  for (int j = 0; j <= 6; ++j)
    for (int k = 0; k <= 6; ++k)
      lines.emplace_back(Eigen::Vector3d(0, j * h, k * h), Eigen::Vector3d(12 * h, j * h, k * h),
                         13);
  lines.emplace_back(Eigen::Vector3d(6 * h, 0, 3 * h), Eigen::Vector3d(6 * h, 6 * h, 3 * h), 7, u);
  std::vector<HairGrid::Strand> strands;
  for (const Line& l : lines)
    strands.push_back(l.strand(a));
  HairGrid g = gridWith(h);
  g.begin({0, 0, 0}, {12 * h, 6 * h, 6 * h}, 0.02, Dt);
  g.add(strands, 2);
  g.finish();
  Eigen::Vector3d mean;
  // (To 1e-10: the nodes hold their sums in fixed point, 2⁻⁴⁰ ≈ 1e-12 per contribution.)
  EXPECT_NEAR(g.fraction({4 * h, 2 * h, 5 * h}, &mean), a / (h * h), 1e-10);
  EXPECT_NEAR(mean.norm(), 0, 1e-15);
  // Half-way between two bed lines: the same (the weights are linear across).
  EXPECT_NEAR(g.fraction({4 * h, 2.5 * h, 5 * h}), a / (h * h), 1e-10);
  const Eigen::Vector3d crossing(6 * h, 3 * h, 3 * h);
  EXPECT_NEAR(g.fraction(crossing, &mean), 2 * a / (h * h), 1e-10);
  EXPECT_NEAR((mean - u / 2).norm(), 0, 1e-9);

  const double rhoS = 3e-6, phi0 = 0.05, beta = 10;
  ContactResponse r;
  g.respond(crossing, rhoS, a, r);
  EXPECT_NEAR(r.drag, rhoS * beta * (a / (h * h)) / phi0, 1e-8 * r.drag);
  EXPECT_NEAR((r.medium - u / 2).norm(), 0, 1e-9);
  EXPECT_TRUE(r.push.isZero(0));
  const Eigen::Vector3d force = r.drag * (r.medium - u); // on the crossing strand, at u
  EXPECT_NEAR(force.z(), -rhoS * beta * 0.4 * 0.15, 1e-8 * rhoS * beta * 0.4 * 0.15);
  ContactResponse alone;
  g.respond({4 * h, 2 * h, 5 * h}, rhoS, a, alone);
  EXPECT_LT(alone.drag, 1e-7 * r.drag); // φ − φ_own is the fixed point's round-off
  EXPECT_TRUE(alone.push.isZero(0));
  // Outside the hair nothing.
  ContactResponse outside;
  g.respond({-1, 0, 0}, rhoS, a, outside);
  EXPECT_FALSE(outside.hasField());
  // Nor far outside, nor at a point that is not one (no cast of it to a node).
  for (const Eigen::Vector3d& far :
       {Eigen::Vector3d(1e30, 0, 0), Eigen::Vector3d(std::nan(""), 0, 0)})
  {
    ContactResponse none;
    g.respond(far, rhoS, a, none);
    EXPECT_FALSE(none.hasField());
    EXPECT_EQ(g.fraction(far), 0);
  }
}

TEST(HairGrid, PackedHairIsPushedBackToItsRestFractionWithinTheStep)
{
  // A bed of hair at rest packed at φ_b = 1.2 φ0 in the layers y = 0 … 3h, wide in x and z
  // (32 cells), empty around. The pressure's potential Q = h_t² P / ρ solves, where the hair
  // is packed, −∇²Q = φ_b − φ0 with Q = 0 outside the hair; across the layers, in the bed's
  // middle, that is the 1-D problem −Q'' = e, Q(−h) = Q(4h) = 0, whose discrete solution is
  // exact for the quadratic e/2 (y + h)(4h − y): Q = 2 e h² on the outer layers, 3 e h² on
  // the inner ones. So a fibre half-way across the bed's top cell (φ = φ_b / 2) is pushed
  // up by ρS |∇Q| / (max(φ, φ0) h_t²) = ρS 2 e h / (φ0 h_t²) per unit length, and one
  // half-way between the two inner layers not at all. Converged (500 sweeps): to 1 % of
  // that, for the bed's sides, 16 cells away, lower Q by about e^{−π 16/5} ≈ 4e-5 of it,
  // and the sideways push (the points lie on node lines, where the trilinear gradient is
  // one-sided) is of that order. With 0 volume, nothing.
  const double h = 0.01, phi0 = 0.05, phiB = 1.2 * phi0, a = phiB * h * h;
  const int w = 32;
  std::vector<Line> lines;
  for (int j = 0; j <= 3; ++j)
    for (int k = 0; k <= w; ++k)
      lines.emplace_back(Eigen::Vector3d(0, j * h, k * h), Eigen::Vector3d(w * h, j * h, k * h),
                         w + 1);
  std::vector<HairGrid::Strand> strands;
  for (const Line& l : lines)
    strands.push_back(l.strand(a));
  const double rhoS = 3e-6, e = phiB - phi0;
  HairGrid g = gridWith(h, 1, 0, 500);
  g.begin({0, 0, 0}, {w * h, 3 * h, w * h}, 0.02, Dt);
  g.add(strands, 2);
  g.finish();
  EXPECT_LT(g.stats().residual, 1e-6 * e);
  // Every node of the bed but its lines' two ends, which hold half a share (φ_b / 2 < φ0).
  EXPECT_EQ(g.stats().pressed, 4 * (w + 1) * (w - 1));
  ContactResponse top, inner;
  const Eigen::Vector3d middle(w / 2 * h, 0, w / 2 * h);
  g.respond(middle + Eigen::Vector3d(0, 3.5 * h, 0), rhoS, 0, top);
  g.respond(middle + Eigen::Vector3d(0, 1.5 * h, 0), rhoS, 0, inner);
  const double expected = rhoS * 2 * e * h / (phi0 * Dt * Dt);
  EXPECT_NEAR(top.push.y(), expected, 0.01 * expected);
  EXPECT_NEAR(top.push.x(), 0, 1e-3 * expected);
  EXPECT_NEAR(top.push.z(), 0, 1e-3 * expected);
  EXPECT_NEAR(inner.push.y(), 0, 1e-3 * expected);
  std::printf("push at the bed's top %.6g N/m (1-D: %.6g N/m), sideways %.3g N/m\n", top.push.y(),
              expected, std::hypot(top.push.x(), top.push.z()));
  HairGrid none = gridWith(h, 0, 0, 500);
  none.begin({0, 0, 0}, {w * h, 3 * h, w * h}, 0.02, Dt);
  none.add(strands, 1);
  none.finish();
  ContactResponse r;
  none.respond(middle + Eigen::Vector3d(0, 3.5 * h, 0), rhoS, 0, r);
  EXPECT_FALSE(r.hasField());
}

namespace
{
// The clump of ClumpScene (50 smooth guides on a 12 mm disc, squeezed by an air flow
// converging on its axis, then shaken vertically) with the grid or without: per frame the
// mean distance to the axis of the points at s = 0.2 m and the spread of the velocities
// there (the RMS difference of each point's velocity from the mean of its 6 nearest).
struct GridClumpRun
{
  std::vector<double> time, meanRadius, spread;
};

Status runGridClump(bool grid, double friction, double ramp, double duration, double area,
                    GridClumpRun& out)
{
  ClumpSpec spec;
  spec.hair.airFriction = 2e-4;
  spec.rampTime = ramp;
  spec.startOscillation = ramp;
  spec.flowRate = 8;
  std::vector<SuperHelix> strands;
  if (Status st = initializeClump(spec, strands); !st)
    return st;
  HairGrid g = gridWith(0.004, 1, friction);
  const double rhoS = spec.hair.linearDensity();
  if (grid)
    for (SuperHelix& h : strands)
      h.setContactForces(
          [&](int, double, const std::vector<StrandSample>& s, std::vector<ContactResponse>& r)
          {
            for (size_t j = 0; j < s.size(); ++j)
              g.respond(s[j].position, rhoS, area, r[j]);
          });
  out = GridClumpRun{};
  std::vector<std::vector<Eigen::Vector3d>> x(strands.size()), v(strands.size());
  auto record = [&]()
  {
    std::vector<Eigen::Vector3d> p, q;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const SuperHelix& h : strands)
    {
      p.push_back(h.position(0.2));
      centre += p.back() / double(strands.size());
      // The velocity at s = 0.2 m: the sample nearest to it.
      const std::vector<StrandSample>& s = h.samples();
      size_t best = 0;
      for (size_t j = 0; j < s.size(); ++j)
        if (std::abs(s[j].s - 0.2) < std::abs(s[best].s - 0.2))
          best = j;
      q.push_back(s[best].velocity);
    }
    double mean = 0, spread = 0;
    for (size_t i = 0; i < p.size(); ++i)
    {
      mean += Eigen::Vector2d(p[i].x() - centre.x(), p[i].z() - centre.z()).norm() / p.size();
      std::vector<std::pair<double, size_t>> near;
      for (size_t j = 0; j < p.size(); ++j)
        if (j != i)
          near.push_back({(p[j] - p[i]).squaredNorm(), j});
      std::partial_sort(near.begin(), near.begin() + 6, near.end());
      Eigen::Vector3d around = Eigen::Vector3d::Zero();
      for (int n = 0; n < 6; ++n)
        around += q[near[n].second] / 6.0;
      spread += (q[i] - around).squaredNorm() / p.size();
    }
    out.time.push_back(strands[0].time());
    out.meanRadius.push_back(mean);
    out.spread.push_back(std::sqrt(spread));
  };
  record();
  const int frames = static_cast<int>(std::lround(duration / Dt));
  for (int f = 0; f < frames; ++f)
  {
    if (grid)
    {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
      for (size_t k = 0; k < strands.size(); ++k)
      {
        const SuperHelix& h = strands[k];
        x[k] = {h.rootState(h.time()).position};
        v[k] = {h.rootState(h.time()).velocity};
        for (const StrandSample& s : h.samples())
        {
          x[k].push_back(s.position);
          v[k].push_back(s.velocity);
        }
        for (const Eigen::Vector3d& y : x[k])
        {
          lo = lo.cwiseMin(y);
          hi = hi.cwiseMax(y);
        }
      }
      std::vector<HairGrid::Strand> list;
      for (size_t k = 0; k < strands.size(); ++k)
        list.push_back({x[k].data(), v[k].data(), int(x[k].size()), area, strands[k].length()});
      g.begin(lo, hi, 0, Dt);
      g.add(list, 2);
      g.finish();
    }
    if (Status st = stepStrands(strands, Dt, 2); !st)
      return st;
    record();
  }
  return Status::Ok();
}

double meanOver(const GridClumpRun& r, const std::vector<double>& series, double from, double to)
{
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < r.time.size(); ++i)
    if (r.time[i] >= from - 1e-9 && r.time[i] <= to + 1e-9)
    {
      sum += series[i];
      ++n;
    }
  return n ? sum / n : 0;
}
} // namespace

TEST(HairGrid, AClumpKeepsItsRestVolumeAndMovesTogether)
{
  // Each guide stands for fibres of cross-section a = φ0 π R² / 50, so that the 50 fill the
  // 12 mm root disc at the rest fraction φ0 = 0.05: the mean distance of their points to
  // the clump's axis is (2/3) R = 8 mm at rest. The air flow converging on the axis
  // (β = 8 1/s at the end of a 1.5 s ramp) gathers them without the grid to a quarter of
  // that; with it, the hair may not pack above φ0 (the pressure undoes it within a step)
  // but the flow drags the fibres back in every step, and the air's drag, implicit in the
  // step, takes part of the push: required, the hair packed at most to 2 φ0 on average, a
  // mean distance above (2/3) R / √2, while squeezed and while shaken (4 mm cells). And the
  // grid's friction (β = 10 1/s) makes the shaken clump move together: the spread of
  // neighbours' velocities smaller than with the same grid without friction.
  const double R = 0.012, phi0 = 0.05, ramp = 1.5, duration = 3;
  const double area = phi0 * M_PI * R * R / 50;
  GridClumpRun with, frictionless, without;
  Status st = runGridClump(true, 10, ramp, duration, area, with);
  ASSERT_TRUE(st.ok()) << st.message();
  st = runGridClump(true, 0, ramp, duration, area, frictionless);
  ASSERT_TRUE(st.ok()) << st.message();
  st = runGridClump(false, 0, ramp, duration, area, without);
  ASSERT_TRUE(st.ok()) << st.message();
  const double rest = 2.0 / 3 * R;
  double smallest = 1e9;
  for (size_t i = 0; i < with.time.size(); ++i)
    if (with.time[i] >= 0.5)
      smallest = std::min(smallest, with.meanRadius[i]);
  const size_t endOfRamp = static_cast<size_t>(std::lround(ramp / Dt));
  EXPECT_NEAR(with.meanRadius[0], rest, 0.02 * rest); // the sunflower fills the disc
  EXPECT_GT(smallest, rest / std::sqrt(2.0));
  EXPECT_LT(without.meanRadius[endOfRamp], 0.3 * rest);
  const double spreadWith = meanOver(with, with.spread, ramp, duration);
  const double spreadFrictionless = meanOver(frictionless, frictionless.spread, ramp, duration);
  EXPECT_LT(spreadWith, spreadFrictionless);
  std::printf("mean radius at s = 0.2 m: rest %.3g mm; with the grid, least %.3g mm after "
              "0.5 s; without, %.3g mm at the end of the ramp; spread of neighbours' velocities "
              "while shaken: %.3g mm/s with the grid's friction, %.3g mm/s without it, %.3g mm/s "
              "without the grid\n",
              1e3 * rest, 1e3 * smallest, 1e3 * without.meanRadius[endOfRamp], 1e3 * spreadWith,
              1e3 * spreadFrictionless, 1e3 * meanOver(without, without.spread, ramp, duration));
}
