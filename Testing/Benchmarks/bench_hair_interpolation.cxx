// Rendered hair from guides, per frame (render/HairInterpolation::evaluate):
//   BM_Interpolate/<rendered strands>/<threads>/<tables>  the demo's 200 wavy Super-Helix
//     guides 1 s into the head shake, 32 points per rendered strand, semi-interpolation, each
//     point pushed out of the head and trunk tables posed at that time (tables 1) or not
//     (tables 0: the interpolation alone), written into new arrays each frame as the filter
//     does. Counters: rendered points, the fraction looked up in the tables, points pushed
//     out and left inside, ns per point (wall), MB of one frame's output, bytes the binding
//     keeps per strand.
//   BM_Bind/<rendered strands>  rooting and binding (once per scalp and guides, not per frame).
// Command and figures: docs/benchmarks.md, "Rendered hair".
#include "DemoScene.h"
#include "render/HairInterpolation.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

using namespace hair;

namespace
{

struct Frame
{
  BundledBody body;
  std::vector<GuideStrand> guides;
  Scene scene; ///< owns the tables the posed parts point to
  GuideCurves curves;
  std::vector<PosedPart> parts;
};

Frame& frame()
{
  static std::unique_ptr<Frame> f;
  if (f)
    return *f;
  f = std::make_unique<Frame>();
  (void)loadBundledBody(HAIR_DATA_DIR, f->body);
  (void)demoGuides(f->body, 200, 10, f->guides);
  f->scene = demoScene(f->body);
  const Scene& scene = f->scene;
  Simulation sim;
  SimulationOptions options;
  options.threads = 2;
  (void)sim.initialize(f->guides, scene, options);
  (void)sim.advanceTo(31);
  // The guides as Hair Simulation's output 0 gives them to Hair Interpolation: drawn from
  // the state at its default 16 points per element, with material frames and curvature.
  if (Status s = drawnCurves(sim, 30, 16, {"curvature"}, f->curves); !s)
  {
    std::fprintf(stderr, "bench_hair_interpolation: %s\n", s.message().c_str());
    std::exit(1);
  }
  scene.posedParts(sim.frame(30).time, f->parts);
  return *f;
}

void BM_Interpolate(benchmark::State& state)
{
  Frame& f = frame();
  InterpolationOptions o;
  o.strands = static_cast<int>(state.range(0));
  o.threads = static_cast<int>(state.range(1));
  HairInterpolation hi;
  if (Status s = hi.bind(f.guides, f.body.mesh, o); !s)
  {
    state.SkipWithError(s.message().c_str());
    return;
  }
  // As the filter does: each frame into new, uninitialized arrays (its VTK arrays), written
  // straight by evaluate().
  const std::vector<PosedPart> none;
  const std::size_t points = std::size_t(o.strands) * std::size_t(o.pointsPerStrand);
  PushOutCounts out;
  for (auto _ : state)
  {
    std::unique_ptr<float[]> xyz(new float[3 * points]), tangents(new float[3 * points]),
        parameter(new float[points]), curvature(new float[points]);
    std::unique_ptr<int[]> guide(new int[std::size_t(o.strands)]);
    RenderedHairArrays arrays;
    arrays.points = xyz.get();
    arrays.tangents = tangents.get();
    arrays.parameter = parameter.get();
    arrays.guide = guide.get();
    arrays.scalars = {curvature.get()};
    out = PushOutCounts();
    if (Status s = hi.evaluate(f.curves, state.range(2) ? f.parts : none, arrays, out); !s)
    {
      state.SkipWithError(s.message().c_str());
      return;
    }
    benchmark::DoNotOptimize(xyz.get());
  }
  state.counters["points"] = double(points);
  state.counters["looked_up"] = double(out.lookedUp) / double(points);
  state.counters["pushed"] = double(out.pushedOut);
  state.counters["inside_after"] = double(out.stillInside);
  state.counters["ns_per_point"] =
      benchmark::Counter(double(points) * 1e-9, benchmark::Counter::kIsIterationInvariantRate |
                                                    benchmark::Counter::kInvert);
  state.counters["MB_out"] = double(8 * points * sizeof(float) + o.strands * sizeof(int)) / 1e6;
  // What the binding keeps per rendered strand (HairInterpolation::bindings()).
  state.counters["B_per_strand"] = double(sizeof(HairInterpolation::Binding));
}

void BM_Bind(benchmark::State& state)
{
  Frame& f = frame();
  InterpolationOptions o;
  o.strands = static_cast<int>(state.range(0));
  for (auto _ : state)
  {
    HairInterpolation hi;
    if (Status s = hi.bind(f.guides, f.body.mesh, o); !s)
    {
      state.SkipWithError(s.message().c_str());
      return;
    }
  }
}

} // namespace

BENCHMARK(BM_Interpolate)
    ->ArgsProduct({{10000, 50000, 100000, 200000}, {1, 2}, {1}})
    ->Args({100000, 1, 0})
    ->Args({100000, 2, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Bind)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
