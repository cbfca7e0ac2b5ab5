/**
 * @class vtkHairAnalysisExecutive
 * @brief The executive of Hair Analysis: ends its loop over time when an input fails.
 *
 * VTK's loop over time (an algorithm sets CONTINUE_EXECUTING; vtkStreamingDemandDrivenPipeline
 * updates it again while the flag holds) only ends when the algorithm clears the flag. When
 * an input fails in the middle of the loop, the algorithm is not called again, the flag
 * stays, and the loop spins for ever (seen with ParaView 5.11: a source that fails at its
 * third time step hangs pvpython). This executive clears the flag when an input fails and
 * tells vtkHairAnalysis, which reports the time and empties its table.
 * It derives from vtkCompositeDataPipeline, not ParaView's vtkPVCompositeDataPipeline, whose
 * additions (array requests of vtkPVPostFilter, extents) concern array selections and
 * structured data, which Hair Analysis has none of; the Filters module stays VTK-only.
 * Plugin/HairAnalysis.xml names it (executive="vtkHairAnalysisExecutive"), and
 * vtkHairAnalysis creates it by default outside ParaView.
 */
#ifndef vtkHairAnalysisExecutive_h
#define vtkHairAnalysisExecutive_h

#include "HairDynamicsFiltersModule.h"

#include <vtkCompositeDataPipeline.h>

class HAIRDYNAMICSFILTERS_EXPORT vtkHairAnalysisExecutive : public vtkCompositeDataPipeline
{
public:
  static vtkHairAnalysisExecutive* New();
  vtkTypeMacro(vtkHairAnalysisExecutive, vtkCompositeDataPipeline);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkHairAnalysisExecutive();
  ~vtkHairAnalysisExecutive() override;
  int ForwardUpstream(vtkInformation* request) override;

private:
  vtkHairAnalysisExecutive(const vtkHairAnalysisExecutive&) = delete;
  void operator=(const vtkHairAnalysisExecutive&) = delete;
};

#endif
