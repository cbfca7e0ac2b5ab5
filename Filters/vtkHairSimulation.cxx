#include "vtkHairSimulation.h"

#include "HairConversion.h"
#include "common/Machine.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkLogger.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTable.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

vtkStandardNewMacro(vtkHairSimulation);

namespace
{
/// The frames a run of `duration` seconds at `rate` frames per second has, frame 0 included.
int frameCount(double duration, double rate)
{
  return static_cast<int>(std::floor(duration / (1.0 / rate) + 1e-9)) + 1;
}
} // namespace

struct vtkHairSimulation::Internals
{
  hair::Simulation Sim;
  bool Initialized = false;
  vtkMTimeType BuiltAt = 0; ///< max MTime of this filter and its inputs when Sim was built
  /// The filter's MTime set by the last change of Points Per Element, and its MTime before
  /// it: a change of drawing only does not build the run again.
  vtkMTimeType DrawnAt = 0, BeforeDrawn = 0;
  std::string Written; ///< the state file this filter created last (its own to replace)
  /// Under MPI, the ranks of ParaView's controller (made at the first request, which every
  /// rank makes); this process alone otherwise.
  hair::Ranks Ranks;
  bool HaveRanks = false;
};

void vtkHairSimulation::SetPointsPerElement(int points)
{
  if (points == this->PointsPerElement)
  {
    return;
  }
  // Only how a frame is drawn: the change is remembered so that the run is not built again
  // for it (RequestData looks past it).
  Internals& in = *this->Internal;
  const vtkMTimeType before = this->GetMTime();
  in.BeforeDrawn = before == in.DrawnAt ? in.BeforeDrawn : before;
  this->PointsPerElement = points;
  this->Modified();
  in.DrawnAt = this->GetMTime();
}

vtkHairSimulation::vtkHairSimulation()
    : QuadratureTolerance(hair::QuadratureChooser::defaultTolerance()),
      Internal(std::make_unique<Internals>())
{
  const Eigen::Vector3d pivot = hair::bundled::neckPivot();
  std::copy(pivot.data(), pivot.data() + 3, this->MotionPivot);
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
}

vtkHairSimulation::~vtkHairSimulation() = default;

void vtkHairSimulation::Reset()
{
  this->Internal->Initialized = false;
  this->Modified();
}

void vtkHairSimulation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const hair::ModelEntry* model = hair::findModel(hair::ModelType(this->Model));
  os << indent << "Model: " << (model ? model->label : "(not a registered model)") << " ("
     << this->Model << ")\n"
     << indent << "TimeStep: " << this->TimeStep << "\n"
     << indent << "Duration: " << this->Duration << "\n"
     << indent << "FrameRate: " << this->FrameRate << "\n"
     << indent << "Gravity: " << this->Gravity[0] << " " << this->Gravity[1] << " "
     << this->Gravity[2] << "\n"
     << indent << "Wind: " << this->Wind[0] << " " << this->Wind[1] << " " << this->Wind[2] << "\n"
     << indent << "BodyMotion: " << this->BodyMotion << " amplitude " << this->MotionAmplitude
     << " frequency " << this->MotionFrequency << " fade-in " << this->MotionFadeIn << " s\n"
     << indent << "PointsPerElement: " << this->PointsPerElement << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "QuadratureTolerance: " << this->QuadratureTolerance << "\n"
     << indent << "Integrator: " << hair::toString(static_cast<hair::Integrator>(this->Integrator))
     << " tolerance " << this->Tolerance << " m/s\n"
     << indent << "Contacts: " << (this->Contacts ? "on" : "off") << " stiffness "
     << this->ContactStiffness << " damping " << this->ContactDamping << " friction "
     << this->FrictionCoefficient << " anisotropy " << this->FrictionAnisotropy << " static "
     << this->StaticFrictionCoefficient << " thickness " << this->ContactThickness
     << " slip velocity " << this->SlipVelocity << "\n"
     << indent << "Hair-hair contacts: " << this->HairHairContacts << " (0 off, 1 coupled, 2 grid, "
     << "3 grid and near field) volume fraction " << this->HairVolumeFraction << " pressure "
     << this->HairVolume << " volume, grid friction " << this->HairGridFriction << " /s cell "
     << this->HairGridCellSize << " m thickness " << this->HairContactThickness << " stiffness "
     << this->HairContactStiffness << " damping " << this->HairContactDamping
     << " friction coefficient " << this->HairFrictionCoefficient << " iterations "
     << this->HairContactIterations << " per length " << (this->HairContactPerLength ? "on" : "off")
     << "\n"
     << indent << "StateFileName: " << this->StateFileName << "\n"
     << indent << "OverwriteStateFile: " << this->OverwriteStateFile << "\n"
     << indent << "Resume: " << this->Resume << "\n";
}

