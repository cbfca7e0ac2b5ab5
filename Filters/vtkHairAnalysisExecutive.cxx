#include "vtkHairAnalysisExecutive.h"

#include "vtkHairAnalysis.h"

#include <vtkInformation.h>
#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkHairAnalysisExecutive);

vtkHairAnalysisExecutive::vtkHairAnalysisExecutive() = default;
vtkHairAnalysisExecutive::~vtkHairAnalysisExecutive() = default;

void vtkHairAnalysisExecutive::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

int vtkHairAnalysisExecutive::ForwardUpstream(vtkInformation* request)
{
  const int ok = this->Superclass::ForwardUpstream(request);
  if (!ok && request->Has(REQUEST_DATA()))
  {
    this->ContinueExecuting = 0;
    if (vtkHairAnalysis* analysis = vtkHairAnalysis::SafeDownCast(this->GetAlgorithm()))
    {
      analysis->InputFailed();
    }
  }
  return ok;
}
