// Rendered hair from guides, per frame (render/HairInterpolation::evaluate):
//   BM_Interpolate/<rendered strands>/<threads>/<tables>  the demo's 200 wavy Super-Helix
//     guides 1 s into the head shake, 32 points per rendered strand, semi-interpolation, each
//     point pushed out of the head and trunk tables posed at that time (tables 1) or not
//     (tables 0: the interpolation alone). Counters: rendered points,
//     points pushed out, bytes of one frame's output.
//   BM_Bind/<rendered strands>  rooting and binding (once per scalp and guides, not per frame).
// Command and figures: docs/benchmarks.md, "Rendered hair".
#include "DemoScene.h"
#include "render/HairInterpolation.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"

#include <benchmark/benchmark.h>

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
  const StateFrame& last = sim.frame(30);
  f->curves.points = last.positions;
  for (std::int64_t o : sim.header().offsets)
    f->curves.offsets.push_back(std::size_t(o));
  f->curves.scalars["curvature"] = last.pointData.at("curvature");
  scene.posedParts(last.time, f->parts);
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
  RenderedHair out;
  const std::vector<PosedPart> none;
  for (auto _ : state)
  {
    if (Status s = hi.evaluate(f.curves, state.range(2) ? f.parts : none, out); !s)
    {
      state.SkipWithError(s.message().c_str());
      return;
    }
  }
  state.counters["points"] = double(o.strands) * o.pointsPerStrand;
  state.counters["pushed"] = double(out.pushedOut);
  state.counters["MB_out"] = double(out.points.size() + out.tangents.size() + out.parameter.size() +
                                    out.scalars.size() * out.parameter.size()) *
                             sizeof(float) / 1e6;
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