int vtkHairSimulation::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    info->Set(vtkAlgorithm::INPUT_IS_REPEATABLE(), 1);
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkHairSimulation::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkPolyData" : "vtkTable");
  return 1;
}

bool vtkHairSimulation::CheckProperties()
{
  struct Range
  {
    const char* name;
    double value, min, max;
    const char* unit;
  };
  const Range ranges[] = {
      {"Time Step", this->TimeStep, 1e-6, 0.1, " s"},
      {"Duration", this->Duration, 0, 3600, " s"},
      {"Frame Rate", this->FrameRate, 0.1, 1000, " frames/s"},
      {"Number Of Threads", double(this->NumberOfThreads), 1, 256, ""},
      {"Points Per Element", double(this->PointsPerElement), 1, 256, ""},
      {"Memory Budget", this->MemoryBudget, 0, 1e9, " MiB"},
      {"Tolerance", this->Tolerance, 0, 1, " m/s"},
  };
  for (const Range& r : ranges)
  {
    if (!(r.value >= r.min && r.value <= r.max))
    {
      vtkErrorMacro(<< "Hair Simulation: " << r.name << " is " << r.value << r.unit << "; give "
                    << r.min << " to " << r.max << r.unit << ".");
      return false;
    }
  }
  return true;
}

int vtkHairSimulation::RequestInformation(vtkInformation*, vtkInformationVector**,
                                          vtkInformationVector* outputVector)
{
  if (!this->CheckProperties())
  {
    return 0;
  }
  const double interval = 1.0 / this->FrameRate;
  const int frames = frameCount(this->Duration, this->FrameRate);
  std::vector<double> times(frames);
  for (int i = 0; i < frames; ++i)
  {
    times[i] = i * interval;
  }
  // Both outputs vary in time (the energy table grows as frames are computed): without
  // TIME_STEPS on port 1, views of the table would never ask for it again.
  const double range[2] = {0, times.back()};
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(port);
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), frames);
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
    // Under MPI each rank's output is its piece of the strands (the table is rank 0's).
    outInfo->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  }
  return 1;
}

int vtkHairSimulation::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                           vtkInformationVector*)
{
  // The strands and tables are static: ask them for no particular time, whole.
  for (int port = 0; port < 2; ++port)
  {
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      vtkInformation* in = inputVector[port]->GetInformationObject(i);
      in->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
      in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    }
  }
  return 1;
}

