// hair_study hairhair: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

#include "der/DerModel.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// Hair–hair contacts (docs/hair-hair-contacts.md): the demo's head shake on the bundled body
// or the dense shaken clump, per frame: pairs of guide pieces that went through each other
// since the previous frame, the body's penetration, the contacts; the energy budget at the
// end.

/// The guides' drawn points, strand by strand, from a frame (points per the header's offsets).
/// Frame `f` of the run drawn at 8 points per element: a curled element is half a turn,
/// and coarser chords miss crossings of the curve.
std::vector<std::vector<Eigen::Vector3d>> polylines(const Simulation& sim, int f)
{
  GuideDrawing drawn;
  if (Status s = sim.drawFrame(f, 8, drawn); !s)
  {
    std::cerr << "hair_study: " << s.message() << "\n";
    std::exit(1);
  }
  const StateHeader& header = drawn.header;
  std::vector<std::vector<Eigen::Vector3d>> out(header.numberOfStrands());
  for (size_t k = 0; k < out.size(); ++k)
    out[k].assign(drawn.frame.positions.begin() + header.offsets[k],
                  drawn.frame.positions.begin() + header.offsets[k + 1]);
  return out;
}

int hairhair(const Arguments& args)
{
  const int withContacts = args.integer("contacts"), guidesCount = args.integer("guides"),
            threads = args.integer("threads"), bodyContacts = args.integer("body");
  const std::string sceneName = args.text("scene");
  const double duration = args.number("duration", sceneName == "demo" ? 5 : 6);
  HairHairParameters p; // its defaults are the table's (hairhairKeys)
  // the demo: 0, automatic; the clump: the tests' 1.2 mm
  p.thickness = args.number("thickness", sceneName == "demo" ? 0 : 1.2e-3);
  p.stiffness = args.number("stiffness");
  p.friction = args.number("friction");
  p.margin = args.number("margin");
  p.iterations = args.integer("iterations");
  const std::map<std::string, HairHairSolver> solvers = {{"grid", HairHairSolver::Grid},
                                                         {"near", HairHairSolver::GridAndNearField},
                                                         {"coupled", HairHairSolver::Coupled}};
  const std::string solverName = args.text("solver");
  HairGridParameters grid;
  grid.volumeFraction = args.number("fraction");
  grid.volume = args.number("volume");
  grid.friction = args.number("grid_friction");
  grid.cellSize = args.number("cell");
  NearFieldParameters near;
  near.sweeps = args.integer("sweeps");
  near.margin = args.number("near_margin");
  near.pieceLength = args.number("piece");
  std::ofstream out;
  Status s;
  if (sceneName == "clump" && !(p.thickness > 0))
    s = Status::Error("thickness=0 (automatic) is for guides on a head; give the clump's.");
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study hairhair: " << s.message() << "\n";
    return 2;
  }
  const int frames = static_cast<int>(std::lround(duration * 30));
  out << "time_s,pass_throughs,nodes_inside,max_depth_m,contacts,pressed,sweeps,rounds,"
         "max_penetration_m,wall_s\n";
  long passTotal = 0, passLater = 0, insideSum = 0;
  double deepest = 0, deepestPair = 0, wall = 0;
  // Every half second on stdout: the pass-throughs since the previous line, the nodes
  // inside the body and the deepest of them at that frame, the pairs solved and pressed.
  long passWindow = 0;
  std::printf("| t (s) | pass-throughs in the last 0.5 s | nodes inside | deepest (mm) | pairs "
              "solved | pressed |\n|---|---|---|---|---|---|\n");
  auto row =
      [&](double t, long passes, long inside, double depth, const HairHairStats* hs, double seconds)
  {
    passWindow += passes;
    if (std::abs(t * 2 - std::round(t * 2)) < 1e-6)
    {
      std::printf("| %.1f | %ld | %ld | %.2f | %ld | %ld |\n", t, passWindow, inside, 1e3 * depth,
                  hs ? hs->contacts : 0L, hs ? hs->active : 0L);
      passWindow = 0;
    }
    out << t << "," << passes << "," << inside << "," << depth << "," << (hs ? hs->contacts : 0)
        << "," << (hs ? hs->active : 0) << "," << (hs ? hs->sweeps : 0) << ","
        << (hs ? hs->rounds : 0) << "," << (hs ? hs->maxPenetration : 0) << "," << seconds << "\n";
    passTotal += passes;
    passLater += t > 1 + 1e-9 ? passes : 0;
    insideSum += inside;
    deepest = std::max(deepest, depth);
    deepestPair = std::max(deepestPair, hs ? hs->maxPenetration : 0);
    wall += seconds;
  };
  if (sceneName == "demo")
  {
    BundledBody body;
    if (s = loadBundledBody(HAIR_DATA_DIR, body); !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    HairType type = HairType::Wavy;
    if (s = presetByName(args.text("hair"), type); !s) // a choice key: one of them
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 2;
    }
    const HairParameters preset = HairParameters::preset(type);
    const ModelType modelType = args.model("model");
    std::vector<GuideStrand> guides;
    if (s = demoGuides(body, guidesCount,
                       findModel(modelType)->elementsFor(preset, DemoGuideLength), guides);
        !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    for (GuideStrand& g : guides)
      g.hair = preset;
    SimulationOptions o;
    o.model = modelType;
    o.threads = threads;
    o.contacts.enabled = bodyContacts == 1;
    o.hairHair.enabled = withContacts == 1;
    o.hairHair.pairs = p;
    o.hairHair.solver = solvers.at(solverName);
    o.hairHair.grid = grid;
    o.hairHair.nearField = near;
    Simulation sim;
    if (s = sim.initialize(guides, demoScene(body), o); !s)
    {
      std::cerr << "hair_study hairhair: " << s.message() << "\n";
      return 1;
    }
    // The contact distance the pass-throughs are counted within: the run's (automatic or
    // given) thickness, the same with contacts off.
    double radius = 0;
    for (const GuideStrand& g : guides)
      radius += g.hair.radius / static_cast<double>(guides.size());
    const double thickness =
        p.thickness > 0 ? p.thickness : HairHairParameters::automaticThickness(radius, guidesCount);
    const double R = 2 * thickness;
    // The pairs' statistics are the Super-Helix's; the grid is every model's that has one.
    const auto* model = dynamic_cast<const SuperHelixModel*>(&sim.model());
    const auto* rods = dynamic_cast<const DerModel*>(&sim.model());
    for (int f = 1; f <= frames; ++f)
    {
      const auto t0 = std::chrono::steady_clock::now();
      if (s = sim.advanceTo(f + 1); !s)
      {
        std::cerr << "hair_study hairhair: " << s.message() << "\n";
        return 1;
      }
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      HairHairStats hhStats;
      if (model && o.hairHair.solver == HairHairSolver::Coupled)
        hhStats = model->hairHair().stats();
      else if (model)
      {
        // The near field's, in the columns of the coupled solve's: pairs tracked, acting,
        // sweeps, pairs found crossed (rounds), the largest gap missing after the sweeps.
        const NearFieldStats& n = model->nearField().stats();
        hhStats.contacts = n.tracked;
        hhStats.active = n.active;
        hhStats.sweeps = n.sweeps;
        hhStats.rounds = static_cast<int>(n.flipped);
        hhStats.maxPenetration = std::max(0.0, n.deficit);
      }
      const auto found = findPassThroughs(polylines(sim, f - 1), polylines(sim, f), R);
      const long passes = static_cast<long>(found.size());
      row(sim.frame(f).time, passes, sim.contacts()[f], sim.maxDepth()[f],
          withContacts ? &hhStats : nullptr, seconds);
    }
    const std::map<std::string, double> e = sim.model().energy().values();
    // Where the hair ends and how packed it is: the guides' mean tip height at the end, and
    // the volume fraction at their samples as the grid last saw it (with the grid on).
    double tip = 0;
    const auto lines = polylines(sim, frames);
    for (const auto& l : lines)
      tip += l.back().y() / static_cast<double>(lines.size());
    std::vector<double> fractions;
    if (withContacts && o.hairHair.solver != HairHairSolver::Coupled && model)
      for (const SuperHelix& h : model->strands())
        for (const StrandSample& q : h.samples())
          fractions.push_back(model->hairGrid().fraction(q.position));
    if (withContacts && rods)
      for (const DerRod& r : rods->rods())
        for (int j = 1; j <= r.edgeCount(); ++j)
          fractions.push_back(rods->hairGrid().fraction(r.position(j)));
    std::sort(fractions.begin(), fractions.end());
    auto pct = [&](double p)
    { return fractions.empty() ? 0.0 : fractions[std::size_t(p * (fractions.size() - 1))]; };
    std::printf("mean tip height %.4f m; volume fraction at the samples: median %.3g, 95th "
                "pct %.3g, largest %.3g\n",
                tip, pct(0.5), pct(0.95), pct(1.0));
    std::printf("demo, %d guides, hair-hair %s (thickness %.3g mm): %ld pass-throughs over %d "
                "frames, %ld after 1 s; body: mean %.1f nodes inside, deepest %.2f mm; deepest "
                "pair %.2f mm of %.2f mm; %.1f s\n",
                guidesCount, withContacts ? "on" : "off", 1e3 * thickness, passTotal, frames,
                passLater, double(insideSum) / frames, 1e3 * deepest, 1e3 * deepestPair, 1e3 * R,
                wall);
    std::printf("energy (J):");
    for (const auto& [name, value] : e)
      std::printf(" %s %.4g", name.c_str(), value);
    std::printf("; |residual| / external work %.3g\n",
                std::abs(e.at("residual")) / std::max(1e-300, std::abs(e.at("external_work"))));
    return 0;
  }
  // The dense clump of the hair–hair tests (ClumpScene: 50 guides on a 12 mm disc, squeezed
  // by a converging flow, the root disc shaken 1 cm at 3 Hz from 3 s), ν = 2e-4.
  const double R = 2 * p.thickness;
  ClumpSpec spec;
  spec.hair.airFriction = 2e-4;
  std::vector<SuperHelix> strands;
  HairHairContacts contacts;
  if (s = initializeClump(spec, strands); s)
    s = contacts.setParameters(p);
  auto drawn = [&]()
  {
    std::vector<std::vector<Eigen::Vector3d>> lines(strands.size());
    for (size_t k = 0; k < strands.size(); ++k)
      strands[k].polyline(4, lines[k]);
    return lines;
  };
  std::vector<std::vector<Eigen::Vector3d>> before = drawn();
  for (int f = 1; s && f <= frames; ++f)
  {
    const auto t0 = std::chrono::steady_clock::now();
    s = withContacts ? stepStrandsWithContacts(strands, contacts, 1.0 / 30, threads)
                     : stepStrands(strands, 1.0 / 30, threads);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<std::vector<Eigen::Vector3d>> after = drawn();
    row(strands[0].time(), static_cast<long>(findPassThroughs(before, after, R).size()), 0, 0,
        withContacts ? &contacts.stats() : nullptr, seconds);
    before = std::move(after);
  }
  if (!s)
  {
    std::cerr << "hair_study hairhair: " << s.message() << "\n";
    return 1;
  }
  double work = 0, residual = 0;
  for (const SuperHelix& h : strands)
  {
    work += std::abs(h.energy().total.rootWork) + std::abs(h.energy().total.windWork);
    residual += h.energy().total.residual;
  }
  std::printf("clump, hair-hair %s: %ld pass-throughs over %d frames; deepest pair %.3f mm of "
              "%.2f mm; %.1f s; residual %.3g J of |root| + |wind| work %.3g J\n",
              withContacts ? "on" : "off", passTotal, frames, 1e3 * deepestPair, 1e3 * R, wall,
              residual, work);
  return 0;
}

} // namespace

