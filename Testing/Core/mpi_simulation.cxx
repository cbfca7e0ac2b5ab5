// hair::Simulation under MPI, in Core: the strands shared among ranks by their roots and
// costs, the same run on 1, 2 and 4 ranks giving the same strands bit for bit (without
// hair–hair contacts each strand's step depends on nothing else), the energy totals equal to
// round-off, the one state file written by every rank reading back the same, more ranks
// than strands, a rank without strands, a failure on one rank stopping every rank, and a
// run streamed through the shared file. CTest runs it under mpirun on 4 ranks
// (Testing/CMakeLists.txt, mpi.mpi_simulation); the runs on fewer ranks use the first ranks
// of the world, the others waiting.
#include "DemoScene.h"
#include "analysis/StrandAnalysis.h"
#include "common/Partition.h"
#include "common/Ranks.h"
#include "io/StateFile.h"
#include "simulation/GhostStrands.h"
#include "simulation/GuideDrawing.h"
#include "simulation/Simulation.h"
#include "superhelixmodel/SuperHelixModel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <mpi.h>
#include <random>
#include <set>

using namespace hair;

namespace
{
int worldRank()
{
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int worldSize()
{
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

/// The first `n` ranks of the world as a run's ranks (collective over the world); the other
/// ranks are not members.
struct FirstRanks
{
  bool member = false;
  Ranks ranks;
};

FirstRanks firstRanks(int n)
{
  const int rank = worldRank();
  MPI_Comm c = MPI_COMM_NULL;
  MPI_Comm_split(MPI_COMM_WORLD, rank < n ? 0 : MPI_UNDEFINED, rank, &c);
  FirstRanks f;
  f.member = c != MPI_COMM_NULL;
  if (f.member)
  {
    f.ranks = Ranks(c);
    MPI_Comm_free(&c);
  }
  return f;
}

std::string temp(const std::string& name)
{
  return ::testing::TempDir() + "hair_mpi_" + name;
}

const BundledBody& body()
{
  static BundledBody b;
  static bool loaded = loadBundledBody(HAIR_DATA_DIR, b).ok();
  EXPECT_TRUE(loaded);
  return b;
}

/// `count` of the demo's guides of `elements` elements, the four presets in turn (strands
/// of different costs), on the demo's scene.
std::vector<GuideStrand> mixedGuides(int count, int elements)
{
  std::vector<GuideStrand> g;
  EXPECT_TRUE(demoGuides(body(), count, elements, g).ok());
  for (std::size_t k = 0; k < g.size(); ++k)
  {
    g[k].hair = HairParameters::preset(static_cast<HairType>(k % 4));
  }
  return g;
}

/// Every strand's numbers in a frame, by its number in the run: its points, velocities, q,
/// q̇, root pose and rates and per-point arrays, one after the other.
using Strands = std::map<std::int64_t, std::vector<double>>;

/// This rank's piece of a frame as (strand number, length, numbers …) records, gathered
/// from every rank of `ranks`.
Strands gatherStrands(const StateHeader& piece, const StateFrame& f, const Ranks& ranks)
{
  std::vector<double> mine;
  const std::size_t c = std::size_t(piece.coordinatesPerStrand);
  for (std::size_t k = 0; k < piece.numberOfStrands(); ++k)
  {
    std::vector<double> v;
    for (std::int64_t i = piece.offsets[k]; i < piece.offsets[k + 1]; ++i)
    {
      v.insert(v.end(), f.positions[i].data(), f.positions[i].data() + 3);
      v.insert(v.end(), f.velocities[i].data(), f.velocities[i].data() + 3);
      for (const auto& [name, values] : f.pointData)
      {
        v.push_back(values[i]);
      }
    }
    v.insert(v.end(), f.q.begin() + k * c, f.q.begin() + (k + 1) * c);
    v.insert(v.end(), f.qdot.begin() + k * c, f.qdot.begin() + (k + 1) * c);
    if (!f.rootFrames.empty())
    {
      v.insert(v.end(), f.rootFrames.begin() + k * RootFrameValues,
               f.rootFrames.begin() + (k + 1) * RootFrameValues);
      v.insert(v.end(), f.rootVelocities.begin() + k * RootVelocityValues,
               f.rootVelocities.begin() + (k + 1) * RootVelocityValues);
    }
    mine.push_back(double(piece.strandId(k)));
    mine.push_back(double(v.size()));
    mine.insert(mine.end(), v.begin(), v.end());
  }
  const std::vector<double> all = ranks.gather(mine);
  Strands out;
  for (std::size_t i = 0; i < all.size();)
  {
    const auto id = static_cast<std::int64_t>(all[i]);
    const auto n = static_cast<std::size_t>(all[i + 1]);
    out[id].assign(all.begin() + std::ptrdiff_t(i + 2), all.begin() + std::ptrdiff_t(i + 2 + n));
    i += 2 + n;
  }
  return out;
}

/// What a run gives: every frame's strands, and its energy table.
struct Outcome
{
  std::vector<Strands> frames;
  std::vector<double> times;
  std::map<std::string, std::vector<double>> table;
  std::vector<int> strandsPerRank;
  Status status;
};

/// The run on `ranks`, `frames` frames, its state file at `file` (none if empty).
/// With `resume`, the run of `file` resumed (docs/state-file.md, "Resuming a run") to
/// `frames` frames.
Outcome run(const std::vector<GuideStrand>& guides, SimulationOptions options, const Ranks& ranks,
            int frames, const std::string& file = {}, double memoryBudget = 1e12,
            bool resume = false)
{
  Outcome r;
  options.ranks = ranks;
  StorageOptions storage;
  storage.stateFile = file;
  storage.replaceStateFile = true;
  storage.frames = frames;
  storage.memoryBudget = memoryBudget;
  storage.resume = resume;
  Simulation sim;
  r.status = sim.initialize(guides, demoScene(body()), options, storage);
  r.status = r.status ? sim.advanceTo(frames) : r.status;
  if (!r.status)
  {
    return r;
  }
  for (int f = 0; f < sim.numberOfFrames(); ++f)
  {
    StateFrame frame;
    EXPECT_TRUE(sim.readFrame(f, frame).ok());
    r.frames.push_back(gatherStrands(sim.piece(), frame, ranks));
  }
  sim.energyTable(r.times, r.table);
  std::vector<std::int64_t> count{std::int64_t(sim.piece().numberOfStrands())};
  for (std::int64_t n : ranks.gather(count))
  {
    r.strandsPerRank.push_back(int(n));
  }
  return r;
}

/// The largest difference between two runs' strands (every number of every strand of every
/// frame; infinity when they hold different strands or frames).
double largestDifference(const Outcome& a, const Outcome& b)
{
  if (a.frames.size() != b.frames.size())
  {
    return INFINITY;
  }
  double worst = 0;
  for (std::size_t f = 0; f < a.frames.size(); ++f)
  {
    if (a.frames[f].size() != b.frames[f].size())
    {
      return INFINITY;
    }
    for (const auto& [id, values] : a.frames[f])
    {
      const auto it = b.frames[f].find(id);
      if (it == b.frames[f].end() || it->second.size() != values.size())
      {
        return INFINITY;
      }
      for (std::size_t i = 0; i < values.size(); ++i)
      {
        worst = std::max(worst, std::abs(values[i] - it->second[i]));
      }
    }
  }
  return worst;
}

/// Energy tables equal to round-off: each rank adds its strands' terms and the ranks add
/// their sums, so a term is the same sum of S per-strand numbers taken in another order, off
/// by at most (S − 1) u Σ|x_i| (Higham, "Accuracy and Stability of Numerical Algorithms",
/// 2nd ed., §4.2, u = 2^−53). Σ|x_i| is bounded here by the sum of the magnitudes of every
/// term of the frame (each strand's terms are parts of them); nodes_inside and max_depth
/// are a count and a maximum, exact.
void expectSameEnergy(const Outcome& a, const Outcome& b, std::size_t strands)
{
  ASSERT_EQ(a.times, b.times);
  ASSERT_EQ(a.table.size(), b.table.size());
  for (std::size_t f = 0; f < a.times.size(); ++f)
  {
    double scale = 0;
    for (const auto& [name, values] : a.table)
    {
      scale += name == "nodes_inside" || name == "max_depth" ? 0 : std::abs(values[f]);
    }
    const double bound = double(strands) * std::ldexp(1.0, -53) * scale;
    for (const auto& [name, values] : a.table)
    {
      const double other = b.table.at(name)[f];
      if (name == "nodes_inside" || name == "max_depth")
      {
        EXPECT_EQ(values[f], other) << name << " at frame " << f;
      }
      else
      {
        EXPECT_LE(std::abs(values[f] - other), bound) << name << " at frame " << f;
      }
    }
  }
}

/// The run's frames as `file` holds them, read whole by the project's reader.
Outcome readBack(const std::string& file)
{
  Outcome r;
  StateFileReader reader;
  r.status = reader.open(file);
  if (!r.status)
  {
    return r;
  }
  for (std::int64_t f = 0; f < reader.numberOfFrames(); ++f)
  {
    StateFrame frame;
    EXPECT_TRUE(reader.readFrame(f, frame).ok());
    // The Super-Helix's nodes are kept in single precision: drawn again from the state, the
    // file's frame is the run's bit for bit.
    EXPECT_TRUE(restoreNodes(reader.header(), frame).ok());
    r.frames.push_back(gatherStrands(reader.header(), frame, Ranks()));
    r.times.push_back(frame.time);
  }
  r.table = reader.energies();
  return r;
}

SimulationOptions optionsFor(ModelType model)
{
  SimulationOptions o;
  o.model = model;
  o.contacts.enabled = true;
  return o;
}

/// The rank tests' guides for `model`: mixedGuides at 5 elements; the rods at 20 edges,
/// smooth and wavy (the wavy preset's curl needs 17 edges, the curly and fuzzy presets' 27
/// and 46: DerSpec::MaxRestTurn).
std::vector<GuideStrand> rankGuides(ModelType model, int count)
{
  const bool rods = model == ModelType::DiscreteElasticRods;
  std::vector<GuideStrand> guides = mixedGuides(count, rods ? 20 : 5);
  for (std::size_t k = 0; rods && k < guides.size(); ++k)
  {
    guides[k].hair = HairParameters::preset(k % 2 ? HairType::Wavy : HairType::Smooth);
  }
  return guides;
}

/// A test's name for the model: its label's letters and digits ("DiscreteElasticRods").
std::string modelTestName(ModelType model)
{
  std::string name;
  for (const char* c = findModel(model)->label; *c; ++c)
  {
    if (std::isalnum(static_cast<unsigned char>(*c)))
    {
      name += *c;
    }
  }
  return name;
}
} // namespace

TEST(Partition, RangesOfTheCurveBalanceWeightsInCompactParts)
{
  // A 20 × 10 grid of points, weight 1 on the left half and 3 on the right (400 in all):
  // 3 parts.
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int i = 0; i < 20; ++i)
  {
    for (int j = 0; j < 10; ++j)
    {
      points.emplace_back(0.01 * i, 0.01 * j, 0);
      weights.push_back(i < 10 ? 1.0 : 3.0);
    }
  }
  const std::vector<int> part = shareAlongCurve(points, weights, 3);
  std::vector<double> load(3, 0);
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    load[part[k]] += weights[k];
  }
  // Each part gets its share (400 / 3) to within one point's weight (3).
  for (double l : load)
  {
    EXPECT_NEAR(l, 400.0 / 3, 3.0);
  }
  // Compact: grid neighbours in different parts. Two straight cuts across the 10-point side
  // (what coordinate bisection gives) part 20 pairs; a range of a Hilbert curve is a blocky
  // region, its boundary a few times that: at most 40 here. (Three ranges of a row-by-row
  // scan would part 60, of a random order about 250 of the 370 pairs.)
  int parted = 0;
  for (int i = 0; i < 20; ++i)
  {
    for (int j = 0; j < 10; ++j)
    {
      const int k = 10 * i + j;
      parted += (i + 1 < 20 && part[k] != part[k + 10]) + (j + 1 < 10 && part[k] != part[k + 1]);
    }
  }
  EXPECT_LE(parted, 40);
  RecordProperty("neighbour_pairs_parted", std::to_string(parted));
  EXPECT_EQ(part, shareAlongCurve(points, weights, 3)); // deterministic
  // Along the curve the parts never decrease: points numbered in the curve's order (as grown
  // guides are) get parts of consecutive numbers.
  const std::vector<std::size_t> order = spaceFillingOrder(points);
  std::vector<Eigen::Vector3d> sorted;
  std::vector<double> sortedWeights;
  for (std::size_t k : order)
  {
    sorted.push_back(points[k]);
    sortedWeights.push_back(weights[k]);
  }
  const std::vector<int> ranges = shareAlongCurve(sorted, sortedWeights, 3);
  EXPECT_TRUE(std::is_sorted(ranges.begin(), ranges.end()));
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    EXPECT_EQ(ranges[i], part[order[i]]);
  }
}

