#pragma once
// The processes (MPI ranks) that share a run: under `mpirun -np N pvbatch`, each rank steps
// its share of the strands, and the few numbers that concern the whole run (energy totals,
// the deepest point, a failure on one rank) are combined here. Without MPI, or on one rank,
// every call is a no-op on this process alone, so Core's callers need not know whether they
// run under MPI. Every call named collective must be made by every rank, in the same order.
#include "common/Status.h"

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

class Ranks
{
public:
  /// This process alone (no MPI call is ever made).
  Ranks() = default;
  /// The processes of `comm` (collective over it: duplicated, so that Core's messages never
  /// meet the caller's; freed with the last copy). MPI_COMM_NULL, or MPI not initialized:
  /// this process alone.
  explicit Ranks(MPI_Comm comm);

  int rank() const { return Rank; }
  int size() const { return Size; }
  /// More than one process.
  bool parallel() const { return Size > 1; }
  /// Collective: the ranks that say `member`, in the same order (on a rank that does not:
  /// this process alone). What a model is given, so that its collective calls are made by
  /// the ranks that hold strands.
  Ranks subset(bool member) const;
  /// The communicator (MPI_COMM_NULL for this process alone).
  MPI_Comm comm() const;

  /// Collective: every rank's status in, on every rank the first failure's (the lowest rank
  /// that failed), its message prefixed with "rank r of N: ", or Ok when none failed. Where
  /// ranks could take different paths (a step that fails on one rank, a write one rank
  /// refuses), this keeps every rank on the same one: stopped together, never waiting for
  /// a rank that left.
  Status agree(const Status& mine) const;
  /// Collective: whether any rank says yes (an abort asked on one rank).
  bool any(bool mine) const;

  /// Collective element-wise reductions, in place; every rank gives the same count.
  void sum(double* values, int count) const;
  void sum(std::int64_t* values, int count) const;
  void max(double* values, int count) const;
  void min(double* values, int count) const;
  double sum(double value) const;
  double max(double value) const;

  /// Collective: every rank's values, concatenated in rank order, on every rank.
  std::vector<double> gather(const std::vector<double>& mine) const;
  std::vector<std::int64_t> gather(const std::vector<std::int64_t>& mine) const;
  /// Collective: what `root` gives, on every rank.
  void broadcast(std::vector<double>& values, int root) const;

  /// Sends `out[i]` to rank partners[i] and returns in `in[i]` what that rank sent here
  /// (bytes). Partners must be mutual (a rank that lists b is listed by b) and not this
  /// rank; each pair exchanges a count and then, if not empty, the bytes: 2 messages each
  /// way per partner, nothing with other ranks.
  void exchange(const std::vector<int>& partners, const std::vector<std::vector<char>>& out,
                std::vector<std::vector<char>>& in) const;

  void barrier() const;

private:
  struct Comm;
  std::shared_ptr<Comm> Shared;
  int Rank = 0, Size = 1;
};

} // namespace hair
