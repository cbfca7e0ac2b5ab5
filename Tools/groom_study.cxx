// groom_study: the measurements of issue 25 on a groom a user would make (docs/study-groom.md),
// through Core's public API, written as CSV for Scripts/study_groom.py.
//
//   groom_study out=<csv> [strands=200] [presets=smooth,wavy,curly,fuzzy]
//               [models=super-helix,projective] [elements=10] [hold=10] [release=10]
//               [threads=2] [curves=<csv>] [static=0] [groom=shaken]
//
// For each model and preset: `strands` guides grown as Hair Strands grows them by default on
// the bundled body's scalp (30 cm along the normal, seed 1), shaken 0.5 s as Hair Simulation
// shakes by default (±0.5 rad at 1 Hz about the neck; the head is back at rest at 0.5 s), and
// that frame given back as the groom (Hair Strands' guide curves: roots moved onto the scalp).
// groom=settled: instead, the guides settled 3 s at rest on the body (with `static`), and
// that frame given back as the groom: hair where it came to rest.
// Then, with head and trunk tables and dt = 1/30 s (frames of 1/30 s):
//   hold     the groom made sag-free, no motion, `hold` s: each strand's largest distance
//            from the groom at any point and frame;
//   grown    the same groom as grown (today), no motion: the same measure;
//   release  the sag-free groom shaken briefly (±0.2 rad at 1 Hz for one cycle from 0.2 s,
//            faded over 0.25 s) and released, `release` s in all: the largest distance from
//            the groom at the last frame and after the shake.
// `static`: the static friction coefficient μ_s for the runs after the groom is made (0: off,
// the default; the shake that makes the groom never has it, so that the groom is the same);
// as Hair Simulation sets it, the projective model's friction is on with it (kinetic 0.3). One row
// per strand; `curves` (optional) receives the groom and each run's last frame for the pictures
// (Scripts/groom_pictures.py). Bad input: a message on stderr and exit status 2; a failed
// computation: exit status 1.
#include "ProjectiveScenes.h"
#include "StudyArguments.h"
#include "collision/PosedPart.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"
#include "strands/GuideCurves.h"
#include "strands/GuideGrowth.h"
#include "strands/RootSampling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace hair;

namespace
{

using Curves = std::vector<std::vector<Eigen::Vector3d>>;

/// The comma-separated words of `text`.
std::vector<std::string> words(const std::string& text)
{
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    out.push_back(item);
  }
  return out;
}

/// The keys of groom_study, with their defaults, ranges and meaning (StudyArguments.h).
const hair::tools::Keys& groomKeys()
{
  using namespace hair::tools;
  static const Keys keys = {
      textKey("out", "", "the output file (required)").as("<csv>"),
      integerKey("strands", "200", 1, 2000, "guides grown on the scalp"),
      textKey("presets", "smooth,wavy,curly,fuzzy", "hair presets, comma-separated"),
      textKey("models", "super-helix,projective", "models, comma-separated"),
      integerKey("elements", "10", 1, 40, "elements per guide"),
      numberKey("hold", "10", 0, 60, "s, the sag-free groom held still").openBelow(),
      numberKey("release", "10", 2, 60, "s, the shake and release run"),
      integerKey("threads", "2", 1, 1e6, "threads"),
      textKey("curves", "", "the groom and each run's last frame (optional)").as("<csv>"),
      numberKey("static", "0", 0, 1e6,
                "the static friction coefficient: 0 (off) or at least the kinetic one"),
      choiceKey("groom", "shaken", {"shaken", "settled"},
                "the frame at 0.5 s of the shake, or 3 s settled at rest")};
  return keys;
}

int fail(const std::string& message, int code)
{
  std::cerr << "groom_study: " << message << "\n";
  return code;
}

