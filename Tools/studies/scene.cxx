// hair_study scene: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Study 4b, CI size: a small scene through Core's Simulation, stored as a state file with
// the layout of docs/state-file.md (the demo's own output is much larger).

int scene(const Arguments& args)
{
  const int strands = args.integer("strands"), n = args.integer("n");
  const double duration = args.number("duration"), dt = args.number("dt");
  const ModelType type = args.model("model");
  Status s;
  if (!args.has("out"))
    s = Status::Error("give the output file: out=<path>.h5.");
  if (!s)
  {
    std::cerr << "hair_study scene: " << s.message() << "\n";
    return 2;
  }
  // Wavy strands (Super-Helix or projective) of 30 cm on a ring of radius 8 cm around the demo's
  // neck pivot, grown outwards and 30° down; the head shakes ±0.5 rad at 1 Hz as in the demo, with
  // a 0.5 m/s wind from the front. No body parts (the demo's contact needs the bundled body's
  // tables).
  std::vector<GuideStrand> guides;
  SimulationOptions o;
  o.model = type;
  o.timeStep = dt; // the projective model steps at most 1 ms (explicit)
  o.frameInterval = 1.0 / 30;
  Scene scene;
  scene.air = AirField::uniform(Eigen::Vector3d(0, 0, -0.5));
  scene.rootMotion = RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), 0.5, 1.0);
  const Eigen::Vector3d centre(0, 1.6, 0.02);
  for (int k = 0; k < strands; ++k)
  {
    const double a = 2 * M_PI * k / strands;
    const Eigen::Vector3d radial(std::cos(a), 0, std::sin(a));
    GuideStrand g;
    g.root = centre + 0.08 * radial;
    g.normal = radial;
    g.growth = (radial * std::cos(M_PI / 6) - Eigen::Vector3d::UnitY() * std::sin(M_PI / 6));
    g.length = 0.3;
    g.elements = n;
    g.hair = HairParameters::preset(HairType::Wavy);
    g.seed = static_cast<std::uint32_t>(k + 1);
    guides.push_back(g);
  }
  Simulation sim;
  StorageOptions storage;
  storage.stateFile = args.text("out");
  storage.replaceStateFile = true; // a study run again writes its own output again
  const int frames = static_cast<int>(std::lround(duration * 30)) + 1;
  if (s = sim.initialize(guides, scene, o, storage); s)
    s = sim.advanceTo(frames);
  if (!s)
  {
    std::cerr << "hair_study scene: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

} // namespace

namespace hair::tools
{
Study sceneStudy()
{
  return {"scene", "a small scene through Simulation, stored as a state file (CI size)",
          Keys{outKey("<h5>"), integerKey("strands", "6", 1, 10000, "guides on a ring"),
               integerKey("n", "10", 1, 400, "elements per guide"),
               numberKey("duration", "1", 1.0 / 30, 1000, "s"),
               numberKey("dt", "1/30", 1e-6, 1.0 / 30, "s, the model's step"),
               modelKey("model", "super-helix", "the strand model")},
          scene};
}
} // namespace hair::tools
