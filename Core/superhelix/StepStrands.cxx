// Many strands at once: stepStrands (chunks of consecutive strands on the run's threads,
// each thread prefetching the next strand of its chunk while it steps one),
// SuperHelix::prefetch, and stepStrandsWithContacts (the step with the contacts between
// strands solved together with it).
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

Status stepStrandsWithContacts(std::vector<SuperHelix>& strands, HairHairContacts& contacts,
                               double dt, int threads)
{
  // Rounds of detection: a contact's force can push a strand towards one it was not paired
  // with; each round looks again from where the solved step takes the samples
  // (docs/hair-hair-contacts.md, "Detection").
  constexpr int DetectionRounds = 3;
  const int count = static_cast<int>(strands.size());
  threads = std::max(1, std::min(threads, count));
  const int chunk = std::max(1, std::min(8, count / (4 * threads)));
  std::vector<Status> results(strands.size());
  auto firstError = [&]() -> Status
  {
    for (const Status& s : results)
      if (!s)
        return s;
    return Status::Ok();
  };
  // Every strand's step without the contacts between strands; the pairs that may touch are
  // found from where that step takes the samples (x + dt v at the free end velocity).
  parallelBlocks(count, chunk, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   for (std::int64_t i = first; i < last; ++i)
                   {
                     if (i + 1 < last)
                       strands[i + 1].prefetch();
                     results[i] = strands[i].beginStep(dt);
                   }
                 });
  if (Status st = firstError(); !st)
    return st;
  // Detection, compliance and solve; then the detection again from where the solved step
  // takes the samples, and a solve with the pairs it adds (a strand pushed by one contact
  // towards another strand), while it adds any, at most DetectionRounds times in all.
  std::vector<std::vector<StrandSample>> samples(strands.size());
  std::vector<int> ids(strands.size());
  for (std::size_t i = 0; i < strands.size(); ++i)
  {
    samples[i] = strands[i].freeSamples();
    ids[i] = strands[i].spec().id;
  }
  std::vector<StrandCompliance> compliance(strands.size());
  for (int round = 0; round < DetectionRounds; ++round)
  {
    if (round == 0)
    {
      if (Status st = contacts.detect(samples, ids, dt); !st)
        return st;
    }
    else
    {
      parallelBlocks(count, chunk, threads,
                     [&](std::int64_t first, std::int64_t last)
                     {
                       for (std::int64_t i = first; i < last; ++i)
                         strands[i].predictedSamples(contacts.response(int(i)), samples[i]);
                     });
      bool grew = false;
      if (Status st = contacts.extend(samples, grew); !st)
        return st;
      if (!grew)
        break;
    }
    parallelBlocks(count, chunk, threads,
                   [&](std::int64_t first, std::int64_t last)
                   {
                     for (std::int64_t i = first; i < last; ++i)
                     {
                       const std::vector<int>& coupling = contacts.couplingSamples(int(i));
                       if (coupling.empty())
                         compliance[i] = StrandCompliance();
                       else if (coupling != compliance[i].samples)
                         results[i] = strands[i].compliance(coupling, compliance[i]);
                     }
                   });
    if (Status st = firstError(); !st)
      return st;
    if (Status st = contacts.solve(compliance); !st)
      return st;
  }
  parallelBlocks(count, chunk, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   for (std::int64_t i = first; i < last; ++i)
                     results[i] =
                         strands[i].endStep(contacts.couplingSamples(int(i)),
                                            contacts.forces(int(i)), contacts.response(int(i)));
                 });
  return firstError();
}

} // namespace hair
