// Cost of the Super-Helix step (docs/benchmarks-superhelix.md has the table and command).
//   BM_Step/<preset>/<N>     one public step(1/30 s) of one 30 cm strand on a shaking head
//                            (one linear solve; counter "substeps" must read 1)
//   BM_Phase_*/<N>           the pieces of one step: reconstruction (kinematics at every
//                            sample), assembly of M and f, the velocity Jacobian C, the
//                            tension stiffness K_T, and the dense LU solve
//   BM_StrandsPerSecond/<T>  256 strands of N = 10 stepped together on T threads
#include "superhelix/SuperHelix.h"

#include <benchmark/benchmark.h>

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
BENCHMARK(BM_StrandsPerSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
