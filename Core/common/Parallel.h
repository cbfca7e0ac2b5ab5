#pragma once
// Parallel loops for Core on OpenMP's threads (GCC's libgomp): Core keeps no thread pool of
// its own. Work is cut into blocks that depend only on its size, never on the number of
// threads, so that anything merged block by block comes out the same on any number of
// threads.
#include "common/Status.h"

#include <cstdint>
#include <functional>

namespace hair
{

/// Calls body(begin, end) once for each block [b·grain, min((b + 1)·grain, count)) of
/// [0, count), on up to `threads` threads (1: the calling thread only, in order). Blocks
/// are handed out one at a time as threads become free, so uneven costs balance. The
/// first exception a block throws is rethrown on the calling thread once every block has
/// run or been skipped; blocks not started by then are skipped.
void parallelBlocks(std::int64_t count, std::int64_t grain, int threads,
                    const std::function<void(std::int64_t begin, std::int64_t end)>& body);

/// Calls each(k) for every k of [0, count) on up to `threads` threads, one k a block (a
/// strand built or stepped), and returns the failure of the smallest k that failed, or Ok:
/// the same message whatever the threads and whichever failed first in time.
Status parallelEach(std::int64_t count, int threads,
                    const std::function<Status(std::int64_t k)>& each);

/// The number of blocks parallelBlocks cuts [0, count) into.
inline std::int64_t blockCount(std::int64_t count, std::int64_t grain)
{
  grain = grain < 1 ? 1 : grain;
  return count <= 0 ? 0 : (count + grain - 1) / grain;
}

} // namespace hair
