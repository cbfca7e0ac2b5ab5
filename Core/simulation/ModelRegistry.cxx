// The models a run can use, by SimulationOptions::model: the one place that names them all.
// A new model implements StrandModel (model/StrandModel.h) in its own layer and gets a line
// here, an enumerator in ModelType and its options in SimulationOptions.
#include "projective/ProjectiveModel.h"
#include "simulation/Simulation.h"
#include "superhelix/SuperHelixModel.h"

namespace hair
{

std::unique_ptr<StrandModel> makeModel(const SimulationOptions& options)
{
  switch (options.model)
  {
  case ModelType::Projective:
    return std::make_unique<ProjectiveModel>(options.projective, options.sagFree);
  case ModelType::SuperHelix:
    break;
  }
  SuperHelixOptions superHelix = options.superHelix;
  superHelix.sagFree = options.sagFree;
  return std::make_unique<SuperHelixModel>(superHelix);
}

} // namespace hair
