// Many strands at once: stepStrands (chunks of consecutive strands on the run's threads,
// each thread prefetching the next strand of its chunk while it steps one),
// SuperHelix::prefetch, and findHairHairContacts from the strands' samples.
#include "superhelix/SuperHelix.h"

#include "common/Parallel.h"

#include <algorithm>
#include <vector>

namespace hair
{

void SuperHelix::prefetch() const
{
  auto lines = [](const void* p, size_t bytes)
  {
    const char* c = static_cast<const char*>(p);
    for (size_t off = 0; off < bytes; off += 64)
      __builtin_prefetch(c + off);
  };
  lines(Cur.nodes.data(), Cur.nodes.size() * sizeof(Node));
  lines(Cur.elements.data(), Cur.elements.size() * sizeof(Element));
  lines(Q.data(), Q.size() * sizeof(double));
  lines(Qdot.data(), Qdot.size() * sizeof(double));
}

Status stepStrands(std::vector<SuperHelix>& strands, double dt, int threads, double tolerance)
{
  const int count = static_cast<int>(strands.size());
  std::vector<Status> results(strands.size());
  threads = std::max(1, std::min(threads, count));
  // Threads take chunks of consecutive strands, so that the strand after the current one
  // in a chunk is stepped by the same thread, later: while one strand computes, the next
  // one's samples are brought in from memory (a strand's data is not in cache when
  // hundreds are stepped in turn, and its loads are too scattered for the hardware's
  // prefetcher). Prefetching a strand another thread may be stepping would read its
  // buffers while they are swapped.
  // Chunks of 8, smaller when there are few strands (at least four chunks per thread).
  const int chunk = std::max(1, std::min(8, count / (4 * threads)));
  parallelBlocks(count, chunk, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   for (std::int64_t i = first; i < last; ++i)
                   {
                     if (i + 1 < last)
                       strands[i + 1].prefetch();
                     results[i] = strands[i].advance(dt, tolerance);
                   }
                 });
  for (const Status& s : results)
    if (!s)
      return s;
  return Status::Ok();
}

Status findHairHairContacts(const std::vector<SuperHelix>& strands, HairHairContacts& contacts)
{
  std::vector<std::vector<StrandSample>> samples(strands.size());
  std::vector<int> ids(strands.size());
  for (std::size_t i = 0; i < strands.size(); ++i)
  {
    samples[i] = strands[i].samples();
    ids[i] = strands[i].spec().id;
  }
  return contacts.update(samples, ids);
}

} // namespace hair
