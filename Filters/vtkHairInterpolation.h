/**
 * @class vtkHairInterpolation
 * @brief A full head of rendered hair from the guides, at any time the guides can give.
 *
 * hair::HairInterpolation does the work (Core/render/): rendered strands rooted on the
 * scalp (input 1) and bound once to the guides near them; every frame, each follows its
 * guides (input 0, the output of Hair Simulation or Hair State Reader) by the
 * semi-interpolation of Bertails et al. 2006 or as a cluster copy of Kurihara et al. 1993,
 * its offsets carried in the guides' material frames, each point pushed out of the
 * collision tables (input 2, optional; those that move with the head posed by the guides'
 * roots). Output: polylines with point data Tangent, ArcParameter and the guides' Speed and
 * curvature, cell data StrandId and GuideId, and in field data the points pushed out.
 */
#ifndef vtkHairInterpolation_h
#define vtkHairInterpolation_h

#include "HairDynamicsFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <memory>

class HAIRDYNAMICSFILTERS_EXPORT vtkHairInterpolation : public vtkPolyDataAlgorithm
{
public:
  static vtkHairInterpolation* New();
  vtkTypeMacro(vtkHairInterpolation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Input 1: the scalp surface the guides grew on.
  void SetScalpConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  /// Input 2: collision tables (Cylindrical Collision Map), any number, optional.
  void AddColliderConnection(vtkAlgorithmOutput* output) { this->AddInputConnection(2, output); }
  void RemoveAllColliders() { this->SetInputConnection(2, nullptr); }

  enum MethodType
  {
    SEMI_INTERPOLATION = 0,
    CLUSTERS = 1
  };
  // Not clamped here: hair::InterpolationOptions::validate refuses bad values with a
  // message naming the property's meaning and its range.
  vtkSetMacro(Method, int);
  vtkGetMacro(Method, int);
  vtkSetMacro(NumberOfStrands, int);
  vtkGetMacro(NumberOfStrands, int);
  vtkSetMacro(PointsPerStrand, int);
  vtkGetMacro(PointsPerStrand, int);
  /// Clumping from the hair type (on) or from ClumpRange (off).
  vtkSetMacro(ClumpingFromHairType, bool);
  vtkGetMacro(ClumpingFromHairType, bool);
  vtkBooleanMacro(ClumpingFromHairType, bool);
  vtkSetVector2Macro(ClumpRange, double);
  vtkGetVector2Macro(ClumpRange, double);
  vtkSetMacro(ClumpRadius, double);
  vtkGetMacro(ClumpRadius, double);
  vtkSetMacro(TipDistance, double);
  vtkGetMacro(TipDistance, double);
  vtkSetMacro(Variation, double);
  vtkGetMacro(Variation, double);
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

protected:
  vtkHairInterpolation();
  ~vtkHairInterpolation() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Method = SEMI_INTERPOLATION;
  int NumberOfStrands = 50000;
  int PointsPerStrand = 32;
  bool ClumpingFromHairType = true;
  double ClumpRange[2] = {0.5, 0.8};
  double ClumpRadius = 0.01;
  double TipDistance = 0.04;
  double Variation = 0.1;
  int Seed = 1;
  int NumberOfThreads = 2;

private:
  vtkHairInterpolation(const vtkHairInterpolation&) = delete;
  void operator=(const vtkHairInterpolation&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
