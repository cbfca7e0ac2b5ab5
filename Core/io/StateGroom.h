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
void readGroom(hid_t file, StateHeader& header);

} // namespace hair::detail
