// hair_study workprecision: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Work against precision over N (docs/study-accuracy.md): the released strand of `integrator`
// (30 cm, smooth, air drag 1e-5, no internal friction, 1 s in frames of 1/30 s) with N
// elements, each step and tolerance, against the midpoint step at 1/7680 s with the same N:
// the tip's largest distance over the frames, the steps (accepted and rejected) and the
// wall time for the simulated second. One CSV row per run.

int workPrecision(const Arguments& args)
{
  const std::vector<double> ns = args.list("ns"), tolerances = args.list("tolerances");
  std::ofstream out;
  Status s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study workprecision: " << s.message() << "\n";
    return 2;
  }
  out << "n,integrator,tolerance_m_per_s,tip_error_m,steps,rejected,first_order,wall_s\n";
  for (double nd : ns)
  {
    const int n = static_cast<int>(std::lround(nd));
    Status st;
    const IntegratorRun ref = releasedStrand(Integrator::Midpoint, 1e-5, 1, 256, 0, st, n);
    for (Integrator in : {Integrator::SemiImplicit, Integrator::Midpoint, Integrator::Bdf2})
      for (double tol : tolerances)
      {
        if (!st)
          break;
        const IntegratorRun r = releasedStrand(in, 1e-5, 1, 1, tol, st, n);
        double e = 0;
        for (size_t i = 0; i < r.tips.size() && i < ref.tips.size(); ++i)
          e = std::max(e, (r.tips[i] - ref.tips[i]).norm());
        if (st)
          out << n << "," << toString(in) << "," << tol << "," << e << "," << r.steps << ","
              << r.rejected << "," << r.firstOrder << "," << r.wall << std::endl;
      }
    if (!st)
    {
      std::cerr << "hair_study workprecision, N = " << n << ": " << st.message() << "\n";
      return 1;
    }
  }
  return 0;
}

} // namespace

namespace hair::tools
{
Study workprecisionStudy()
{
  return {"workprecision", "work against precision over N for the released strand",
          Keys{outKey("<csv>"), listKey("ns", "5,10,20,40", 1, 400, "elements N of each run"),
               listKey("tolerances", "0.05,0.02,0.01,0.005", 1e-6, 1, "m/s, the step tolerances")},
          workPrecision};
}
} // namespace hair::tools
