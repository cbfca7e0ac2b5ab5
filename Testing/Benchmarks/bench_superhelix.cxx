// Cost of the Super-Helix step (docs/benchmarks.md has the table and command).
//   BM_Step/<preset>/<N>     one public step(1/30 s) of one 30 cm strand on a shaking head
//                            (one linear solve; counter "substeps" must read 1)
//   BM_Phase_*/<N>           the pieces of one step: reconstruction (kinematics at every
//                            sample), assembly of M and f, the velocity Jacobian C, the
//                            tension stiffness K_T, and the dense LU solve
//   BM_StrandsPerSecond/<T>  256 strands of N = 10 stepped together on T threads
//   BM_RealTimeGuides/<T>    1000 strands of N = 10 on T threads: frames of 1/30 s per second
//   BM_ReferenceState/<p>    guard for speed work: q after 30 steps (each preset, N = 10)
//                            against values recorded before it; errors past 1e-9 relative
//   BM_StepTolerance/<p>/<k> the step of BM_Step (N = 10) with the quadrature tolerance
//                            k = 0: default (5.3e-6), 1: 1e-4, 2: 1e-3, 3: 1e-2; counters:
//                            samples per step, and after 2 s of the shake the difference of
//                            q from a tight rule (1e-12), q_dev, next to the time step's
//                            own error at 1/30 s (from 1/480 s), dt_dev, both relative to
//                            max |q|: what a looser rule buys and what it costs
//   BM_IntegratorSideBySide/<p>/<m>  one step(1/30 s) at N = 10 of the semi-implicit and of the
//                            second-order (midpoint) step, from the same states, interleaved
//                            in blocks of 10 steps; m = 0: the 3 Hz ±30° shake of BM_Step,
//                            m = 1: the demo's gentler shake, ±0.5 rad at 1 Hz; counters:
//                            µs per step of each (the least time for the same 30 steps),
//                            their ratio, and the share of the midpoint's steps taken first
//                            order (declined, or skipped after a declined one)
//   BM_GramSideBySide/<p>    the velocity Jacobian C and the whole step (N = 10) with the
//                            element moments summed per sample and from the Gram matrix
//                            (StrandSpec::gramMinSamples above any count, and 1), the two
//                            ways interleaved in blocks of a few µs, so that the machine's
//                            slow periods (seconds long) hit both alike; counters: minimum
//                            µs per call of each way, and samples per element
#include "GoldenStates.h"
#include "HeadShake.h"
#include "superhelix/SuperHelix.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

using namespace hair;

