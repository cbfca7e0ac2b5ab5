// Cost of the Super-Helix step (docs/benchmarks-superhelix.md has the table and command).
//   BM_Step/<preset>/<N>     one public step(1/30 s) of one 30 cm strand on a shaking head
//                            (one linear solve; counter "substeps" must read 1)
//   BM_Phase_*/<N>           the pieces of one step: reconstruction (kinematics at every
//                            sample), assembly of M and f, the velocity Jacobian C, the
//                            tension stiffness K_T, and the dense LU solve
//   BM_StrandsPerSecond/<T>  256 strands of N = 10 stepped together on T threads
//   BM_ReferenceState/<p>    guard for speed work: q after 30 steps (wavy, curly, N = 10)
//                            against values recorded before it; errors past 1e-9 relative
#include "superhelix/SuperHelix.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace hair;

namespace
{
StrandSpec shakenStrand(HairType type, int n, int id = 0)
{
  StrandSpec s = StrandSpec::uniform(0.3, n, HairParameters::preset(type));
  s.id = id;
  s.seed = 1 + id;
  HeadShake shake;
  shake.attachment = Eigen::Vector3d(0.1, 0.002 * (id % 50), 0);
  shake.attachmentFrame.col(0) = Eigen::Vector3d(0, -1, 0);
  shake.attachmentFrame.col(1) = Eigen::Vector3d(1, 0, 0);
  shake.attachmentFrame.col(2) = Eigen::Vector3d(0, 0, 1);
  s.root = shake;
  return s;
}

// A strand 1 s into the head shake: curved and moving, as in use.
SuperHelix warmStrand(HairType type, int n)
{
  SuperHelix h;
  (void)h.initialize(shakenStrand(type, n));
  for (int i = 0; i < 30; ++i)
    (void)h.step(1.0 / 30);
  return h;
}

void BM_Step(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  SuperHelix h = warmStrand(type, static_cast<int>(state.range(1)));
  double substeps = 0;
  for (auto _ : state)
  {
    Status st = h.step(1.0 / 30);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
    substeps += h.lastSubsteps();
  }
  state.counters["substeps"] = benchmark::Counter(substeps, benchmark::Counter::kAvgIterations);
  state.SetLabel(toString(type));
}

void BM_Phase_Reconstruct(benchmark::State& state)
{
  SuperHelix h = warmStrand(HairType::Wavy, static_cast<int>(state.range(0)));
  for (auto _ : state)
  {
    h.reconstruct();
    benchmark::ClobberMemory();
  }
}

void BM_Phase_AssembleMassAndForce(benchmark::State& state)
{
  SuperHelix h = warmStrand(HairType::Wavy, static_cast<int>(state.range(0)));
  h.reconstruct();
  for (auto _ : state)
  {
    h.assemble();
    benchmark::DoNotOptimize(h.massMatrix().data());
  }
}

void BM_Phase_VelocityJacobian(benchmark::State& state)
{
  SuperHelix h = warmStrand(HairType::Wavy, static_cast<int>(state.range(0)));
  h.reconstruct();
  h.assemble();
  for (auto _ : state)
  {
    h.assembleVelocityJacobian();
    benchmark::DoNotOptimize(h.velocityJacobian().data());
  }
}

void BM_Phase_TensionStiffness(benchmark::State& state)
{
  SuperHelix h = warmStrand(HairType::Wavy, static_cast<int>(state.range(0)));
  h.reconstruct();
  h.assemble();
  for (auto _ : state)
  {
    h.assembleTensionStiffness(1.0 / 30);
    benchmark::DoNotOptimize(h.tensionStiffness().data());
  }
}

void BM_Phase_Solve(benchmark::State& state)
{
  SuperHelix h = warmStrand(HairType::Wavy, static_cast<int>(state.range(0)));
  h.reconstruct();
  h.assemble();
  h.assembleVelocityJacobian();
  h.assembleTensionStiffness(1.0 / 30);
  Eigen::VectorXd qd;
  for (auto _ : state)
  {
    (void)h.solve(1.0 / 30, qd);
    benchmark::DoNotOptimize(qd.data());
  }
}

void BM_StrandsPerSecond(benchmark::State& state)
{
  const int threads = static_cast<int>(state.range(0));
  std::vector<SuperHelix> strands(256);
  for (int i = 0; i < 256; ++i)
    (void)strands[i].initialize(shakenStrand(static_cast<HairType>(i % 4), 10, i));
  for (int k = 0; k < 10; ++k)
    (void)stepStrands(strands, 1.0 / 30, threads);
  for (auto _ : state)
  {
    Status st = stepStrands(strands, 1.0 / 30, threads);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
  }
  state.SetItemsProcessed(state.iterations() * 256);
  state.counters["threads"] = threads;
}

// q after 30 steps of 1/30 s on the head shake (warmStrand), N = 10, recorded with the code
// of commit 072a09d (before the speed work of docs/benchmarks-superhelix.md, fourth
// revision). A speed change must leave the results the same to round-off: the step is
// deterministic, and 30 steps amplified round-off changes of the speed work to < 1e-12
// relative, so 1e-9 separates round-off from a change of the computation.
constexpr double ReferenceWavy[30] = {
    75.335414823395794,   37.217701075197724, 11.419982482641899,  49.633985294004596,
    67.12508089139854,    5.0347264162640659, 56.514628979386217,  92.665291918538074,
    -5.5321090185182289,  51.46526215386595,  78.483807242076935,  7.6145601318718477,
    33.151372665966186,   100.79680481634928, -3.0803713130280537, 39.044820676336755,
    95.125464394921522,   4.0593233236996538, 21.216302402310859,  107.05843010758987,
    -0.56569743686111451, 22.588748730128149, 101.92326015675653,  1.3882403212260155,
    14.544205869400338,   100.79031669448244, 1.0418636781939887,  8.8959745291706191,
    95.372273932964035,   0.53643899985790333};
constexpr double ReferenceCurly[30] = {
    29.822812657721109,  167.92622447135423, 30.109545619516226,  93.587973024686434,
    121.41321771518733,  23.476229247129787, 71.773458825684713,  173.42020107369177,
    -5.3142803944947437, 56.836001156376518, 150.34818529192859,  -13.033426502224447,
    44.636631869520372,  163.91665778383864, -1.4908391836972386, 47.533882884778563,
    166.24487070996616,  4.654402653105894,  42.990294429792549,  173.49425446456689,
    1.8719543282278674,  36.011518098178229, 169.92427689421356,  0.21503357840321571,
    29.83052481542018,   164.00029714410317, 0.40410550168281245, 24.473775367362876,
    159.14896211392255,  0.95480662018339402};

void BM_ReferenceState(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  const double* ref = type == HairType::Wavy ? ReferenceWavy : ReferenceCurly;
  double deviation = 0;
  for (auto _ : state)
  {
    const SuperHelix h = warmStrand(type, 10);
    double diff = 0, scale = 0;
    for (int i = 0; i < 30; ++i)
    {
      diff = std::max(diff, std::abs(h.q()[i] - ref[i]));
      scale = std::max(scale, std::abs(ref[i]));
    }
    deviation = diff / scale;
  }
  state.counters["rel_dev"] = deviation;
  state.SetLabel(toString(type));
  if (!(deviation <= 1e-9))
    state.SkipWithError("q after 30 steps differs from the recorded reference by more than 1e-9 "
                        "relative: the speed change altered the results.");
}

void stepArgs(benchmark::internal::Benchmark* b)
{
  for (int type : {0, 1, 2, 3})
    for (int n : {1, 2, 5, 10, 20, 40})
      b->Args({type, n});
}

void nArgs(benchmark::internal::Benchmark* b)
{
  for (int n : {1, 2, 5, 10, 20, 40})
    b->Arg(n);
}
} // namespace

BENCHMARK(BM_Step)->Apply(stepArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Phase_Reconstruct)->Apply(nArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Phase_AssembleMassAndForce)->Apply(nArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Phase_VelocityJacobian)->Apply(nArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Phase_TensionStiffness)->Apply(nArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Phase_Solve)->Apply(nArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReferenceState)->Arg(1)->Arg(2)->Iterations(1);
BENCHMARK(BM_StrandsPerSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
