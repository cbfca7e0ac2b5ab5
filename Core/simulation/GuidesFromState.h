#pragma once
// The guides a state file's run started from, read back from its header: the per-strand
// parameters and vectors (/strands) and, when the run had one, each strand's guide curve and
// rest-shape choice (/groom, /strands/rest_shape). With the scene the run attributes describe,
// they are what Simulation::initialize needs to run the study again (docs/state-file.md).
#include "common/Status.h"
#include "io/StateFile.h"
#include "strands/GuideStrand.h"

#include <vector>

namespace hair
{

/// One guide per strand of `header`. Refuses a header without one of the per-strand
/// parameters or vectors a guide needs (files written before they were stored), naming it.
/// A parameter marked optional (strands/StrandParameters.h) that is missing keeps its
/// default.
Status guidesFromState(const StateHeader& header, std::vector<GuideStrand>& guides);

} // namespace hair