TEST(Partition, TheCurveVisitsQuadrantsInTurn)
{
  // A Hilbert curve through a square visits its quadrants one after the other: four equal
  // ranges of a 16 × 16 grid are its four 8 × 8 quadrants (the grid's cells do not fall on
  // the curve's own cells exactly, so a quadrant's box may grow by a row: at most 9 × 9).
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 16; ++i)
  {
    for (int j = 0; j < 16; ++j)
    {
      points.emplace_back(i, j, 0);
    }
  }
  const std::vector<int> part = shareAlongCurve(points, std::vector<double>(256, 1.0), 4);
  std::vector<Eigen::Vector3d> lo(4, Eigen::Vector3d::Constant(1e9)), hi(4, -lo[0]);
  std::vector<int> count(4, 0);
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    lo[part[k]] = lo[part[k]].cwiseMin(points[k]);
    hi[part[k]] = hi[part[k]].cwiseMax(points[k]);
    ++count[part[k]];
  }
  for (int p = 0; p < 4; ++p)
  {
    EXPECT_EQ(count[p], 64);
    EXPECT_LE(hi[p].x() - lo[p].x(), 8.0) << "part " << p;
    EXPECT_LE(hi[p].y() - lo[p].y(), 8.0) << "part " << p;
  }
}

TEST(Partition, FewerPointsThanPartsLeavesPartsEmpty)
{
  const std::vector<Eigen::Vector3d> one{Eigen::Vector3d(1, 2, 3)};
  EXPECT_EQ(shareAlongCurve(one, {1.0}, 4), std::vector<int>{3});
  const std::vector<Eigen::Vector3d> three{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                           Eigen::Vector3d(2, 0, 0)};
  const std::vector<int> part = shareAlongCurve(three, {1.0, 1.0, 1.0}, 4);
  EXPECT_EQ(std::set<int>(part.begin(), part.end()).size(), 3u);
}

