#include "contact/HairHairOptions.h"

#include <cmath>
#include <string>

namespace hair
{

const char* toString(HairHairSolver solver)
{
  switch (solver)
  {
  case HairHairSolver::Grid:
    return "grid";
  case HairHairSolver::GridAndNearField:
    return "grid and near field";
  case HairHairSolver::Coupled:
    return "coupled";
  }
  return "unknown";
}

Status HairHairOptions::validate() const
{
  if (!enabled)
  {
    return Status::Ok();
  }
  const int value = static_cast<int>(solver);
  if (value < 1 || value > 3)
  {
    return Status::Error("the hair–hair solver " + std::to_string(value) +
                         " is not one: give 1 (coupled pairs), 2 (grid) or 3 (grid and near "
                         "field).");
  }
  if (Status s = pairs.validate(); !s)
  {
    return Status::Error("hair–hair contacts: " + s.message());
  }
  if (solver != HairHairSolver::Coupled)
  {
    if (Status s = grid.validate(); !s)
    {
      return Status::Error("hair–hair interaction: " + s.message());
    }
  }
  if (solver == HairHairSolver::GridAndNearField)
  {
    NearFieldParameters nf = nearField;
    nf.thickness = 1e-3; // resolved from pairs.thickness by the model
    if (Status s = nf.validate(); !s)
    {
      return Status::Error("hair–hair interaction: " + s.message());
    }
  }
  return Status::Ok();
}

std::vector<std::pair<std::string, double>> HairHairOptions::gridAttributes(double cellSize) const
{
  std::vector<std::pair<std::string, double>> at = {
      {"hair_hair_contacts", enabled ? static_cast<int>(solver) : 0}};
  if (usesGrid())
  {
    at.insert(at.end(), {{"hair_hair_head_fibres", HairHairParameters::HeadFibres},
                         {"hair_volume_fraction", grid.volumeFraction},
                         {"hair_volume", grid.volume},
                         {"hair_volume_iterations", grid.iterations},
                         {"hair_grid_friction", grid.friction},
                         {"hair_grid_cell_size", cellSize}});
  }
  return at;
}

double guideClumpArea(double fibreRadius, double guides)
{
  const double fibres = guides > 0 ? HairHairParameters::HeadFibres / guides : 0.0;
  return fibres * M_PI * fibreRadius * fibreRadius;
}

} // namespace hair
