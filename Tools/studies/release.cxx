// hair_study release: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 4a: the energy budget of a strand released horizontally under gravity.

int release(const Arguments& args)
{
  const int n = args.integer("n");
  const double dt = args.number("dt"), duration = args.number("duration"),
               length = args.number("length");
  HairType type = HairType::Wavy;
  std::ofstream out;
  Status s = presetByName(args.text("preset"), type);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study release: " << s.message() << "\n";
    return 2;
  }
  // Clamped at the origin with tangent +x (horizontal), gravity −y, in its natural
  // (wavy) shape and at rest: released at t = 0. The preset's internal friction and air
  // drag act; there is no wind, the root does not move, no contact, no tip load.
  StrandSpec spec = StrandSpec::uniform(length, n, HairParameters::preset(type));
  SuperHelix h;
  if (s = h.initialize(spec); !s)
  {
    std::cerr << "hair_study release: " << s.message() << "\n";
    return 1;
  }
  out << "time_s,kinetic,elastic,gravitational,friction_dissipated,air_dissipated,root_work,"
         "wind_work,contact_work,load_work,residual,substeps\n";
  energyRow(out, h);
  const long steps = std::lround(duration / dt);
  for (long i = 0; i < steps; ++i)
  {
    if (s = h.step(dt); !s)
    {
      std::cerr << "hair_study release: " << s.message() << "\n";
      return 1;
    }
    energyRow(out, h);
  }
  return 0;
}

} // namespace

namespace hair::tools
{
Study releaseStudy()
{
  return {
      "release", "the energy budget of a strand released horizontally under gravity",
      Keys{outKey("<csv>"), integerKey("n", "10", 1, 400, "elements"),
           numberKey("dt", "1/30", 1e-6, 1, "s, the step"),
           numberKey("duration", "2", 0, 1000, "s"), numberKey("length", "0.3", 1e-3, 10, "m"),
           choiceKey("preset", "wavy", {"smooth", "wavy", "curly", "fuzzy"}, "the hair preset")},
      release};
}
} // namespace hair::tools
