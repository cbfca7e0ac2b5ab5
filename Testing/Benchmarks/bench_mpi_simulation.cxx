// hair::Simulation under MPI, in Core: the demo's scene (wavy guides combed on the bundled
// body, head and trunk tables, the shake and the wind, body contacts) with `guides` guides,
// each rank stepping its share, every frame written to one state file by every rank.
// Scripts/bench_mpi.py (core) runs it under mpirun on 1 and 2 ranks and prints the tables of
// docs/benchmarks.md ("Under MPI").
//
//   mpirun -np N build/Testing/bench_mpi_simulation <guides> <frames> <state.h5 | -> [threads]
//   [wavy | quadrants] [nogrid]
//
// Frame 0 and the first step (building the run, opening the file) are not timed. Rank 0
// prints one line of JSON: each timed frame's wall time (between barriers), and per rank its
// strands, its step cost by the model's estimate, and where its time went
// (hair::SimulationTimings, per frame): stepping, waiting for the other ranks' steps, the
// frame's record, storing it.
#include "DemoScene.h"
#include "common/Ranks.h"
#include "simulation/Simulation.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace hair;

int main(int argc, char** argv)
{
  MPI_Init(&argc, &argv);
  const Ranks world(MPI_COMM_WORLD);
  if (argc < 4)
  {
    if (world.rank() == 0)
    {
      std::fprintf(stderr,
                   "usage: %s guides frames state.h5|- [threads] [wavy|quadrants] [nogrid]\n",
                   argv[0]);
    }
    MPI_Finalize();
    return 2;
  }
  const int count = std::atoi(argv[1]), frames = std::atoi(argv[2]);
  const std::string state = argv[3];
  const int threads = argc > 4 ? std::atoi(argv[4]) : 1;
  const bool quadrants = argc > 5 && std::string(argv[5]) == "quadrants";
  const bool noGrid = argc > 6 && std::string(argv[6]) == "nogrid"; // hair–hair off

  BundledBody body;
  std::vector<GuideStrand> guides;
  Status s = loadBundledBody(HAIR_DATA_DIR, body);
  s = s ? demoGuides(body, count, 10, guides) : s;
  if (s && quadrants)
  {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const GuideStrand& g : guides)
    {
      centre += g.root / double(guides.size());
    }
    const HairType types[] = {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy};
    for (GuideStrand& g : guides)
    {
      const Eigen::Vector3d d = g.root - centre;
      g.hair = HairParameters::preset(types[(d.x() > 0 ? 1 : 0) + (d.z() > 0 ? 2 : 0)]);
    }
  }
  SimulationOptions o;
  o.threads = threads;
  o.ranks = world;
  o.contacts.enabled = true;
  o.hairHair.enabled = !noGrid;
  StorageOptions storage;
  storage.stateFile = state == "-" ? "" : state;
  storage.replaceStateFile = true;
  storage.frames = frames + 1;
  Simulation sim;
  const auto built = std::chrono::steady_clock::now();
  s = s ? sim.initialize(guides, demoScene(body), o, storage) : s;
  s = s ? sim.advanceTo(2) : s;
  world.barrier();
  const double build =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count();
  const SimulationTimings before = sim.timings();
  std::vector<double> wall;
  for (int f = 3; s && f <= frames + 1; ++f)
  {
    world.barrier();
    const auto t0 = std::chrono::steady_clock::now();
    s = sim.advanceTo(f);
    world.barrier();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  if (!s)
  {
    if (world.rank() == 0)
    {
      std::fprintf(stderr, "%s\n", s.message().c_str());
    }
    MPI_Finalize();
    return 1;
  }
  const SimulationTimings& t = sim.timings();
  const double n = t.frames - before.frames;
  double cost = 0;
  std::unique_ptr<StrandModel> model;
  (void)makeModel(o, model); // the run above was made with it
  const StateHeader& piece = sim.piece();
  for (std::size_t k = 0; k < piece.numberOfStrands(); ++k)
  {
    cost += model->stepCost(guides[piece.strandId(k)]);
  }
  const std::vector<double> mine{
      double(sim.piece().numberOfStrands()), cost,
      (t.stepWall - before.stepWall) / n,    (t.stepCpu - before.stepCpu) / n,
      (t.waitWall - before.waitWall) / n,    (t.recordWall - before.recordWall) / n,
      (t.recordCpu - before.recordCpu) / n,  (t.storeWall - before.storeWall) / n,
      (t.storeCpu - before.storeCpu) / n};
  const std::vector<double> all = world.gather(mine);
  if (world.rank() == 0)
  {
    std::printf("{\"ranks\": %d, \"guides\": %d, \"threads\": %d, "
                "\"build_s\": %.6f, \"points\": %lld, \"wall\": [",
                world.size(), count, threads, build,
                static_cast<long long>(sim.header().numberOfPoints()));
    for (std::size_t i = 0; i < wall.size(); ++i)
    {
      std::printf("%s%.6f", i ? ", " : "", wall[i]);
    }
    std::printf("], \"per_rank\": [");
    const char* names[] = {"strands",     "cost_us",    "step_wall",  "step_cpu", "wait_wall",
                           "record_wall", "record_cpu", "store_wall", "store_cpu"};
    const std::size_t fields = mine.size();
    for (int r = 0; r < world.size(); ++r)
    {
      std::printf("%s{", r ? ", " : "");
      for (std::size_t i = 0; i < fields; ++i)
      {
        std::printf("%s\"%s\": %.6g", i ? ", " : "", names[i], all[r * fields + i]);
      }
      std::printf("}");
    }
    std::printf("], \"preset_cost_us\": [");
    const HairType types[] = {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy};
    for (int i = 0; i < 4; ++i)
    {
      GuideStrand g = guides.front();
      g.hair = HairParameters::preset(types[i]);
      std::printf("%s%.4f", i ? ", " : "", model->stepCost(g));
    }
    std::printf("]}\n");
  }
  MPI_Finalize();
  return 0;
}
