#include "common/Ranks.h"

#include <algorithm>

namespace hair
{

struct Ranks::Comm
{
  MPI_Comm Handle = MPI_COMM_NULL;
  ~Comm()
  {
    int finalized = 1;
    MPI_Finalized(&finalized);
    if (!finalized && Handle != MPI_COMM_NULL)
    {
      MPI_Comm_free(&Handle);
    }
  }
};

Ranks::Ranks(MPI_Comm comm)
{
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized || comm == MPI_COMM_NULL)
  {
    return;
  }
  auto c = std::make_shared<Comm>();
  MPI_Comm_dup(comm, &c->Handle);
  MPI_Comm_rank(c->Handle, &Rank);
  MPI_Comm_size(c->Handle, &Size);
  Shared = std::move(c);
}

Ranks Ranks::subset(bool member) const
{
  if (!Shared)
  {
    return Ranks();
  }
  MPI_Comm sub = MPI_COMM_NULL;
  MPI_Comm_split(Shared->Handle, member ? 0 : MPI_UNDEFINED, Rank, &sub);
  if (sub == MPI_COMM_NULL)
  {
    return Ranks();
  }
  Ranks r;
  auto c = std::make_shared<Comm>();
  c->Handle = sub; // freed with the last copy, as a duplicate is
  MPI_Comm_rank(sub, &r.Rank);
  MPI_Comm_size(sub, &r.Size);
  r.Shared = std::move(c);
  return r;
}

MPI_Comm Ranks::comm() const
{
  return Shared ? Shared->Handle : MPI_COMM_NULL;
}

Status Ranks::agree(const Status& mine) const
{
  if (!Shared)
  {
    return mine;
  }
  int first = mine ? Size : Rank;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, Shared->Handle);
  if (first == Size)
  {
    return Status::Ok();
  }
  std::string message = first == Rank ? mine.message() : std::string();
  long length = static_cast<long>(message.size());
  MPI_Bcast(&length, 1, MPI_LONG, first, Shared->Handle);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), static_cast<int>(length), MPI_CHAR, first, Shared->Handle);
  if (Size == 1)
  {
    return Status::Error(message);
  }
  return Status::Error("rank " + std::to_string(first) + " of " + std::to_string(Size) + ": " +
                       message);
}

bool Ranks::any(bool mine) const
{
  if (!Shared)
  {
    return mine;
  }
  int flag = mine ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_MAX, Shared->Handle);
  return flag != 0;
}

void Ranks::sum(double* values, int count) const
{
  if (Shared && count > 0)
  {
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, Shared->Handle);
  }
}

void Ranks::sum(std::int64_t* values, int count) const
{
  if (Shared && count > 0)
  {
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_INT64_T, MPI_SUM, Shared->Handle);
  }
}

void Ranks::max(double* values, int count) const
{
  if (Shared && count > 0)
  {
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_MAX, Shared->Handle);
  }
}

void Ranks::min(double* values, int count) const
{
  if (Shared && count > 0)
  {
    MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_MIN, Shared->Handle);
  }
}

double Ranks::sum(double value) const
{
  sum(&value, 1);
  return value;
}

double Ranks::max(double value) const
{
  max(&value, 1);
  return value;
}

namespace
{
template <typename T>
std::vector<T> gatherAll(MPI_Comm comm, int size, const std::vector<T>& mine, MPI_Datatype type)
{
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), displacements(size, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r)
  {
    displacements[r] = displacements[r - 1] + counts[r - 1];
  }
  std::vector<T> all(static_cast<std::size_t>(displacements.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, type, all.data(), counts.data(), displacements.data(), type,
                 comm);
  return all;
}
} // namespace

std::vector<double> Ranks::gather(const std::vector<double>& mine) const
{
  return Shared ? gatherAll(Shared->Handle, Size, mine, MPI_DOUBLE) : mine;
}

std::vector<std::int64_t> Ranks::gather(const std::vector<std::int64_t>& mine) const
{
  return Shared ? gatherAll(Shared->Handle, Size, mine, MPI_INT64_T) : mine;
}

void Ranks::broadcast(std::vector<double>& values, int root) const
{
  if (!Shared)
  {
    return;
  }
  long count = static_cast<long>(values.size());
  MPI_Bcast(&count, 1, MPI_LONG, root, Shared->Handle);
  values.resize(static_cast<std::size_t>(count));
  MPI_Bcast(values.data(), static_cast<int>(count), MPI_DOUBLE, root, Shared->Handle);
}

void Ranks::exchange(const std::vector<int>& partners, const std::vector<std::vector<char>>& out,
                     std::vector<std::vector<char>>& in) const
{
  const std::size_t n = partners.size();
  in.assign(n, {});
  if (!Shared || n == 0)
  {
    return;
  }
  const MPI_Comm c = Shared->Handle;
  constexpr int CountTag = 7301, DataTag = 7302;
  std::vector<long> sizesOut(n), sizesIn(n);
  std::vector<MPI_Request> requests;
  requests.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    sizesOut[i] = static_cast<long>(out[i].size());
    requests.emplace_back();
    MPI_Irecv(&sizesIn[i], 1, MPI_LONG, partners[i], CountTag, c, &requests.back());
    requests.emplace_back();
    MPI_Isend(&sizesOut[i], 1, MPI_LONG, partners[i], CountTag, c, &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  requests.clear();
  for (std::size_t i = 0; i < n; ++i)
  {
    in[i].resize(static_cast<std::size_t>(sizesIn[i]));
    if (sizesIn[i] > 0)
    {
      requests.emplace_back();
      MPI_Irecv(in[i].data(), static_cast<int>(sizesIn[i]), MPI_BYTE, partners[i], DataTag, c,
                &requests.back());
    }
    if (sizesOut[i] > 0)
    {
      requests.emplace_back();
      MPI_Isend(out[i].data(), static_cast<int>(sizesOut[i]), MPI_BYTE, partners[i], DataTag, c,
                &requests.back());
    }
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

void Ranks::barrier() const
{
  if (Shared)
  {
    MPI_Barrier(Shared->Handle);
  }
}

} // namespace hair