TEST(Ranks, AFailureOnOneRankReachesEveryRank)
{
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  const Status mine = world.rank() == 1 ? Status::Error("the disk is full") : Status::Ok();
  const Status all = world.agree(mine);
  ASSERT_FALSE(all.ok());
  EXPECT_EQ(all.message(), "rank 1 of " + std::to_string(world.size()) + ": the disk is full");
  EXPECT_TRUE(world.agree(Status::Ok()).ok());
  EXPECT_TRUE(world.any(world.rank() == world.size() - 1));
  EXPECT_FALSE(world.any(false));
}

TEST(Ranks, ExchangeReachesExactlyThePartners)
{
  const Ranks world(MPI_COMM_WORLD);
  const int n = world.size(), r = world.rank();
  if (n < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  // A ring: each rank sends its neighbours its number, as many bytes as the neighbour's.
  std::vector<int> partners{(r + 1) % n};
  if (n > 2)
  {
    partners.push_back((r + n - 1) % n);
  }
  std::vector<std::vector<char>> out, in;
  for (int p : partners)
  {
    out.emplace_back(std::size_t(p + 1), char('a' + r));
  }
  world.exchange(partners, out, in);
  ASSERT_EQ(in.size(), partners.size());
  for (std::size_t i = 0; i < partners.size(); ++i)
  {
    EXPECT_EQ(in[i], std::vector<char>(std::size_t(r + 1), char('a' + partners[i])));
  }
}

class RankIndependence : public ::testing::TestWithParam<ModelType>
{
};

TEST_P(RankIndependence, OneTwoAndFourRanksGiveTheSameStrandsAndTheSameFile)
{
  if (worldSize() < 4)
  {
    GTEST_SKIP() << "needs 4 ranks (mpirun -np 4)";
  }
  const ModelType model = GetParam();
  const std::vector<GuideStrand> guides = rankGuides(model, 24);
  const SimulationOptions options = optionsFor(model);
  const int frames = 10;
  const char* name = findModel(model)->name;
  std::map<int, Outcome> runs, files;
  for (int n : {1, 2, 4})
  {
    const FirstRanks sub = firstRanks(n);
    const std::string file = temp(std::string(name) + "_" + std::to_string(n) + ".h5");
    // No ASSERT until every collective call is made: a rank leaving early would leave the
    // others waiting.
    if (sub.member)
    {
      runs[n] = run(guides, options, sub.ranks, frames, file);
      EXPECT_TRUE(runs[n].status.ok()) << runs[n].status.message();
    }
    MPI_Barrier(MPI_COMM_WORLD);
    if (worldRank() == 0)
    {
      files[n] = readBack(file);
      EXPECT_TRUE(files[n].status.ok()) << files[n].status.message();
    }
  }
  if (worldRank() != 0)
  {
    return;
  }
  for (int n : {1, 2, 4})
  {
    ASSERT_TRUE(runs[n].status.ok() && files[n].status.ok());
  }
  // Shared by cost, every rank got strands (24 strands of four costs on 2 and 4 ranks).
  EXPECT_EQ(runs[2].strandsPerRank.size(), 2u);
  EXPECT_EQ(runs[4].strandsPerRank.size(), 4u);
  for (int n : {2, 4})
  {
    for (int count : runs[n].strandsPerRank)
    {
      EXPECT_GT(count, 0);
    }
    EXPECT_EQ(largestDifference(runs[1], runs[n]), 0.0) << n << " ranks";
    expectSameEnergy(runs[1], runs[n], guides.size());
    EXPECT_EQ(largestDifference(runs[1], files[n]), 0.0) << "the file of " << n << " ranks";
  }
  EXPECT_EQ(largestDifference(runs[1], files[1]), 0.0);
  for (int n : {1, 2, 4})
  {
    // The file holds what the run computed: its times and energy terms exactly.
    EXPECT_EQ(files[n].times, runs[n].times);
    for (const auto& [term, values] : files[n].table)
    {
      EXPECT_EQ(values, runs[n].table.at(term)) << term << ", the file of " << n << " ranks";
    }
  }
  std::printf("%s: strands per rank on 2 ranks %d %d, on 4 ranks %d %d %d %d; largest "
              "difference from 1 rank 0\n",
              name, runs[2].strandsPerRank[0], runs[2].strandsPerRank[1], runs[4].strandsPerRank[0],
              runs[4].strandsPerRank[1], runs[4].strandsPerRank[2], runs[4].strandsPerRank[3]);
}

namespace
{
/// A run of `frames` frames into `file`, stopped after `stop` of them (collective).
Status stopped(const std::vector<GuideStrand>& guides, SimulationOptions o, const Ranks& ranks,
               int frames, int stop, const std::string& file)
{
  o.ranks = ranks;
  StorageOptions storage;
  storage.stateFile = file;
  storage.replaceStateFile = true;
  storage.frames = frames;
  Simulation sim;
  Status s = sim.initialize(guides, demoScene(body()), o, storage);
  return s ? sim.advanceTo(stop) : s;
}
} // namespace

TEST(Resume, ARunStoppedAtRandomFramesGoesOnBitForBitOnTheSameRanks)
{
  // Every rank of the world (2 or 4), the Super-Helix with the grid (on by default) and
  // static friction (anchors): stopped after a random frame (its writer closed as a
  // wall-time limit's SIGTERM would), resumed, equal to the unbroken run. The kill itself
  // is mpi.killed_run's (SIGKILL to mpirun and every rank).
  const FirstRanks all = firstRanks(worldSize());
  const std::vector<GuideStrand> guides = mixedGuides(24, 8);
  SimulationOptions o = optionsFor(ModelType::SuperHelix);
  o.contacts.staticFriction = 0.4;
  const int frames = 14;
  const Outcome whole = run(guides, o, all.ranks, frames, temp("resume_whole.h5"));
  ASSERT_TRUE(whole.status.ok()) << whole.status.message();
  std::mt19937 random(34); // the same frames on every rank
  for (int trial = 0; trial < 10; ++trial)
  {
    const int stop = std::uniform_int_distribution<int>(1, frames - 1)(random);
    const std::string file = temp("resume_stopped.h5");
    const Status first = stopped(guides, o, all.ranks, frames, stop, file);
    const Outcome resumed = run(guides, o, all.ranks, frames, file, 1e12, true);
    ASSERT_TRUE(first.ok() && resumed.status.ok()) << resumed.status.message();
    EXPECT_EQ(largestDifference(whole, resumed), 0.0) << "stopped after " << stop << " frames";
    EXPECT_EQ(resumed.times, whole.times);
    EXPECT_EQ(resumed.table.at("kinetic"), whole.table.at("kinetic"));
  }
}

TEST(Resume, AFileGoesOnAsItWasWrittenByOneProcessOrByRanks)
{
  // One process's file grows (SWMR); ranks' files have room from the start: each is resumed
  // as it was written, and the other is refused, saying how, the file left as it was.
  const std::vector<GuideStrand> guides = mixedGuides(8, 5);
  const SimulationOptions o = optionsFor(ModelType::SuperHelix);
  const std::string one = temp("resume_one.h5"), two = temp("resume_two.h5");
  const FirstRanks first = firstRanks(1), pair = firstRanks(2);
  if (first.member)
  {
    EXPECT_TRUE(stopped(guides, o, first.ranks, 6, 3, one).ok());
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (pair.member)
  {
    EXPECT_TRUE(stopped(guides, o, pair.ranks, 6, 3, two).ok());
    const Outcome onRanks = run(guides, o, pair.ranks, 6, one, 1e12, true);
    EXPECT_NE(onRanks.status.message().find("was written by one process (it grows as frames "
                                            "are added): it is resumed by one process, not by 2 "
                                            "MPI ranks."),
              std::string::npos)
        << onRanks.status.message();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (first.member)
  {
    const Outcome alone = run(guides, o, first.ranks, 6, two, 1e12, true);
    EXPECT_NE(alone.status.message().find("was written by MPI ranks together"), std::string::npos)
        << alone.status.message();
    for (const std::string& file : {one, two})
    {
      StateFileReader r;
      EXPECT_TRUE(r.open(file).ok());
      EXPECT_EQ(r.numberOfFrames(), 3) << file;
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

TEST(Resume, ARunOfTwoRanksGoesOnOnThreeAndFour)
{
  if (worldSize() < 4)
  {
    GTEST_SKIP() << "needs 4 ranks (mpirun -np 4)";
  }
  // The strands' steps do not depend on the ranks (RankIndependence): a file of 2 ranks
  // resumed on 3 or 4 gives the unbroken run's frames, bit for bit, each rank restoring the
  // strands it is given.
  const std::vector<GuideStrand> guides = mixedGuides(24, 5);
  const SimulationOptions o = optionsFor(ModelType::SuperHelix);
  const int frames = 10;
  const FirstRanks all = firstRanks(4);
  const Outcome whole = run(guides, o, all.ranks, frames, temp("resume_whole4.h5"));
  ASSERT_TRUE(whole.status.ok());
  for (int n : {3, 4})
  {
    const std::string file = temp("resume_" + std::to_string(n) + ".h5");
    const FirstRanks two = firstRanks(2);
    if (two.member)
    {
      EXPECT_TRUE(stopped(guides, o, two.ranks, frames, 5, file).ok());
    }
    MPI_Barrier(MPI_COMM_WORLD);
    const FirstRanks more = firstRanks(n);
    if (more.member)
    {
      const Outcome resumed = run(guides, o, more.ranks, frames, file, 1e12, true);
      // No ASSERT between collective calls: a rank leaving early would leave the others
      // waiting.
      EXPECT_TRUE(resumed.status.ok()) << resumed.status.message();
      if (resumed.status.ok())
      {
        EXPECT_EQ(largestDifference(whole, resumed), 0.0) << "resumed on " << n << " ranks";
      }
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
}

std::vector<ModelType> everyModel()
{
  std::vector<ModelType> types;
  for (const ModelEntry& e : registeredModels())
  {
    types.push_back(e.type);
  }
  return types;
}

INSTANTIATE_TEST_SUITE_P(EveryModel, RankIndependence, ::testing::ValuesIn(everyModel()),
                         [](const ::testing::TestParamInfo<ModelType>& info)
                         { return modelTestName(info.param); });

TEST(StepStatistics, TheEnergyTablesStatisticsAreTheWholeRuns)
{
  // The second-order step with a tolerance: strands take different numbers of sub-steps,
  // some first order. On 2 ranks the strands are the same bit for bit, and the table's
  // statistics are the whole run's, not rank 0's: the mean sub-steps and rejections over
  // every strand and the share of first-order steps equal one rank's to round-off (a sum
  // of per-rank sums: (S − 1) u relative, Higham §4.2), the error estimate (a maximum)
  // exactly.
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  const std::vector<GuideStrand> guides = mixedGuides(12, 5);
  SimulationOptions o = optionsFor(ModelType::SuperHelix);
  o.superHelix.integrator = Integrator::Midpoint;
  o.superHelix.tolerance = 0.002;
  Outcome one, two;
  {
    const FirstRanks sub = firstRanks(1);
    if (sub.member)
    {
      one = run(guides, o, sub.ranks, 8);
    }
  }
  {
    const FirstRanks sub = firstRanks(2);
    if (sub.member)
    {
      two = run(guides, o, sub.ranks, 8);
    }
  }
  if (world.rank() != 0)
  {
    return;
  }
  ASSERT_TRUE(one.status.ok()) << one.status.message();
  ASSERT_TRUE(two.status.ok()) << two.status.message();
  // Sub-steps leave each strand's own time off by round-off of its own; every strand is
  // stepped from the model's time, so the strands are the same bit for bit on 2 ranks (they
  // were 4e-8 m apart when the model took its time from its first strand).
  EXPECT_EQ(largestDifference(one, two), 0.0);
  const double bound = double(guides.size()) * std::ldexp(1.0, -53);
  bool varied = false;
  for (const char* name : {"substeps", "rejected_substeps", "first_order_share", "error_estimate"})
  {
    const std::vector<double>& a = one.table.at(name);
    const std::vector<double>& b = two.table.at(name);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t f = 0; f < a.size(); ++f)
    {
      if (std::string(name) == "error_estimate")
      {
        EXPECT_EQ(a[f], b[f]) << name << " at frame " << f;
      }
      else
      {
        EXPECT_LE(std::abs(a[f] - b[f]), bound * std::abs(a[f])) << name << " at frame " << f;
      }
    }
    varied = varied || std::any_of(a.begin(), a.end(),
                                   [&](double v) {
                                     return std::string(name) == "substeps" && v != 1.0 && v != 0.0;
                                   });
  }
  // The statistics vary over the strands (a mean that is not one step a frame), so rank 0's
  // own would differ from the whole run's.
  EXPECT_TRUE(varied);
}

TEST(StepStatistics, EachRuleReducesItsStatisticAsItSays)
{
  // Rank r holds r + 1 strands and reports a = r, b = 2 r + 1, c = 10 − r, d = r (no rule):
  // the whole run's mean of a over the strands, Σ(r (r + 1)) / Σ(r + 1); of c weighted by b,
  // Σ(c b (r + 1)) / Σ(b (r + 1)); the largest b; the sum of a; d as a mean like a.
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  using R = StepStatisticRule::Reduction;
  const std::vector<StepStatisticRule> rules = {
      {"a", R::StrandMean, ""}, {"c", R::StrandMean, "b"}, {"b", R::Max, ""}, {"e", R::Sum, ""}};
  const double r = world.rank();
  std::map<std::string, double> v = {{"a", r}, {"b", 2 * r + 1}, {"c", 10 - r}, {"d", r}, {"e", r}};
  reduceStepStatistics(v, rules, r + 1, world);
  double na = 0, da = 0, nc = 0, dc = 0, e = 0;
  for (int k = 0; k < world.size(); ++k)
  {
    na += k * (k + 1.0);
    da += k + 1.0;
    nc += (10.0 - k) * (2.0 * k + 1) * (k + 1.0);
    dc += (2.0 * k + 1) * (k + 1.0);
    e += k;
  }
  // Sums of a few small integers: exact in double.
  EXPECT_EQ(v["a"], na / da);
  EXPECT_EQ(v["d"], na / da);
  EXPECT_EQ(v["c"], nc / dc);
  EXPECT_EQ(v["b"], 2.0 * (world.size() - 1) + 1);
  EXPECT_EQ(v["e"], e);
}

TEST(MoreRanksThanStrands, ThreeStrandsOrOneOnFourRanks)
{
  if (worldSize() < 4)
  {
    GTEST_SKIP() << "needs 4 ranks (mpirun -np 4)";
  }
  for (int count : {3, 1})
  {
    const std::vector<GuideStrand> guides = mixedGuides(count, 5);
    const std::string file = temp("few_" + std::to_string(count) + ".h5");
    Outcome one, four;
    {
      const FirstRanks sub = firstRanks(1);
      if (sub.member)
      {
        one = run(guides, optionsFor(ModelType::SuperHelix), sub.ranks, 8);
        EXPECT_TRUE(one.status.ok()) << one.status.message();
      }
    }
    const Ranks world(MPI_COMM_WORLD);
    four = run(guides, optionsFor(ModelType::SuperHelix), world, 8, file);
    EXPECT_TRUE(four.status.ok()) << four.status.message(); // the same on every rank
    if (world.rank() != 0 || !one.status.ok() || !four.status.ok())
    {
      continue; // no ASSERT on one rank before the next collective call
    }
    int empty = 0;
    for (int n : four.strandsPerRank)
    {
      empty += n == 0;
    }
    EXPECT_EQ(empty, 4 - count) << count << " strands";
    if (count == 1)
    {
      EXPECT_EQ(four.strandsPerRank[0], 0) << "rank 0, which writes the times, has no strand";
    }
    EXPECT_EQ(largestDifference(one, four), 0.0) << count << " strands";
    expectSameEnergy(one, four, guides.size());
    const Outcome file4 = readBack(file);
    EXPECT_TRUE(file4.status.ok()) << file4.status.message();
    EXPECT_EQ(largestDifference(one, file4), 0.0);
    EXPECT_EQ(file4.times, four.times);
  }
}

TEST(Failures, AStrandThatBlowsUpOnOneRankStopsEveryRank)
{
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  const std::vector<GuideStrand> guides = mixedGuides(8, 5);
  // One step a frame, and three: then strand 5 fails at the frame's second step, and the
  // other ranks, whose strands stepped, must stop there too rather than build the next
  // step's grid (collective) without it. The grid is on (the default).
  struct Case
  {
    double frameInterval, failAfter;
    int kept; // frames 0 … kept − 1: the hook is asked at the start of each step
  };
  for (const Case c : {Case{1.0 / 30, 0.15, 6}, Case{0.1, 0.12, 2}})
  {
    SimulationOptions o = optionsFor(ModelType::SuperHelix);
    ASSERT_TRUE(o.hairHair.usesGrid());
    o.ranks = world;
    o.frameInterval = c.frameInterval;
    // Strand 5 gets a NaN force from failAfter on: its step fails on the rank that has it.
    o.superHelix.additionalContacts = [c](int strand, double t, const std::vector<StrandSample>&,
                                          std::vector<ContactResponse>& response)
    {
      if (strand == 5 && t > c.failAfter)
      {
        response[0].force.x() = std::nan("");
      }
    };
    const std::string file = temp("failed.h5");
    StorageOptions storage;
    storage.stateFile = file;
    storage.replaceStateFile = true;
    storage.frames = 30;
    Simulation sim;
    ASSERT_TRUE(sim.initialize(guides, demoScene(body()), o, storage).ok());
    std::unique_ptr<StrandModel> model;
    ASSERT_TRUE(makeModel(o, model).ok());
    const std::vector<int> owner = shareStrands(guides, *model, world.size());
    const Status s = sim.advanceTo(30);
    ASSERT_FALSE(s.ok());
    // Every rank stops, with the message of the rank that has strand 5.
    EXPECT_EQ(s.message().rfind("rank " + std::to_string(owner[5]) + " of " +
                                    std::to_string(world.size()) + ": ",
                                0),
              0u)
        << s.message();
    EXPECT_NE(s.message().find("strand 5"), std::string::npos) << s.message();
    const int kept = sim.numberOfFrames();
    EXPECT_EQ(kept, c.kept) << c.frameInterval;
    EXPECT_EQ(sim.advanceTo(31).message(), s.message()); // it stays stopped, on every rank
    EXPECT_EQ(sim.numberOfFrames(), kept);
    world.barrier();
    if (world.rank() == 0)
    {
      StateFileReader r;
      ASSERT_TRUE(r.open(file).ok());
      EXPECT_EQ(r.numberOfFrames(), kept);
      EXPECT_EQ(r.version(), 3);
    }
    world.barrier();
  }
}

TEST(Failures, HairHairPairsAreRefusedOnMoreThanOneRank)
{
  // The pairs of the near field and of the coupled solve would be found among each rank's
  // own strands only (a run that silently differs from one rank's): refused on every rank,
  // with what to do; on one rank the run is built. (The grid, the default, runs: below.)
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  const std::vector<GuideStrand> guides = mixedGuides(8, 5);
  for (HairHairSolver solver : {HairHairSolver::GridAndNearField, HairHairSolver::Coupled})
  {
    SimulationOptions o = optionsFor(ModelType::SuperHelix);
    o.hairHair.enabled = true;
    o.hairHair.solver = solver;
    o.ranks = world;
    Simulation sim;
    const Status s = sim.initialize(guides, demoScene(body()), o, StorageOptions());
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.message().find("is not available under MPI"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("Choose the grid"), std::string::npos) << s.message();
    const FirstRanks sub = firstRanks(1);
    if (sub.member)
    {
      o.ranks = sub.ranks;
      Simulation alone;
      const Status one = alone.initialize(guides, demoScene(body()), o, StorageOptions());
      EXPECT_TRUE(one.ok()) << one.message();
    }
  }
}

class GridRanks : public ::testing::TestWithParam<ModelType>
{
};

TEST_P(GridRanks, TheGridIsSummedOverTheRanksAndTheStrandsAreTheSameOnAnyNumberOfRanks)
{
  // 60 of the demo's guides, close on the scalp so that the grid acts (its friction
  // dissipates and its pressure works), 15 frames of the shake on 1, 2 and 4 ranks: each
  // rank splats its own strands and the grid is summed over the ranks (in fixed point, so
  // the sum is the same in any order): the strands are the same, bit for bit, and so is
  // the energy table.
  if (worldSize() < 4)
  {
    GTEST_SKIP() << "needs 4 ranks (mpirun -np 4)";
  }
  const ModelType model = GetParam(); // every model with the grid
  const std::vector<GuideStrand> guides = rankGuides(model, 60);
  const SimulationOptions o = optionsFor(model);
  ASSERT_TRUE(o.hairHair.enabled);
  ASSERT_EQ(o.hairHair.solver, HairHairSolver::Grid);
  std::map<int, Outcome> runs;
  for (int n : {1, 2, 4})
  {
    const FirstRanks sub = firstRanks(n);
    if (sub.member)
    {
      runs[n] = run(guides, o, sub.ranks, 15);
      EXPECT_TRUE(runs[n].status.ok()) << runs[n].status.message();
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
  if (worldRank() != 0)
  {
    return;
  }
  for (int n : {1, 2, 4})
  {
    ASSERT_TRUE(runs[n].status.ok());
  }
  EXPECT_GT(runs[1].table.at("hair_grid_dissipated").back(), 0);
  EXPECT_NE(runs[1].table.at("hair_grid_work").back(), 0);
  for (int n : {2, 4})
  {
    EXPECT_EQ(largestDifference(runs[1], runs[n]), 0.0) << n << " ranks";
    expectSameEnergy(runs[1], runs[n], guides.size());
  }
  std::printf("%s: the grid on 1, 2 and 4 ranks: largest difference 0; dissipated %.3g J, "
              "work %.3g J\n",
              findModel(model)->name, runs[1].table.at("hair_grid_dissipated").back(),
              runs[1].table.at("hair_grid_work").back());
}

INSTANTIATE_TEST_SUITE_P(ModelsWithTheGrid, GridRanks,
                         ::testing::Values(ModelType::SuperHelix, ModelType::DiscreteElasticRods),
                         [](const ::testing::TestParamInfo<ModelType>& info)
                         { return modelTestName(info.param); });

TEST(Failures, AFrameOneRankRefusesIsWrittenByNone)
{
  const Ranks world(MPI_COMM_WORLD);
  if (world.size() < 2)
  {
    GTEST_SKIP() << "needs 2 ranks";
  }
  // Two strands of three points per rank; the frame of rank 1 holds a NaN at frame 2.
  StateHeader h;
  h.model = "test";
  const int strands = 2 * world.size();
  for (int k = 0; k <= strands; ++k)
  {
    h.offsets.push_back(3 * k);
  }
  FileSharing sharing;
  sharing.ranks = world;
  sharing.strands = {2 * world.rank(), 2 * world.rank() + 1};
  sharing.frames = 5;
  const std::string file = temp("refused.h5");
  StateFileWriter w;
  ASSERT_TRUE(w.create(file, h, {}, StateFileWriter::Existing::ReplaceStateFile, sharing).ok());
  Status s;
  int t = 0;
  for (; t < 5 && s; ++t)
  {
    StateFrame f;
    f.time = t * 0.1;
    for (int i = 0; i < 6; ++i)
    {
      f.positions.emplace_back(world.rank(), i, t);
      f.velocities.emplace_back(0, 0, 0);
    }
    if (t == 2 && world.rank() == 1)
    {
      f.positions[4].y() = std::nan("");
    }
    s = w.append(f);
  }
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("rank 1 of"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("NaN"), std::string::npos) << s.message();
  EXPECT_EQ(t, 3);
  EXPECT_EQ(w.numberOfFrames(), 2);
  // The file reads back its two whole frames, every rank's points in place.
  StateFrame back;
  ASSERT_TRUE(w.readPiece(1, back).ok());
  EXPECT_EQ(back.positions[5], Eigen::Vector3d(world.rank(), 5, 1));
  w.close();
  world.barrier();
  if (world.rank() == 0)
  {
    StateFileReader r;
    ASSERT_TRUE(r.open(file).ok());
    ASSERT_EQ(r.numberOfFrames(), 2);
    StateFrame f;
    ASSERT_TRUE(r.readFrame(1, f).ok());
    for (int p = 0; p < world.size(); ++p)
    {
      EXPECT_EQ(f.positions[6 * p + 4], Eigen::Vector3d(p, 4, 1));
    }
    StateFrame piece;
    ASSERT_TRUE(r.readPiece(1, {1, 2}, piece).ok());
    ASSERT_EQ(piece.positions.size(), 6u);
    EXPECT_EQ(piece.positions[0], Eigen::Vector3d(0, 3, 1));
    EXPECT_EQ(piece.positions[3], Eigen::Vector3d(1, 0, 1));
  }
}

TEST(Streaming, ARunLongerThanMemoryReadsReleasedFramesBackFromTheSharedFile)
{
  const Ranks world(MPI_COMM_WORLD);
  const std::vector<GuideStrand> guides = mixedGuides(12, 5);
  const Outcome whole = run(guides, optionsFor(ModelType::SuperHelix), world, 12);
  ASSERT_TRUE(whole.status.ok()) << whole.status.message();
  // Room for three and a half frames of the largest piece: the ranks keep the same three,
  // and read the others back from the shared file, each its piece.
  double perFrame = 0;
  {
    Simulation probe;
    SimulationOptions o = optionsFor(ModelType::SuperHelix);
    o.ranks = world;
    ASSERT_TRUE(probe.initialize(guides, demoScene(body()), o).ok());
    perFrame = world.max(probe.bytesPerFrame());
  }
  SimulationOptions o = optionsFor(ModelType::SuperHelix);
  o.ranks = world;
  StorageOptions storage;
  storage.stateFile = temp("streamed.h5");
  storage.replaceStateFile = true;
  storage.frames = 12;
  storage.memoryBudget = 3.5 * perFrame;
  Simulation sim;
  ASSERT_TRUE(sim.initialize(guides, demoScene(body()), o, storage).ok());
  ASSERT_TRUE(sim.advanceTo(12).ok());
  EXPECT_FALSE(sim.hasFrameData(0));
  EXPECT_TRUE(sim.hasFrameData(11));
  Outcome streamed;
  for (int f : {11, 0, 5, 9, 1}) // any order
  {
    StateFrame frame;
    ASSERT_TRUE(sim.readFrame(f, frame).ok());
    const Strands got = gatherStrands(sim.piece(), frame, world);
    if (world.rank() == 0)
    {
      Outcome a, b;
      a.frames = {whole.frames[f]};
      b.frames = {got};
      EXPECT_EQ(largestDifference(a, b), 0.0) << "frame " << f;
    }
  }
}

TEST(GhostStrands, GhostsAreTheOtherRanksStrandsWithinReach)
{
  const Ranks world(MPI_COMM_WORLD);
  const std::vector<GuideStrand> guides = mixedGuides(60, 3);
  std::vector<Eigen::Vector3d> roots;
  for (const GuideStrand& g : guides)
  {
    roots.push_back(g.root);
  }
  const double spacing = typicalSpacing(roots);
  // Against the definition, by brute force: the median distance to the nearest other root.
  std::vector<double> nearest;
  for (std::size_t i = 0; i < roots.size(); ++i)
  {
    double d = INFINITY;
    for (std::size_t j = 0; j < roots.size(); ++j)
    {
      d = j == i ? d : std::min(d, (roots[i] - roots[j]).norm());
    }
    nearest.push_back(d);
  }
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  EXPECT_EQ(spacing, nearest[nearest.size() / 2]);

  const std::vector<int> owner =
      shareAlongCurve(roots, std::vector<double>(roots.size(), 1.0), world.size());
  GhostStrands ghosts;
  ghosts.plan(roots, owner, world.rank(), 3 * spacing);
  std::vector<std::int64_t> expected;
  for (std::size_t n = 0; n < roots.size(); ++n)
  {
    bool near = false;
    for (std::size_t k = 0; k < roots.size(); ++k)
    {
      near = near || (owner[k] == world.rank() && owner[n] != world.rank() &&
                      (roots[n] - roots[k]).norm() <= 3 * spacing);
    }
    if (near)
    {
      expected.push_back(std::int64_t(n));
    }
  }
  EXPECT_EQ(ghosts.ghosts(), expected);
  // Partners are mutual: each rank's list, gathered, names it back.
  std::vector<double> mine(ghosts.partners().begin(), ghosts.partners().end());
  std::vector<double> counts{double(mine.size())};
  const std::vector<double> all = world.gather(mine), sizes = world.gather(counts);
  std::vector<std::set<int>> partners(world.size());
  std::size_t at = 0;
  for (int r = 0; r < world.size(); ++r)
  {
    for (int i = 0; i < int(sizes[r]); ++i)
    {
      partners[r].insert(int(all[at++]));
    }
  }
  for (int r = 0; r < world.size(); ++r)
  {
    for (int p : partners[r])
    {
      EXPECT_TRUE(partners[p].count(r)) << r << " lists " << p;
    }
  }
}

TEST(StrandAnalysis, PiecesMeasureAsTheWhole)
{
  const Ranks world(MPI_COMM_WORLD);
  // 21 strands of 3 to 7 points, shared round-robin among the ranks.
  StrandsFrame whole, piece;
  whole.offsets = piece.offsets = {0};
  for (int k = 0; k < 21; ++k)
  {
    const int n = 3 + k % 5;
    for (StrandsFrame* f : {&whole, &piece})
    {
      if (f == &piece && k % world.size() != world.rank())
      {
        continue;
      }
      for (int i = 0; i < n; ++i)
      {
        f->positions.emplace_back(0.01 * k + 0.003 * i * i, -0.02 * i, std::sin(k + i));
        f->curvature.push_back(std::cos(3.0 * k + i));
        f->twist.push_back(0.1 * k - i);
        f->contactDepth.push_back(i == 1 ? 1e-4 * k : 0.0);
      }
      f->offsets.push_back(std::int64_t(f->positions.size()));
      f->ids.push_back(k);
    }
  }
  StrandAnalysisOptions o;
  o.tracked = {20, 3};
  o.group = {1, 5, 8, 13, 17};
  StrandAnalysis one, shared;
  ASSERT_TRUE(one.configure(o).ok());
  ASSERT_TRUE(shared.configure(o).ok());
  StrandMeasures a, b;
  ASSERT_TRUE(one.measure(whole, a).ok());
  ASSERT_TRUE(shared.measure(piece, b, world).ok());
  // Maxima, counts, the span and the tracked tips exactly; the means to round-off (21 terms).
  EXPECT_EQ(a.span, b.span);
  EXPECT_EQ(a.maxCurvature, b.maxCurvature);
  EXPECT_EQ(a.maxTwist, b.maxTwist);
  EXPECT_EQ(a.maxDeflection, b.maxDeflection);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.maxContactDepth, b.maxContactDepth);
  EXPECT_EQ(a.trackedTips, b.trackedTips);
  EXPECT_LE((a.meanTip - b.meanTip).norm(), 20 * std::ldexp(1.0, -53) * 2.0);
  EXPECT_NEAR(a.meanDeflection, b.meanDeflection, 20 * std::ldexp(1.0, -53));
  // A strand no rank has is refused on every rank.
  o.tracked = {21};
  ASSERT_TRUE(shared.configure(o).ok());
  const Status s = shared.measure(piece, b, world);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("strand 21"), std::string::npos) << s.message();
}

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 prints; every rank runs every test (they are collective).
  if (worldRank() != 0)
  {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS();
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}
