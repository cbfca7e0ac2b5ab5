#include "common/Parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <vector>

#include <omp.h>

namespace hair
{

void parallelBlocks(std::int64_t count, std::int64_t grain, int threads,
                    const std::function<void(std::int64_t begin, std::int64_t end)>& body)
{
  grain = std::max<std::int64_t>(1, grain);
  const std::int64_t blocks = blockCount(count, grain);
  const int team =
      static_cast<int>(std::clamp<std::int64_t>(threads, 1, std::max<std::int64_t>(blocks, 1)));
  if (team == 1)
  {
    for (std::int64_t b = 0; b < blocks; ++b)
    {
      body(b * grain, std::min(count, (b + 1) * grain));
    }
    return;
  }
  std::exception_ptr error;
  std::atomic<bool> failed{false};
#pragma omp parallel for num_threads(team) schedule(dynamic, 1)
  for (std::int64_t b = 0; b < blocks; ++b)
  {
    if (failed.load(std::memory_order_relaxed))
    {
      continue;
    }
    try
    {
      body(b * grain, std::min(count, (b + 1) * grain));
    }
    catch (...)
    {
#pragma omp critical(hair_parallel_error)
      if (!error)
      {
        error = std::current_exception();
      }
      failed.store(true, std::memory_order_relaxed);
    }
  }
  if (error)
  {
    std::rethrow_exception(error);
  }
}

Status parallelEach(std::int64_t count, int threads,
                    const std::function<Status(std::int64_t k)>& each)
{
  std::vector<Status> results(static_cast<std::size_t>(std::max<std::int64_t>(count, 0)));
  parallelBlocks(count, 1, threads,
                 [&](std::int64_t begin, std::int64_t end)
                 {
                   for (std::int64_t k = begin; k < end; ++k)
                   {
                     results[static_cast<std::size_t>(k)] = each(k);
                   }
                 });
  for (const Status& s : results)
  {
    if (!s)
    {
      return s;
    }
  }
  return Status::Ok();
}

} // namespace hair
