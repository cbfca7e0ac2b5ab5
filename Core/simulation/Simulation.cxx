#include "simulation/Simulation.h"

#include "collision/PosedPart.h"
#include "common/Machine.h"
#include "common/Parallel.h"
#include "common/Partition.h"
#include "simulation/SameRun.h"
#include "strands/StrandParameters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <sstream>

namespace hair
{

struct Simulation::Impl
{
  SimulationOptions Options;
  Scene World;
  std::unique_ptr<StrandModel> Model;
  StateHeader Header;
  std::vector<std::string> Extra;
  FrameStore Store;
  std::vector<long> Contacts;
  std::vector<double> Depth;
  std::vector<std::map<std::string, double>> Steps; ///< the model's stepStatistics per frame
  Status Failed; ///< set when a step failed: the strands may then be at different times
  std::vector<GroomReport> Reports;
  /// This rank's strands: their numbers in the run, increasing (every strand without MPI).
  std::vector<std::int64_t> Mine;
  /// Every strand's rank and root at rest (the same on every rank), and the ghosts planned
  /// last (for GhostLevels levels).
  std::vector<int> Owner;
  std::vector<Eigen::Vector3d> Roots;
  mutable GhostStrands Ghosts;
  mutable int GhostLevels = 0;
  SimulationTimings Timings;
  double Time = 0; ///< the run's time (a rank without strands has no model time)
  /// The state file keeps each frame's continuation (Header.continuationWidth > 0), and the
  /// last one saved (its arrays reused from frame to frame).
  bool Continues = false;
  StateContinuation Saved;

