#include "vtkHairStrands.h"

#include "HairConversion.h"
#include "strands/BundledBody.h"
#include "strands/GuideGrowth.h"
#include "strands/HairParameters.h"
#include "strands/RootSampling.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <Eigen/Geometry>

#include <cmath>

vtkStandardNewMacro(vtkHairStrands);

vtkHairStrands::vtkHairStrands() = default;

void vtkHairStrands::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfStrands: " << this->NumberOfStrands << "\n"
     << indent << "StrandLength: " << this->StrandLength << "\n"
     << indent << "NumberOfElements: " << this->NumberOfElements << "\n"
     << indent << "HairType: " << this->HairType << "\n"
     << indent << "Seed: " << this->Seed << "\n"
     << indent << "Region: " << this->Region << " (" << this->RegionArray << ", "
     << this->RegionRange[0] << " .. " << this->RegionRange[1] << ")\n"
     << indent << "Growth: " << this->Growth << ", CombDirection " << this->CombDirection[0] << " "
     << this->CombDirection[1] << " " << this->CombDirection[2] << ", CombWeight "
     << this->CombWeight << "\n"
     << indent << "Custom: radius " << this->Radius << ", ellipticity " << this->Ellipticity
     << ", E " << this->YoungModulus << ", Poisson " << this->PoissonRatio << ", density "
     << this->Density << ", helix " << this->HelixRadius << " / " << this->HelixStep << ", gamma "
     << this->InternalFriction << ", nu " << this->AirFriction << ", variation "
     << this->CurvatureVariation << "\n";
}

int vtkHairStrands::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector*)
{
  // Roots are spread over the whole scalp: every process samples the same whole surface.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  return 1;
}

