// hair_study clump: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 3, clump part: a clump of guides, squeezed by a converging air flow and held apart
// by hair–hair contacts, whose root disc then oscillates vertically (Super-Helices paper,
// Bertails et al. 2006, figs. 6–7), for several internal frictions γ.

struct ClumpConfig
{
  /// Smooth, round, straight hair (the Euler–Bernoulli strand of the other studies) with an
  /// air friction 20 × the preset's: the converging flow's grip, strong enough to gather
  /// the strands within the ramp. γ is set per run.
  ClumpSpec scene = []
  {
    ClumpSpec c;
    c.hair.airFriction = 2e-4;
    return c;
  }();
  double duration = 6;
  int updatesPerFrame = 1;
  double frame = 1.0 / 30;
  bool contacts = true; ///< false: the same run without hair–hair contacts (the reference)
  HairHairParameters contact;
};

/// One run at internal friction γ; writes its rows (gamma, time, …) to `out`.
Status runClump(const ClumpConfig& c, double gamma, std::ostream& out)
{
  ClumpSpec spec = c.scene;
  spec.hair.internalFriction = gamma;
  std::vector<SuperHelix> strands;
  if (Status st = initializeClump(spec, strands); !st)
    return st;
  HairHairContacts contacts;
  if (Status st = contacts.setParameters(c.contact); !st)
    return st;

  double deepest = 0;
  long lastContacts = 0;
  auto record = [&]()
  {
    // Span ℓ_A as docs/hair-analysis.md defines it: the largest distance between two tips
    // projected on the horizontal plane (vertical = +y); and the mean distance of the tips
    // to the clump's axis (the vertical through the tips' centroid).
    std::vector<Eigen::Vector2d> tips;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const SuperHelix& h : strands)
    {
      const Eigen::Vector3d p = h.position(spec.length);
      tips.emplace_back(p.x(), p.z());
      centre += tips.back();
    }
    centre /= spec.count;
    double mean = 0, span = 0;
    for (size_t i = 0; i < tips.size(); ++i)
    {
      mean += (tips[i] - centre).norm();
      for (size_t j = 0; j < i; ++j)
        span = std::max(span, (tips[i] - tips[j]).norm());
    }
    const double t = strands[0].time();
    out << gamma << "," << t << "," << clumpRootOffset(spec, t) << "," << span << ","
        << mean / spec.count << "," << lastContacts << "," << deepest << "\n";
    deepest = 0;
  };
  record();
  const long frames = std::lround(c.duration / c.frame);
  for (long f = 0; f < frames; ++f)
  {
    // updatesPerFrame steps per frame, each solving the contacts that may arise within it
    // together with the strands' steps (docs/hair-hair-contacts.md; one per 1/30 s frame is
    // enough for the shaken clump).
    double remaining = c.frame;
    for (int u = 0; u < c.updatesPerFrame; ++u)
    {
      const double h = u + 1 == c.updatesPerFrame ? remaining : c.frame / c.updatesPerFrame;
      const Status st = c.contacts ? stepStrandsWithContacts(strands, contacts, h, 2)
                                   : stepStrands(strands, h, 2);
      if (!st)
      {
        std::ostringstream m;
        m << "gamma = " << gamma << " kg m^3/s, t = " << strands[0].time()
          << " s: " << st.message();
        return Status::Error(m.str());
      }
      if (c.contacts)
      {
        deepest = std::max(deepest, contacts.stats().maxPenetration);
        lastContacts = contacts.stats().active;
      }
      remaining -= h;
    }
    record();
  }
  return Status::Ok();
}

int clump(const Arguments& args)
{
  ClumpConfig c;
  const int quick = args.integer("quick");
  // Quick (CI): 20 strands on a disc of the same density (ρ0 √(20/50)), the flow ramped over
  // 1.5 s, the oscillation from 1.5 s to 3 s.
  c.scene.count = args.integer("strands", quick ? 20 : 50);
  c.duration = args.number("duration", quick ? 3 : 6);
  c.scene.rampTime = args.number("ramp", quick ? 1.5 : 3);
  const std::vector<double> gammas = args.list("gammas");
  c.updatesPerFrame = args.integer("updates");
  c.contact.thickness = args.number("thickness");
  const int withContacts = args.integer("contacts"), perLength = args.integer("perlength");
  c.contact.referenceLength = args.number("reflength");
  c.scene.amplitude = args.number("amplitude");
  c.scene.frequency = args.number("frequency");
  std::ofstream out;
  Status s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study clump: " << s.message() << "\n";
    return 2;
  }
  // 50 strands on 12 mm: the density of the test.
  c.scene.discRadius = 0.012 * std::sqrt(c.scene.count / 50.0);
  c.scene.startOscillation = c.scene.rampTime;
  c.contacts = withContacts == 1;
  c.contact.perLength = perLength == 1; // the per-length penalty (docs/hair-hair-contacts.md)
  out << "gamma,time_s,root_y_m,span_m,mean_radius_m,contacts,max_penetration_m\n";
  for (double g : gammas)
    if (s = runClump(c, g, out); !s)
    {
      std::cerr << "hair_study clump: " << s.message() << "\n";
      return 1;
    }
  return 0;
}

} // namespace

namespace hair::tools
{
Study clumpStudy()
{
  return {
      "clump", "a clump squeezed by a converging flow, its root disc shaken (hair-hair contacts)",
      Keys{
          outKey("<csv>"),
          integerKey("quick", "0", 0, 1, "1: the CI size (20 strands, ramp 1.5 s, 3 s)"),
          integerKey("strands", "50 (quick: 20)", 2, 2000, "guides on the root disc")
              .computedDefault(),
          numberKey("duration", "6 (quick: 3)", 1.0 / 30, 1000, "s").computedDefault(),
          numberKey("ramp", "3 (quick: 1.5)", 1.0 / 30, 1000, "s, the flow's ramp; then the shake")
              .computedDefault(),
          listKey("gammas", "5e-11,1e-10,2e-10,5e-10", 0, 1e-6, "internal frictions, one run each"),
          integerKey("updates", "1", 1, 64, "contact updates per frame"),
          numberKey("thickness", "1.2e-3", 1e-5, 0.1, "m, the hair-hair contact thickness"),
          integerKey("contacts", "1", 0, 1, "hair-hair contacts on"),
          integerKey("perlength", "0", 0, 1, "1: the contact stiffness per unit length"),
          numberKey("reflength", "0.01", 1e-4, 1, "m, its reference length (with perlength=1)"),
          numberKey("amplitude", "0.01", 0, 1, "m, the root disc's vertical shake"),
          numberKey("frequency", "3", 0, 100, "Hz, the shake's")},
      clump};
}
} // namespace hair::tools
