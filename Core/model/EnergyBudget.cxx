#include "model/EnergyBudget.h"

#include <algorithm>

namespace hair
{

namespace
{
bool isRequired(const std::string& name)
{
  for (const char* n : {energy::Kinetic, energy::Elastic, energy::Gravitational, energy::Dissipated,
                        energy::ExternalWork})
  {
    if (name == n)
    {
      return true;
    }
  }
  return false;
}
} // namespace

void EnergyBudget::add(const std::string& name, EnergyKind kind, double value)
{
  Terms.push_back({name, kind, value});
}

double EnergyBudget::total(EnergyKind kind) const
{
  double sum = 0;
  for (const Term& t : Terms)
  {
    if (t.kind == kind)
    {
      sum += t.value;
    }
  }
  return sum;
}

std::map<std::string, double> EnergyBudget::values() const
{
  std::map<std::string, double> v;
  v[energy::Kinetic] = 0;
  v[energy::Elastic] = 0;
  v[energy::Gravitational] = 0;
  for (const Term& t : Terms)
  {
    v[t.name] = t.value;
  }
  v[energy::Dissipated] = total(EnergyKind::Dissipation);
  v[energy::ExternalWork] = total(EnergyKind::Work);
  return v;
}

std::vector<std::string> EnergyBudget::extraNames() const
{
  std::vector<std::string> names;
  for (const Term& t : Terms)
  {
    if (!isRequired(t.name) && std::find(names.begin(), names.end(), t.name) == names.end())
    {
      names.push_back(t.name);
    }
  }
  return names;
}

void addGridContactWork(EnergyBudget& budget, double contactWork, double fieldWork,
                        double fieldDissipated)
{
  budget.add("contact_work", EnergyKind::Work, contactWork - fieldWork);
  budget.add(energy::HairGridWork, EnergyKind::Work, fieldWork + fieldDissipated);
  budget.add(energy::HairGridDissipated, EnergyKind::Dissipation, fieldDissipated);
}

} // namespace hair
