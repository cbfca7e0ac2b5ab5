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

namespace
{
// The strands of a step on the run's threads: chunks of consecutive strands (8, fewer when
// there are few strands: at least four chunks per thread), each strand's status kept, the
// first error in strand order reported.
struct StrandJobs
{
  int count, threads, chunk;
  std::vector<Status> results;
  StrandJobs(std::size_t strands, int wanted)
      : count(static_cast<int>(strands)), threads(std::max(1, std::min(wanted, count))),
        chunk(std::max(1, std::min(8, count / (4 * threads)))), results(strands)
  {
  }
  Status firstError() const
  {
    for (const Status& s : results)
      if (!s)
        return s;
    return Status::Ok();
  }
};
} // namespace

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
  // Threads take chunks of consecutive strands, so that the strand after the current one
  // in a chunk is stepped by the same thread, later: while one strand computes, the next
  // one's samples are brought in from memory (a strand's data is not in cache when
  // hundreds are stepped in turn, and its loads are too scattered for the hardware's
  // prefetcher). Prefetching a strand another thread may be stepping would read its
  // buffers while they are swapped.
  StrandJobs jobs(strands.size(), threads);
  std::vector<Status>& results = jobs.results;
  parallelBlocks(jobs.count, jobs.chunk, jobs.threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   for (std::int64_t i = first; i < last; ++i)
                   {
                     if (i + 1 < last)
                       strands[i + 1].prefetch();
                     results[i] = strands[i].advance(dt, tolerance);
                   }
                 });
  if (Status s = jobs.firstError(); !s)
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
  StrandJobs jobs(strands.size(), threads);
  const int count = jobs.count, chunk = jobs.chunk;
  threads = jobs.threads;
  std::vector<Status>& results = jobs.results;
  auto firstError = [&]() { return jobs.firstError(); };
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

Status stepStrandsWithNearField(std::vector<SuperHelix>& strands, NearFieldContacts& near,
                                double dt, int threads, const Eigen::Isometry3d& carry)
{
  StrandJobs jobs(strands.size(), threads);
  const int count = jobs.count, chunk = jobs.chunk;
  threads = jobs.threads;
  std::vector<Status>& results = jobs.results;
  auto firstError = [&]() { return jobs.firstError(); };
  // Every strand's step without the pairs' forces (the far field and the body are in it),
  // and its material nodes: where they are, where that step takes them.
  std::vector<std::vector<double>> arcs(strands.size());
  std::vector<std::vector<StrandSample>> nodes(strands.size());
  std::vector<std::vector<Eigen::Vector3d>> startVelocities(strands.size());
  std::vector<int> ids(strands.size());
  parallelBlocks(count, chunk, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   std::vector<StrandSample> now;
                   for (std::int64_t i = first; i < last; ++i)
                   {
                     if (i + 1 < last)
                       strands[i + 1].prefetch();
                     results[i] = strands[i].beginStep(dt);
                     if (!results[i])
                       continue;
                     arcs[i] = near.nodeArcLengths(strands[i].length());
                     strands[i].materialPoints(arcs[i], true, nodes[i]);
                     strands[i].materialPoints(arcs[i], false, now);
                     startVelocities[i].resize(now.size());
                     for (std::size_t k = 0; k < now.size(); ++k)
                       startVelocities[i][k] = now[k].velocity;
                     ids[i] = strands[i].spec().id;
                   }
                 });
  if (Status st = firstError(); !st)
    return st;
  // The pairs that act; their forces with the compliances of the strands they load (at the
  // nodes, exact); every strand's step ended with them.
  if (Status st = near.detect(nodes, ids, dt, carry, &startVelocities); !st)
    return st;
  std::vector<Eigen::MatrixXd> delassus(strands.size()), response(strands.size());
  parallelBlocks(count, chunk, threads,
                 [&](std::int64_t first, std::int64_t last)
                 {
                   std::vector<std::array<double, 2>> s, w;
                   std::vector<Eigen::Vector3d> d;
                   for (std::int64_t i = first; i < last; ++i)
                   {
                     const std::vector<NearFieldLoad>& loads = near.loads(int(i));
                     if (loads.empty())
                       continue;
                     s.resize(loads.size());
                     w.resize(loads.size());
                     d.resize(loads.size());
                     for (std::size_t l = 0; l < loads.size(); ++l)
                     {
                       s[l] = {loads[l].s[0], loads[l].s[1]};
                       w[l] = {loads[l].weight[0], loads[l].weight[1]};
                       d[l] = loads[l].direction;
                     }
                     results[i] = strands[i].loadCompliance(s, w, d, delassus[i], response[i]);
                   }
                 });
  if (Status st = firstError(); !st)
    return st;
  if (Status st = near.solve(delassus); !st)
    return st;
  parallelBlocks(
      count, chunk, threads,
      [&](std::int64_t first, std::int64_t last)
      {
        for (std::int64_t i = first; i < last; ++i)
        {
          const std::vector<NearFieldLoad>& loads = near.loads(int(i));
          if (loads.empty())
          {
            results[i] = strands[i].endStep({}, {}, Eigen::VectorXd());
            continue;
          }
          // The step's velocities are exact (Y λ, from the loads' compliance); the forces
          // enter the strand's energy flows at the samples around each load's point, split
          // by arc length.
          const std::vector<double>& lambda = near.loadForces(int(i));
          const Eigen::VectorXd dq =
              response[i] * Eigen::Map<const Eigen::VectorXd>(lambda.data(), lambda.size());
          const std::vector<StrandSample>& q = strands[i].samples();
          std::vector<int> at;
          std::vector<Eigen::Vector3d> forces;
          auto add = [&](double sk, const Eigen::Vector3d& f)
          {
            const auto it = std::upper_bound(
                q.begin(), q.end(), sk, [](double x, const StrandSample& y) { return x < y.s; });
            const int j =
                std::clamp(static_cast<int>(it - q.begin()) - 1, 0, static_cast<int>(q.size()) - 2);
            const double t = std::clamp((sk - q[j].s) / (q[j + 1].s - q[j].s), 0.0, 1.0);
            for (int e = 0; e < 2; ++e)
            {
              const int sample = j + e;
              const Eigen::Vector3d part = (e == 0 ? 1 - t : t) * f;
              const auto pos = std::lower_bound(at.begin(), at.end(), sample);
              if (pos != at.end() && *pos == sample)
                forces[pos - at.begin()] += part;
              else
              {
                forces.insert(forces.begin() + (pos - at.begin()), part);
                at.insert(pos, sample);
              }
            }
          };
          for (std::size_t l = 0; l < loads.size(); ++l)
            for (int e = 0; e < 2; ++e)
              if (loads[l].weight[e] != 0)
                add(loads[l].s[e], (lambda[l] * loads[l].weight[e]) * loads[l].direction);
          results[i] = strands[i].endStep(at, forces, dq);
        }
      });
  return firstError();
}

} // namespace hair
