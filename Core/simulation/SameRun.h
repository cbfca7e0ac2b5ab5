#pragma once
// Whether a state file holds the run a resumed simulation is given: its model, strands,
// parameters, groom, scene and energy terms, compared with those the run would write.
#include "common/Status.h"
#include "io/StateFile.h"

#include <string>
#include <vector>

namespace hair
{

/// Refuses, saying what differs (the first few differences, by name), a file of format
/// version `fileVersion` whose header and energy terms are not those of `run` and
/// `runTerms` (the extra terms): another run's file, the same run with a parameter changed,
/// or a file written by another version of HairDynamics.
Status sameRun(const StateHeader& file, int fileVersion, const std::vector<std::string>& fileTerms,
               const StateHeader& run, const std::vector<std::string>& runTerms);

} // namespace hair
