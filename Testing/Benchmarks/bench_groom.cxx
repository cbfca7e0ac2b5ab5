// What a groom costs when a run starts, per strand (docs/benchmarks.md#grooms): the
// Super-Helix fit of a guide curve (a shaken strand of the preset drawn at 16 points per
// element, as Hair Simulation draws it; N = 10, 30 cm) and the sag-free rest shape of that
// shape, without contacts: its balance and Hessian (3N pairs of assemblies), and, where the
// shape cannot be held, the settling into the closest stable one.
// Run: bench_groom --benchmark_min_time=1 --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true
#include "HeadShake.h"
#include "groom/CurveFit.h"
#include "groom/SagFree.h"
#include "helix/Centerline.h"

#include <benchmark/benchmark.h>

using namespace hair;

namespace
{
const HairType Types[] = {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy};

/// The preset's strand shaken for 0.5 s (the stability case's root), and its spec held at the
/// root's pose then.
bool shaken(HairType type, SuperHelix& h)
{
  if (!h.initialize(shakenStrand(type, 10)).ok())
  {
    return false;
  }
  for (int i = 0; i < 15; ++i)
  {
    if (!h.step(1.0 / 30).ok())
    {
      return false;
    }
  }
  return true;
}

void fitBench(benchmark::State& state)
{
  SuperHelix h;
  if (!shaken(Types[state.range(0)], h))
  {
    state.SkipWithError("strand");
    return;
  }
  StrandPoints p;
  drawSuperHelix(h.spec().elementLengths, h.q().data(), h.qdot().data(), h.rootState(h.time()), 16,
                 p);
  const Eigen::Vector3d normal = h.rootState(h.time()).orientation.col(1);
  SuperHelixFit fit;
  for (auto _ : state)
  {
    if (!fitSuperHelix(p.positions, normal, 10, fit).ok())
    {
      state.SkipWithError("fit");
      return;
    }
  }
  state.counters["max_error_m"] = fit.maxError;
  state.counters["iterations"] = fit.iterations;
}

void sagFreeBench(benchmark::State& state)
{
  SuperHelix h;
  if (!shaken(Types[state.range(0)], h))
  {
    state.SkipWithError("strand");
    return;
  }
  StrandSpec spec = h.spec();
  const RootState r = h.rootState(h.time());
  spec.root = [r](double) { return r; };
  SagFreeResult result;
  for (auto _ : state)
  {
    if (!sagFree(spec, h.q(), ContactForces(), SagFreeOptions(), result).ok())
    {
      state.SkipWithError("sag-free");
      return;
    }
  }
  state.counters["outcome"] = static_cast<int>(result.outcome);
  state.counters["deviation_m"] = result.deviation;
}
} // namespace

BENCHMARK(fitBench)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(sagFreeBench)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