int vtkHairSimulation::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                   vtkInformationVector* outputVector)
{
  Internals& in = *this->Internal;
  vtkPolyData* strandsIn = vtkPolyData::GetData(inputVector[0], 0);

  // Under MPI (pvbatch, pvserver), every rank runs this with the whole inputs; each steps its
  // share of the strands and outputs it as its piece, and the one state file is written by
  // all (docs/hair-simulation.md, "Under MPI"). Every call below that names the ranks is
  // made by every rank.
  if (!in.HaveRanks)
  {
    in.Ranks = hair::convert::toRanks(vtkMultiProcessController::GetGlobalController());
    in.HaveRanks = true;
  }
  const hair::Ranks& ranks = in.Ranks;

  if (!this->CheckProperties())
  {
    return 0;
  }
  // (Re)build the run when a property or an input changed since it was built (on every rank
  // if on any: the ranks step together).
  vtkMTimeType mtime = this->GetMTime();
  if (mtime == in.DrawnAt)
  {
    mtime = in.BeforeDrawn; // nothing but Points Per Element changed since
  }
  mtime = std::max(mtime, strandsIn ? strandsIn->GetMTime() : 0);
  for (int i = 0; i < inputVector[1]->GetNumberOfInformationObjects(); ++i)
  {
    vtkImageData* t = vtkImageData::GetData(inputVector[1], i);
    mtime = std::max(mtime, t ? t->GetMTime() : 0);
  }
  if (ranks.any(!in.Initialized || mtime > in.BuiltAt))
  {
    in.Initialized = false;
    if (!this->Build(inputVector))
    {
      return 0;
    }
    in.Initialized = true;
    in.BuiltAt = mtime;
  }

  // The frame of the requested time, computing forward from the last one, each written (and
  // flushed) as soon as it exists, so that a run that is killed or aborted keeps everything
  // computed before.
  const double interval = 1.0 / this->FrameRate;
  int index = 0;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    index = static_cast<int>(std::lround(std::max(0.0, t) / interval));
  }
  index = std::min(index, frameCount(this->Duration, this->FrameRate) - 1);
  const int before = in.Sim.numberOfFrames();
  for (int f = before; f <= index; ++f)
  {
    if (hair::Status s = in.Sim.advanceTo(f + 1); !s)
    {
      vtkErrorMacro(<< "Hair Simulation: " << s.message());
      return 0;
    }
    this->UpdateProgress(double(f - before + 1) / (index - before + 1));
    if (ranks.any(this->GetAbortExecute() != 0))
    {
      vtkWarningMacro(<< "Hair Simulation: aborted at t = " << in.Sim.frame(f).time
                      << " s; the frames computed so far are kept.");
      index = f;
      break;
    }
  }
  hair::StateFrame frame;
  if (hair::Status s = in.Sim.readFrame(index, frame); !s)
  {
    vtkErrorMacro(<< "Hair Simulation: " << s.message());
    return 0;
  }
  // The frame drawn at Points Per Element from its state (this rank's piece under MPI,
  // StrandId the strands' numbers in the run), with the material frame at every point
  // (simulation/GuideDrawing.h).
  hair::GuideDrawing drawing;
  if (hair::Status s = hair::drawGuides(in.Sim.piece(), frame, this->PointsPerElement,
                                        this->NumberOfThreads, drawing);
      !s)
  {
    vtkErrorMacro(<< "Hair Simulation: " << s.message());
    return 0;
  }
  vtkPolyData* strandsOut = vtkPolyData::GetData(outputVector, 0);
  hair::convert::toStrands(drawing, strandsOut);
  // Ghost levels asked for (Hair Interpolation asks for one): the strands of other ranks
  // near this rank's, marked as ghost cells, so that a piece is interpolated near its edges
  // as if the neighbouring pieces were there.
  int ghostLevels = 0;
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS()))
  {
    ghostLevels = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS());
  }
  ghostLevels = static_cast<int>(ranks.max(double(ghostLevels)));
  if (ranks.parallel() && ghostLevels > 0)
  {
    hair::StateHeader ghostHeader;
    hair::StateFrame ghostFrame;
    hair::GuideDrawing ghosts;
    hair::Status s = in.Sim.ghostFrame(index, ghostLevels, ghostHeader, ghostFrame);
    s = s ? hair::drawGuides(ghostHeader, ghostFrame, this->PointsPerElement, this->NumberOfThreads,
                             ghosts)
          : s;
    if (!s)
    {
      vtkErrorMacro(<< "Hair Simulation: the ghost strands: " << s.message());
      return 0;
    }
    vtkNew<vtkPolyData> ghostStrands;
    hair::convert::toStrands(ghosts, ghostStrands);
    hair::convert::appendGhosts(strandsOut, ghostStrands);
    strandsOut->GetInformation()->Set(vtkDataObject::DATA_NUMBER_OF_GHOST_LEVELS(), ghostLevels);
  }
  strandsOut->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frame.time);

  // Energy and contacts of every frame computed so far: the whole run's, on rank 0 (every
  // rank has them; ParaView appends the ranks' tables).
  std::vector<double> times;
  std::map<std::string, std::vector<double>> columns;
  in.Sim.energyTable(times, columns);
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  table->Initialize();
  if (ranks.rank() == 0)
  {
    // The energy terms are the frames' (the other columns: penetration, step statistics).
    std::vector<std::string> terms;
    for (const auto& term : in.Sim.frame(0).energy)
    {
      terms.push_back(term.first);
    }
    hair::convert::toEnergyTable(times, columns, terms, table);
  }
  table->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frame.time);
  return 1;
}

