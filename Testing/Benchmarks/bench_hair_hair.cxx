// Hair–hair interaction on the demo's scene, against the same frames without it
// (docs/hair-hair-interaction.md; figures and commands in docs/benchmarks.md).
//   BM_Frame/<guides>/<hair-hair>/<threads>: one 1/30 s frame of hair::Simulation on the
//     demo's scene (DemoScene: wavy guides of 30 cm, N = 10, combed on the bundled scalp, the
//     head shaking ±0.5 rad at 1 Hz, head and trunk tables with the body's contacts, a 0.5 m/s
//     wind), 200, 1000 or 5000 guides, hair–hair interaction by Hair Simulation's Hair Hair
//     Contacts: off (0), the coupled solve of every close pair (1), the grid (2, the
//     default), the grid and the near field (3); on 1 or 2 threads, after 0.5 s of the run.
//     The coupled solve and the near field are registered at 200 guides only (seconds a
//     frame at 1000).
//   Wall time (UseRealTime), the process's CPU time (all threads), and per frame the shares
//   of the grid (its splat), the near field's search and its solve [ms], the pairs the near
//   field tracked and those that acted, per guide.
//   BM_PassThrough/<guides>: the pass-through count (contact/PassThrough.h) between two
//     consecutive frames of the demo's run without hair–hair interaction (frames 15 and 16,
//     the drawn polylines, within 2 × the automatic thickness), as hair_study hairhair counts.
//   BM_Detect/<guides>: HairHairContacts::detect on frame 16's polylines as samples (their
//     points, with their velocities over a 1/30 s step; one thread): the search alone.
#include "DemoScene.h"
#include "contact/HairHairContacts.h"
#include "contact/PassThrough.h"
#include "simulation/Simulation.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

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
  const int mode = static_cast<int>(state.range(1));
  const int threads = static_cast<int>(state.range(2));
  std::vector<GuideStrand> guides;
  if (Status st = demoGuides(body(), count, 10, guides); !st)
  {
    state.SkipWithError(st.message().c_str());
    return;
  }
  SimulationOptions o;
  o.threads = threads;
  o.contacts.enabled = true;
  o.hairHair.enabled = mode != 0;
  if (mode != 0)
    o.hairHair.solver = static_cast<HairHairSolver>(mode);
  Simulation sim;
  Status st = sim.initialize(guides, demoScene(body()), o);
  if (st)
    st = sim.advanceTo(1 + WarmupFrames);
  if (!st)
  {
    state.SkipWithError(st.message().c_str());
    return;
  }
  const auto* model = dynamic_cast<const SuperHelixModel*>(&sim.model());
  int frames = 1 + WarmupFrames;
  double grid = 0, volume = 0, search = 0, solve = 0, tracked = 0, active = 0;
  for (auto _ : state)
  {
    if (!(st = sim.advanceTo(++frames)))
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
    if (mode >= 2 && model)
    {
      grid += model->hairGrid().stats().seconds;
      volume += model->hairGrid().stats().solveSeconds;
      search += model->nearField().stats().searchSeconds;
      solve += model->nearField().stats().solveSeconds;
      tracked += model->nearField().stats().tracked;
      active += model->nearField().stats().active;
    }
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["guides"] = count;
  state.counters["grid_ms"] = 1e3 * grid / n;
  state.counters["volume_ms"] = 1e3 * volume / n;
  state.counters["search_ms"] = 1e3 * search / n;
  state.counters["solve_ms"] = 1e3 * solve / n;
  state.counters["tracked_per_guide"] = tracked / n / count;
  state.counters["active_per_guide"] = active / n / count;
}
// The drawn polylines and their points' velocities at frames 15 and 16 of the demo's run
// without hair–hair contacts, and the automatic contact distance R = 2 × thickness.
struct TwoFrames
{
  std::vector<std::vector<Eigen::Vector3d>> before, after, velocities;
  double R = 0;
  Status status = Status::Ok();
};

const TwoFrames& twoFrames(int count)
{
  static std::map<int, TwoFrames> cache;
  if (const auto it = cache.find(count); it != cache.end())
    return it->second;
  TwoFrames& f = cache[count];
  std::vector<GuideStrand> guides;
  f.status = demoGuides(body(), count, 10, guides);
  SimulationOptions o;
  o.threads = 2;
  o.contacts.enabled = true;
  o.hairHair.enabled = false;
  Simulation sim;
  if (f.status)
    f.status = sim.initialize(guides, demoScene(body()), o);
  if (f.status)
    f.status = sim.advanceTo(1 + WarmupFrames + 1);
  if (!f.status)
    return f;
  auto lines = [&](const std::vector<Eigen::Vector3d>& points)
  {
    std::vector<std::vector<Eigen::Vector3d>> out(sim.header().numberOfStrands());
    for (size_t k = 0; k < out.size(); ++k)
      out[k].assign(points.begin() + sim.header().offsets[k],
                    points.begin() + sim.header().offsets[k + 1]);
    return out;
  };
  f.before = lines(sim.frame(WarmupFrames).positions);
  f.after = lines(sim.frame(WarmupFrames + 1).positions);
  f.velocities = lines(sim.frame(WarmupFrames + 1).velocities);
  f.R = 2 * guides[0].hair.radius * std::sqrt(120000.0 / (count * 0.5));
  return f;
}

void BM_PassThrough(benchmark::State& state)
{
  const TwoFrames& f = twoFrames(static_cast<int>(state.range(0)));
  if (!f.status)
  {
    state.SkipWithError(f.status.message().c_str());
    return;
  }
  std::size_t found = 0;
  for (auto _ : state)
    found = findPassThroughs(f.before, f.after, f.R).size();
  state.counters["passes"] = double(found);
}

void BM_Detect(benchmark::State& state)
{
  const TwoFrames& f = twoFrames(static_cast<int>(state.range(0)));
  if (!f.status)
  {
    state.SkipWithError(f.status.message().c_str());
    return;
  }
  std::vector<std::vector<StrandSample>> samples(f.after.size());
  for (size_t i = 0; i < samples.size(); ++i)
    for (size_t k = 0; k < f.after[i].size(); ++k)
    {
      StrandSample q;
      q.s = k == 0 ? 0 : samples[i].back().s + (f.after[i][k] - f.after[i][k - 1]).norm();
      q.weight = 1;
      q.position = f.after[i][k];
      q.velocity = f.velocities[i][k];
      samples[i].push_back(q);
    }
  HairHairParameters p;
  p.thickness = f.R / 2;
  HairHairContacts contacts;
  Status st = contacts.setParameters(p);
  for (auto _ : state)
    if (st)
      st = contacts.detect(samples, {}, 1.0 / 30);
  if (!st)
    state.SkipWithError(st.message().c_str());
  state.counters["candidates"] = double(contacts.stats().candidatePairs);
  state.counters["contacts"] = double(contacts.stats().contacts);
}
} // namespace

BENCHMARK(BM_Frame)
    ->ArgsProduct({{200, 1000, 5000}, {0, 2}, {1, 2}})
    ->Iterations(10)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frame)
    ->ArgsProduct({{200}, {1, 3}, {1, 2}})
    ->Iterations(10)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_PassThrough)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Detect)->Arg(200)->Arg(1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
