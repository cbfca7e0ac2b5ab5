/**
 * @class vtkHairAnalysis
 * @brief One row per frame of a hair run: time, energy terms, tip positions, the span of a
 * group of tips, extreme curvature and twist, tip deflection and displacement, contacts.
 *
 * hair::StrandAnalysis does the measuring; this filter walks through every time step of
 * its input in one request (the CONTINUE_EXECUTING loop of ParaView's "Plot Data Over
 * Time" and vtkTemporalStatistics), with progress and Abort. Port 0: the strands over time
 * (output 0 of Hair Simulation or Hair State Reader: polylines root first, point arrays
 * curvature, twist and contact_depth, cell array StrandId). Port 1 (Energy, optional): the
 * energy table of the same source (its output 1); each frame's row is copied. Output: a
 * vtkTable, columns documented in docs/hair-analysis.md.
 */
#ifndef vtkHairAnalysis_h
#define vtkHairAnalysis_h

#include "HairDynamicsFiltersModule.h"

#include <vtkTableAlgorithm.h>

#include <memory>
#include <vector>

class HAIRDYNAMICSFILTERS_EXPORT vtkHairAnalysis : public vtkTableAlgorithm
{
public:
  static vtkHairAnalysis* New();
  vtkTypeMacro(vtkHairAnalysis, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The energy table (output 1 of the Hair Simulation or Hair State Reader on port 0).
  void SetEnergyConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  /// Strands (by StrandId) whose tips get columns of their own.
  void AddTrackedStrand(int id);
  void RemoveAllTrackedStrands();
  const std::vector<int>& GetTrackedStrands() const { return this->TrackedStrands; }
  /// Strands (by StrandId) whose span is measured; none: every strand.
  void AddGroupStrand(int id);
  void RemoveAllGroupStrands();
  const std::vector<int>& GetGroupStrands() const { return this->GroupStrands; }

  /// Up, against gravity: span and deflection are measured perpendicular to it.
  vtkSetVector3Macro(Vertical, double);
  vtkGetVector3Macro(Vertical, double);

  /// Called by vtkHairAnalysisExecutive when an input failed: ends the loop over time,
  /// empties the output and says at which time.
  void InputFailed();

protected:
  vtkHairAnalysis();
  /// vtkHairAnalysisExecutive: ends the loop over time when an input fails.
  vtkExecutive* CreateDefaultExecutive() override;
  ~vtkHairAnalysis() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::vector<int> TrackedStrands;
  std::vector<int> GroupStrands;
  double Vertical[3] = {0, 1, 0};

private:
  vtkHairAnalysis(const vtkHairAnalysis&) = delete;
  void operator=(const vtkHairAnalysis&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
