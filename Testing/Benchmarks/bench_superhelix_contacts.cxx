// Cost of hair–body contacts in the Super-Helix step (docs/superhelix-contacts.md has the
// table and the command), on the demo's scene: guides on the bundled scalp (wavy, 30 cm,
// N = 10, combed), the head shaking ±0.5 rad at 1 Hz, head and trunk tables.
//   BM_Step/<guides>/<contacts>/<threads>  one step of 1/30 s of every guide on 1 or 2
//                                 threads, with contacts (1) or without (0), side by side,
//                                 from the same state (1 s into the shake with contacts);
//                                 on 2 threads read the wall time ("Time"): frames per
//                                 second = 1000 / Time in ms (30 is real time)
//   BM_Respond/<guides>           BodyContacts::respond alone for every guide's samples
//   BM_SimulationFrame/<threads>  one frame of hair::Simulation (what Hair Simulation runs):
//                                 1000 guides of the same scene, the step of every guide and
//                                 the frame's record (display points, their velocities and
//                                 depths, energies); frames per second = 1000 / Time in ms
//   BM_StrandInContact/<N>/<contacts>  one step of one wavy strand (30 cm, N elements), every
//                                 sample in contact (1: a synthetic response with stiffness
//                                 and non-symmetric damping, no force) or none (0): what the
//                                 implicit contact terms cost a strand lying on the scalp. No
//                                 gravity and a fixed root: the strand rests in its natural
//                                 shape in both variants, so they take the same steps.
#include "DemoScene.h"
#include "ProjectiveScenes.h"
#include "contact/BodyContacts.h"
#include "simulation/Simulation.h"
#include "superhelix/SuperHelix.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <vector>

using namespace hair;

namespace
{
struct Bench
{
  BundledBody body;
  Scene world; ///< the head shaking ±0.5 rad at 1 Hz about the neck, the trunk still
  BodyContacts contacts;
  std::vector<SuperHelix> strands; ///< 1 s into the shake, contacts on

