#pragma once
#include <functional>

namespace hair
{
/// Called with the fraction done, in [0, 1], during long work. Returning false asks the
/// work to stop as soon as it can; the work then returns an error Status saying it was
/// aborted and leaves its output untouched.
using Progress = std::function<bool(double fraction)>;
} // namespace hair