/// Frame `i` of the run drawn at Hair Simulation's default 16 points per element, as curves.
Curves curvesOf(const Simulation& sim, int i)
{
  GuideDrawing drawn;
  if (Status s = sim.drawFrame(i, 16, drawn); !s)
  {
    std::cerr << "groom_study: " << s.message() << "\n";
    std::exit(1);
  }
  const StateHeader& h = drawn.header;
  const StateFrame& f = drawn.frame;
  Curves c;
  for (std::size_t k = 0; k < h.numberOfStrands(); ++k)
  {
    c.emplace_back(f.positions.begin() + h.offsets[k], f.positions.begin() + h.offsets[k + 1]);
  }
  return c;
}

/// Per strand, the largest distance between the frame's points and the groom's (the same
/// points: the groom was drawn at the run's resolution).
std::vector<double> distances(const Curves& groom, const Curves& now)
{
  std::vector<double> d(groom.size(), 0.0);
  for (std::size_t k = 0; k < groom.size(); ++k)
  {
    for (std::size_t i = 0; i < groom[k].size() && i < now[k].size(); ++i)
    {
      d[k] = std::max(d[k], (groom[k][i] - now[k][i]).norm());
    }
  }
  return d;
}

struct Run
{
  std::vector<double> worst; ///< largest distance from the groom over the frames measured
  std::vector<double> last;  ///< at the last frame
  std::vector<GroomReport> reports;
  Curves end;
  double seconds = 0;
};

/// Static friction μ_s for both models, as Hair Simulation sets it.
void setStaticFriction(SimulationOptions& o, double muStatic)
{
  o.contacts.staticFriction = muStatic;
}

/// A run of `frames` frames from `guides` in `scene`; the distance from `groom` measured on
/// the frames from `from` on.
Status simulate(const std::vector<GuideStrand>& guides, const Scene& scene,
                const SimulationOptions& o, int frames, int from, const Curves& groom, Run& run)
{
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim;
  if (Status s = sim.initialize(guides, scene, o); !s)
  {
    return s;
  }
  if (Status s = sim.advanceTo(frames); !s)
  {
    return s;
  }
  run.reports = sim.groomReports();
  run.worst.assign(guides.size(), 0.0);
  for (int i = from; i < frames; ++i)
  {
    const Curves now = curvesOf(sim, i);
    const std::vector<double> d = distances(groom, now);
    for (std::size_t k = 0; k < d.size(); ++k)
    {
      run.worst[k] = std::max(run.worst[k], d[k]);
    }
    if (i + 1 == frames)
    {
      run.last = d;
      run.end = now;
    }
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return Status::Ok();
}

void writeCurves(std::ofstream& out, const std::string& model, const std::string& preset,
                 const std::string& what, const Curves& curves)
{
  for (std::size_t k = 0; k < curves.size(); ++k)
  {
    for (std::size_t i = 0; i < curves[k].size(); ++i)
    {
      const Eigen::Vector3d& x = curves[k][i];
      out << model << ',' << preset << ',' << what << ',' << k << ',' << i << ',' << x.x() << ','
          << x.y() << ',' << x.z() << '\n';
    }
  }
}

} // namespace

