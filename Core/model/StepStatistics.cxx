#include "model/StepStatistics.h"

#include <algorithm>

namespace hair
{

void reduceStepStatistics(std::map<std::string, double>& values,
                          const std::vector<StepStatisticRule>& rules, double strands,
                          const Ranks& ranks)
{
  if (!ranks.parallel())
  {
    return;
  }
  using Reduction = StepStatisticRule::Reduction;
  // Every statistic the rules name, then those without a rule (the same on every rank only
  // if the models report the same names: a model reports the same names on every rank).
  std::vector<StepStatisticRule> all = rules;
  for (const auto& entry : values)
  {
    const std::string& name = entry.first;
    const bool ruled = std::any_of(rules.begin(), rules.end(),
                                   [&](const StepStatisticRule& r) { return r.name == name; });
    if (!ruled)
    {
      all.push_back({name, Reduction::StrandMean, ""});
    }
  }
  if (all.empty())
  {
    return;
  }
  auto value = [&](const std::string& name)
  {
    const auto it = values.find(name);
    return it == values.end() ? 0.0 : it->second;
  };
  // The local numerators and denominators of every mean, from the values before any is
  // reduced (a weight is the rank's own), summed in one exchange; then the maxima.
  std::vector<double> sums;
  for (const StepStatisticRule& r : all)
  {
    if (r.reduction == Reduction::StrandMean)
    {
      const double weight = r.weight.empty() ? 1.0 : value(r.weight);
      sums.push_back(value(r.name) * weight * strands);
      sums.push_back(weight * strands);
    }
    else if (r.reduction == Reduction::Sum)
    {
      sums.push_back(value(r.name));
    }
  }
  ranks.sum(sums.data(), int(sums.size()));
  std::size_t at = 0;
  for (const StepStatisticRule& r : all)
  {
    switch (r.reduction)
    {
    case Reduction::StrandMean:
      values[r.name] = sums[at + 1] > 0 ? sums[at] / sums[at + 1] : 0.0;
      at += 2;
      break;
    case Reduction::Sum:
      values[r.name] = sums[at++];
      break;
    case Reduction::Max:
      values[r.name] = ranks.max(value(r.name));
      break;
    }
  }
}

} // namespace hair