  ContactForces hook() const
  {
    return
        [this](int, double t, const std::vector<StrandSample>& s, std::vector<ContactResponse>& r)
    {
      thread_local std::vector<PosedPart> parts;
      world.posedParts(t, parts);
      contacts.respond(s, strands[0].spec().hair.linearDensity(), parts.data(), 2, r);
    };
  }
};

/// The demo's guides, with seeds 1 + k (Simulation then adds k): the guides the recorded
/// figures were taken with.
std::vector<GuideStrand> benchGuides(const BundledBody& body, int count)
{
  std::vector<GuideStrand> guides;
  (void)demoGuides(body, count, 10, guides);
  for (std::size_t k = 0; k < guides.size(); ++k)
    guides[k].seed = 1 + static_cast<std::uint32_t>(k);
  return guides;
}

Bench& scene(int guides)
{
  static std::map<int, std::unique_ptr<Bench>> cache;
  std::unique_ptr<Bench>& s = cache[guides];
  if (s)
    return *s;
  s = std::make_unique<Bench>();
  (void)loadBundledBody(HAIR_DATA_DIR, s->body);
  s->world = demoScene(s->body);
  (void)s->contacts.setParameters(BodyContactParameters());
  const std::vector<GuideStrand> g = benchGuides(s->body, guides);
  s->strands.resize(g.size());
  for (std::size_t k = 0; k < g.size(); ++k)
  {
    StrandSpec spec = StrandSpec::uniform(0.3, 10, HairParameters::preset(HairType::Wavy));
    spec.id = static_cast<int>(k);
    spec.seed = g[k].seed;
    spec.root = s->world.rootMotion.carriedRoot(g[k].root, g[k].rootFrame());
    (void)s->strands[k].initialize(spec);
    s->strands[k].setContactForces(s->hook());
  }
  for (int i = 0; i < 30; ++i)
    (void)stepStrands(s->strands, 1.0 / 30, 2);
  return *s;
}

void BM_Step(benchmark::State& state)
{
  Bench& s = scene(static_cast<int>(state.range(0)));
  const bool contacts = state.range(1) != 0;
  const int threads = static_cast<int>(state.range(2));
  std::vector<SuperHelix> strands = s.strands; // the same state for both variants
  for (SuperHelix& h : strands)
    h.setContactForces(contacts ? s.hook() : ContactForces());
  double substeps = 0;
  for (auto _ : state)
  {
    const Status st = stepStrands(strands, 1.0 / 30, threads);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
    for (const SuperHelix& h : strands)
      substeps += h.lastSubsteps();
  }
  state.counters["substeps"] =
      benchmark::Counter(substeps / strands.size(), benchmark::Counter::kAvgIterations);
  state.counters["us_per_guide"] = benchmark::Counter(
      double(strands.size()) * state.iterations(),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
  state.SetLabel(contacts ? "contacts" : "no contacts");
}

void BM_Respond(benchmark::State& state)
{
  Bench& s = scene(static_cast<int>(state.range(0)));
  std::vector<std::vector<StrandSample>> samples;
  for (const SuperHelix& h : s.strands)
    samples.push_back(h.samples());
  std::vector<PosedPart> bodies;
  s.world.posedParts(1.0, bodies);
  std::vector<ContactResponse> r;
  const double rhoS = s.strands[0].spec().hair.linearDensity();
  for (auto _ : state)
  {
    for (const std::vector<StrandSample>& smp : samples)
    {
      r.assign(smp.size(), ContactResponse());
      s.contacts.respond(smp, rhoS, bodies.data(), 2, r);
      benchmark::DoNotOptimize(r.data());
    }
  }
  state.SetItemsProcessed(state.iterations() * samples.size());
}

void BM_StrandInContact(benchmark::State& state)
{
  const int n = static_cast<int>(state.range(0));
  const bool contacts = state.range(1) != 0;
  StrandSpec spec = StrandSpec::uniform(0.3, n, HairParameters::preset(HairType::Wavy));
  spec.gravity.setZero();
  SuperHelix warm;
  if (!warm.initialize(spec))
  {
    state.SkipWithError("initialize failed");
    return;
  }
  if (contacts)
    warm.setContactForces(
        [](int, double, const std::vector<StrandSample>& s, std::vector<ContactResponse>& r)
        {
          const Eigen::Vector3d up(0, 1, 0);
          for (size_t i = 0; i < s.size(); ++i)
          {
            r[i].stiffness = 10 * up * up.transpose();
            r[i].damping = 1e-3 * Eigen::Matrix3d::Identity();
            r[i].damping(0, 1) = 2e-4;
          }
        });
  for (int i = 0; i < 10; ++i)
    (void)warm.step(1.0 / 30);
  SuperHelix h = warm;
  int steps = 0;
  for (auto _ : state)
  {
    if (++steps % 30 == 0)
    {
      state.PauseTiming();
      h = warm;
      state.ResumeTiming();
    }
    const Status st = h.step(1.0 / 30);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
  }
  state.SetLabel(contacts ? "every sample in contact" : "no contacts");
}
void BM_SimulationFrame(benchmark::State& state)
{
  Bench& s = scene(1000); // for the body, its tables and the roots' layout
  static const std::vector<GuideStrand> guides = benchGuides(s.body, 1000);
  const Scene world = demoScene(s.body);
  SimulationOptions o;
  o.threads = static_cast<int>(state.range(0));
  Simulation sim;
  Status st = sim.initialize(guides, world, o);
  if (!st)
  {
    state.SkipWithError(st.message().c_str());
    return;
  }
  int frames = 1;
  for (auto _ : state)
  {
    if (frames == 61) // 2 s, then again from the start (frames are kept in memory)
    {
      state.PauseTiming();
      st = sim.initialize(guides, world, o);
      frames = 1;
      state.ResumeTiming();
    }
    st = sim.advanceTo(++frames);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
  }
}
void stepArgs(benchmark::internal::Benchmark* b)
{
  for (int guides : {200, 1000, 5000})
    for (int contacts : {0, 1})
      b->Args({guides, contacts, 1});
  for (int contacts : {0, 1})
    b->Args({1000, contacts, 2});
}
} // namespace

BENCHMARK(BM_Step)->Apply(stepArgs)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_StrandInContact)->ArgsProduct({{10, 20, 40}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SimulationFrame)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);
BENCHMARK(BM_Respond)->Arg(200)->Arg(1000)->Arg(5000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