bool vtkHairSimulation::Build(vtkInformationVector** inputVector)
{
  Internals& in = *this->Internal;
  std::vector<hair::GuideStrand> guides;
  if (hair::Status s = hair::convert::toGuides(vtkPolyData::GetData(inputVector[0], 0), guides); !s)
  {
    vtkErrorMacro(<< "Hair Simulation: " << s.message());
    return false;
  }
  // The scene: the tables (those marked Moves With Head follow the head), the head's
  // motion carrying the roots, gravity and a uniform wind.
  hair::Scene scene;
  if (this->BodyMotion != NONE)
  {
    scene.rootMotion = hair::RigidMotion::oscillation(
        static_cast<hair::RigidMotion::Kind>(this->BodyMotion), Eigen::Vector3d(this->MotionPivot),
        Eigen::Vector3d(this->MotionAxis), this->MotionAmplitude, this->MotionFrequency);
    if (this->MotionFadeIn > 0)
    {
      scene.rootMotion.during(0).fading(this->MotionFadeIn);
    }
  }
  for (int i = 0; i < inputVector[1]->GetNumberOfInformationObjects(); ++i)
  {
    hair::ScenePart p;
    bool movesWithHead = false;
    if (hair::Status s = hair::convert::fromImage(vtkImageData::GetData(inputVector[1], i), p.table,
                                                  &p.name, &movesWithHead);
        !s)
    {
      vtkErrorMacro(<< "Hair Simulation: collision table " << i << ": " << s.message());
      return false;
    }
    p.name = p.name.empty() ? "part " + std::to_string(i) : p.name;
    p.motion = movesWithHead ? scene.rootMotion : hair::RigidMotion::still();
    scene.parts.push_back(std::move(p));
  }
  scene.gravity = Eigen::Vector3d(this->Gravity);
  scene.air = hair::AirField::uniform(Eigen::Vector3d(this->Wind));

  hair::SimulationOptions o;
  o.model = hair::ModelType(this->Model); // Simulation refuses one no one registered
  o.timeStep = this->TimeStep;
  o.frameInterval = 1.0 / this->FrameRate;
  o.threads = this->NumberOfThreads;
  o.ranks = in.Ranks;
  hair::SuperHelixOptions& sh = o.superHelix;
  sh.quadratureTolerance = this->QuadratureTolerance;
  // IntegratorType's values are hair::Integrator's.
  sh.integrator = static_cast<hair::Integrator>(this->Integrator);
  sh.tolerance = this->Tolerance;
  o.contacts.enabled = this->Contacts;
  o.contacts.stiffness = this->ContactStiffness;
  o.contacts.dampingRatio = this->ContactDamping;
  o.contacts.friction = this->FrictionCoefficient;
  o.contacts.anisotropy = this->FrictionAnisotropy;
  o.contacts.staticFriction = this->StaticFrictionCoefficient;
  o.contacts.thickness = this->ContactThickness;
  o.contacts.slipVelocity = this->SlipVelocity;
  o.hairHair.enabled = this->HairHairContacts != HAIR_HAIR_OFF;
  if (o.hairHair.enabled)
  {
    // Any other value is refused by the options' validation, with the values it takes.
    o.hairHair.solver = static_cast<hair::HairHairSolver>(this->HairHairContacts);
  }
  o.hairHair.grid.volumeFraction = this->HairVolumeFraction;
  o.hairHair.grid.volume = this->HairVolume;
  o.hairHair.grid.friction = this->HairGridFriction;
  o.hairHair.grid.cellSize = this->HairGridCellSize;
  o.hairHair.pairs.thickness = this->HairContactThickness;
  o.hairHair.pairs.stiffness = this->HairContactStiffness;
  o.hairHair.pairs.damping = this->HairContactDamping;
  o.hairHair.pairs.friction = this->HairFrictionCoefficient;
  o.hairHair.pairs.iterations = this->HairContactIterations;
  o.hairHair.pairs.perLength = this->HairContactPerLength;

  // Frames stay in memory while the run fits in the budget; a longer run with a state file
  // keeps only the newest frames in memory and reads the others back from the file; without
  // one it is refused before any of it is computed (running out of memory part-way would
  // take ParaView down with it).
  hair::StorageOptions storage;
  storage.stateFile = this->StateFileName;
  // A file this filter wrote itself is its own to replace when it runs again (a property
  // changed); any other existing state file only with Overwrite State File.
  storage.replaceStateFile = this->OverwriteStateFile || this->StateFileName == in.Written;
  storage.memoryBudget =
      this->MemoryBudget > 0 ? this->MemoryBudget * 1048576.0 : 0.5 * hair::physicalMemoryBytes();
  storage.frames = frameCount(this->Duration, this->FrameRate);
  storage.resume = this->Resume;
  const hair::Status started = in.Sim.initialize(guides, scene, o, storage);
  if (started && !this->StateFileName.empty())
  {
    in.Written = this->StateFileName;
  }
  if (started)
  {
    this->WarnGroom();
  }
  if (hair::Status s = started; !s)
  {
    const bool memory = s.message().find("of memory") != std::string::npos;
    vtkErrorMacro(<< "Hair Simulation: " << s.message()
                  << (memory ? std::string(" (Frames: Duration × Frame Rate + 1; the budget: ") +
                                   (this->MemoryBudget > 0
                                        ? "Memory Budget"
                                        : "half of this machine's memory, or Memory Budget") +
                                   "; the state file: State File Name.)"
                             : std::string()));
    return false;
  }
  return true;
}

