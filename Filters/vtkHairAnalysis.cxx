#include "vtkHairAnalysis.h"

#include "vtkHairAnalysisExecutive.h"

#include "HairConversion.h"
#include "analysis/StrandAnalysis.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkHairAnalysis);

namespace
{
/// Whether column `name` of an Energy table is an energy term: one its field data
/// "EnergyTerms" names (Hair Simulation's and Hair State Reader's tables say which; the
/// penetration and a model's step statistics are not, and are not in a state file); a table
/// without that list: every column but Time.
bool isEnergyColumn(vtkTable* table, const std::string& name)
{
  auto* terms =
      vtkStringArray::SafeDownCast(table->GetFieldData()->GetAbstractArray("EnergyTerms"));
  if (!terms)
  {
    return name != "Time";
  }
  return terms->LookupValue(name) >= 0;
}
} // namespace

struct vtkHairAnalysis::Internals
{
  /// Under MPI, the ranks of ParaView's controller (made at the first request); this
  /// process alone otherwise.
  hair::Ranks Ranks;
  bool HaveRanks = false;
  std::vector<double> Times; ///< the input's TIME_STEPS
  int Current = 0;           ///< index into Times of the frame the loop is at
  hair::StrandAnalysis Analysis;
  /// The columns, filled one row per frame; Order keeps the columns' order.
  std::vector<std::string> Order;
  std::map<std::string, std::vector<double>> Columns;
  std::vector<std::string> EnergyNames; ///< fixed by the first frame

  void add(const std::string& name, double value)
  {
    auto [it, inserted] = Columns.try_emplace(name);
    if (inserted)
    {
      Order.push_back(name);
    }
    it->second.push_back(value);
  }
  void clear()
  {
    Order.clear();
    Columns.clear();
    EnergyNames.clear();
  }
};

vtkHairAnalysis::vtkHairAnalysis() : Internal(std::make_unique<Internals>())
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

vtkHairAnalysis::~vtkHairAnalysis() = default;

vtkExecutive* vtkHairAnalysis::CreateDefaultExecutive()
{
  return vtkHairAnalysisExecutive::New();
}

void vtkHairAnalysis::InputFailed()
{
  Internals& in = *this->Internal;
  const double t = in.Current < static_cast<int>(in.Times.size()) ? in.Times[in.Current] : 0;
  vtkErrorMacro(<< "Hair Analysis: the input failed at t = " << t << " s (frame " << in.Current
                << " of " << in.Times.size() << "; see its error); the table is left empty.");
  in.Current = 0;
  in.clear();
  if (vtkTable* output = vtkTable::SafeDownCast(this->GetOutputDataObject(0)))
  {
    output->Initialize();
  }
}

void vtkHairAnalysis::AddTrackedStrand(int id)
{
  this->TrackedStrands.push_back(id);
  this->Modified();
}

void vtkHairAnalysis::RemoveAllTrackedStrands()
{
  if (!this->TrackedStrands.empty())
  {
    this->TrackedStrands.clear();
    this->Modified();
  }
}

void vtkHairAnalysis::AddGroupStrand(int id)
{
  this->GroupStrands.push_back(id);
  this->Modified();
}

void vtkHairAnalysis::RemoveAllGroupStrands()
{
  if (!this->GroupStrands.empty())
  {
    this->GroupStrands.clear();
    this->Modified();
  }
}

void vtkHairAnalysis::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TrackedStrands:";
  for (int id : this->TrackedStrands)
  {
    os << " " << id;
  }
  os << "\n" << indent << "GroupStrands:";
  for (int id : this->GroupStrands)
  {
    os << " " << id;
  }
  if (this->GroupStrands.empty())
  {
    os << " (every strand)";
  }
  os << "\n"
     << indent << "Vertical: " << this->Vertical[0] << " " << this->Vertical[1] << " "
     << this->Vertical[2] << "\n";
}