namespace hair::tools
{
Study hairhairStudy()
{
  const HairHairParameters hh;
  const HairGridParameters grid;
  const NearFieldParameters near;
  return {
      "hairhair",
      "hair-hair contacts: pass-throughs, body penetration, contacts, the energy budget",
      Keys{
          outKey("<csv>"),
          choiceKey("scene", "demo", {"demo", "clump"}, "the demo's head or the clump"),
          integerKey("contacts", "1", 0, 1, "hair-hair contacts on"),
          integerKey("body", "1", 0, 1, "body contacts on (demo)"),
          integerKey("guides", "200", 1, 20000, "the demo's guides"),
          integerKey("threads", "2", 1, 256, "threads"),
          numberKey("duration", "5 (demo), 6 (clump)", 1.0 / 30, 1000, "s").computedDefault(),
          numberKey("thickness", "0 (demo: automatic), 1.2e-3 (clump)", 0, 0.1,
                    "m, the hair-hair contact thickness")
              .computedDefault(),
          numberKey("stiffness", shortest(hh.stiffness), 1e-6, 1e6, "the contacts' stiffness"),
          numberKey("friction", shortest(hh.friction), 0, 10, "the contacts' friction"),
          numberKey("margin", shortest(hh.margin), 0, 4, "the contacts' margin"),
          integerKey("iterations", std::to_string(hh.iterations), 1, 1000,
                     "the contact solve's iterations"),
          choiceKey("solver", "grid", {"grid", "near", "coupled"},
                    "the hair-hair solver: the grid, the grid and the near field, or coupled"),
          numberKey("fraction", shortest(grid.volumeFraction), 1e-4, 0.9,
                    "the grid's volume fraction"),
          numberKey("volume", shortest(grid.volume), 0, 1, "the grid's volume"),
          numberKey("grid_friction", shortest(grid.friction), 0, 1e4, "the grid's friction"),
          numberKey("cell", shortest(grid.cellSize), 0, 1, "m, the grid's cell (0: automatic)"),
          integerKey("sweeps", std::to_string(near.sweeps), 1, 1000, "the near field's sweeps"),
          numberKey("near_margin", shortest(near.margin), 0, 4, "the near field's margin"),
          numberKey("piece", shortest(near.pieceLength), 1e-4, 0.1,
                    "m, the near field's piece length"),
          choiceKey("hair", "wavy", {"smooth", "wavy", "curly", "fuzzy"}, "the demo's hair preset"),
          modelKey("model", "super-helix",
                   "the demo's strand model (its registered elements a guide)")},
      hairhair};
}
} // namespace hair::tools
