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
//   BM_GramSideBySide/<p>    the velocity Jacobian C and the whole step (N = 10) with the
//                            element moments summed per sample and from the Gram matrix
//                            (StrandSpec::gramMinSamples above any count, and 1), the two
//                            ways interleaved in blocks of a few µs, so that the machine's
//                            slow periods (seconds long) hit both alike; counters: minimum
//                            µs per call of each way, and samples per element
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

// q after 30 steps of 1/30 s on the head shake (warmStrand), N = 10, recorded once the
// natural curvature and the per-element quadrature rule were in place, before any speed
// work on them (Testing/Core/test_golden.cxx checks the same values in CTest). A speed change must
// leave the results the same to round-off: the step is deterministic, and 30 steps amplify a 1e-7
// relative perturbation of q to < 2e-7 (measured), so round-off stays < 1e-12 relative and 1e-9
// separates it from a change of the computation.
constexpr double ReferenceSmooth[30] = {
    1.5922737531962414,    -16.85074906169794,    5.1838328189659713,   0.98800619864179295,
    3.0471274488105662,    -0.34956653533683596,  0.91357070243902427,  2.9088588864907834,
    -0.10363726529722755,  0.6659471100217762,    3.8957262174562883,   0.020034820261155772,
    0.27289364267736221,   4.7577993064505755,    0.13691999684047396,  -0.055890672116472417,
    4.693500703619705,     0.15086965531599683,   -0.10350428050937709, 2.5345757491571757,
    0.14570600378609863,   -0.026021906975813774, 0.19412201769774828,  0.17745473597946593,
    0.0021220450692968889, -0.37585186496223555,  0.055321273933891774, 0.00031039622294003351,
    -0.048636949752406566, -0.010970753697031658};
constexpr double ReferenceWavy[30] = {
    74.946674377898617,   36.610130506718669, 11.358030844515039,  50.194649502951577,
    66.528960047679675,   5.0870586984078763, 56.088995658467397,  91.752912380153774,
    -5.2534305891714146,  52.201111896098446, 77.91227435714616,   7.1975598249657615,
    32.664227491422629,   99.740324242640497, -2.3665758772481502, 39.522590100792904,
    94.691670074655661,   3.3831685300242444, 21.030120010014251,  106.09396621198192,
    0.079927277268686092, 22.711149000349312, 101.43471055880282,  0.96482044611332318,
    14.68654395256015,    100.11177260015535, 1.255762259245546,   8.7470417852071094,
    94.855170327519176,   0.47899620560562062};
constexpr double ReferenceCurly[30] = {
    31.491562379654447,  165.64701409149092, 30.818368578647725,  94.858520886144348,
    119.52342313209414,  20.366557714708204, 70.661650673272703,  169.97343196775611,
    -6.5297467167940013, 53.21625533311088,  147.55583005450436,  -12.627252740619689,
    44.789074963603319,  161.93721400985123, 0.91928407775772991, 49.218651730932052,
    163.14777459808434,  4.9342955344937689, 41.90159948445099,   170.26470665063474,
    0.97612301036669757, 35.254177723118119, 165.65414895321683,  0.19133548938429956,
    29.620041949461935,  160.80307736858157, 0.39370440444905103, 24.146074502356392,
    157.76218451464152,  1.0222146049774723};
constexpr double ReferenceFuzzy[30] = {
    452.25947829702858,   254.67911078173788,  21.57956459547654,    455.84916319348173,
    275.34950186916552,   -12.327668883716303, 457.49608290900125,   275.0161678883415,
    8.4423310285129443,   437.97467332784248,  272.69565583875129,   -4.4129816216380151,
    447.09753522556957,   266.75846151664024,  0.63952693576956143,  458.53251218499884,
    279.1602417765971,    0.42261366093269359, 458.19086811437569,   285.01189946711298,
    0.044863497883796288, 443.115684836936,    286.59958730318016,   -0.15187329324547527,
    439.42487683787618,   278.40589262466023,  0.075393591803353033, 438.666873362594,
    269.15859941108027,   0.099003429746303939};

void BM_ReferenceState(benchmark::State& state)
{
  const HairType type = static_cast<HairType>(state.range(0));
  const double* const refs[] = {ReferenceSmooth, ReferenceWavy, ReferenceCurly, ReferenceFuzzy};
  const double* ref = refs[static_cast<int>(type)];
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
BENCHMARK(BM_StrandsPerSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RealTimeGuides)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