  const Ranks& ranks() const { return Options.ranks; }
  /// The model's state now as a frame, with the penetration into the scene's parts at the
  /// same time (the same parts, poses and look-ups for every model). Under MPI (collective)
  /// this rank's piece, with the whole run's time, energy and penetration.
  StateFrame record();
  /// The model's continuation now, for the state file (collective); null when the file keeps
  /// none.
  const StateContinuation* continuation();
  /// How much room the state file keeps for continuations (Header.continuationWidth and
  /// continuationRunValues; none for a model that cannot be resumed). Collective.
  void planContinuation();
  /// Initialize's end for a resumed run: the file checked to be this run's, the model and
  /// the frames so far restored from its last whole frame with a continuation, and the file
  /// opened to go on after it. Collective.
  Status resume(const StorageOptions& storage, const FileSharing& sharing);
  void header(const std::vector<GuideStrand>& strands);
  /// The header's /groom: curves, rest coordinates and reports, when any guide has a groom
  /// or a sag-free rest shape (files of other runs are unchanged).
  void groom(const std::vector<GuideStrand>& strands);
};

void Simulation::Impl::groom(const std::vector<GuideStrand>& strands)
{
  const bool any = std::any_of(strands.begin(), strands.end(),
                               [](const GuideStrand& g)
                               { return !g.curve.empty() || g.restShape == RestShape::SagFree; });
  if (!any)
  {
    return;
  }
  StateGroom& g = Header.groom;
  g.curveOffsets.assign(1, 0);
  for (const GuideStrand& s : strands)
  {
    g.curvePoints.insert(g.curvePoints.end(), s.curve.begin(), s.curve.end());
    g.curveOffsets.push_back(static_cast<std::int64_t>(g.curvePoints.size()));
  }
  Model->restCoordinates(g.restCoordinates);
  if (Reports.size() == strands.size())
  {
    for (const GroomReportValue& v : groomReportValues())
    {
      std::vector<double>& values = g.strandValues[v.file];
      for (const GroomReport& r : Reports)
      {
        values.push_back(v.get(r));
      }
    }
  }
}

StateFrame Simulation::Impl::record()
{
  // Into the frame the store gave back (its arrays keep their memory from frame to frame).
  StateFrame f = Store.spare();
  if (!Mine.empty())
  {
    Model->writeFrame(f);
  }
  // Every rank with strands took the same steps to the same time; one without takes theirs.
  f.time = ranks().max(Mine.empty() ? -std::numeric_limits<double>::infinity() : Model->time());
  Time = f.time;
  f.energy = Model->energy().values();
  Steps.push_back(Model->stepStatistics());
  // The whole run's (every rank calls it, with the same rules, strands or not).
  reduceStepStatistics(Steps.back(), Model->stepStatisticRules(), double(Mine.size()), ranks());
  std::vector<PosedPart> parts;
  World.posedParts(f.time, parts);
  // The penetration at the model's nodes (the frame's points): how deep each is inside a
  // body part, how many are inside and the deepest.
  std::vector<double>& depthOf = f.pointData["contact_depth"];
  depthOf.assign(f.positions.size(), 0.0);
  std::vector<char> inside(f.positions.size(), 0);
  parallelBlocks(static_cast<std::int64_t>(f.positions.size()), 4096, Options.threads,
                 [&](std::int64_t begin, std::int64_t end)
                 {
                   for (std::int64_t i = begin; i < end; ++i)
                   {
                     inside[i] = insideDepth(parts, f.positions[i], depthOf[i]);
                   }
                 });
  long count = 0;
  double deepest = 0;
  for (std::size_t i = 0; i < f.positions.size(); ++i)
  {
    count += inside[i];
    deepest = std::max(deepest, depthOf[i]);
  }
  if (ranks().parallel())
  {
    // The whole run's energy (each rank's sums added: the same terms, in the map's order on
    // every rank) and penetration.
    std::vector<double> sums;
    for (const auto& [name, value] : f.energy)
    {
      sums.push_back(value);
    }
    sums.push_back(double(count));
    ranks().sum(sums.data(), int(sums.size()));
    std::size_t i = 0;
    for (auto& [name, value] : f.energy)
    {
      value = sums[i++];
    }
    count = static_cast<long>(std::llround(sums[i]));
    deepest = ranks().max(deepest);
  }
  Contacts.push_back(count);
  Depth.push_back(deepest);
  return f;
}

void Simulation::Impl::header(const std::vector<GuideStrand>& strands)
{
  Model->describe(Header);
  if (ranks().parallel())
  {
    // The model described this rank's strands: the run's offsets from every rank's counts,
    // and the coordinates per strand of the ranks that have strands.
    std::vector<std::int64_t> points(strands.size(), 0);
    for (std::size_t i = 0; i < Mine.size(); ++i)
    {
      points[Mine[i]] = Header.offsets[i + 1] - Header.offsets[i];
    }
    ranks().sum(points.data(), int(points.size()));
    Header.offsets.assign(1, 0);
    for (std::int64_t n : points)
    {
      Header.offsets.push_back(Header.offsets.back() + n);
    }
    Header.coordinatesPerStrand =
        static_cast<int>(ranks().max(double(Header.coordinatesPerStrand)));
  }
  for (const StrandParameter& p : strandParameters())
  {
    std::vector<double>& values = Header.strandParameters[p.file];
    for (const GuideStrand& g : strands)
    {
      values.push_back(p.get(g));
    }
  }
  for (const StrandVector& v : strandVectors())
  {
    std::vector<Eigen::Vector3d>& values = Header.strandVectors[v.file];
    for (const GuideStrand& g : strands)
    {
      values.push_back(v.get(g));
    }
  }
  Header.rootFrames = true; // every model's writeFrame gives them (model/StrandModel.h)
  // The penetration at the nodes, beside the model's own per-point arrays; curvature and twist
  // are drawn with the points.
  if (std::find(Header.pointData.begin(), Header.pointData.end(), "contact_depth") ==
      Header.pointData.end())
  {
    Header.pointData.push_back("contact_depth");
  }
  auto& at = Header.attributes;
  at["time_step"] = Options.timeStep;
  at["frame_interval"] = Options.frameInterval;
  const Eigen::Vector3d wind = World.air.velocity(Eigen::Vector3d::Zero(), 0);
  for (int c = 0; c < 3; ++c)
  {
    at[std::string("gravity_") + "xyz"[c]] = World.gravity[c];
    at[std::string("wind_") + "xyz"[c]] = wind[c];
  }
  const RigidMotion& m = World.rootMotion;
  at["motion_kind"] = static_cast<int>(m.kind());
  at["motion_amplitude"] = m.amplitude();
  at["motion_frequency"] = m.frequency();
  at["motion_fade"] = m.fade();
  at["scene_fingerprint"] = World.fingerprint();
}

void Simulation::Impl::planContinuation()
{
  double room[2] = {0, 0}; // numbers per strand (their count first), the model's own
  if (!Mine.empty() && Model->continuationRefusal().empty())
  {
    for (std::size_t k = 0; k < Mine.size(); ++k)
    {
      room[0] = std::max(room[0], double(Model->continuationCapacity(k) + 1));
    }
    Model->saveContinuation(Saved);
    room[1] = double(Saved.run.size());
  }
  room[0] = ranks().max(room[0]);
  room[1] = ranks().max(room[1]);
  Header.continuationWidth = int(room[0]);
  Header.continuationRunValues = int(room[1]);
  Continues = room[0] > 0;
}

const StateContinuation* Simulation::Impl::continuation()
{
  if (!Continues)
  {
    return nullptr;
  }
  if (!Mine.empty())
  {
    Model->saveContinuation(Saved);
  }
  else
  {
    Saved.strands.clear();
    Saved.run.assign(std::size_t(Header.continuationRunValues),
                     -std::numeric_limits<double>::infinity());
  }
  if (ranks().parallel() && !Saved.run.empty())
  {
    // The model's own numbers are the same on every rank with strands: a rank without
    // takes theirs (rank 0 writes them).
    std::vector<double> negated(Saved.run.size());
    for (std::size_t i = 0; i < negated.size(); ++i)
    {
      negated[i] = -Saved.run[i];
    }
    ranks().min(negated.data(), int(negated.size()));
    for (std::size_t i = 0; i < negated.size(); ++i)
    {
      Saved.run[i] = -negated[i];
    }
  }
  Saved.frame = Store.size();
  return &Saved;
}

Status Simulation::Impl::resume(const StorageOptions& storage, const FileSharing& sharing)
{
  const Ranks& all = ranks();
  const std::string file = "the state file '" + storage.stateFile + "' ";
  Status s = Status::Ok();
  if (!Mine.empty())
  {
    if (const std::string why = Model->continuationRefusal(); !why.empty())
    {
      s = Status::Error("this run cannot be resumed: " + why + ".");
    }
  }
  if (s && !Continues)
  {
    s = Status::Error("this run cannot be resumed: it keeps no continuation.");
  }
  // Every rank reads the file for its own strands (read only; the file is opened for
  // writing once every rank has read it).
  StateFileReader reader;
  StateContinuation saved;
  if (s)
  {
    s = reader.open(storage.stateFile);
    if (!s)
    {
      s = Status::Error("nothing to resume: " + s.message());
    }
  }
  if (s)
  {
    std::vector<std::string> terms;
    for (const auto& [name, values] : reader.energies())
    {
      terms.push_back(name);
    }
    if (Status same = sameRun(reader.header(), reader.version(), terms, Header, Extra); !same)
    {
      s = Status::Error(file + same.message());
    }
  }
  if (s && reader.sharedByRanks() != all.parallel())
  {
    s = Status::Error(
        file + (reader.sharedByRanks()
                    ? std::string("was written by MPI ranks together (with room for the run's "
                                  "frames from the start): it is resumed under MPI, on 2 ranks "
                                  "or more.")
                    : "was written by one process (it grows as frames are added): it is resumed "
                      "by one process, not by " +
                          std::to_string(all.size()) + " MPI ranks."));
  }
  s = s ? reader.readContinuation(&Mine, saved) : s;
  if (Status agreed = all.agree(s); !agreed)
  {
    return agreed;
  }
  // Every rank from the same frame.
  double from[2] = {double(saved.frame), double(saved.frame)};
  all.min(&from[0], 1);
  from[1] = all.max(from[1]);
  if (from[0] != from[1])
  {
    return Status::Error(file + "names different frames to resume from on different ranks (" +
                         std::to_string(long(from[0])) + " and " + std::to_string(long(from[1])) +
                         "): it changed while it was read.");
  }
  const std::int64_t last = saved.frame;
  if (last + 1 > storage.frames && storage.frames > 0)
  {
    return Status::Error(file + "holds " + std::to_string(last + 1) +
                         " frames, more than this run's " + std::to_string(storage.frames) +
                         ": a resumed run drops no whole frame. Resume with a Duration of at "
                         "least the file's run.");
  }
  // The frames so far: times and energies, and the penetration of each (its piece's
  // contact_depth, summed over the ranks); the last one whole.
  const StateHeader piece = all.parallel() ? Header.piece(Mine) : Header;
  std::vector<StateFrame> frames(std::size_t(last + 1));
  for (std::int64_t i = 0; i <= last && s; ++i)
  {
    StateFrame f;
    s = reader.readPiece(i, Mine, f);
    if (!s)
    {
      break;
    }
    long count = 0;
    double deepest = 0;
    for (double d : f.pointData["contact_depth"])
    {
      count += d > 0;
      deepest = std::max(deepest, d);
    }
    Contacts.push_back(count);
    Depth.push_back(deepest);
    if (i == last)
    {
      s = restoreNodes(piece, f);
      frames[std::size_t(i)] = std::move(f);
    }
    frames[std::size_t(i)].time = reader.times()[std::size_t(i)];
    for (const auto& [name, values] : reader.energies())
    {
      frames[std::size_t(i)].energy[name] = values[std::size_t(i)];
    }
  }
  reader.close();
  if (Status agreed = all.agree(s); !agreed)
  {
    return Status::Error(file + "cannot be read back: " + agreed.message());
  }
  if (all.parallel())
  {
    std::vector<double> counts(Contacts.begin(), Contacts.end());
    all.sum(counts.data(), int(counts.size()));
    for (std::size_t i = 0; i < counts.size(); ++i)
    {
      Contacts[i] = static_cast<long>(std::llround(counts[i]));
      Depth[i] = all.max(Depth[i]);
    }
  }
  // The model's step statistics are not in the file: unknown (NaN) for the frames so far.
  std::map<std::string, double> unknown =
      Mine.empty() ? std::map<std::string, double>() : Model->stepStatistics();
  for (auto& [name, value] : unknown)
  {
    value = std::numeric_limits<double>::quiet_NaN();
  }
  Steps.assign(frames.size(), unknown);
  s = Mine.empty() ? Status::Ok() : Model->restoreContinuation(saved);
  if (Status agreed = all.agree(s); !agreed)
  {
    return Status::Error(file + "cannot be resumed: " + agreed.message());
  }
  Time = frames.back().time;
  return Store.resume(Header, Extra, std::move(frames), storage, sharing);
}

std::vector<int> shareStrands(const std::vector<GuideStrand>& guides, const StrandModel& model,
                              int ranks)
{
  std::vector<Eigen::Vector3d> roots;
  std::vector<double> costs;
  for (const GuideStrand& g : guides)
  {
    roots.push_back(g.root);
    costs.push_back(model.stepCost(g));
  }
  return shareAlongCurve(roots, costs, ranks);
}

namespace
{
/// Wall time and the process's CPU time since the last lap.
struct Clock
{
  std::chrono::steady_clock::time_point Wall = std::chrono::steady_clock::now();
  std::clock_t Cpu = std::clock();
  void lap(double& wall, double& cpu)
  {
    const auto w = std::chrono::steady_clock::now();
    const std::clock_t c = std::clock();
    wall += std::chrono::duration<double>(w - Wall).count();
    cpu += double(c - Cpu) / CLOCKS_PER_SEC;
    Wall = w;
    Cpu = c;
  }
};

/// Under MPI, every rank must be given the same guides (the pipeline gives each rank the
/// whole strands input): their number and a sum of their every number, compared.
Status sameOnEveryRank(const std::vector<GuideStrand>& strands, const Ranks& ranks)
{
  if (!ranks.parallel())
  {
    return Status::Ok();
  }
  double sum = 0;
  for (std::size_t k = 0; k < strands.size(); ++k)
  {
    const GuideStrand& g = strands[k];
    const HairParameters& h = g.hair;
    const double values[] = {
        g.root.x(),         g.root.y(),          g.root.z(),    g.growth.x(),  g.growth.y(),
        g.growth.z(),       g.normal.x(),        g.normal.y(),  g.normal.z(),  g.length,
        double(g.elements), double(g.seed),      h.radius,      h.ellipticity, h.youngModulus,
        h.poissonRatio,     h.density,           h.helixRadius, h.helixStep,   h.internalFriction,
        h.airFriction,      h.curvatureVariation};
    double i = 1;
    for (double v : values)
    {
      sum += v * (double(k) + i++ / 32);
    }
  }
  double lo[2] = {double(strands.size()), sum}, hi[2] = {lo[0], lo[1]};
  ranks.min(lo, 2);
  ranks.max(hi, 2);
  if (lo[0] != hi[0] || !(lo[1] == hi[1] || (std::isnan(lo[1]) && std::isnan(hi[1]))))
  {
    return Status::Error("the ranks were given different guide strands (between " +
                         std::to_string(long(lo[0])) + " and " + std::to_string(long(hi[0])) +
                         " strands, or different values): under MPI every rank must be given the "
                         "whole, same strands input.");
  }
  return Status::Ok();
}
} // namespace

Simulation::Simulation() : P(std::make_unique<Impl>()) {}
Simulation::~Simulation() = default;

Status checkRunMemory(const std::vector<GuideStrand>& strands, const SimulationOptions& options,
                      double availableBytes)
{
  // The model's memory per element as measured (StrandModel::bytesPerElement); a frame keeps
  // per node its position, velocity and depth and per element its coordinates and rates,
  // under 80 bytes per node.
  std::unique_ptr<StrandModel> model;
  if (Status s = makeModel(options, model); !s)
  {
    return s;
  }
  const double perElement = model->bytesPerElement(), perPoint = 80;
  double elements = 0, points = 0;
  for (const GuideStrand& g : strands)
  {
    elements += g.elements;
    points += double(g.elements) + 1;
  }
  const double need = elements * perElement + 2 * points * perPoint;
  if (need <= 0.75 * availableBytes)
  {
    return Status::Ok();
  }
  auto gb = [](double bytes)
  {
    std::ostringstream m;
    m.precision(3);
    m << bytes / 1e9 << " GB";
    return m.str();
  };
  std::ostringstream m;
  m << "the run's " << strands.size() << " strands of " << strands[0].elements
    << " elements would need about " << gb(need) << " of memory to start (the model, "
    << gb(elements * perElement) << ", and its first frame of " << points << " points), more "
    << "than three quarters of this machine's " << gb(availableBytes)
    << ": use fewer strands or fewer elements.";
  return Status::Error(m.str());
}

Status Simulation::initialize(const std::vector<GuideStrand>& strands, const Scene& scene,
                              const SimulationOptions& options, const StorageOptions& storage)
{
  P = std::make_unique<Impl>();
  auto r = std::make_unique<Impl>();
  if (strands.empty())
  {
    return Status::Error("there are no strands to simulate: give at least one guide strand.");
  }
  if (Status s = options.run().validate(); !s)
  {
    return s;
  }
  for (std::size_t k = 0; k < strands.size(); ++k)
  {
    if (Status s = strands[k].validate("strand " + std::to_string(k)); !s)
    {
      return s;
    }
    if (strands[k].elements != strands[0].elements)
    {
      return Status::Error("strand " + std::to_string(k) + " has " +
                           std::to_string(strands[k].elements) + " elements, strand 0 has " +
                           std::to_string(strands[0].elements) +
                           ": all strands of a run need the same number.");
    }
  }
  if (Status s = scene.validate(); !s)
  {
    return s;
  }
  const Ranks& ranks = options.ranks;
  if (Status s = sameOnEveryRank(strands, ranks); !s)
  {
    return s;
  }
  if (ranks.parallel())
  {
    // The groom's fit and rest shape are made per strand on the rank that holds it, but its
    // reports and /groom are written from one rank's guides: not yet shared among ranks.
    for (std::size_t k = 0; k < strands.size(); ++k)
    {
      if (!strands[k].curve.empty() || strands[k].restShape == RestShape::SagFree)
      {
        return Status::Error(
            "strand " + std::to_string(k) + " has a groom (" +
            (strands[k].curve.empty() ? std::string("a sag-free rest shape")
                                      : std::string("a guide curve")) +
            "): grooms are not available under MPI yet (" + std::to_string(ranks.size()) +
            " ranks). Run on one rank (without mpirun, or mpirun -np 1), or grow the guides "
            "as grown.");
      }
    }
  }
  r->Options = options;
  r->World = scene;
  if (Status s = makeModel(options, r->Model); !s)
  {
    return s;
  }
  // This rank's share of the strands (all of them without MPI).
  std::vector<GuideStrand> mine;
  RunSettings run = options.run();
  const std::vector<int> owner = ranks.parallel() ? shareStrands(strands, *r->Model, ranks.size())
                                                  : std::vector<int>(strands.size(), 0);
  r->Owner = owner;
  for (const GuideStrand& g : strands)
  {
    r->Roots.push_back(g.root);
  }
  for (std::size_t k = 0; k < strands.size(); ++k)
  {
    if (owner[k] == ranks.rank())
    {
      r->Mine.push_back(std::int64_t(k));
      run.strandIds.push_back(int(k));
      mine.push_back(strands[k]);
    }
  }
  // Under MPI each rank holds the model and the frames of its share only: its share is what
  // must fit (ranks that share a machine are not added up).
  if (Status s = ranks.agree(mine.empty() ? Status::Ok()
                                          : checkRunMemory(mine, options, physicalMemoryBytes()));
      !s)
  {
    return s;
  }
  // The model's own collective calls (a grid summed over the ranks) are made by the ranks
  // that hold strands: the others never call it.
  run.ranks = ranks.subset(!mine.empty());
  Status built = mine.empty() ? Status::Ok() : r->Model->initialize(mine, scene, run);
  if (Status s = ranks.agree(built); !s)
  {
    return s;
  }
  // The guides as the model built them (a groom's fitted length and root tangent), so that
  // the file draws the strands again as they ran, and the groom with its reports.
  // (Under MPI no guide has a groom, and a model knows only its rank's share.)
  std::vector<GuideStrand> asBuilt = strands;
  if (!ranks.parallel())
  {
    r->Model->groomed(asBuilt, r->Reports);
  }
  r->header(asBuilt);
  r->groom(asBuilt);
  r->Extra = r->Model->energy().extraNames();
  if (!storage.stateFile.empty())
  {
    r->planContinuation();
  }
  FileSharing sharing;
  sharing.ranks = ranks;
  sharing.strands = r->Mine;
  if (storage.resume)
  {
    if (storage.stateFile.empty())
    {
      return Status::Error("a run is resumed from its state file: give the state file's name.");
    }
    if (Status s = r->resume(storage, sharing); !s)
    {
      return s;
    }
    P = std::move(r);
    return Status::Ok();
  }
  StateFrame first = r->record();
  const StateContinuation* continuation = r->continuation();
  if (Status s =
          r->Store.open(r->Header, r->Extra, std::move(first), storage, sharing, continuation);
      !s)
  {
    return s;
  }
  P = std::move(r);
  return Status::Ok();
}

Status Simulation::advanceTo(int frames, const Progress& progress)
{
  if (!P->Model)
  {
    return Status::Error("the simulation is not initialized.");
  }
  if (!P->Failed)
  {
    return P->Failed; // a failed step leaves strands at different times: stay stopped
  }
  const int first = numberOfFrames();
  const Ranks& ranks = P->ranks();
  SimulationTimings& times = P->Timings;
  for (int f = first; f < frames; ++f)
  {
    Clock clock;
    Status stepped =
        P->Mine.empty() ? Status::Ok() : P->Model->advanceTo(f * P->Options.frameInterval);
    clock.lap(times.stepWall, times.stepCpu);
    double unused = 0;
    Status agreed = ranks.agree(stepped);
    clock.lap(times.waitWall, unused);
    if (!agreed)
    {
      P->Failed = agreed;
      return agreed;
    }
    StateFrame recorded = P->record();
    const StateContinuation* continuation = P->continuation();
    clock.lap(times.recordWall, times.recordCpu);
    Status stored = P->Store.add(std::move(recorded), continuation);
    clock.lap(times.storeWall, times.storeCpu);
    ++times.frames;
    if (!stored)
    {
      P->Failed = stored;
      return stored;
    }
    if (ranks.any(progress && !progress(double(f - first + 1) / (frames - first))))
    {
      return Status::Error("the simulation was aborted at t = " + std::to_string(P->Time) +
                           " s; the frames computed so far are kept.");
    }
  }
  return Status::Ok();
}

int Simulation::numberOfFrames() const
{
  return P->Store.size();
}

const StateFrame& Simulation::frame(int index) const
{
  return P->Store.frame(index);
}

bool Simulation::hasFrameData(int index) const
{
  return P->Store.inMemory(index);
}

Status Simulation::readFrame(int index, StateFrame& out) const
{
  return P->Store.read(index, out);
}

Status Simulation::drawFrame(int index, int pointsPerElement, GuideDrawing& out) const
{
  StateFrame frame;
  if (Status s = readFrame(index, frame); !s)
  {
    return s;
  }
  return drawGuides(piece(), frame, pointsPerElement, P->Options.threads, out);
}

double Simulation::bytesPerFrame() const
{
  return P->Store.bytesPerFrame();
}

Status Simulation::checkMemory(int frames, double availableBytes) const
{
  return FrameStore::checkMemory(frames, bytesPerFrame(), availableBytes,
                                 P->Header.numberOfPoints());
}

const StateHeader& Simulation::header() const
{
  return P->Header;
}

const StateHeader& Simulation::piece() const
{
  return P->Store.piece();
}

Status Simulation::ghostFrame(int index, int levels, StateHeader& header, StateFrame& frame) const
{
  const Ranks& ranks = P->ranks();
  if (!P->Model || !ranks.parallel() || levels < 1)
  {
    header = P->Header.piece({});
    frame = StateFrame();
    return Status::Ok();
  }
  if (levels != P->GhostLevels)
  {
    P->Ghosts.plan(P->Roots, P->Owner, ranks.rank(), 3.0 * levels * typicalSpacing(P->Roots));
    P->GhostLevels = levels;
  }
  StateFrame mine;
  if (Status s = readFrame(index, mine); !s)
  {
    return s;
  }
  header = P->Header.piece(P->Ghosts.ghosts());
  return P->Ghosts.exchange(ranks, P->Header, piece(), mine, frame);
}

const std::vector<std::string>& Simulation::extraEnergyTerms() const
{
  return P->Extra;
}

const std::vector<long>& Simulation::contacts() const
{
  return P->Contacts;
}

const std::vector<double>& Simulation::maxDepth() const
{
  return P->Depth;
}

void Simulation::energyTable(std::vector<double>& times,
                             std::map<std::string, std::vector<double>>& columns) const
{
  times.clear();
  columns.clear();
  for (int f = 0; f < numberOfFrames(); ++f)
  {
    const StateFrame& fr = frame(f);
    times.push_back(fr.time);
    for (const auto& [name, value] : fr.energy)
    {
      columns[name].push_back(value);
    }
    columns["nodes_inside"].push_back(static_cast<double>(P->Contacts[f]));
    columns["max_depth"].push_back(P->Depth[f]);
    for (const auto& [name, value] : P->Steps[f])
    {
      columns[name].push_back(value);
    }
  }
}

const StrandModel& Simulation::model() const
{
  return *P->Model;
}

const std::vector<GroomReport>& Simulation::groomReports() const
{
  return P->Reports;
}

const SimulationTimings& Simulation::timings() const
{
  return P->Timings;
}

} // namespace hair
