#pragma once
// Hair–hair interaction as a run asks for it, whatever the strand model: which solver, and
// the parameters of each (docs/hair-hair-interaction.md). A model that lacks a solver
// refuses it by name (StrandModel::initialize).
#include "common/Status.h"
#include "contact/HairGrid.h"
#include "contact/HairHairContacts.h"
#include "contact/NearField.h"

#include <string>
#include <utility>
#include <vector>

namespace hair
{

/// How the guides interact with each other. The values are Hair Simulation's Hair Hair
/// Contacts (0 there: off) and the state file's hair_hair_contacts attribute.
enum class HairHairSolver
{
  /// The far field on a grid (contact/HairGrid): every strand's volume and friction with
  /// the hair around it, at a fraction of the step's cost, on any number of ranks. Every
  /// model.
  Grid = 2,
  /// The grid and the near field against crossing (contact/NearField): pairs of pieces
  /// tracked over time, pushed back along their side when they touch or flip. One rank;
  /// the Super-Helix.
  GridAndNearField = 3,
  /// Every close pair solved together with the step, with Coulomb friction
  /// (contact/HairHairContacts): for small studies; tens of times the step on a head. One
  /// rank; the Super-Helix.
  Coupled = 1
};
/// "grid", "grid and near field", "coupled" (messages).
const char* toString(HairHairSolver solver);

struct HairHairOptions
{
  /// On by default: the grid's volume and friction.
  bool enabled = true;
  HairHairSolver solver = HairHairSolver::Grid;
  /// The pairs' parameters: `pairs.thickness` is the contact distance of the pairs (0:
  /// automatic, HairHairParameters::automaticThickness); the rest is the coupled solve's.
  HairHairParameters pairs;
  HairGridParameters grid;       ///< the far field (Grid, GridAndNearField)
  NearFieldParameters nearField; ///< the near field (GridAndNearField)
  /// Whether the far field's grid is on (Grid, GridAndNearField).
  bool usesGrid() const { return enabled && solver != HairHairSolver::Coupled; }
  /// Names the first bad option, what is wrong and what to do.
  Status validate() const;
  /// The state file's attributes of the solver and the grid (docs/state-file.md): the solver
  /// (hair_hair_contacts, 0 off) and, with the grid, its parameters and `cellSize` [m], the
  /// cell as used.
  std::vector<std::pair<std::string, double>> gridAttributes(double cellSize) const;
};

/// The cross-section [m²] of the fibres one guide stands for, the grid's volume per unit of
/// its length: a head's HairHairParameters::HeadFibres fibres of radius `fibreRadius` [m]
/// shared among the run's `guides` guides (every rank's).
double guideClumpArea(double fibreRadius, double guides);

} // namespace hair
