#pragma once
// How a model's step statistics (StrandModel::stepStatistics: named numbers about its own
// stepping since the previous frame, for the energy table) become the whole run's under
// MPI, where each rank's model reports on its share of the strands only.
#include "common/Ranks.h"

#include <map>
#include <string>
#include <vector>

namespace hair
{

/// How one named statistic of a rank's strands is reduced over the ranks.
struct StepStatisticRule
{
  enum class Reduction
  {
    /// A mean over the strands: each rank's value weighted by its number of strands and,
    /// when `weight` names another statistic, by that statistic's value on the rank (a share
    /// of sub-steps is weighted by the sub-steps it is a share of).
    StrandMean,
    Max, ///< the largest of the ranks' values (an error estimate)
    Sum  ///< the ranks' values added (a count over the strands)
  };
  std::string name;
  Reduction reduction = Reduction::StrandMean;
  std::string weight; ///< StrandMean only: the statistic weighting it (empty: none)
};

/// The whole run's step statistics from this rank's `values` over its `strands` strands.
/// Collective over `ranks` (every rank passes the same `rules`, in the same order, whether
/// or not it has strands); a statistic without a rule is reduced as a StrandMean, and a rule
/// whose statistic a rank lacks counts it as 0. Without MPI `values` is left as it is.
void reduceStepStatistics(std::map<std::string, double>& values,
                          const std::vector<StepStatisticRule>& rules, double strands,
                          const Ranks& ranks);

} // namespace hair