namespace
{
// A strand 1 s into the head shake: curved and moving, as in use.
SuperHelix warmStrand(HairType type, int n)
{
  SuperHelix h;
  (void)h.initialize(shakenStrand(type, n));
  for (int i = 0; i < 30; ++i)
    (void)h.step(1.0 / 30);
  return h;
}

// The steps from t = 1 s to 2 s of the shake, over and over (a copy of `warm` every 30
// steps, outside the timing): the cost follows the samples, which follow the strand's
// curvature, so a strand left shaking for the whole run would give figures that depend on how
// long it ran. afterStep(strand) runs after each step, timed.
template <class AfterStep>
void cycledSteps(benchmark::State& state, const SuperHelix& warm, AfterStep afterStep)
{
  SuperHelix h = warm;
  int k = 0;
  for (auto _ : state)
  {
    if (k == 30)
    {
      state.PauseTiming();
      h = warm;
      k = 0;
      state.ResumeTiming();
    }
    const Status st = h.step(1.0 / 30);
    if (!st)
    {
      state.SkipWithError(st.message().c_str());
      break;
    }
    ++k;
    afterStep(h);
  }
}

void BM_Step(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  const SuperHelix warm = warmStrand(type, static_cast<int>(state.range(1)));
  double substeps = 0;
  cycledSteps(state, warm, [&](const SuperHelix& h) { substeps += h.lastSubsteps(); });
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

// `count` strands of N = 10, the four presets in turn, on the head shake, stepped together
// on `threads` threads, one 1/30 s step per iteration (after 10 steps of warm-up).
void stepMixedStrands(benchmark::State& state, int count, int threads)
{
  std::vector<SuperHelix> strands(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i)
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
  state.counters["threads"] = threads;
}

void BM_StrandsPerSecond(benchmark::State& state)
{
  stepMixedStrands(state, 256, static_cast<int>(state.range(0)));
  state.SetItemsProcessed(state.iterations() * 256);
}

// The purpose: 1000 guide strands (N = 10, the four presets in turn) in real time,
// i.e. 30 frames of 1/30 s per second of wall time. items_per_second is frames per second.
void BM_RealTimeGuides(benchmark::State& state)
{
  stepMixedStrands(state, 1000, static_cast<int>(state.range(0)));
  state.SetItemsProcessed(state.iterations());
}

// q after 30 steps of 1/30 s on the head shake (warmStrand), N = 10, against the golden
// values (Testing/Fixtures/GoldenStates.h, which says why 1e-9 relative).
void BM_ReferenceState(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  const double* ref = golden::ShakenQ[static_cast<int>(type)];
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
  if (!(deviation <= golden::ShakenQTolerance))
    state.SkipWithError("q after 30 steps differs from the recorded reference by more than 1e-9 "
                        "relative: the speed change altered the results.");
}

constexpr double Tolerances[] = {0, 1e-4, 1e-3, 1e-2}; // 0: the default

// q after 2 s of the head shake (N = 10), with `perFrame` steps per 1/30 s.
Eigen::VectorXd shakenQ(HairType type, double tolerance, int perFrame)
{
  StrandSpec spec = shakenStrand(type, 10);
  if (tolerance > 0)
    spec.quadratureTolerance = tolerance;
  SuperHelix h;
  (void)h.initialize(spec);
  for (int i = 0; i < 60 * perFrame; ++i)
    (void)h.step(1.0 / (30 * perFrame));
  return h.q();
}

void BM_StepTolerance(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  const double tolerance = Tolerances[state.range(1)];
  StrandSpec spec = shakenStrand(type, 10);
  if (tolerance > 0)
    spec.quadratureTolerance = tolerance;
  SuperHelix warm;
  (void)warm.initialize(spec);
  for (int i = 0; i < 30; ++i)
    (void)warm.step(1.0 / 30);
  double samples = 0;
  cycledSteps(state, warm,
              [&](const SuperHelix& h) { samples += static_cast<double>(h.samples().size()); });
  const Eigen::VectorXd q = shakenQ(type, tolerance, 1), tight = shakenQ(type, 1e-12, 1);
  const Eigen::VectorXd fine = shakenQ(type, 1e-12, 16);
  const double scale = tight.cwiseAbs().maxCoeff();
  state.counters["samples"] = benchmark::Counter(samples, benchmark::Counter::kAvgIterations);
  state.counters["q_dev"] = (q - tight).cwiseAbs().maxCoeff() / scale;
  state.counters["dt_dev"] = (tight - fine).cwiseAbs().maxCoeff() / scale;
  state.SetLabel(toString(type));
}

void BM_GramSideBySide(benchmark::State& state)
{
  const SuperHelix warm = warmStrand(static_cast<HairType>(state.range(0)), 10);
  // The warm state in two strands whose specs differ only in the threshold.
  SuperHelix warmWay[2];
  for (int way = 0; way < 2; ++way)
  {
    StrandSpec spec = warm.spec();
    spec.gramMinSamples = way == 0 ? 1 << 30 : 1;
    (void)warmWay[way].initialize(spec, warm.time());
    (void)warmWay[way].setState(warm.q(), warm.qdot());
  }
  using Clock = std::chrono::steady_clock;
  double bestC[2] = {1e30, 1e30}, bestStep[2] = {1e30, 1e30};
  for (auto _ : state)
    for (int way = 0; way < 2; ++way)
    {
      SuperHelix h = warmWay[way];
      h.reconstruct();
      h.assemble();
      auto t0 = Clock::now();
      for (int i = 0; i < 20; ++i)
        h.assembleVelocityJacobian();
      auto t1 = Clock::now();
      bestC[way] =
          std::min(bestC[way], std::chrono::duration<double, std::micro>(t1 - t0).count() / 20);
      t0 = Clock::now();
      for (int i = 0; i < 10; ++i)
        (void)h.step(1.0 / 30);
      t1 = Clock::now();
      bestStep[way] =
          std::min(bestStep[way], std::chrono::duration<double, std::micro>(t1 - t0).count() / 10);
    }
  SuperHelix h = warm;
  h.reconstruct();
  state.counters["C_per_sample_us"] = bestC[0];
  state.counters["C_gram_us"] = bestC[1];
  state.counters["step_per_sample_us"] = bestStep[0];
  state.counters["step_gram_us"] = bestStep[1];
  state.counters["samples_per_element"] = double(h.samples().size()) / 10;
}

void BM_IntegratorSideBySide(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  StrandSpec spec = shakenStrand(type, 10);
  if (state.range(1) == 1)
  {
    HeadShake gentle;
    gentle.amplitude = 0.5;
    gentle.frequency = 1.0;
    gentle.attachment = Eigen::Vector3d(0.1, 0, 0);
    gentle.attachmentFrame.col(0) = Eigen::Vector3d(0, -1, 0);
    gentle.attachmentFrame.col(1) = Eigen::Vector3d(1, 0, 0);
    gentle.attachmentFrame.col(2) = Eigen::Vector3d(0, 0, 1);
    spec.root = gentle;
  }
  // 1 s into the motion with the semi-implicit step; then 30 steps (1 s … 2 s) of each
  // integrator from that state, in blocks of 10, over and over.
  SuperHelix warm;
  (void)warm.initialize(spec);
  for (int i = 0; i < 30; ++i)
    (void)warm.step(1.0 / 30);
  // The three steps: semi-implicit, midpoint, BDF2 (whose first step from the set state is
  // semi-implicit: it has no history).
  constexpr int Ways = 3;
  const Integrator ways[Ways] = {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2};
  SuperHelix start[Ways];
  for (int way = 0; way < Ways; ++way)
  {
    StrandSpec s = spec;
    s.integrator = ways[way];
    (void)start[way].initialize(s, warm.time());
    (void)start[way].setState(warm.q(), warm.qdot());
  }
  using Clock = std::chrono::steady_clock;
  // Per iteration the same 30 steps of each, in interleaved blocks of 10; the figure of an
  // integrator is its least time for the 30 over the iterations (a block-wise minimum would
  // favour the midpoint's blocks that skip the attempt after a declined step).
  double best[Ways] = {1e30, 1e30, 1e30};
  long steps = 0, firstOrder[Ways] = {0, 0, 0};
  for (auto _ : state)
  {
    double cycle[Ways] = {0, 0, 0};
    SuperHelix h[Ways] = {start[0], start[1], start[2]};
    for (int block = 0; block < 3; ++block)
    {
      for (int way = 0; way < Ways; ++way)
      {
        int declined = 0;
        const auto t0 = Clock::now();
        for (int i = 0; i < 10; ++i)
        {
          (void)h[way].step(1.0 / 30);
          declined += h[way].lastFirstOrder();
        }
        cycle[way] += std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        firstOrder[way] += declined;
      }
      steps += 10;
    }
    for (int way = 0; way < Ways; ++way)
      best[way] = std::min(best[way], cycle[way] / 30);
  }
  state.counters["semi_implicit_us"] = best[0];
  state.counters["midpoint_us"] = best[1];
  state.counters["ratio"] = best[1] / best[0];
  state.counters["midpoint_first_order"] = double(firstOrder[1]) / std::max(1L, steps);
  state.counters["bdf2_us"] = best[2];
  state.counters["bdf2_ratio"] = best[2] / best[0];
  state.counters["bdf2_first_order"] = double(firstOrder[2]) / std::max(1L, steps);
  state.SetLabel(toString(type));
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
BENCHMARK(BM_ReferenceState)->DenseRange(0, 3)->Iterations(1);
BENCHMARK(BM_StepTolerance)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GramSideBySide)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IntegratorSideBySide)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StrandsPerSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RealTimeGuides)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
