// Cost of the hair–hair contact update against the cost of stepping the strands
// (docs/hair-hair-contacts.md has the table and the command).
//   BM_HairHair/<strands>/<coherence>  guides of N = 10, 30 cm (smooth preset), rooted on the
//     cap y > 0.3 r of a head-sized sphere (radius r = 10 cm, evenly by a Fibonacci spiral; on
//     that cap no two roots are above each other), clamped
//     pointing down and hanging (no body collision), the head turning ±10° at 0.5 Hz (the
//     issue's ±30° at 3 Hz makes the dense hair of 1000 guides blow up at 1/30 s; see
//     docs/hair-hair-contacts.md). A guide stands for the hair around it, so its clump fills
//     its share of the scalp: thickness = 0.4 × √(cap area / strands), neighbours' clumps 20 %
//     apart at the roots (7.4, 3.3 and 1.5 mm for 200, 1000 and 5000 guides); same margin.
//     Each iteration is one frame: update() (timed: the benchmark's time) then stepStrands on
//     one thread (counter step_ms). Counters: rebuilt (fraction of updates that rebuilt the
//     grid), candidates and contacts per update.
#include "HeadShake.h"
#include "contact/HairHairContacts.h"
#include "superhelix/SuperHelix.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <vector>

using namespace hair;

namespace
{
std::vector<SuperHelix> headOfHair(int count)
{
  HairParameters hair = HairParameters::preset(HairType::Smooth);
  std::vector<SuperHelix> strands(count);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i)
  {
    const double y = 1 - 0.7 * (i + 0.5) / count; // the cap y > 0.3, even in area
    const double r = std::sqrt(1 - y * y), phi = i * golden;
    const Eigen::Vector3d n(r * std::cos(phi), y, r * std::sin(phi));
    HeadShake shake;
    shake.amplitude = M_PI / 18;
    shake.frequency = 0.5;
    shake.attachment = 0.1 * n;
    shake.attachmentFrame.col(0) = Eigen::Vector3d(0, -1, 0);
    shake.attachmentFrame.col(1) = Eigen::Vector3d(1, 0, 0);
    shake.attachmentFrame.col(2) = Eigen::Vector3d(0, 0, 1);
    StrandSpec s = StrandSpec::uniform(0.3, 10, hair);
    s.id = i;
    s.seed = 1 + i;
    s.root = shake;
    (void)strands[i].initialize(s);
  }
  return strands;
}

void BM_HairHair(benchmark::State& state)
{
  const int count = static_cast<int>(state.range(0));
  const bool coherence = state.range(1) != 0;
  std::vector<SuperHelix> strands = headOfHair(count);
  HairHairContacts contacts;
  HairHairParameters p;
  const double capArea = 2 * M_PI * 0.1 * 0.1 * 0.7; // 2π r² (1 − 0.3)
  p.thickness = 0.4 * std::sqrt(capArea / count);
  p.margin = p.thickness;
  if (!coherence)
    p.margin = 0;
  (void)contacts.setParameters(p);
  for (SuperHelix& h : strands)
    h.setContactForces(contacts.hook());
  const double dt = 1.0 / 30;
  // 1 s of shaking first: the hair is moving, as in use.
  for (int i = 0; i < 30; ++i)
  {
    (void)findHairHairContacts(strands, contacts);
    (void)stepStrands(strands, dt, 1);
  }
  double stepSeconds = 0, rebuilt = 0, candidates = 0, found = 0;
  for (auto _ : state)
  {
    const auto t0 = std::chrono::steady_clock::now();
    Status st = findHairHairContacts(strands, contacts);
    const auto t1 = std::chrono::steady_clock::now();
    if (st)
      st = stepStrands(strands, dt, 1);
    const auto t2 = std::chrono::steady_clock::now();
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
    state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    stepSeconds += std::chrono::duration<double>(t2 - t1).count();
    rebuilt += contacts.stats().rebuilt;
    candidates += contacts.stats().candidatePairs;
    found += contacts.stats().contacts;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["step_ms"] = 1e3 * stepSeconds / n;
  state.counters["rebuilt"] = rebuilt / n;
  state.counters["candidates"] = candidates / n;
  state.counters["contacts"] = found / n;
}
} // namespace

BENCHMARK(BM_HairHair)
    ->ArgsProduct({{200, 1000, 5000}, {0, 1}})
    ->Iterations(30)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