namespace
{
/// Triangles whose three points pass `keep`.
template <typename Keep>
std::vector<std::uint8_t> byPoints(const hair::TriangleMesh& mesh, Keep keep)
{
  std::vector<std::uint8_t> region(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
  {
    const auto& tri = mesh.triangles[t];
    region[t] = keep(tri[0]) && keep(tri[1]) && keep(tri[2]);
  }
  return region;
}
} // namespace

int vtkHairStrands::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);

  // Hair parameters: a preset or every value given.
  hair::HairParameters params;
  if (this->HairType == CUSTOM)
  {
    params.radius = this->Radius;
    params.ellipticity = this->Ellipticity;
    params.youngModulus = this->YoungModulus;
    params.poissonRatio = this->PoissonRatio;
    params.density = this->Density;
    params.helixRadius = this->HelixRadius;
    params.helixStep = this->HelixStep;
    params.internalFriction = this->InternalFriction;
    params.airFriction = this->AirFriction;
    params.curvatureVariation = this->CurvatureVariation;
  }
  else
  {
    params = hair::HairParameters::preset(static_cast<hair::HairType>(this->HairType));
  }
  if (hair::Status s = params.validate(); !s)
  {
    vtkErrorMacro(<< "Hair Strands: " << s.message());
    return 0;
  }

  // Every property checked before any work (hair::GrowthOptions::validate, the same ranges
  // as the XML's domains).
  hair::GrowthOptions grow;
  grow.length = this->StrandLength;
  grow.elements = this->NumberOfElements;
  grow.combed = this->Growth == COMB;
  grow.combDirection = Eigen::Vector3d(this->CombDirection);
  grow.combWeight = this->CombWeight;
  grow.hair = params;
  grow.seed = static_cast<std::uint32_t>(this->Seed);
  if (hair::Status s = grow.validate(); !s)
  {
    vtkErrorMacro(<< "Hair Strands: " << s.message());
    return 0;
  }

  // Roots: one per input point (a point set with normals), or spread over the surface.
  std::vector<hair::Root> roots;
  if (input && input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0 &&
      input->GetNumberOfPoints() > 0)
  {
    vtkDataArray* normals = input->GetPointData()->GetNormals();
    if (!normals)
    {
      vtkErrorMacro(<< "Hair Strands: the input has points but no polygons and no point "
                       "normals: give a surface, or points with a Normals array (one strand "
                       "grows from each point along its normal).");
      return 0;
    }
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
    {
      hair::Root r;
      input->GetPoint(i, r.position.data());
      normals->GetTuple(i, r.normal.data());
      if (!r.position.allFinite() || !r.normal.allFinite() || r.normal.norm() == 0)
      {
        vtkErrorMacro(<< "Hair Strands: input point " << i
                      << " has a NaN coordinate or a zero or NaN normal; fix or remove it.");
        return 0;
      }
      r.normal.normalize();
      roots.push_back(r);
    }
  }
  else
  {
    hair::TriangleMesh mesh;
    if (hair::Status s = hair::convert::toTriangleMesh(input, "the scalp surface", mesh); !s)
    {
      vtkErrorMacro(<< "Hair Strands: " << s.message());
      return 0;
    }
    std::vector<std::uint8_t> region;
    if (this->Region == AUTOMATIC_SCALP)
    {
      if (hair::bundled::isBundledBody(mesh))
      {
        region = hair::bundled::scalp(mesh);
      }
      else
      {
        vtkWarningMacro(<< "Hair Strands: the automatic scalp is that of the bundled body "
                           "(Data/body.vtk); this mesh is another, so roots cover the whole "
                           "surface. Choose a point mask or a scalar range to restrict them.");
      }
    }
    else if (this->Region == POINT_MASK || this->Region == SCALAR_RANGE)
    {
      vtkDataArray* a = input->GetPointData()->GetArray(this->RegionArray.c_str());
      if (!a || a->GetNumberOfComponents() != 1)
      {
        vtkErrorMacro(<< "Hair Strands: the region array '" << this->RegionArray
                      << "' is not a one-component point array of the input: name one of its "
                         "point arrays in Region Array.");
        return 0;
      }
      // toTriangleMesh keeps the input's point ids (vtkTriangleFilter passes points through).
      if (a->GetNumberOfTuples() != static_cast<vtkIdType>(mesh.points.size()))
      {
        vtkErrorMacro(<< "Hair Strands: the region array does not have one value per point.");
        return 0;
      }
      const double lo = this->RegionRange[0], hi = this->RegionRange[1];
      region = this->Region == POINT_MASK
                   ? byPoints(mesh, [a](int i) { return a->GetTuple1(i) != 0; })
                   : byPoints(mesh, [a, lo, hi](int i)
                              { return a->GetTuple1(i) >= lo && a->GetTuple1(i) <= hi; });
    }
    hair::RootSamplingOptions options;
    options.count = this->NumberOfStrands;
    options.seed = static_cast<std::uint32_t>(this->Seed);
    if (hair::Status s = hair::sampleRoots(mesh, region, options, roots); !s)
    {
      vtkErrorMacro(<< "Hair Strands: " << s.message());
      return 0;
    }
    // Normals face out of the solid: flip them all if the mesh's triangles face inwards.
    if (mesh.signedVolume() < 0)
    {
      for (hair::Root& r : roots)
      {
        r.normal = -r.normal;
      }
    }
  }

  // Straight strands along the growth direction.
  std::vector<hair::GuideStrand> guides;
  if (hair::Status s = hair::growGuides(roots, grow, guides); !s)
  {
    vtkErrorMacro(<< "Hair Strands: " << s.message());
    return 0;
  }
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  for (const hair::GuideStrand& g : guides)
  {
    polylines.push_back(hair::grownPolyline(g));
  }
  hair::convert::fromGuides(guides, polylines, output);
  vtkNew<vtkIntArray> type; // for display: the preset (or Custom) the strands were grown with
  type->SetName("HairType");
  type->SetNumberOfTuples(static_cast<vtkIdType>(guides.size()));
  type->Fill(this->HairType);
  output->GetCellData()->AddArray(type);
  return 1;
}
