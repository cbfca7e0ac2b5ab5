// One step of the projective strand model (Kurihara, Anjyo, Thalmann 1993) on the paper's
// scale: 1000 guide strands × 40 segments on the bundled body's scalp, wind from the front,
// colliding with the head (spherical table) and trunk (cylindrical table), on one thread
// and two. The same step with no body parts gives the share spent in collision:
//   share = 1 − time(no parts) / time(head + trunk);
// and with friction on (μ_s = 0.4, μ = 0.3, a = 0.2) what friction costs.
// Run: bench_projective --benchmark_min_time=2 --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true      (docs/benchmarks.md)
#include "ProjectiveScenes.h"

#include <benchmark/benchmark.h>

#include <memory>

using namespace hair;

namespace
{
struct Setup
{
  BundledBody body;
  std::vector<ProjectiveStrand> strands;
};

const Setup& setup()
{
  static std::unique_ptr<Setup> s;
  if (!s)
  {
    s = std::make_unique<Setup>();
    if (!loadBundledBody(HAIR_DATA_DIR, s->body).ok())
    {
      return *s;
    }
    ScalpOptions so; // 1000 strands of 40 segments, 0.4 m
    scalpStrands(s->body, so, s->strands);
  }
  return *s;
}

void stepBench(benchmark::State& state)
{
  const int threads = static_cast<int>(state.range(0));
  const bool collide = state.range(1) != 0;
  const bool friction = state.range(2) != 0;
  const Setup& s = setup();
  if (s.strands.empty())
  {
    state.SkipWithError("could not load the bundled body (Data/body.vtk, body_parts.txt)");
    return;
  }
  double duration = 0;
  Scene scene = paperScene(s.body, PaperScene::Wind, duration);
  if (!collide)
  {
    scene.parts.clear();
  }
  ProjectiveOptions o;
  o.threads = threads;
  if (friction)
  {
    o.staticFriction = 0.4;
    o.friction = 0.3;
  }
  ProjectiveStrands sim;
  if (!sim.initialize(s.strands, scene, o).ok())
  {
    state.SkipWithError("initialize failed");
    return;
  }
  // Let the hair fall onto the body and the wind rise first (0.6 s), so that the steps
  // measured carry the contacts of the scene; every 200 steps (0.2 s) go back to that
  // state (untimed), so that every run measures the same stretch of the scene whatever
  // its number of iterations.
  sim.advance(0.6);
  const ProjectiveStrands start = sim;
  long contacts = 0, projections = 0, stuck = 0, sliding = 0, steps = 0;
  for (auto _ : state)
  {
    if (++steps % 200 == 0)
    {
      state.PauseTiming();
      sim = start;
      state.ResumeTiming();
    }
    ProjectiveStepStats st;
    sim.step(&st);
    contacts += st.contacts;
    projections += st.projections;
    stuck += st.stuck;
    sliding += st.sliding;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["steps/s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["contacts"] = contacts / n;
  state.counters["projections"] = projections / n;
  state.counters["stuck"] = stuck / n;
  state.counters["sliding"] = sliding / n;
  state.counters["segments"] = 40.0 * s.strands.size();
}
} // namespace

BENCHMARK(stepBench)
    ->ArgNames({"threads", "collision", "friction"})
    ->Args({1, 1, 0})
    ->Args({2, 1, 0})
    ->Args({1, 0, 0})
    ->Args({2, 0, 0})
    ->Args({1, 1, 1})
    ->Args({2, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
