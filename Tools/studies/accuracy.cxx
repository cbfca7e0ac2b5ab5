// hair_study accuracy: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Accuracy on the demo scene (docs/study-accuracy.md): the demo's guides on the bundled body
// (head and trunk tables, the default hair–hair grid, the head's shake and the wind) run with
// each of `runs` (integrator:tolerance, comma-separated) and with `reference`; per run the
// wall time of the simulation (threads as given), each strand's largest tip distance from the
// reference's over the frames (median and 95th percentile over the strands), the energy
// closure |residual| / (|work done on the hair| + |dissipated|) at the end (the demo's
// summary), the sub-steps and the share taken first order. The reference's tips are kept in
// `cache` and reused when it was made with the same guides, seconds and reference.

struct SceneRun
{
  std::vector<std::vector<Eigen::Vector3d>> tips; // per frame, per strand
  double wall = 0, closure = 0, substeps = 0, rejected = 0, firstOrder = 0;
};

Status runAccuracyScene(const BundledBody& body, const std::vector<GuideStrand>& guides,
                        Integrator integrator, double tolerance, int perFrame, int threads,
                        int frames, bool bodyContacts, bool grid, SceneRun& r)
{
  SimulationOptions o;
  o.threads = threads;
  o.timeStep = o.frameInterval / perFrame;
  o.contacts.enabled = bodyContacts;
  o.hairHair.enabled = grid;
  o.superHelix.integrator = integrator;
  o.superHelix.tolerance = tolerance;
  Simulation sim;
  if (Status s = sim.initialize(guides, demoScene(body), o); !s)
    return s;
  const auto start = std::chrono::steady_clock::now();
  if (Status s = sim.advanceTo(frames); !s)
    return s;
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.tips.assign(frames, {});
  for (int f = 0; f < frames; ++f)
  {
    GuideDrawing drawn;
    if (Status s = sim.drawFrame(f, 1, drawn); !s)
      return s;
    const auto& offsets = drawn.header.offsets;
    for (size_t k = 0; k + 1 < offsets.size(); ++k)
      r.tips[f].push_back(drawn.frame.positions[offsets[k + 1] - 1]);
  }
  std::vector<double> times;
  std::map<std::string, std::vector<double>> c;
  sim.energyTable(times, c);
  const size_t last = times.size() - 1;
  r.closure = std::abs(c["residual"][last]) / std::max(1e-300, std::abs(c["external_work"][last]) +
                                                                   std::abs(c["dissipated"][last]));
  for (size_t i = 1; i < times.size(); ++i)
  {
    r.substeps += c["substeps"][i];
    r.rejected += c["rejected_substeps"][i];
    r.firstOrder += c["first_order_share"][i] * c["substeps"][i];
  }
  r.firstOrder /= std::max(1e-300, r.substeps);
  r.substeps /= std::max<size_t>(1, last);
  r.rejected /= std::max<size_t>(1, last);
  return Status::Ok();
}

// integrator[:tolerance[:steps per frame]]
struct AccuracyRun
{
  Integrator integrator = Integrator::SemiImplicit;
  double tolerance = 0;
  int perFrame = 1;
};

Status parseRun(const std::string& text, AccuracyRun& run)
{
  const size_t colon = text.find(':');
  if (Status s = integratorByName(text.substr(0, colon), run.integrator); !s)
    return s;
  if (colon != std::string::npos)
  {
    std::string rest = text.substr(colon + 1);
    std::replace(rest.begin(), rest.end(), ':', ' ');
    std::istringstream in(rest);
    if (!(in >> run.tolerance) || !(run.tolerance >= 0))
      return Status::Error("run '" + text + "': the tolerance after ':' must be a number >= 0.");
    if (!(in >> run.perFrame))
      run.perFrame = 1;
    if (run.perFrame < 1 || run.perFrame > 1000)
      return Status::Error("run '" + text + "': the steps per frame must be in [1, 1000].");
  }
  return Status::Ok();
}

