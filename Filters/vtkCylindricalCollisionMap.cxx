#include "vtkCylindricalCollisionMap.h"

#include "HairConversion.h"
#include "collision/CollisionTable.h"

#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTimerLog.h>

#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkCylindricalCollisionMap);

vtkCylindricalCollisionMap::vtkCylindricalCollisionMap()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(2);
}

void vtkCylindricalCollisionMap::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Projection: " << (this->Projection == SPHERICAL ? "spherical" : "cylindrical")
     << "\n";
  os << indent << "AutomaticFrame: " << this->AutomaticFrame << "\n";
  os << indent << "Origin: " << this->Origin[0] << " " << this->Origin[1] << " " << this->Origin[2]
     << "\n";
  os << indent << "Axis: " << this->Axis[0] << " " << this->Axis[1] << " " << this->Axis[2] << "\n";
  os << indent << "ReferenceDirection: " << this->ReferenceDirection[0] << " "
     << this->ReferenceDirection[1] << " " << this->ReferenceDirection[2] << "\n";
  os << indent << "HeightRange: " << this->HeightRange[0] << " " << this->HeightRange[1] << "\n";
  os << indent << "Resolution: " << this->Resolution[0] << " " << this->Resolution[1] << "\n";
  os << indent << "MaximumRadius: " << this->MaximumRadius << "\n";
  os << indent << "BodyPartName: " << this->BodyPartName << "\n";
  os << indent << "MovesWithHead: " << this->MovesWithHead << "\n";
}

int vtkCylindricalCollisionMap::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkPolyData");
  return 1;
}

int vtkCylindricalCollisionMap::RequestInformation(vtkInformation*, vtkInformationVector**,
                                                   vtkInformationVector* outputVector)
{
  // The table is small and whole on every process: downstream simulations need all of it.
  const int extent[6] = {
      0, std::max(this->Resolution[0], 1) - 1, 0, std::max(this->Resolution[1], 1) - 1, 0, 0};
  outputVector->GetInformationObject(0)->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(),
                                             extent, 6);
  return 1;
}

int vtkCylindricalCollisionMap::RequestUpdateExtent(vtkInformation*,
                                                    vtkInformationVector** inputVector,
                                                    vtkInformationVector*)
{
  // Rays need the whole surface: ask every process for all of it (under pvbatch with
  // several ranks each rank builds the same table from the same mesh).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

int vtkCylindricalCollisionMap::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                            vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkImageData* table = vtkImageData::GetData(outputVector, 0);
  vtkPolyData* surface = vtkPolyData::GetData(outputVector, 1);

  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  hair::TriangleMesh mesh;
  if (hair::Status s = hair::convert::toTriangleMesh(input, "the input mesh", mesh); !s)
  {
    vtkErrorMacro(<< s.message());
    return 0;
  }

  hair::TableSpec spec;
  spec.projection =
      this->Projection == SPHERICAL ? hair::Projection::Spherical : hair::Projection::Cylindrical;
  spec.azimuthSamples = this->Resolution[0];
  spec.secondSamples = this->Resolution[1];
  // 0 means no limit; a negative or NaN radius is refused by the spec's validation.
  spec.maxRadius =
      this->MaximumRadius == 0 ? std::numeric_limits<double>::infinity() : this->MaximumRadius;
  if (this->AutomaticFrame)
  {
    const auto [lo, hi] = mesh.bounds();
    const Eigen::Vector3d size = hi - lo;
    int a = 0;
    size.maxCoeff(&a);
    spec.frame.origin = 0.5 * (lo + hi);
    spec.frame.axis = Eigen::Vector3d::Unit(a);
    spec.frame.reference = Eigen::Vector3d::Unit((a + 1) % 3);
    // Rays at the very ends of the box would only graze the mesh: keep a tenth of a
    // percent inside.
    const double half = 0.5 * size[a] * 0.999;
    spec.heightMin = -half;
    spec.heightMax = half;
  }
  else
  {
    spec.frame.origin = Eigen::Vector3d(this->Origin);
    spec.frame.axis = Eigen::Vector3d(this->Axis);
    spec.frame.reference = Eigen::Vector3d(this->ReferenceDirection);
    spec.heightMin = this->HeightRange[0];
    spec.heightMax = this->HeightRange[1];
  }
  if (hair::Status s = spec.validate(); !s)
  {
    vtkErrorMacro(<< "Cylindrical Collision Map: " << s.message());
    return 0;
  }
  {
    const auto [lo, hi] = mesh.bounds();
    if (hair::Status s = spec.fitsBody(lo, hi); !s)
    {
      vtkErrorMacro(<< "Cylindrical Collision Map: " << s.message());
      return 0;
    }
  }

  hair::MeshQueries body(mesh);
  if (body.signedVolume() == 0)
  {
    vtkWarningMacro(<< "the input mesh is not a closed surface: which side is inside is then "
                       "taken from the order of its triangles; check the Surface output.");
  }
  hair::CollisionTable result;
  const hair::Status built = result.build(spec, body,
                                          [this](double f)
                                          {
                                            this->UpdateProgress(f);
                                            return !this->GetAbortExecute();
                                          });
  if (!built)
  {
    vtkErrorMacro(<< "Cylindrical Collision Map: " << built.message());
    return 0;
  }
  hair::convert::toImage(result, this->BodyPartName, this->MovesWithHead, table);
  hair::convert::toSurface(result, surface);
  timer->StopTimer();
  vtkLog(INFO, << "Cylindrical Collision Map: table " << spec.azimuthSamples << " x "
               << spec.secondSamples << " from " << mesh.triangles.size() << " triangles, "
               << result.numberOfHits() << " samples hit, " << timer->GetElapsedTime()
               << " s on 1 thread");
  return 1;
}
