#pragma once
// The one sub-step controller of the Super-Helix model: the rules by which a strand's own
// sub-steps (SuperHelix::advance, "Accuracy on request") and the common sub-steps of the
// coupled hair–hair step (SuperHelixModel::advanceTo) are sized from their error estimates
// (docs/super-helix.md, "Accuracy on request"; docs/hair-hair-contacts.md).
#include <algorithm>
#include <cmath>

namespace hair
{

namespace substeps
{
/// The next sub-step is h · Safety / r^(1/(p − 1)), at most Growth times and at least Shrink
/// times the last, for an estimate e ∝ h^p and r = e / allowed.
constexpr double Safety = 0.9, Shrink = 0.2, Growth = 2.0;

/// The factor on the last sub-step for an estimate `ratio` r = e / allowed of order
/// `errorPower` p in the sub-step (2: the first-order update's local error, the midpoint and
/// semi-implicit steps'; 3: BDF2's own local error); Growth when the estimate is 0.
inline double factor(double ratio, int errorPower)
{
  return ratio > 0 ? Safety / (errorPower == 3 ? std::sqrt(ratio) : ratio) : Growth;
}

/// A sub-step `h` fitted to the `remaining` time of the interval: the whole rest when it
/// reaches it, two equal halves rather than a long step and a sliver, or h.
inline double land(double h, double remaining)
{
  if (h >= remaining * (1 - 1e-9))
    return remaining;
  return h > 0.5 * remaining ? 0.5 * remaining : h;
}

/// The sub-step after an accepted one of `taken` with `factor`; `planned`: the one it was
/// planned as (longer when it was shortened to land on the interval's end, which must not
/// hold back the next): at most Growth times the longer of the two.
inline double afterAccepted(double taken, double factor, double planned)
{
  return std::max(Shrink * taken, std::min(taken * factor, Growth * std::max(planned, taken)));
}

/// The sub-step to take again after a rejected one of `taken`: smaller, by at most Shrink.
inline double afterRejected(double taken, double factor)
{
  return taken * std::max(Shrink, std::min(Safety, factor));
}
} // namespace substeps

} // namespace hair
