// hair_study integrator: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Issue 23: the two time steps measured side by side (docs/super-helix.md, "The
// second-order step", "Accuracy on request"). One CSV row per run:
//   case, integrator, dt_s, tolerance_m_per_s, figure, value, steps, rejected, first_order,
//   wall_s
// release: a 30 cm smooth strand clamped horizontally, no friction, no air, 2 s; figure
//   residual_share = residual / gravitational energy released at 2 s.
// tip: the same strand with air drag 1e-5 kg/(m·s), 1 s, frames of 1/30 s; figure
//   tip_error_m = the largest distance of its tip from that of the second-order step at
//   1/7680 s over the frames (the reference, itself within 2.8e-5 m of 1/15360 s).
// tolerance: the tip's strand in frames of 1/30 s with advance(1/30, tolerance/30).
// demo (demo=1): the demo scene (Testing/Fixtures/DemoScene: wavy guides on the bundled
//   body's scalp, head and trunk tables, ±0.5 rad 1 Hz shake, 0.5 m/s wind) through
//   Simulation, `seconds` long, with and without contacts; figure closure = max |residual| /
//   max |work done on the hair|, and the cost per simulated second.
// quick=1: fewer step sizes and tolerances (seconds of run time).

int integrator(const Arguments& args)
{
  const int quick = args.integer("quick"), demo = args.integer("demo"),
            guides = args.integer("guides");
  const double seconds = args.number("seconds");
  std::ofstream out;
  Status s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study integrator: " << s.message() << "\n";
    return 2;
  }
  out << "case,integrator,dt_s,tolerance_m_per_s,figure,value,steps,rejected,first_order,wall_s\n";
  const Integrator both[] = {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2};
  auto row = [&](const char* what, Integrator in, double dt, double tol, const char* figure,
                 double value, const IntegratorRun& r)
  {
    out << what << "," << toString(in) << "," << dt << "," << tol << "," << figure << "," << value
        << "," << r.steps << "," << r.rejected << "," << r.firstOrder << "," << r.wall << "\n";
  };
  auto fail = [&](const Status& st)
  {
    std::cerr << "hair_study integrator: " << st.message() << "\n";
    return 1;
  };
  const std::vector<int> perFrame =
      quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 2, 4, 8, 16, 32, 64, 128};
  for (Integrator in : both)
    for (int per : perFrame)
    {
      Status st;
      const IntegratorRun r = releasedStrand(in, 0, 2, per, 0, st);
      if (!st)
        return fail(st);
      row("release", in, 1.0 / (30 * per), 0, "residual_share", r.residualShare, r);
    }
  Status st;
  const IntegratorRun ref = releasedStrand(Integrator::Midpoint, 1e-5, 1, 256, 0, st);
  if (!st)
    return fail(st);
  auto tipError = [&](const IntegratorRun& r)
  {
    double e = 0;
    for (size_t i = 0; i < r.tips.size() && i < ref.tips.size(); ++i)
      e = std::max(e, (r.tips[i] - ref.tips[i]).norm());
    return e;
  };
  for (Integrator in : both)
    for (int per : perFrame)
    {
      if (per > 64)
        continue;
      const IntegratorRun r = releasedStrand(in, 1e-5, 1, per, 0, st);
      if (!st)
        return fail(st);
      row("tip", in, 1.0 / (30 * per), 0, "tip_error_m", tipError(r), r);
    }
  const std::vector<double> tolerances = quick
                                             ? std::vector<double>{0.05, 0.005}
                                             : std::vector<double>{0.05, 0.02, 0.01, 0.005, 0.002};
  for (Integrator in : both)
    for (double tol : tolerances)
    {
      const IntegratorRun r = releasedStrand(in, 1e-5, 1, 1, tol, st);
      if (!st)
        return fail(st);
      row("tolerance", in, 1.0 / 30, tol, "tip_error_m", tipError(r), r);
    }
  if (!demo)
    return 0;
  BundledBody body;
  if (st = loadBundledBody(HAIR_DATA_DIR, body); !st)
    return fail(st);
  std::vector<GuideStrand> demoStrands;
  if (st = demoGuides(body, guides, 10, demoStrands); !st)
    return fail(st);
  for (int contacts : {1, 0})
    for (Integrator in : both)
      for (double tol : {0.0, 0.005})
      {
        SimulationOptions o;
        o.threads = 1;
        o.superHelix.integrator = in;
        o.superHelix.tolerance = tol;
        o.contacts.enabled = contacts != 0;
        Simulation sim;
        if (st = sim.initialize(demoStrands, demoScene(body), o); !st)
          return fail(st);
        const auto start = std::chrono::steady_clock::now();
        if (st = sim.advanceTo(static_cast<int>(std::lround(seconds * 30)) + 1); !st)
          return fail(st);
        IntegratorRun r;
        r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::vector<double> times;
        std::map<std::string, std::vector<double>> c;
        sim.energyTable(times, c);
        double residual = 0, work = 0, substeps = 0, rejected = 0, firstOrder = 0;
        for (size_t i = 0; i < times.size(); ++i)
        {
          const double w = -(c["gravitational"][i] - c["gravitational"][0]) + c["root_work"][i] +
                           c["wind_work"][i] + c["contact_work"][i];
          residual = std::max(residual, std::abs(c["residual"][i]));
          work = std::max(work, std::abs(w));
          substeps += c["substeps"][i];
          rejected += c["rejected_substeps"][i];
          firstOrder += c["first_order_share"][i] * c["substeps"][i];
        }
        // Per strand and simulated second.
        r.steps = std::lround(substeps / seconds);
        r.rejected = std::lround(rejected / seconds);
        r.firstOrder = std::lround(firstOrder / seconds);
        r.wall /= seconds;
        row(contacts ? "demo_contacts" : "demo_no_contacts", in, 1.0 / 30, tol, "closure",
            residual / work, r);
      }
  return 0;
}

} // namespace

namespace hair::tools
{
Study integratorStudy()
{
  return {
      "integrator", "the time steps side by side: energy residual, tip error, tolerance, the demo",
      Keys{outKey("<csv>"), integerKey("quick", "0", 0, 1, "1: fewer step sizes and tolerances"),
           integerKey("demo", "0", 0, 1, "1: the demo scene's runs too"),
           integerKey("guides", "200", 1, 10000, "the demo's guides"),
           numberKey("seconds", "5", 1.0 / 30, 100, "s, the demo's run")},
      integrator};
}
} // namespace hair::tools
