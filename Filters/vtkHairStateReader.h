/**
 * @class vtkHairStateReader
 * @brief Reads a HairDynamics state file (HDF5) back over time, without simulating.
 *
 * hair::StateFileReader does the reading; this reader turns a frame into polylines.
 * Output 0 (Strands): the strands at the requested time, one polyline per strand, point
 * data Velocity (and Speed), Tangent and Director1 (the material frame, when the file
 * stores the root poses), cell data StrandId and every per-strand parameter and vector of
 * the file. Super-Helix strands are drawn again from q at PointsPerElement
 * (hair::drawGuides).
 * Output 1 (Energy): a vtkTable with one row per frame, columns Time and every energy term.
 * Reports TIME_STEPS (the frames' times); a request between frames gets the frame at or
 * before it, one before the first frame the first, one after the last the last, and NaN an
 * error. The file is opened anew at every RequestInformation (Reload Files), so each reader
 * of a file being written sees its new frames.
 */
#ifndef vtkHairStateReader_h
#define vtkHairStateReader_h

#include "HairDynamicsFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <memory>
#include <string>

class HAIRDYNAMICSFILTERS_EXPORT vtkHairStateReader : public vtkPolyDataAlgorithm
{
public:
  static vtkHairStateReader* New();
  vtkTypeMacro(vtkHairStateReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The state file (.h5) written by Hair Simulation.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);

  /// Super-Helix points per element, drawn exactly on the helices from the file's q and root
  /// poses (a file without root poses is shown at its stored points); the projective model's
  /// points are its segments' nodes whatever this says.
  vtkSetClampMacro(PointsPerElement, int, 1, 256);
  vtkGetMacro(PointsPerElement, int);

  /// 1 when `fileName` is a HairDynamics state file (ParaView's File > Open asks this).
  int CanReadFile(const char* fileName);

protected:
  vtkHairStateReader();
  ~vtkHairStateReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string FileName;
  int PointsPerElement = 16;

private:
  vtkHairStateReader(const vtkHairStateReader&) = delete;
  void operator=(const vtkHairStateReader&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
