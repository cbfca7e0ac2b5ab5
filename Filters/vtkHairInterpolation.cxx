#include "vtkHairInterpolation.h"

#include "HairConversion.h"
#include "render/HairInterpolation.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <string>
#include <vector>

vtkStandardNewMacro(vtkHairInterpolation);

struct vtkHairInterpolation::Internals
{
  hair::HairInterpolation Hair;
  bool Bound = false; ///< bound (under MPI a rank may have no rendered strand to bind)
  /// Under MPI, the ranks of ParaView's controller (made at the first request).
  hair::Ranks Ranks;
  bool HaveRanks = false;
  // What the binding was made from: rebound when a property, the scalp or the guides as
  // grown change (the guides' curves change every frame and are not part of it).
  vtkMTimeType BoundAt = 0;
  std::vector<hair::GuideStrand> Rest;
  // The tables as read, rebuilt when an input changes.
  std::vector<hair::CollisionTable> Tables;
  std::vector<bool> MovesWithHead;
  vtkMTimeType TablesAt = 0;
  /// The output's polylines, shared by every frame while the counts stay.
  vtkSmartPointer<vtkCellArray> Lines;
};

vtkHairInterpolation::vtkHairInterpolation() : Internal(std::make_unique<Internals>())
{
  this->SetNumberOfInputPorts(3);
}

vtkHairInterpolation::~vtkHairInterpolation() = default;

void vtkHairInterpolation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << this->Method << "\n"
     << indent << "NumberOfStrands: " << this->NumberOfStrands << "\n"
     << indent << "PointsPerStrand: " << this->PointsPerStrand << "\n"
     << indent << "ClumpingFromHairType: " << this->ClumpingFromHairType << "\n"
     << indent << "ClumpRange: " << this->ClumpRange[0] << " " << this->ClumpRange[1] << "\n"
     << indent << "ClumpRadius: " << this->ClumpRadius << "\n"
     << indent << "TipDistance: " << this->TipDistance << "\n"
     << indent << "Variation: " << this->Variation << "\n"
     << indent << "Seed: " << this->Seed << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

int vtkHairInterpolation::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port < 2)
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

int vtkHairInterpolation::RequestInformation(vtkInformation*, vtkInformationVector**,
                                             vtkInformationVector* outputVector)
{
  // Under MPI each rank renders the hair of its piece of the guides.
  outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkHairInterpolation::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                              vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
                         ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
                         : 1;
  // The guides: this piece, and under MPI one level of ghost strands (the neighbouring
  // pieces' guides near this one's); the scalp and the tables: whole, on every rank.
  if (vtkInformation* guides = inputVector[0]->GetInformationObject(0))
  {
    guides->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(),
                pieces > 1 ? 1 : 0);
  }
  for (int port = 1; port < 3; ++port)
  {
    for (int i = 0; i < inputVector[port]->GetNumberOfInformationObjects(); ++i)
    {
      vtkInformation* in = inputVector[port]->GetInformationObject(i);
      in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
      in->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
    }
  }
  return 1;
}

namespace
{
bool sameRest(const std::vector<hair::GuideStrand>& a, const std::vector<hair::GuideStrand>& b)
{
  if (a.size() != b.size())
    return false;
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    if (a[k].root != b[k].root || a[k].growth != b[k].growth || a[k].normal != b[k].normal ||
        a[k].length != b[k].length || a[k].hair.helixRadius != b[k].hair.helixRadius ||
        a[k].hair.helixStep != b[k].hair.helixStep)
      return false;
  }
  return true;
}
} // namespace