void vtkHairSimulation::WarnGroom()
{
  // Sag-free strands whose shape no natural shape can hold start in the closest stable shape:
  // each named with the reason (the output's RestShapeStatus, GroomDeviation and Stability
  // cell arrays carry them all).
  const std::vector<hair::GroomReport>& reports = this->Internal->Sim.groomReports();
  // Grown strands that entered the body start draped over it (the projective model).
  std::size_t draped = 0;
  double moved = 0;
  for (const hair::GroomReport& r : reports)
  {
    draped += r.drape > 0;
    moved = std::max(moved, r.drape);
  }
  if (draped > 0)
  {
    vtkWarningMacro(<< "Hair Simulation: " << draped << " of " << reports.size()
                    << " grown strands entered the body's tables and start draped over it "
                       "(moved up to "
                    << 1e3 * moved << " mm; their rest shape is the grown one).");
  }
  std::vector<std::size_t> notHeld;
  for (std::size_t k = 0; k < reports.size(); ++k)
  {
    if (reports[k].outcome == hair::RestOutcome::Unstable ||
        reports[k].outcome == hair::RestOutcome::BeyondBending)
    {
      notHeld.push_back(k);
    }
  }
  if (notHeld.empty())
  {
    return;
  }
  std::ostringstream m;
  m << "Hair Simulation: " << notHeld.size() << " of " << reports.size()
    << " strands cannot be held in their shape at t = 0 by any natural shape; each starts in "
       "the closest stable shape instead (cell arrays RestShapeStatus, GroomDeviation):";
  const std::size_t shown = 10;
  for (std::size_t i = 0; i < notHeld.size() && i < shown; ++i)
  {
    m << "\n  strand " << notHeld[i] << ": " << reports[notHeld[i]].reason << ".";
  }
  if (notHeld.size() > shown)
  {
    m << "\n  and " << notHeld.size() - shown << " more.";
  }
  vtkWarningMacro(<< m.str());
}