int accuracy(const Arguments& args)
{
  const int guidesCount = args.integer("guides"), bodyContacts = args.integer("body"),
            grid = args.integer("grid"), threads = args.integer("threads");
  const double seconds = args.number("seconds");
  std::ofstream out;
  Status s;
  std::vector<AccuracyRun> runs;
  {
    std::stringstream list(args.text("runs"));
    std::string item;
    while (s && std::getline(list, item, ','))
    {
      AccuracyRun run;
      s = parseRun(item, run);
      runs.push_back(run);
    }
  }
  AccuracyRun reference;
  const std::string referenceName = args.text("reference");
  if (s)
    s = parseRun(referenceName, reference);
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study accuracy: " << s.message() << "\n";
    return 2;
  }
  auto fail = [](const Status& st)
  {
    std::cerr << "hair_study accuracy: " << st.message() << "\n";
    return 1;
  };
  BundledBody body;
  std::vector<GuideStrand> guides;
  if (s = loadBundledBody(HAIR_DATA_DIR, body); !s)
    return fail(s);
  if (s = demoGuides(body, guidesCount, 10, guides); !s)
    return fail(s);
  const int frames = static_cast<int>(std::lround(seconds * 30)) + 1;
  // The reference: from the cache when it matches, else run (and cached).
  std::ostringstream key;
  key << "# guides=" << guidesCount << " seconds=" << seconds << " reference=" << referenceName
      << " body=" << bodyContacts << " grid=" << grid;
  SceneRun ref;
  const std::string cache = args.text("cache");
  if (!cache.empty())
  {
    std::ifstream in(cache);
    std::string line;
    if (in && std::getline(in, line) && line == key.str())
    {
      ref.tips.assign(frames, std::vector<Eigen::Vector3d>(guides.size()));
      int f = 0, k = 0;
      double x, y, z;
      char comma;
      while (in >> f >> comma >> k >> comma >> x >> comma >> y >> comma >> z)
        if (f >= 0 && f < frames && k >= 0 && k < static_cast<int>(guides.size()))
          ref.tips[f][k] = Eigen::Vector3d(x, y, z);
      std::cerr << "hair_study accuracy: reference from " << cache << "\n";
    }
  }
  if (ref.tips.empty())
  {
    if (s = runAccuracyScene(body, guides, reference.integrator, reference.tolerance,
                             reference.perFrame, threads, frames, bodyContacts != 0, grid != 0,
                             ref);
        !s)
      return fail(s);
    std::cerr << "hair_study accuracy: reference " << referenceName << " took " << ref.wall
              << " s\n";
    if (!cache.empty())
    {
      std::ofstream c(cache);
      c << key.str() << "\n";
      c.precision(17);
      for (int f = 0; f < frames; ++f)
        for (size_t k = 0; k < ref.tips[f].size(); ++k)
          c << f << "," << k << "," << ref.tips[f][k].x() << "," << ref.tips[f][k].y() << ","
            << ref.tips[f][k].z() << "\n";
    }
  }
  out << "integrator,tolerance_m_per_s,steps_per_frame,wall_s,wall_ratio,tip_error_median_m,"
         "tip_error_p95_m,closure,substeps_per_frame,rejected_per_frame,first_order_share\n";
  double firstWall = 0;
  for (const AccuracyRun& run : runs)
  {
    SceneRun r;
    if (s = runAccuracyScene(body, guides, run.integrator, run.tolerance, run.perFrame, threads,
                             frames, bodyContacts != 0, grid != 0, r);
        !s)
      return fail(s);
    std::vector<double> errors(guides.size(), 0.0);
    for (int f = 0; f < frames; ++f)
      for (size_t k = 0; k < guides.size(); ++k)
        errors[k] = std::max(errors[k], (r.tips[f][k] - ref.tips[f][k]).norm());
    std::sort(errors.begin(), errors.end());
    auto quantile = [&](double p) {
      return errors[std::min(errors.size() - 1,
                             static_cast<size_t>(p * (errors.size() - 1) + 0.5))];
    };
    if (firstWall == 0)
      firstWall = r.wall;
    out << toString(run.integrator) << "," << run.tolerance << "," << run.perFrame << "," << r.wall
        << "," << r.wall / firstWall << "," << quantile(0.5) << "," << quantile(0.95) << ","
        << r.closure << "," << r.substeps << "," << r.rejected << "," << r.firstOrder << std::endl;
  }
  return 0;
}

} // namespace

namespace hair::tools
{
Study accuracyStudy()
{
  return {"accuracy",
          "accuracy on the demo scene: each run's tips against a reference's, and its cost",
          Keys{outKey("<csv>"),
               textKey("runs", "semi-implicit:0,bdf2:0",
                       "integrator[:tolerance[:steps per frame]], comma-separated"),
               textKey("reference", "semi-implicit:0.001", "the reference run, written as a run"),
               textKey("cache", "", "the reference's tips, kept and reused (optional)").as("<csv>"),
               integerKey("guides", "200", 1, 10000, "the demo's guides"),
               numberKey("seconds", "2", 1.0 / 30, 100, "s"),
               integerKey("threads", "2", 1, 256, "threads"),
               integerKey("body", "1", 0, 1, "body contacts on"),
               integerKey("grid", "1", 0, 1, "the hair-hair grid on")},
          accuracy};
}
} // namespace hair::tools
