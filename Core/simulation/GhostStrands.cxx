#include "simulation/GhostStrands.h"

#include "geometry/UniformGrid.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <unordered_map>

namespace hair
{

namespace
{
void append(std::vector<char>& out, const double* values, std::size_t count)
{
  const std::size_t at = out.size();
  out.resize(at + count * sizeof(double));
  if (count > 0)
  {
    std::memcpy(out.data() + at, values, count * sizeof(double));
  }
}
} // namespace

double typicalSpacing(const std::vector<Eigen::Vector3d>& roots)
{
  if (roots.size() < 2)
  {
    return 0;
  }
  // A grid of cells about the size of the mean spacing on the roots' box: each root's
  // nearest other is the first of its two nearest that is not itself.
  Eigen::Vector3d lo = roots[0], hi = roots[0];
  for (const Eigen::Vector3d& r : roots)
  {
    lo = lo.cwiseMin(r);
    hi = hi.cwiseMax(r);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-9);
  const double cell = std::max(extent / std::sqrt(double(roots.size())), extent * 1e-6);
  UniformGrid grid;
  grid.build(roots, cell);
  std::vector<double> nearest(roots.size());
  std::vector<int> found;
  for (std::size_t i = 0; i < roots.size(); ++i)
  {
    grid.nearest(roots[i], 2, found);
    nearest[i] = INFINITY;
    for (int n : found)
      if (n != int(i))
      {
        nearest[i] = (roots[n] - roots[i]).norm();
        break;
      }
  }
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

void GhostStrands::plan(const std::vector<Eigen::Vector3d>& roots, const std::vector<int>& owner,
                        int rank, double reach)
{
  Partners.clear();
  Send.clear();
  Receive.clear();
  Ghosts.clear();
  if (!(reach > 0) || roots.empty())
  {
    return;
  }
  UniformGrid grid;
  grid.build(roots, reach);
  std::map<int, std::set<std::int64_t>> send, receive;
  for (std::size_t k = 0; k < roots.size(); ++k)
  {
    if (owner[k] != rank)
    {
      continue;
    }
    grid.forEachWithin(roots[k], reach,
                       [&](int n)
                       {
                         if (owner[n] != rank)
                         {
                           receive[owner[n]].insert(std::int64_t(n));
                           send[owner[n]].insert(std::int64_t(k));
                         }
                       });
  }
  for (const auto& [partner, strands] : receive)
  {
    Partners.push_back(partner);
    Receive.emplace_back(strands.begin(), strands.end());
    Send.emplace_back(send[partner].begin(), send[partner].end());
    Ghosts.insert(Ghosts.end(), strands.begin(), strands.end());
  }
  std::sort(Ghosts.begin(), Ghosts.end());
}

Status GhostStrands::exchange(const Ranks& ranks, const StateHeader& run, const StateHeader& mine,
                              const StateFrame& piece, StateFrame& ghosts) const
{
  // Strand k of `h` in `f`, packed: its rows of every array of the frame's schema
  // (frameFields(), then the per-point scalars), in that order.
  auto pack = [&](const StateHeader& h, const StateFrame& f, std::size_t k, std::vector<char>& out)
  {
    forEachArray(h, f,
                 [&](const FrameArray& a)
                 {
                   const auto [first, count] = a.strandSpan(h, k);
                   append(out, a.data + first, count);
                 });
  };
  std::unordered_map<std::int64_t, std::size_t> place; // own strand number -> index in `mine`
  for (std::size_t k = 0; k < mine.numberOfStrands(); ++k)
  {
    place[mine.strandId(k)] = k;
  }
  std::vector<std::vector<char>> out(Partners.size()), in;
  for (std::size_t p = 0; p < Partners.size(); ++p)
  {
    for (std::int64_t id : Send[p])
    {
      pack(mine, piece, place.at(id), out[p]);
    }
  }
  ranks.exchange(Partners, out, in);

  // The ghosts' frame, strand by strand in increasing numbers.
  const StateHeader h = run.piece(Ghosts);
  ghosts = StateFrame();
  ghosts.time = piece.time;
  forEachArray(h, ghosts, true, [](const FrameArray&) {});
  std::unordered_map<std::int64_t, std::size_t> ghostPlace;
  for (std::size_t k = 0; k < Ghosts.size(); ++k)
  {
    ghostPlace[Ghosts[k]] = k;
  }
  Status received = Status::Ok();
  for (std::size_t p = 0; p < Partners.size() && received; ++p)
  {
    std::size_t at = 0;
    auto take = [&](double* to, std::size_t count) -> bool
    {
      if (at + count * sizeof(double) > in[p].size())
      {
        return false;
      }
      if (count > 0)
      {
        std::memcpy(to, in[p].data() + at, count * sizeof(double));
      }
      at += count * sizeof(double);
      return true;
    };
    for (std::int64_t id : Receive[p])
    {
      const std::size_t k = ghostPlace.at(id);
      bool ok = true;
      forEachArray(h, ghosts, false,
                   [&](const FrameArray& a)
                   {
                     const auto [first, count] = a.strandSpan(h, k);
                     ok = ok && take(a.data + first, count);
                   });
      if (!ok)
      {
        received = Status::Error("the ghost strands from rank " + std::to_string(Partners[p]) +
                                 " came short: the ranks' runs differ.");
        break;
      }
    }
  }
  return ranks.agree(received);
}

} // namespace hair
