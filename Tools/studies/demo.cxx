// hair_study demo: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 4b, the demo's scene with its body: the guides, head and trunk tables, shake and
// wind of Scripts/demo.sh (Testing/Fixtures/DemoScene) through Core's Simulation, stored as
// a state file, at a chosen step: the projective model's contact budget against its step.

int demo(const Arguments& args)
{
  const int strands = args.integer("strands");
  const ModelType type = args.model("model");
  const int n = args.integer(
      "n", findModel(type)->elementsFor(HairParameters::preset(DemoHairType), DemoGuideLength));
  const double duration = args.number("duration"), dt = args.number("dt");
  const int threads = args.integer("threads");
  Status s;
  if (!args.has("out"))
    s = Status::Error("give the output file: out=<path>.h5.");
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 2;
  }
  BundledBody body;
  std::vector<GuideStrand> guides;
  s = loadBundledBody(args.text("data"), body);
  if (s)
    s = demoGuides(body, strands, n, guides);
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 1;
  }
  SimulationOptions o;
  o.model = type;
  o.timeStep = dt; // the projective model steps at most 1 ms, a whole number per frame
  o.frameInterval = 1.0 / 30;
  o.threads = threads;
  Simulation sim;
  StorageOptions storage;
  storage.stateFile = args.text("out");
  storage.replaceStateFile = true; // a study run again writes its own output again
  const int frames = static_cast<int>(std::lround(duration * 30)) + 1;
  if (s = sim.initialize(guides, demoScene(body), o, storage); s)
    s = sim.advanceTo(frames);
  if (!s)
  {
    std::cerr << "hair_study demo: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

} // namespace

namespace hair::tools
{
/// The default of n= as the usage shows it: each model's number for the demo's guides
/// (ModelEntry::elementsFor), "10 (super-helix), 40 (projective), …".
static std::string demoElements()
{
  std::string text;
  for (const ModelEntry& m : registeredModels())
    text += (text.empty() ? "" : ", ") +
            std::to_string(m.elementsFor(HairParameters::preset(DemoHairType), DemoGuideLength)) +
            " (" + m.name + ")";
  return text;
}

Study demoStudy()
{
  return {"demo", "the demo's scene on the bundled body through Simulation, stored as a state file",
          Keys{outKey("<h5>"), integerKey("strands", "200", 1, 10000, "guides on the scalp"),
               modelKey("model", "projective", "the strand model"),
               integerKey("n", demoElements(), 1, 400, "elements per guide").computedDefault(),
               numberKey("duration", "5", 1.0 / 30, 1000, "s"),
               numberKey("dt", "1/30", 1e-6, 1.0 / 30, "s, the model's step"),
               integerKey("threads", "2", 1, 256, "threads"),
               textKey("data", HAIR_DATA_DIR, "the directory of the bundled body")},
          demo};
}
} // namespace hair::tools
