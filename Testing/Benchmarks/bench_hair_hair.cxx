// Hair–hair contacts on the demo's scene, against the same frames without them
// (docs/hair-hair-contacts.md; figures and commands in docs/benchmarks.md).
//   BM_Frame/<guides>/<hair-hair>/<threads>: one 1/30 s frame of hair::Simulation on the
//     demo's scene (DemoScene: wavy guides of 30 cm, N = 10, combed on the bundled scalp, the
//     head shaking ±0.5 rad at 1 Hz, head and trunk tables with the body's contacts, a 0.5 m/s
//     wind), 200, 1000 or 5000 guides, hair–hair contacts off (0) or on (1), on 1 or 2
//     threads, after 0.5 s of the run. The clumps fill the head's fibres shared among the
//     guides (HairHairParameters::automaticThickness: 1.21, 0.54, 0.24 mm), given
//     explicitly so that a build of another commit runs the same scene: this file uses only
//     hair::Simulation's options, which are the same before and after the coupled solve
//     (copy it into a baseline tree to compare; docs/benchmarks.md).
//   Wall time (UseRealTime) and the process's CPU time (all threads).
#include "DemoScene.h"
#include "simulation/Simulation.h"

#include <benchmark/benchmark.h>

#include <cmath>

using namespace hair;

namespace
{
constexpr int WarmupFrames = 15;

const BundledBody& body()
{
  static BundledBody b;
  static const Status st = loadBundledBody(HAIR_DATA_DIR, b);
  (void)st;
  return b;
}

void BM_Frame(benchmark::State& state)
{
  const int count = static_cast<int>(state.range(0));
  const bool hairHair = state.range(1) != 0;
  const int threads = static_cast<int>(state.range(2));
  std::vector<GuideStrand> guides;
  if (Status st = demoGuides(body(), count, 10, guides); !st)
  {
    state.SkipWithError(st.message().c_str());
    return;
  }
  SimulationOptions o;
  o.threads = threads;
  o.superHelix.contacts.enabled = true;
  o.superHelix.hairHairEnabled = hairHair;
  // r √(120 000 / (guides × ½)) for the wavy preset's r = 35 µm.
  o.superHelix.hairHair.thickness = guides[0].hair.radius * std::sqrt(120000.0 / (count * 0.5));
  Simulation sim;
  Status st = sim.initialize(guides, demoScene(body()), o);
  if (st)
    st = sim.advanceTo(1 + WarmupFrames);
  if (!st)
  {
    state.SkipWithError(st.message().c_str());
    return;
  }
  int frames = 1 + WarmupFrames;
  for (auto _ : state)
  {
    if (!(st = sim.advanceTo(++frames)))
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
  }
  state.counters["guides"] = count;
  state.counters["thickness_mm"] = 1e3 * o.superHelix.hairHair.thickness;
}
} // namespace

BENCHMARK(BM_Frame)
    ->ArgsProduct({{200, 1000, 5000}, {0, 1}, {1, 2}})
    ->Iterations(3)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
