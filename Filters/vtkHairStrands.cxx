#include "vtkHairStrands.h"

#include "HairConversion.h"
#include "strands/BundledBody.h"
#include "strands/GuideCurves.h"
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
#include <memory>

vtkStandardNewMacro(vtkHairStrands);

vtkHairStrands::vtkHairStrands()
{
  this->SetNumberOfInputPorts(2);
}

int vtkHairStrands::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

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
     << this->CurvatureVariation << "\n"
     << indent << "RestShape: " << this->RestShape << "\n"
     << indent << "MaximumRootDistance: " << this->MaximumRootDistance << "\n";
}

int vtkHairStrands::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector*)
{
  // Roots are spread over the whole scalp: every process samples the same whole surface (and
  // takes every guide curve).
  for (int port = 0; port < 2; ++port)
  {
    if (vtkInformation* inInfo = inputVector[port]->GetInformationObject(0))
    {
      inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    }
  }
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

  // Guide curves: one groomed guide per curve.
  vtkPolyData* curves = vtkPolyData::GetData(inputVector[1], 0);
  if (curves)
  {
    return this->GuidesFromCurves(input, curves, params, output);
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
  for (hair::GuideStrand& g : guides)
  {
    g.restShape = static_cast<hair::RestShape>(this->RestShape);
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

int vtkHairStrands::GuidesFromCurves(vtkPolyData* surface, vtkPolyData* curvesIn,
                                     const hair::HairParameters& params, vtkPolyData* output)
{
  if (!(this->MaximumRootDistance >= 0 && this->MaximumRootDistance <= 1))
  {
    vtkErrorMacro(<< "Hair Strands: the maximum root distance is " << this->MaximumRootDistance
                  << "; give a distance from 0 to 1 (mesh units).");
    return 0;
  }
  hair::CurveGuideOptions options;
  options.elements = this->NumberOfElements;
  options.hair = params;
  options.seed = static_cast<std::uint32_t>(this->Seed);
  options.restShape = static_cast<hair::RestShape>(this->RestShape);
  options.maxRootDistance = this->MaximumRootDistance;
  if (hair::Status s = options.validate(); !s)
  {
    vtkErrorMacro(<< "Hair Strands: " << s.message());
    return 0;
  }
  std::vector<std::vector<Eigen::Vector3d>> curves;
  std::vector<Eigen::Vector3d> normals;
  if (hair::Status s = hair::convert::toCurves(curvesIn, curves, normals); !s)
  {
    vtkErrorMacro(<< "Hair Strands: " << s.message());
    return 0;
  }
  // The roots go onto the surface of port 0 when it is one (a point set has none).
  std::unique_ptr<hair::MeshQueries> scalp;
  if (surface && surface->GetNumberOfPolys() + surface->GetNumberOfStrips() > 0)
  {
    hair::TriangleMesh mesh;
    if (hair::Status s = hair::convert::toTriangleMesh(surface, "the scalp surface", mesh); !s)
    {
      vtkErrorMacro(<< "Hair Strands: " << s.message());
      return 0;
    }
    scalp = std::make_unique<hair::MeshQueries>(mesh);
  }
  std::vector<hair::GuideStrand> guides;
  std::vector<int> source;
  std::vector<hair::CurveRefusal> refused;
  const hair::Status made =
      hair::guidesFromCurves(curves, normals, scalp.get(), options, guides, source, refused);
  // Each refused curve by name; the others are kept.
  const std::size_t shown = 20;
  for (std::size_t i = 0; i < refused.size() && i < shown; ++i)
  {
    vtkWarningMacro(<< "Hair Strands: " << refused[i].reason << " It is left out.");
  }
  if (refused.size() > shown)
  {
    vtkWarningMacro(<< "Hair Strands: " << refused.size() - shown
                    << " more guide curves are left out for the same kinds of reasons.");
  }
  if (!made)
  {
    vtkErrorMacro(<< "Hair Strands: " << made.message());
    return 0;
  }
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  for (const hair::GuideStrand& g : guides)
  {
    polylines.push_back(g.curve);
  }
  hair::convert::fromGuides(guides, polylines, output);
  vtkNew<vtkIntArray> type;
  type->SetName("HairType");
  type->SetNumberOfTuples(static_cast<vtkIdType>(guides.size()));
  type->Fill(this->HairType);
  output->GetCellData()->AddArray(type);
  vtkNew<vtkIntArray> id; // which input curve each guide comes from
  id->SetName("CurveId");
  id->SetNumberOfTuples(static_cast<vtkIdType>(guides.size()));
  for (std::size_t k = 0; k < source.size(); ++k)
  {
    id->SetValue(static_cast<vtkIdType>(k), source[k]);
  }
  output->GetCellData()->AddArray(id);
  return 1;
}
