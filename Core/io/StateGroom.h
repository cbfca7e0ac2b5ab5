#pragma once
// The optional /groom group of the state file (StateGroom, docs/state-file.md): written by
// the writer when a run has a groom, read by the reader when a file has one. Kept apart from
// the required layout: a file without it reads as before, and a version-1 reader that does
// not know it never opens the group.
#include "io/StateFile.h"

#include <hdf5.h>

namespace hair::detail
{

/// Writes header.groom under /groom (nothing when it is empty).
Status writeGroom(hid_t file, const StateHeader& header);
/// Reads /groom into header.groom when the file has it and its shapes agree with the header;
/// leaves header.groom empty otherwise (a groom is optional: what does not fit is skipped).
/// A dataset declaring more than `maxValues` values is skipped unread (the reader's bound from
/// the file's size and the memory at hand: a damaged file cannot make it allocate more).
void readGroom(hid_t file, StateHeader& header, double maxValues);

} // namespace hair::detail
