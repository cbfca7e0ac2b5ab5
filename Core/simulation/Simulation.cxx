#include "simulation/Simulation.h"

#include "collision/PosedPart.h"
#include "common/Machine.h"
#include "common/Parallel.h"
#include "strands/StrandParameters.h"

#include <algorithm>
#include <cmath>
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

  /// The model's state now as a frame, with the penetration into the scene's parts at the
  /// same time (the same parts, poses and look-ups for every model).
  StateFrame record();
  void header(const std::vector<GuideStrand>& strands);
};

StateFrame Simulation::Impl::record()
{
  StateFrame f;
  Model->writeFrame(f);
  f.time = Model->time();
  f.energy = Model->energy().values();
  Steps.push_back(Model->stepStatistics());
  std::vector<PosedPart> parts;
  World.posedParts(f.time, parts);
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
  Contacts.push_back(count);
  Depth.push_back(deepest);
  return f;
}

void Simulation::Impl::header(const std::vector<GuideStrand>& strands)
{
  Model->describe(Header);
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
  Header.pointData = {"curvature", "twist", "contact_depth"};
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
}

Simulation::Simulation() : P(std::make_unique<Impl>()) {}
Simulation::~Simulation() = default;

Status checkRunMemory(const std::vector<GuideStrand>& strands, const SimulationOptions& options,
                      double availableBytes)
{
  // Measured with hair_study scene (200 and 400 wavy strands of 10, 50 and 100 elements, two
  // frames, maximum resident memory): the Super-Helix model takes about 2.6 kB per element,
  // the projective one 0.7 kB per segment; a frame's point takes its position and velocity
  // and a few per-point scalars, about 80 bytes.
  const bool superHelix = options.model == ModelType::SuperHelix;
  const double perElement = superHelix ? 2600 : 700, perPoint = 80;
  const int per = superHelix ? std::max(1, options.superHelix.pointsPerElement) : 1;
  double elements = 0, points = 0;
  for (const GuideStrand& g : strands)
  {
    elements += g.elements;
    points += double(g.elements) * per + 1;
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
    << ": use fewer strands, fewer elements or fewer points per element.";
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
  if (Status s = checkRunMemory(strands, options, physicalMemoryBytes()); !s)
  {
    return s;
  }
  r->Options = options;
  r->World = scene;
  r->Model = makeModel(options);
  if (Status s = r->Model->initialize(strands, scene, options.run()); !s)
  {
    return s;
  }
  r->header(strands);
  r->Extra = r->Model->energy().extraNames();
  if (Status s = r->Store.open(r->Header, r->Extra, r->record(), storage); !s)
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
  for (int f = first; f < frames; ++f)
  {
    if (Status s = P->Model->advanceTo(f * P->Options.frameInterval); !s)
    {
      P->Failed = s;
      return s;
    }
    if (Status s = P->Store.add(P->record()); !s)
    {
      P->Failed = s;
      return s;
    }
    if (progress && !progress(double(f - first + 1) / (frames - first)))
    {
      return Status::Error("the simulation was aborted at t = " + std::to_string(P->Model->time()) +
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

} // namespace hair
