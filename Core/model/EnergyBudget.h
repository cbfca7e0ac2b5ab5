#pragma once
// One energy budget for every model: named terms, each a state energy, a work done on the
// hair, a dissipation or the integrator's residual, so that the frame loop, the state file
// and the plots treat any model alike. With E = Σ state terms,
//   E(t) − E(0) = Σ works − Σ dissipations + residual,
// which closes by construction of the residual (what the time integrator itself adds).
#include <map>
#include <string>
#include <vector>

namespace hair
{

enum class EnergyKind
{
  State,       ///< kinetic, elastic, gravitational energy at the frame's time [J]
  Work,        ///< work done on the hair since the start [J]
  Dissipation, ///< energy dissipated since the start (≥ 0) [J]
  Residual     ///< what the integrator added since the start (< 0: numerical dissipation) [J]
};

/// The names every budget has (and every state file stores): the three state energies and
/// the two sums.
namespace energy
{
constexpr const char* Kinetic = "kinetic";
constexpr const char* Elastic = "elastic";
constexpr const char* Gravitational = "gravitational";
constexpr const char* Dissipated = "dissipated";      ///< Σ of the dissipation terms
constexpr const char* ExternalWork = "external_work"; ///< Σ of the work terms
constexpr const char* Residual = "residual";
/// The far field of hair–hair interaction (contact/HairGrid), apart from the body's contact
/// work: the work of its forces plus what its drag dissipated, and that dissipation.
constexpr const char* HairGridWork = "hair_grid_work";
constexpr const char* HairGridDissipated = "hair_grid_dissipated";
} // namespace energy

class EnergyBudget
{
public:
  struct Term
  {
    std::string name;
    EnergyKind kind;
    double value;
  };

  /// Adds a term. A model's one dissipation term may be named "dissipated" (the sum of one
  /// term is itself); no other term may take the name of a sum.
  void add(const std::string& name, EnergyKind kind, double value);
  const std::vector<Term>& terms() const { return Terms; }

  double total(EnergyKind kind) const;
  /// Every term by name, with the sums "dissipated" and "external_work" (always present).
  std::map<std::string, double> values() const;
  /// The names of values() beyond the five every budget has, in the order added.
  std::vector<std::string> extraNames() const;

private:
  std::vector<Term> Terms;
};

/// The contact work of strands whose contact responses include the hair grid's far field
/// (ContactResponse's drag and push): of `contactWork`, the grid's `fieldWork` is reported as
/// hair_grid_work together with what its drag dissipated (`fieldDissipated`, also reported
/// as hair_grid_dissipated), the rest as contact_work; works − dissipations is unchanged.
void addGridContactWork(EnergyBudget& budget, double contactWork, double fieldWork,
                        double fieldDissipated);

} // namespace hair