int vtkHairAnalysis::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkHairAnalysis::RequestInformation(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  Internals& in = *this->Internal;
  in.Times.clear();
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()))
  {
    const double* t = inInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    in.Times.assign(t, t + inInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  }
  // The table covers every time at once: it does not vary with the time a view shows.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  // Under MPI every rank measures its piece (and takes part in the reductions).
  outInfo->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkHairAnalysis::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                         vtkInformationVector*)
{
  const Internals& in = *this->Internal;
  if (in.Current >= static_cast<int>(in.Times.size()))
  {
    return 1;
  }
  const double t = in.Times[in.Current];
  for (int port = 0; port < 2; ++port)
  {
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      inputVector[port]->GetInformationObject(i)->Set(
          vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP(), t);
    }
  }
  return 1;
}

namespace
{
const char* const Source = "connect output 0 (Strands) of Hair Simulation or Hair State Reader";

/// The strands' polylines and point arrays -> a Core frame, each strand numbered by its
/// StrandId. `piece`: one rank's piece under MPI, which may have no strand.
hair::Status toFrame(vtkPolyData* input, hair::StrandsFrame& frame, bool piece)
{
  frame = hair::StrandsFrame();
  if (piece && input && input->GetNumberOfLines() == 0)
  {
    return hair::Status::Ok();
  }
  if (!input || input->GetNumberOfLines() == 0)
  {
    return hair::Status::Error(std::string("the input has no polylines: ") + Source + ".");
  }
  vtkPointData* pd = input->GetPointData();
  const char* pointArrays[] = {"curvature", "twist", "contact_depth"};
  vtkDataArray* arrays[3];
  for (int a = 0; a < 3; ++a)
  {
    arrays[a] = pd->GetArray(pointArrays[a]);
    if (!arrays[a])
    {
      return hair::Status::Error(
          std::string("the input lacks the point array '") + pointArrays[a] +
          "': Hair Simulation's output 0 has it, and so does Hair State Reader's when the "
          "state file has /frames/" +
          pointArrays[a] + " (files written by Hair Simulation do).");
    }
  }
  vtkDataArray* strandIds = input->GetCellData()->GetArray("StrandId");
  if (!strandIds)
  {
    return hair::Status::Error(std::string("the input lacks the cell array 'StrandId': ") + Source +
                               ".");
  }
  frame.offsets.push_back(0);
  vtkCellArray* lines = input->GetLines();
  vtkNew<vtkIdList> points;
  // Ghost strands (another rank's, which a downstream filter asked for) are measured there.
  vtkDataArray* ghosts = input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  vtkIdType cell = input->GetNumberOfVerts(); // cells are numbered verts first, then lines
  for (lines->InitTraversal(); lines->GetNextCell(points); ++cell)
  {
    if (ghosts && (int(ghosts->GetComponent(cell, 0)) & vtkDataSetAttributes::DUPLICATECELL))
    {
      continue;
    }
    for (vtkIdType i = 0; i < points->GetNumberOfIds(); ++i)
    {
      const vtkIdType p = points->GetId(i);
      Eigen::Vector3d x;
      input->GetPoint(p, x.data());
      frame.positions.push_back(x);
      frame.curvature.push_back(arrays[0]->GetComponent(p, 0));
      frame.twist.push_back(arrays[1]->GetComponent(p, 0));
      frame.contactDepth.push_back(arrays[2]->GetComponent(p, 0));
    }
    frame.offsets.push_back(static_cast<std::int64_t>(frame.positions.size()));
    frame.ids.push_back(static_cast<std::int64_t>(strandIds->GetComponent(cell, 0)));
  }
  return hair::Status::Ok();
}

/// The StrandIds the property `what` names, each checked to be in the input (under MPI: in
/// some rank's piece; collective).
hair::Status toIds(const std::vector<int>& wanted, const hair::StrandsFrame& frame,
                   const char* what, const hair::Ranks& ranks, std::vector<std::int64_t>& out)
{
  out.assign(wanted.begin(), wanted.end());
  const std::vector<std::int64_t>& ids = frame.ids;
  std::vector<double> found(wanted.size(), 0);
  for (std::size_t i = 0; i < wanted.size(); ++i)
  {
    found[i] = std::find(ids.begin(), ids.end(), wanted[i]) != ids.end() ? 1 : 0;
  }
  double range[2] = {ids.empty() ? HUGE_VAL : double(*std::min_element(ids.begin(), ids.end())),
                     ids.empty() ? HUGE_VAL : -double(*std::max_element(ids.begin(), ids.end()))};
  ranks.sum(found.data(), int(found.size()));
  ranks.min(range, 2);
  for (std::size_t i = 0; i < wanted.size(); ++i)
  {
    if (found[i] == 0)
    {
      std::ostringstream os;
      os << what << ": strand " << wanted[i] << " is not in the input (its StrandId values are ";
      if (range[0] != HUGE_VAL)
      {
        os << "among " << std::int64_t(range[0]) << " … " << std::int64_t(-range[1]);
      }
      os << "): give ids of the input's strands.";
      return hair::Status::Error(os.str());
    }
  }
  return hair::Status::Ok();
}
} // namespace

