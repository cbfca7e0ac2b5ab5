#include "vtkHairInterpolation.h"

#include "HairConversion.h"
#include "render/HairInterpolation.h"

#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include <string>
#include <vector>

vtkStandardNewMacro(vtkHairInterpolation);

struct vtkHairInterpolation::Internals
{
  hair::HairInterpolation Hair;
  // What the binding was made from: rebound when a property, the scalp or the guides as
  // grown change (the guides' curves change every frame and are not part of it).
  vtkMTimeType BoundAt = 0;
  std::vector<hair::GuideStrand> Rest;
  // The tables as read, rebuilt when an input changes.
  std::vector<hair::CollisionTable> Tables;
  std::vector<bool> MovesWithHead;
  vtkMTimeType TablesAt = 0;
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

  std::vector<hair::GuideStrand> rest;
  hair::GuideCurves curves;
  if (hair::Status s = hair::convert::toGuideCurves(guidesIn, rest, curves); !s)
  {
    vtkErrorMacro(<< "Hair Interpolation: input 0 (the guides): " << s.message());
    return 0;
  }
  const vtkMTimeType bindTime = std::max(this->GetMTime(), scalpIn ? scalpIn->GetMTime() : 0);
  if (!in.Hair.isBound() || bindTime > in.BoundAt || !sameRest(rest, in.Rest))
  {
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
    if (hair::Status s = in.Hair.bind(rest, scalp, o); !s)
    {
      vtkErrorMacro(<< "Hair Interpolation: " << s.message());
      return 0;
    }
    in.BoundAt = bindTime;
    in.Rest = rest;
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

  hair::RenderedHair rendered;
  const hair::Status s = in.Hair.evaluate(curves, parts, rendered,
                                          [this](double f)
                                          {
                                            this->UpdateProgress(f);
                                            return !this->GetAbortExecute();
                                          });
  if (!s)
  {
    vtkErrorMacro(<< "Hair Interpolation: " << s.message());
    return 0;
  }
  hair::convert::fromRenderedHair(rendered, output);
  return 1;
}
