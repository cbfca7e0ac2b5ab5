#include "vtkHairSimulation.h"

#include "HairConversion.h"
#include "io/StateFile.h"
#include "simulation/Simulation.h"

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
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTable.h>

#include <cmath>
#include <limits>
#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

vtkStandardNewMacro(vtkHairSimulation);

struct vtkHairSimulation::Internals
{
  hair::Simulation Sim;
  bool Initialized = false;
  vtkMTimeType BuiltAt = 0; ///< max MTime of this filter and its inputs when Sim was built
  hair::StateFileWriter Writer;
  std::string WrittenTo;
  /// Frames kept in memory with their arrays: all of them when the run fits in the memory
  /// budget; otherwise (with a state file) the newest Window, older ones read back from it.
  int Window = std::numeric_limits<int>::max();
};

vtkHairSimulation::vtkHairSimulation()
    : QuadratureTolerance(hair::QuadratureChooser::defaultTolerance()),
      Internal(std::make_unique<Internals>())
{
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
  os << indent << "Model: " << (this->Model == SUPER_HELIX ? "Super-Helix" : "Projective") << "\n"
     << indent << "TimeStep: " << this->TimeStep << "\n"
     << indent << "Duration: " << this->Duration << "\n"
     << indent << "FrameRate: " << this->FrameRate << "\n"
     << indent << "Gravity: " << this->Gravity[0] << " " << this->Gravity[1] << " "
     << this->Gravity[2] << "\n"
     << indent << "Wind: " << this->Wind[0] << " " << this->Wind[1] << " " << this->Wind[2] << "\n"
     << indent << "BodyMotion: " << this->BodyMotion << " amplitude " << this->MotionAmplitude
     << " frequency " << this->MotionFrequency << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "QuadratureTolerance: " << this->QuadratureTolerance << "\n"
     << indent << "Contacts: " << (this->Contacts ? "on" : "off") << " stiffness "
     << this->ContactStiffness << " damping " << this->ContactDamping << " friction "
     << this->FrictionCoefficient << " anisotropy " << this->FrictionAnisotropy << " thickness "
     << this->ContactThickness << " slip velocity " << this->SlipVelocity << "\n"
     << indent << "Hair-hair contacts: " << (this->HairHairContacts ? "on" : "off") << " thickness "
     << this->HairContactThickness << " stiffness " << this->HairContactStiffness << " damping "
     << this->HairContactDamping << " friction " << this->HairContactFriction << " per length "
     << (this->HairContactPerLength ? "on" : "off") << "\n"
     << indent << "StateFileName: " << this->StateFileName << "\n";
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

int vtkHairSimulation::RequestInformation(vtkInformation*, vtkInformationVector**,
                                          vtkInformationVector* outputVector)
{
  const double interval = 1.0 / this->FrameRate;
  const int frames = static_cast<int>(std::floor(this->Duration / interval + 1e-9)) + 1;
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

namespace
{
/// Hair Strands' polylines and cell arrays -> guide strands.
hair::Status toGuides(vtkPolyData* input, std::vector<hair::GuideStrand>& guides)
{
  if (!input || input->GetNumberOfLines() == 0)
  {
    return hair::Status::Error("the strands input has no polylines: connect Hair Strands.");
  }
  vtkCellData* cd = input->GetCellData();
  const char* required[] = {"RootNormal",  "GrowthDirection",    "Length",       "NumberOfElements",
                            "Radius",      "Ellipticity",        "YoungModulus", "PoissonRatio",
                            "Density",     "HelixRadius",        "HelixStep",    "InternalFriction",
                            "AirFriction", "CurvatureVariation", "Seed"};
  for (const char* name : required)
  {
    if (!cd->GetArray(name))
    {
      return hair::Status::Error(std::string("the strands input lacks the cell array '") + name +
                                 "': make the strands with Hair Strands.");
    }
  }
  auto value = [cd](const char* name, vtkIdType c) { return cd->GetArray(name)->GetTuple1(c); };
  vtkCellArray* lines = input->GetLines();
  vtkNew<vtkIdList> ids;
  vtkIdType cell = input->GetNumberOfVerts();
  guides.clear();
  for (lines->InitTraversal(); lines->GetNextCell(ids); ++cell)
  {
    hair::GuideStrand g;
    input->GetPoint(ids->GetId(0), g.root.data());
    cd->GetArray("RootNormal")->GetTuple(cell, g.normal.data());
    cd->GetArray("GrowthDirection")->GetTuple(cell, g.growth.data());
    g.length = value("Length", cell);
    g.elements = static_cast<int>(value("NumberOfElements", cell));
    g.hair.radius = value("Radius", cell);
    g.hair.ellipticity = value("Ellipticity", cell);
    g.hair.youngModulus = value("YoungModulus", cell);
    g.hair.poissonRatio = value("PoissonRatio", cell);
    g.hair.density = value("Density", cell);
    g.hair.helixRadius = value("HelixRadius", cell);
    g.hair.helixStep = value("HelixStep", cell);
    g.hair.internalFriction = value("InternalFriction", cell);
    g.hair.airFriction = value("AirFriction", cell);
    g.hair.curvatureVariation = value("CurvatureVariation", cell);
    g.seed = static_cast<std::uint32_t>(value("Seed", cell));
    guides.push_back(g);
  }
  return hair::Status::Ok();
}
} // namespace

namespace
{
/// The machine's physical memory in bytes (infinite where it cannot be asked).
double physicalMemoryBytes()
{
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
  if (pages > 0 && size > 0)
  {
    return double(pages) * double(size);
  }
#endif
  return std::numeric_limits<double>::infinity();
}
} // namespace

int vtkHairSimulation::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                   vtkInformationVector* outputVector)
{
  Internals& in = *this->Internal;
  vtkPolyData* strandsIn = vtkPolyData::GetData(inputVector[0], 0);

  // Under MPI (pvbatch), rank 0 simulates every strand and writes the state file; the other
  // ranks hold no strands (one writer per file; splitting strands across ranks is to come).
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1 && controller->GetLocalProcessId() > 0)
  {
    vtkPolyData::GetData(outputVector, 0)->Initialize();
    vtkTable::GetData(outputVector, 1)->Initialize();
    return 1;
  }

  // (Re)build the scene when a property or an input changed since it was built.
  vtkMTimeType mtime = this->GetMTime();
  mtime = std::max(mtime, strandsIn ? strandsIn->GetMTime() : 0);
  for (int i = 0; i < inputVector[1]->GetNumberOfInformationObjects(); ++i)
  {
    vtkImageData* t = vtkImageData::GetData(inputVector[1], i);
    mtime = std::max(mtime, t ? t->GetMTime() : 0);
  }
  if (!in.Initialized || mtime > in.BuiltAt)
  {
    in.Initialized = false;
    in.Writer.close();
    std::vector<hair::GuideStrand> guides;
    if (hair::Status s = toGuides(strandsIn, guides); !s)
    {
      vtkErrorMacro(<< "Hair Simulation: " << s.message());
      return 0;
    }
    std::vector<hair::SimulationPart> parts;
    for (int i = 0; i < inputVector[1]->GetNumberOfInformationObjects(); ++i)
    {
      hair::SimulationPart p;
      std::string name;
      if (hair::Status s = hair::convert::fromImage(vtkImageData::GetData(inputVector[1], i),
                                                    p.part.table, &name, &p.movesWithHead);
          !s)
      {
        vtkErrorMacro(<< "Hair Simulation: collision table " << i << ": " << s.message());
        return 0;
      }
      p.part.name = name.empty() ? "part " + std::to_string(i) : name;
      parts.push_back(std::move(p));
    }
    hair::SimulationOptions o;
    o.model =
        this->Model == PROJECTIVE ? hair::StrandModel::Projective : hair::StrandModel::SuperHelix;
    o.timeStep = this->TimeStep;
    o.frameInterval = 1.0 / this->FrameRate;
    o.gravity = Eigen::Vector3d(this->Gravity);
    o.wind = Eigen::Vector3d(this->Wind);
    o.threads = this->NumberOfThreads;
    o.quadratureTolerance = this->QuadratureTolerance;
    o.motion.kind = static_cast<hair::HeadMotion::Kind>(this->BodyMotion);
    o.motion.amplitude = this->MotionAmplitude;
    o.motion.frequency = this->MotionFrequency;
    o.motion.axis = Eigen::Vector3d(this->MotionAxis);
    o.motion.pivot = Eigen::Vector3d(this->MotionPivot);
    o.contacts.enabled = this->Contacts;
    o.contacts.stiffness = this->ContactStiffness;
    o.contacts.dampingRatio = this->ContactDamping;
    o.contacts.friction = this->FrictionCoefficient;
    o.contacts.anisotropy = this->FrictionAnisotropy;
    o.contacts.thickness = this->ContactThickness;
    o.hairHairEnabled = this->HairHairContacts;
    o.hairHair.thickness = this->HairContactThickness;
    o.hairHair.stiffness = this->HairContactStiffness;
    o.hairHair.damping = this->HairContactDamping;
    o.hairHair.friction = this->HairContactFriction;
    o.hairHair.perLength = this->HairContactPerLength;
    o.contacts.slipVelocity = this->SlipVelocity;
    if (hair::Status s = in.Sim.initialize(guides, parts, o); !s)
    {
      vtkErrorMacro(<< "Hair Simulation: " << s.message());
      return 0;
    }
    // Frames stay in memory while the run fits in the budget. A longer run with a state file
    // keeps only the newest frames' arrays (the others are read back from the file); without
    // one it is refused before any of it is computed (running out of memory part-way would
    // take ParaView down with it).
    const int frames =
        static_cast<int>(std::floor(this->Duration / (1.0 / this->FrameRate) + 1e-9)) + 1;
    const double budget =
        this->MemoryBudget > 0 ? this->MemoryBudget * 1048576.0 : 0.5 * physicalMemoryBytes();
    const std::string budgetText =
        this->MemoryBudget > 0
            ? " The budget is Memory Budget."
            : " The budget is half of this machine's memory; Memory Budget sets another.";
    in.Window = std::numeric_limits<int>::max();
    if (hair::Status s = in.Sim.checkMemory(frames, budget); !s)
    {
      const double window = std::floor(budget / std::max(in.Sim.bytesPerFrame(), 1.0));
      if (this->StateFileName.empty() || window < 2)
      {
        vtkErrorMacro(<< "Hair Simulation: " << s.message()
                      << (this->StateFileName.empty()
                              ? " Or set State File Name: the frames beyond the budget are then "
                                "kept in the file only, and read back from it when asked for."
                              : " Even streaming to the state file needs two frames in memory.")
                      << budgetText);
        return 0;
      }
      in.Window = static_cast<int>(std::min(window, double(frames)));
    }
    if (!this->StateFileName.empty())
    {
      hair::Status s =
          in.Writer.create(this->StateFileName, in.Sim.header(), in.Sim.extraEnergyTerms());
      s = s ? in.Writer.append(in.Sim.frame(0)) : s;
      if (!s)
      {
        vtkErrorMacro(<< "Hair Simulation: " << s.message());
        return 0;
      }
    }
    in.Initialized = true;
    in.BuiltAt = mtime;
  }

  // The frame of the requested time; computing forward from the last cached frame.
  const double interval = 1.0 / this->FrameRate;
  int index = 0;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    index = static_cast<int>(std::lround(std::max(0.0, t) / interval));
  }
  const int last = static_cast<int>(std::floor(this->Duration / interval + 1e-9));
  index = std::min(index, last);
  // Frame by frame, each written (and flushed) as soon as it exists, so that a run that is
  // killed or aborted keeps everything computed before.
  const int before = in.Sim.numberOfFrames();
  for (int f = before; f <= index; ++f)
  {
    const hair::Status s = in.Sim.advanceTo(f + 1);
    if (!s)
    {
      vtkErrorMacro(<< "Hair Simulation: " << s.message());
      return 0;
    }
    if (in.Writer.isOpen())
    {
      if (hair::Status w = in.Writer.append(in.Sim.frame(f)); !w)
      {
        vtkErrorMacro(<< "Hair Simulation: " << w.message());
        in.Writer.close();
      }
    }
    if (in.Window < std::numeric_limits<int>::max())
    {
      // Streaming: the frame leaving the window is in the file (written in order), so its
      // arrays can go. A file that failed cannot take them: stop rather than lose frames.
      if (!in.Writer.isOpen())
      {
        vtkErrorMacro(<< "Hair Simulation: the state file " << this->StateFileName
                      << " can no longer be written, and this run does not fit in memory "
                         "without it; stopped at t = "
                      << in.Sim.frame(f).time << " s (the frames before it are in the file).");
        return 0;
      }
      in.Sim.releaseFrameData(f - in.Window);
    }
    this->UpdateProgress(double(f - before + 1) / (index - before + 1));
    if (this->GetAbortExecute())
    {
      vtkWarningMacro(<< "Hair Simulation: aborted at t = " << in.Sim.frame(f).time
                      << " s; the frames computed so far are kept.");
      index = f;
      break;
    }
  }
  // A frame that left the streaming window is read back from the state file (opened for
  // each such request: the file grows while the run goes on).
  hair::StateFrame fromFile;
  if (!in.Sim.hasFrameData(index))
  {
    hair::StateFileReader reader;
    hair::Status s = reader.open(this->StateFileName);
    s = s ? reader.readFrame(index, fromFile) : s;
    if (!s)
    {
      vtkErrorMacro(<< "Hair Simulation: frame " << index << " (t = " << in.Sim.frame(index).time
                    << " s) is no longer in memory and could not be read back from "
                    << this->StateFileName << ": " << s.message());
      return 0;
    }
  }
  const hair::StateFrame& frame = in.Sim.hasFrameData(index) ? in.Sim.frame(index) : fromFile;
  vtkPolyData* strandsOut = vtkPolyData::GetData(outputVector, 0);
  hair::convert::toStrands(in.Sim.header(), frame, strandsOut);
  strandsOut->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frame.time);

  // Energy and contacts of every frame computed so far.
  std::vector<double> times;
  std::map<std::string, std::vector<double>> energies;
  for (int f = 0; f < in.Sim.numberOfFrames(); ++f)
  {
    times.push_back(in.Sim.frame(f).time);
    for (const auto& [name, value] : in.Sim.frame(f).energy)
    {
      energies[name].push_back(value);
    }
    energies["nodes_inside"].push_back(static_cast<double>(in.Sim.contacts()[f]));
    energies["max_depth"].push_back(in.Sim.maxDepth()[f]);
  }
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  hair::convert::toEnergyTable(times, energies, table);
  table->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frame.time);
  return 1;
}
