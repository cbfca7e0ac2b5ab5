// Drawing a Super-Helix from q and its root (drawSuperHelix, what every frame of the run and
// of the state reader costs per strand): a shaken curly strand of 10 elements at 4, 16 and
// 32 points per element, points, velocities and material frames.
// Run: bench_guide_drawing --benchmark_min_time=1 --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true      (docs/benchmarks.md)
#include "HeadShake.h"
#include "helix/Centerline.h"

#include <benchmark/benchmark.h>

using namespace hair;

namespace
{
void drawBench(benchmark::State& state)
{
  SuperHelix h;
  if (!h.initialize(shakenStrand(HairType::Curly, 10)).ok())
  {
    state.SkipWithError("strand");
    return;
  }
  for (int i = 0; i < 10; ++i)
  {
    if (!h.step(1.0 / 30).ok())
    {
      state.SkipWithError("step");
      return;
    }
  }
  const RootState root = h.rootState(h.time());
  const int per = static_cast<int>(state.range(0));
  StrandPoints p;
  for (auto _ : state)
  {
    drawSuperHelix(h.spec().elementLengths, h.q().data(), h.qdot().data(), root, per, p);
    benchmark::DoNotOptimize(p.positions.data());
  }
  state.counters["points"] = double(p.positions.size());
  state.counters["ns_per_point"] =
      benchmark::Counter(double(p.positions.size()), benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}
} // namespace

BENCHMARK(drawBench)->Arg(4)->Arg(16)->Arg(32)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
