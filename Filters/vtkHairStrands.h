/**
 * @class vtkHairStrands
 * @brief Guide strands grown on a scalp: roots spread evenly over a surface region (or one
 * per input point), each a straight polyline along the surface normal or a comb direction;
 * or, with guide curves on the second port, one groomed guide per curve (its root moved onto
 * the surface), each with a rest shape as grown or sag-free.
 *
 * The roots come from hair::sampleRoots, the physical parameters from hair::HairParameters
 * (the four presets of the Super-Helices paper, or Custom). Output: one polyline of
 * NumberOfElements + 1 points per strand; cell data carry every per-strand parameter a
 * simulation needs (StrandId, Length, NumberOfElements, HairType, Radius, Ellipticity,
 * YoungModulus, PoissonRatio, Density, HelixRadius, HelixStep, InternalFriction,
 * AirFriction, CurvatureVariation, RootNormal, GrowthDirection, Seed).
 */
#ifndef vtkHairStrands_h
#define vtkHairStrands_h

#include "HairDynamicsFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <string>

class vtkAlgorithmOutput;
namespace hair
{
struct HairParameters;
}

class HAIRDYNAMICSFILTERS_EXPORT vtkHairStrands : public vtkPolyDataAlgorithm
{
public:
  static vtkHairStrands* New();
  vtkTypeMacro(vtkHairStrands, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum RegionType
  {
    AUTOMATIC_SCALP = 0, ///< the bundled body's scalp (whole surface for other meshes)
    WHOLE_SURFACE = 1,
    POINT_MASK = 2,  ///< triangles whose points all have RegionArray != 0
    SCALAR_RANGE = 3 ///< triangles whose points all have RegionArray within RegionRange
  };
  enum GrowthType
  {
    NORMAL = 0,
    COMB = 1 ///< normal blended towards CombDirection by CombWeight
  };
  enum RestShapeType
  {
    AS_GROWN = 0, ///< the model's own natural shape: the strands sag from their shape at t = 0
    SAG_FREE = 1  ///< the shape at t = 0 a static equilibrium (hair::RestShape::SagFree)
  };
  enum HairTypeEnum
  {
    SMOOTH = 0,
    WAVY = 1,
    CURLY = 2,
    FUZZY = 3,
    CUSTOM = 4
  };

  vtkSetMacro(NumberOfStrands, int);
  vtkGetMacro(NumberOfStrands, int);
  vtkSetMacro(StrandLength, double);
  vtkGetMacro(StrandLength, double);
  vtkSetMacro(NumberOfElements, int);
  vtkGetMacro(NumberOfElements, int);
  vtkSetClampMacro(HairType, int, SMOOTH, CUSTOM);
  vtkGetMacro(HairType, int);
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);

  vtkSetClampMacro(Region, int, AUTOMATIC_SCALP, SCALAR_RANGE);
  vtkGetMacro(Region, int);
  vtkSetStdStringFromCharMacro(RegionArray);
  vtkGetCharFromStdStringMacro(RegionArray);
  vtkSetVector2Macro(RegionRange, double);
  vtkGetVector2Macro(RegionRange, double);

  /// Guide curves (polylines, root first) on port 1: one guide per curve instead of grown
  /// strands.
  void SetGuideCurvesConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  vtkSetClampMacro(RestShape, int, AS_GROWN, SAG_FREE);
  vtkGetMacro(RestShape, int);
  vtkSetMacro(MaximumRootDistance, double);
  vtkGetMacro(MaximumRootDistance, double);

  vtkSetClampMacro(Growth, int, NORMAL, COMB);
  vtkGetMacro(Growth, int);
  vtkSetVector3Macro(CombDirection, double);
  vtkGetVector3Macro(CombDirection, double);
  vtkSetMacro(CombWeight, double);
  vtkGetMacro(CombWeight, double);

  ///@{ Physical parameters, used when HairType is Custom (SI units).
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  vtkSetMacro(Ellipticity, double);
  vtkGetMacro(Ellipticity, double);
  vtkSetMacro(YoungModulus, double);
  vtkGetMacro(YoungModulus, double);
  vtkSetMacro(PoissonRatio, double);
  vtkGetMacro(PoissonRatio, double);
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  vtkSetMacro(HelixRadius, double);
  vtkGetMacro(HelixRadius, double);
  vtkSetMacro(HelixStep, double);
  vtkGetMacro(HelixStep, double);
  vtkSetMacro(InternalFriction, double);
  vtkGetMacro(InternalFriction, double);
  vtkSetMacro(AirFriction, double);
  vtkGetMacro(AirFriction, double);
  vtkSetMacro(CurvatureVariation, double);
  vtkGetMacro(CurvatureVariation, double);
  ///@}

protected:
  vtkHairStrands();
  ~vtkHairStrands() override = default;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// Port 1's curves made guides (roots moved onto the surface of port 0 when it is one).
  int GuidesFromCurves(vtkPolyData* surface, vtkPolyData* curves,
                       const hair::HairParameters& params, vtkPolyData* output);

  int NumberOfStrands = 200;
  double StrandLength = 0.3;
  int NumberOfElements = 10;
  int HairType = WAVY;
  int Seed = 1;
  int Region = AUTOMATIC_SCALP;
  std::string RegionArray;
  double RegionRange[2] = {1, 1};
  int RestShape = AS_GROWN;
  double MaximumRootDistance = 0.01;
  int Growth = NORMAL;
  double CombDirection[3] = {0, -1, 0};
  double CombWeight = 0.5;
  double Radius = 50e-6;
  double Ellipticity = 1.0;
  double YoungModulus = 1e9;
  double PoissonRatio = 0.48;
  double Density = 1300;
  double HelixRadius = 0;
  double HelixStep = 0;
  double InternalFriction = 1e-10;
  double AirFriction = 1e-5;
  double CurvatureVariation = 0;

private:
  vtkHairStrands(const vtkHairStrands&) = delete;
  void operator=(const vtkHairStrands&) = delete;
};

#endif