int vtkHairInterpolation::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                      vtkInformationVector* outputVector)
{
  Internals& in = *this->Internal;
  vtkPolyData* guidesIn = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* scalpIn = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);

  // Under MPI (pvbatch, pvserver) each rank renders the hair rooted nearest its own guides,
  // bound among its guides and their ghosts (the neighbouring pieces' guides near its own,
  // which Hair Simulation adds when asked for a ghost level); every call naming the ranks
  // is made by every rank.
  if (!in.HaveRanks)
  {
    in.Ranks = hair::convert::toRanks(vtkMultiProcessController::GetGlobalController());
    in.HaveRanks = true;
  }
  const hair::Ranks& ranks = in.Ranks;
  std::vector<hair::GuideStrand> rest;
  hair::GuideCurves curves;
  std::vector<std::uint8_t> ghost;
  hair::Status converted = hair::Status::Ok();
  if (!ranks.parallel() || (guidesIn && guidesIn->GetNumberOfLines() > 0))
  {
    converted = hair::convert::toGuideCurves(guidesIn, rest, curves);
    vtkDataArray* ghosts =
        guidesIn ? guidesIn->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName())
                 : nullptr;
    for (std::size_t k = 0; converted && ghosts && k < rest.size(); ++k)
    {
      const vtkIdType cell = guidesIn->GetNumberOfVerts() + vtkIdType(k);
      ghost.push_back(
          (int(ghosts->GetComponent(cell, 0)) & vtkDataSetAttributes::DUPLICATECELL) ? 1 : 0);
    }
  }
  if (hair::Status s = ranks.agree(converted); !s)
  {
    vtkErrorMacro(<< "Hair Interpolation: input 0 (the guides): " << s.message());
    return 0;
  }
  const vtkMTimeType bindTime = std::max(this->GetMTime(), scalpIn ? scalpIn->GetMTime() : 0);
  if (ranks.any(!in.Bound || bindTime > in.BoundAt || !sameRest(rest, in.Rest)))
  {
    in.Bound = false;
    hair::TriangleMesh scalp;
    if (hair::Status s = hair::convert::toTriangleMesh(scalpIn, "input 1 (the scalp)", scalp); !s)
    {
      vtkErrorMacro(<< "Hair Interpolation: " << s.message());
      return 0;
    }
    hair::InterpolationOptions o;
    o.method = this->Method == CLUSTERS ? hair::InterpolationMethod::Clusters
                                        : hair::InterpolationMethod::SemiInterpolation;
    o.strands = this->NumberOfStrands;
    o.pointsPerStrand = this->PointsPerStrand;
    if (!this->ClumpingFromHairType)
    {
      o.clumpStart = this->ClumpRange[0];
      o.clumpEnd = this->ClumpRange[1];
    }
    o.clumpRadius = this->ClumpRadius;
    o.tipDistance = this->TipDistance;
    o.variation = this->Variation;
    o.seed = static_cast<std::uint32_t>(this->Seed);
    o.threads = this->NumberOfThreads;
    if (hair::Status s = in.Hair.bind(rest, scalp, o, ghost, ranks); !s)
    {
      vtkErrorMacro(<< "Hair Interpolation: " << s.message());
      return 0;
    }
    in.Bound = true;
    in.BoundAt = bindTime;
    in.Rest = rest;
  }
  if (!in.Hair.isBound())
  {
    output->Initialize(); // a rank whose piece roots no rendered hair
    return 1;
  }

  // The tables: those that move with the head posed by the guides' roots.
  vtkMTimeType tablesTime = this->GetMTime();
  const int tables = inputVector[2]->GetNumberOfInformationObjects();
  for (int i = 0; i < tables; ++i)
  {
    vtkImageData* t = vtkImageData::GetData(inputVector[2], i);
    tablesTime = std::max(tablesTime, t ? t->GetMTime() : 0);
  }
  if (tablesTime > in.TablesAt || static_cast<int>(in.Tables.size()) != tables)
  {
    in.Tables.assign(tables, hair::CollisionTable());
    in.MovesWithHead.assign(tables, false);
    for (int i = 0; i < tables; ++i)
    {
      bool moves = false;
      if (hair::Status s = hair::convert::fromImage(vtkImageData::GetData(inputVector[2], i),
                                                    in.Tables[i], nullptr, &moves);
          !s)
      {
        vtkErrorMacro(<< "Hair Interpolation: collision table " << i << ": " << s.message());
        in.Tables.clear();
        return 0;
      }
      in.MovesWithHead[i] = moves;
    }
    in.TablesAt = tablesTime;
  }
  std::vector<hair::PosedPart> parts;
  const Eigen::Isometry3d head = in.Hair.rootMotion(curves);
  for (std::size_t i = 0; i < in.Tables.size(); ++i)
  {
    hair::PosedPart p = hair::PosedPart::still(in.Tables[i]);
    if (in.MovesWithHead[i])
    {
      p.pose = head;
    }
    parts.push_back(p);
  }

  // Written straight into the output's arrays.
  std::vector<std::string> scalarNames;
  for (const auto& entry : curves.scalars)
  {
    scalarNames.push_back(entry.first);
  }
  const hair::RenderedHairArrays arrays =
      hair::convert::prepareRenderedHair(output, vtkIdType(in.Hair.strandCount()),
                                         in.Hair.options().pointsPerStrand, scalarNames, in.Lines);
  hair::PushOutCounts counts;
  const hair::Status s = in.Hair.evaluate(curves, parts, arrays, counts,
                                          [this](double f)
                                          {
                                            this->UpdateProgress(f);
                                            return !this->GetAbortExecute();
                                          });
  if (!s)
  {
    output->Initialize();
    vtkErrorMacro(<< "Hair Interpolation: " << s.message());
    return 0;
  }
  hair::convert::addPushOutCounts(counts, output);
  if (ranks.parallel())
  {
    // GuideId: the guide's StrandId, not its place in this piece.
    vtkDataArray* ids = guidesIn->GetCellData()->GetArray("StrandId");
    vtkDataArray* guide = output->GetCellData()->GetArray("GuideId");
    for (vtkIdType r = 0; ids && guide && r < guide->GetNumberOfTuples(); ++r)
    {
      const vtkIdType cell = guidesIn->GetNumberOfVerts() + vtkIdType(guide->GetComponent(r, 0));
      guide->SetComponent(r, 0, ids->GetComponent(cell, 0));
    }
  }
  return 1;
}