int vtkHairAnalysis::RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                                 vtkInformationVector* outputVector)
{
  Internals& in = *this->Internal;
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  vtkPolyData* strands = vtkPolyData::GetData(inputVector[0], 0);
  // Stops the loop over time; the next request starts from the first frame again.
  auto stop = [&]()
  {
    request->Remove(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING());
    in.Current = 0;
  };
  auto fail = [&](const std::string& message)
  {
    vtkErrorMacro(<< "Hair Analysis: " << message);
    stop();
    in.clear();
    output->Initialize();
    return 0;
  };

  // Under MPI (pvbatch, pvserver) each rank measures its piece of the strands, the measures
  // are the whole frame's (reduced over the ranks by hair::StrandAnalysis), the Energy input
  // is rank 0's, and the table is rank 0's; the ranks stop, fail or go on together.
  if (!in.HaveRanks)
  {
    in.Ranks = hair::convert::toRanks(vtkMultiProcessController::GetGlobalController());
    in.HaveRanks = true;
  }
  const hair::Ranks& ranks = in.Ranks;
  const bool writer = ranks.rank() == 0;
  if (in.Times.empty())
  {
    return fail(std::string("the input reports no time steps: ") + Source + ".");
  }

  hair::StrandsFrame frame;
  if (hair::Status s = ranks.agree(toFrame(strands, frame, ranks.parallel())); !s)
  {
    return fail(s.message());
  }
  if (in.Current == 0)
  {
    in.clear();
    hair::StrandAnalysisOptions o;
    o.vertical = Eigen::Vector3d(this->Vertical);
    hair::Status s = toIds(this->TrackedStrands, frame, "Tracked Strands", ranks, o.tracked);
    s = s ? toIds(this->GroupStrands, frame, "Group", ranks, o.group) : s;
    s = s ? in.Analysis.configure(o) : s;
    if (!s)
    {
      return fail(s.message());
    }
  }
  hair::StrandMeasures m;
  if (hair::Status s = in.Analysis.measure(frame, m, ranks); !s)
  {
    return fail("at t = " + std::to_string(in.Times[in.Current]) + " s: " + s.message());
  }

  const double t = in.Times[in.Current];
  in.add("Time", t);
  // The energy terms: the row of the Energy table at the time of the strands' frame (rank
  // 0's table; its failure is every rank's).
  vtkTable* energy = writer ? vtkTable::GetData(inputVector[1], 0) : nullptr;
  auto energyRow = [&]() -> std::string
  {
    if (!energy)
    {
      if (in.Current > 0 && !in.EnergyNames.empty())
      {
        return "the Energy input went away during the loop over time.";
      }
      return {};
    }
    vtkDataArray* times = vtkArrayDownCast<vtkDataArray>(energy->GetColumnByName("Time"));
    if (!times)
    {
      return "the Energy input has no Time column: connect output 1 (Energy) of the "
             "same Hair Simulation or Hair State Reader as the Input.";
    }
    vtkInformation* dataInfo = strands->GetInformation();
    const double frameTime = dataInfo->Has(vtkDataObject::DATA_TIME_STEP())
                                 ? dataInfo->Get(vtkDataObject::DATA_TIME_STEP())
                                 : t;
    // Both columns come from the same frame record: the times are equal, not close.
    vtkIdType row = 0;
    while (row < times->GetNumberOfTuples() && times->GetComponent(row, 0) != frameTime)
    {
      ++row;
    }
    if (row == times->GetNumberOfTuples())
    {
      std::ostringstream os;
      os.precision(17);
      os << "the Energy input has no row at the strands' time " << frameTime
         << " s: connect output 1 (Energy) of the same Hair Simulation or Hair State Reader "
            "as the Input.";
      return os.str();
    }
    if (in.Current == 0)
    {
      for (vtkIdType c = 0; c < energy->GetNumberOfColumns(); ++c)
      {
        const char* name = energy->GetColumnName(c);
        if (name && isEnergyColumn(energy, name) &&
            vtkArrayDownCast<vtkDataArray>(energy->GetColumn(c)))
        {
          in.EnergyNames.emplace_back(name);
        }
      }
    }
    for (const std::string& name : in.EnergyNames)
    {
      vtkDataArray* column = vtkArrayDownCast<vtkDataArray>(energy->GetColumnByName(name.c_str()));
      if (!column)
      {
        return "the Energy input lost its column '" + name + "' at t = " + std::to_string(t) +
               " s.";
      }
      in.add(name, column->GetComponent(row, 0));
    }
    return {};
  };
  const std::string problem = energyRow();
  if (hair::Status s =
          ranks.agree(problem.empty() ? hair::Status::Ok() : hair::Status::Error(problem));
      !s)
  {
    return fail(s.message());
  }
  in.add("mean_tip_x", m.meanTip.x());
  in.add("mean_tip_y", m.meanTip.y());
  in.add("mean_tip_z", m.meanTip.z());
  for (std::size_t i = 0; i < this->TrackedStrands.size(); ++i)
  {
    const auto first = this->TrackedStrands.begin();
    if (std::find(first, first + i, this->TrackedStrands[i]) != first + i)
    {
      continue; // a strand named twice has its columns once
    }
    const std::string prefix = "tip_" + std::to_string(this->TrackedStrands[i]) + "_";
    in.add(prefix + "x", m.trackedTips[i].x());
    in.add(prefix + "y", m.trackedTips[i].y());
    in.add(prefix + "z", m.trackedTips[i].z());
  }
  in.add("span", m.span);
  in.add("max_curvature", m.maxCurvature);
  in.add("max_twist", m.maxTwist);
  in.add("max_deflection", m.maxDeflection);
  in.add("mean_deflection", m.meanDeflection);
  in.add("max_tip_displacement", m.maxTipDisplacement);
  in.add("mean_tip_displacement", m.meanTipDisplacement);
  in.add("contacts", static_cast<double>(m.contacts));
  in.add("max_contact_depth", m.maxContactDepth);

  ++in.Current;
  const int total = static_cast<int>(in.Times.size());
  this->UpdateProgress(double(in.Current) / total);
  const bool aborted = ranks.any(this->GetAbortExecute() != 0);
  if (in.Current < total && !aborted)
  {
    request->Set(vtkStreamingDemandDrivenPipeline::CONTINUE_EXECUTING(), 1);
    return 1;
  }
  if (aborted)
  {
    vtkWarningMacro(<< "Hair Analysis: aborted after " << in.Current << " of " << total
                    << " frames; the table holds those.");
  }
  stop();
  output->Initialize();
  for (const std::string& name : writer ? in.Order : std::vector<std::string>())
  {
    const std::vector<double>& values = in.Columns[name];
    vtkNew<vtkDoubleArray> column;
    column->SetName(name.c_str());
    column->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      column->SetValue(static_cast<vtkIdType>(i), values[i]);
    }
    output->AddColumn(column);
  }
  in.clear();
  return 1;
}