int main(int argc, char** argv)
{
  hair::tools::Arguments args;
  if (argc == 2 && std::string(argv[1]) == "help")
  {
    std::cout << "groom_study: issue 25's measurements of sag-free grooms on the bundled body.\n";
    hair::tools::describe(std::cout, groomKeys());
    return 0;
  }
  if (Status s = args.parse(argc, argv, 1, groomKeys(), "groom_study"); !s)
  {
    return fail(s.message(), 2);
  }
  if (!args.has("out"))
  {
    std::cerr << "groom_study: give the output file: out=<csv>.\n"
              << "usage: groom_study " << hair::tools::usageLine(groomKeys(), 20) << "\n";
    return 2;
  }
  const int strands = args.integer("strands"), elements = args.integer("elements"),
            threads = args.integer("threads");
  const double hold = args.number("hold"), release = args.number("release"),
               staticFriction = args.number("static");
  const std::string groomKind = args.text("groom");
  if (!(staticFriction == 0 || staticFriction >= BodyContactParameters().friction))
  {
    return fail("static is 0 (off) or at least the kinetic friction coefficient, " +
                    std::to_string(BodyContactParameters().friction) + ".",
                2);
  }
  const std::map<std::string, HairType> presets = {{"smooth", HairType::Smooth},
                                                   {"wavy", HairType::Wavy},
                                                   {"curly", HairType::Curly},
                                                   {"fuzzy", HairType::Fuzzy}};
  std::vector<std::string> presetNames = words(args.text("presets"));
  std::vector<std::string> modelNames = words(args.text("models"));
  for (const std::string& p : presetNames)
  {
    if (!presets.count(p))
    {
      return fail("unknown preset '" + p + "' (smooth, wavy, curly, fuzzy).", 2);
    }
  }
  for (const std::string& m : modelNames)
  {
    ModelType type;
    if (Status s = parseModel(m, "models=", type); !s)
    {
      return fail(s.message(), 2);
    }
  }
  std::ofstream out(args.text("out"));
  if (!out)
  {
    return fail("cannot write " + args.text("out") + ".", 2);
  }
  out.precision(9);
  std::ofstream curvesOut;
  if (args.has("curves"))
  {
    curvesOut.open(args.text("curves"));
    if (!curvesOut)
    {
      return fail("cannot write " + args.text("curves") + ".", 2);
    }
    curvesOut.precision(9);
    curvesOut << "model,preset,frame,strand,point,x,y,z\n";
  }

  BundledBody body;
  if (Status s = loadBundledBody(HAIR_DATA_DIR, body); !s)
  {
    return fail(s.message(), 1);
  }
  const MeshQueries scalp(body.mesh);
  std::vector<Root> roots;
  RootSamplingOptions ro;
  ro.count = strands;
  if (Status s = sampleRoots(body.mesh, bundled::scalp(body.mesh), ro, roots); !s)
  {
    return fail(s.message(), 1);
  }
  if (body.mesh.signedVolume() < 0)
  {
    for (Root& r : roots)
    {
      r.normal = -r.normal;
    }
  }
  Scene still;
  still.parts = {body.parts[body.head], body.parts[body.trunk]};
  Scene shaken = still;
  shaken.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.5, 1.0);
  shaken.parts[0].motion = shaken.rootMotion;
  Scene nudged = still;
  nudged.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.2, 1.0);
  nudged.rootMotion.during(0.2, 1.0).fading(0.25);
  nudged.parts[0].motion = nudged.rootMotion;
  const int holdFrames = static_cast<int>(std::lround(30 * hold)) + 1;
  const int releaseFrames = static_cast<int>(std::lround(30 * release)) + 1;
  const int afterShake = static_cast<int>(std::lround(30 * 1.2)) + 1; // the shake ends at 1.2 s

  out << "model,preset,strand,fit_error_m,rest_status,groom_deviation_m,stability,"
         "groom_depth_m,sag_free_max_m,as_grown_max_m,release_max_after_m,release_final_m\n";
  std::vector<PosedPart> posed;
  still.posedParts(0, posed);
  for (const std::string& modelName : modelNames)
  {
    for (const std::string& presetName : presetNames)
    {
      SimulationOptions o;
      (void)parseModel(modelName, "models=", o.model); // checked above
      o.threads = threads;
      // Each strand balanced on its own, as the sag-free rest shape is (no hair–hair term in
      // the balance): the grid's volume would push a groom packed above its rest fraction.
      o.hairHair.enabled = false;
      GrowthOptions grow;
      grow.elements = elements;
      grow.hair = HairParameters::preset(presets.at(presetName));
      std::vector<GuideStrand> grown;
      if (Status s = growGuides(roots, grow, grown); !s)
      {
        return fail(s.message(), 1);
      }
      // The groom: the shaken frame at 0.5 s, or the frame at 3 s at rest.
      Run shake;
      const bool settled = groomKind == "settled";
      setStaticFriction(o, settled ? staticFriction : 0.0);
      if (Status s = settled ? simulate(grown, still, o, 91, 90, Curves(grown.size()), shake)
                             : simulate(grown, shaken, o, 16, 15, Curves(grown.size()), shake);
          !s)
      {
        return fail(modelName + ", " + presetName + ", groom: " + s.message(), 1);
      }
      const Curves groomCurves = shake.end;
      setStaticFriction(o, staticFriction);
      std::vector<Eigen::Vector3d> normals;
      for (const GuideStrand& g : grown)
      {
        normals.push_back(g.normal);
      }
      CurveGuideOptions co;
      co.elements = elements;
      co.hair = grow.hair;
      co.restShape = RestShape::SagFree;
      std::vector<GuideStrand> groom;
      std::vector<int> source;
      std::vector<CurveRefusal> refused;
      if (Status s = guidesFromCurves(groomCurves, normals, &scalp, co, groom, source, refused); !s)
      {
        return fail(s.message(), 1);
      }
      if (!refused.empty())
      {
        return fail(modelName + ", " + presetName + ": " + refused[0].reason, 1);
      }
      // The groom as the runs see it: the curves with their roots on the scalp.
      Curves target;
      for (const GuideStrand& g : groom)
      {
        target.push_back(g.curve);
      }
      // A run a step of which fails (a strand blowing up stops a whole run) is reported and
      // its figures left NaN; the others go on.
      const double nan = std::numeric_limits<double>::quiet_NaN();
      auto measured = [&](const char* what, Status s, Run& run)
      {
        if (!s)
        {
          std::cerr << modelName << " " << presetName << ", " << what << ": " << s.message()
                    << "\n";
          run.worst.assign(groom.size(), nan);
          run.last.assign(groom.size(), nan);
          run.reports.resize(groom.size());
        }
      };
      Run held, fallen, released;
      measured("sag-free", simulate(groom, still, o, holdFrames, 0, target, held), held);
      std::vector<GuideStrand> asGrown = groom;
      for (GuideStrand& g : asGrown)
      {
        g.restShape = RestShape::AsGrown;
      }
      measured("as grown", simulate(asGrown, still, o, holdFrames, 0, target, fallen), fallen);
      measured("release", simulate(groom, nudged, o, releaseFrames, afterShake, target, released),
               released);
      int within = 0;
      for (std::size_t k = 0; k < groom.size(); ++k)
      {
        const GroomReport& r = held.reports[k];
        within += held.worst[k] <= 1e-3;
        // How deep the groom itself lies inside the body's tables (a frame taken from motion
        // can be pressed into the head): no strand can be held there.
        double depth = 0;
        for (const Eigen::Vector3d& x : target[k])
        {
          double d = 0;
          if (insideDepth(posed, x, d))
          {
            depth = std::max(depth, d);
          }
        }
        out << modelName << ',' << presetName << ',' << k << ',' << r.fitError << ','
            << static_cast<int>(r.outcome) << ',' << r.deviation << ',' << r.stability << ','
            << depth << ',' << held.worst[k] << ',' << fallen.worst[k] << ',' << released.worst[k]
            << ',' << released.last[k] << '\n';
      }
      std::cerr << modelName << " " << presetName << ": " << within << " of " << groom.size()
                << " within 1 mm (sag-free runs " << held.seconds << " s, as grown "
                << fallen.seconds << " s, release " << released.seconds << " s)\n";
      if (curvesOut && !held.end.empty() && !fallen.end.empty())
      {
        writeCurves(curvesOut, modelName, presetName, "groom", target);
        writeCurves(curvesOut, modelName, presetName, "sag_free_end", held.end);
        writeCurves(curvesOut, modelName, presetName, "as_grown_end", fallen.end);
      }
    }
  }
  return 0;
}
