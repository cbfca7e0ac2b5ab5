/**
 * @class vtkCylindricalCollisionMap
 * @brief Turns a body part's surface into a collision table (Kurihara et al. 1993).
 *
 * Casts rays from an axis (cylindrical projection) or a centre (spherical projection)
 * against the input surface with CGAL's AABB tree and keeps, for each sample, the
 * outermost solid interval along the ray, its normals and whether the ray met the part.
 * The work is hair::CollisionTable's; this filter moves data in and out.
 *
 * Output 0 (Table): vtkImageData, azimuth × height (or polar angle), point arrays Radius,
 * InnerRadius, Normal, InnerNormal, Hit; the frame in field data.
 * Output 1 (Surface): the surface the table represents, to overlay on the mesh.
 */
#ifndef vtkCylindricalCollisionMap_h
#define vtkCylindricalCollisionMap_h

#include "HairDynamicsFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <string>

class HAIRDYNAMICSFILTERS_EXPORT vtkCylindricalCollisionMap : public vtkPolyDataAlgorithm
{
public:
  static vtkCylindricalCollisionMap* New();
  vtkTypeMacro(vtkCylindricalCollisionMap, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ProjectionType
  {
    CYLINDRICAL = 0,
    SPHERICAL = 1
  };

  ///@{
  /// Cylindrical (radius against azimuth and height about an axis, the paper's) or
  /// spherical (radius against azimuth and polar angle about a centre; fits a head better).
  vtkSetClampMacro(Projection, int, CYLINDRICAL, SPHERICAL);
  vtkGetMacro(Projection, int);
  ///@}

  ///@{
  /// When on (the default), the frame comes from the input's bounds: origin at the centre of
  /// the bounding box, axis along its longest side, azimuth 0 along the next coordinate axis
  /// (Y axis -> +Z, the bundled body's face), heights over the whole box. When off, Origin,
  /// Axis, ReferenceDirection and HeightRange are used.
  vtkSetMacro(AutomaticFrame, bool);
  vtkGetMacro(AutomaticFrame, bool);
  vtkBooleanMacro(AutomaticFrame, bool);
  ///@}

  vtkSetVector3Macro(Origin, double);
  vtkGetVector3Macro(Origin, double);
  vtkSetVector3Macro(Axis, double);
  vtkGetVector3Macro(Axis, double);
  vtkSetVector3Macro(ReferenceDirection, double);
  vtkGetVector3Macro(ReferenceDirection, double);
  /// Heights along the axis, measured from Origin (cylindrical projection only).
  vtkSetVector2Macro(HeightRange, double);
  vtkGetVector2Macro(HeightRange, double);

  /// Samples in azimuth and in height (or polar angle). The paper used 40 × 40.
  vtkSetVector2Macro(Resolution, int);
  vtkGetVector2Macro(Resolution, int);

  /// Rays stop this far from the axis or centre; 0 means no limit.
  vtkSetMacro(MaximumRadius, double);
  vtkGetMacro(MaximumRadius, double);

  /// The body part's name, carried in the table's field data (e.g. "head").
  vtkSetStdStringFromCharMacro(BodyPartName);
  vtkGetCharFromStdStringMacro(BodyPartName);

  /// Whether this part moves with the head when a simulation shakes or nods it.
  vtkSetMacro(MovesWithHead, bool);
  vtkGetMacro(MovesWithHead, bool);
  vtkBooleanMacro(MovesWithHead, bool);

protected:
  vtkCylindricalCollisionMap();
  ~vtkCylindricalCollisionMap() override = default;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Projection = CYLINDRICAL;
  bool AutomaticFrame = true;
  double Origin[3] = {0, 0, 0};
  double Axis[3] = {0, 1, 0};
  double ReferenceDirection[3] = {0, 0, 1};
  double HeightRange[2] = {0, 1};
  int Resolution[2] = {40, 40};
  double MaximumRadius = 0;
  std::string BodyPartName = "body";
  bool MovesWithHead = false;

private:
  vtkCylindricalCollisionMap(const vtkCylindricalCollisionMap&) = delete;
  void operator=(const vtkCylindricalCollisionMap&) = delete;
};

#endif
