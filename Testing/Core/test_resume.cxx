// A run killed at a random moment (SIGKILL, as a cluster's wall-time limit does) and resumed
// from its state file adds the frames an unbroken run has, bit for bit; a file that is not
// the run's (a parameter changed, another run's, another version, a model state the file
// does not keep) is refused with a message that says which (issue 34).
#include "DemoScene.h"
#include "io/StateFile.h"
#include "simulation/Simulation.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

using namespace hair;

namespace
{
const BundledBody& body()
{
  static BundledBody b;
  static bool loaded = loadBundledBody(HAIR_DATA_DIR, b).ok();
  EXPECT_TRUE(loaded);
  return b;
}

std::string temp(const std::string& name)
{
  return ::testing::TempDir() + "hair_resume_" + name;
}

/// The demo's guides, the four presets in turn.
std::vector<GuideStrand> guides(int count, int elements)
{
  std::vector<GuideStrand> g;
  EXPECT_TRUE(demoGuides(body(), count, elements, g).ok());
  for (std::size_t k = 0; k < g.size(); ++k)
  {
    g[k].hair = HairParameters::preset(static_cast<HairType>(k % 4));
  }
  return g;
}

/// A run to compare: its model and options, its guides, its frames.
struct Case
{
  std::string name;
  SimulationOptions options;
  std::vector<GuideStrand> strands;
  int frames = 0;
};

/// The Super-Helix on the demo's scene with what carries state from step to step: body
/// contacts with static friction (anchors), the hair grid (on by default), and with
/// `tolerance` the sub-step controller.
Case superHelix(double tolerance = 0)
{
  Case c;
  c.name = tolerance > 0 ? "super-helix-tolerance" : "super-helix";
  c.options.model = ModelType::SuperHelix;
  c.options.contacts.staticFriction = 0.4;
  c.options.superHelix.tolerance = tolerance;
  c.options.threads = 2;
  c.strands = guides(tolerance > 0 ? 12 : 24, 10);
  c.frames = tolerance > 0 ? 20 : 40;
  return c;
}

/// The projective strands on the same scene with Coulomb friction (anchors, loads).
Case projective()
{
  Case c;
  c.name = "projective";
  c.options.model = ModelType::Projective;
  c.options.contacts.staticFriction = 0.4;
  c.options.threads = 2;
  c.strands = guides(16, 20);
  c.frames = 24;
  return c;
}

StorageOptions storage(const std::string& file, int frames, bool resume = false)
{
  StorageOptions s;
  s.stateFile = file;
  s.replaceStateFile = true;
  s.frames = frames;
  s.resume = resume;
  return s;
}

Status runTo(const Case& c, const std::string& file, int frames, bool resume = false,
             const Progress& progress = {})
{
  Simulation sim;
  Status s =
      sim.initialize(c.strands, demoScene(body()), c.options, storage(file, c.frames, resume));
  return s ? sim.advanceTo(frames, progress) : s;
}

/// Every frame of two files equal bit for bit: times, energies, every array. The first
/// difference, or empty.
std::string difference(const std::string& a, const std::string& b)
{
  StateFileReader ra, rb;
  if (Status s = ra.open(a); !s)
    return s.message();
  if (Status s = rb.open(b); !s)
    return s.message();
  if (ra.numberOfFrames() != rb.numberOfFrames())
    return "frames: " + std::to_string(ra.numberOfFrames()) + " and " +
           std::to_string(rb.numberOfFrames());
  if (std::memcmp(ra.times().data(), rb.times().data(), ra.times().size() * sizeof(double)) != 0)
    return "times differ";
  for (const auto& [name, values] : ra.energies())
  {
    const auto& other = rb.energies().at(name);
    for (std::size_t i = 0; i < values.size(); ++i)
      if (std::memcmp(&values[i], &other[i], sizeof(double)) != 0)
        return "energy '" + name + "' differs at frame " + std::to_string(i);
  }
  for (std::int64_t f = 0; f < ra.numberOfFrames(); ++f)
  {
    StateFrame fa, fb;
    if (!ra.readFrame(f, fa).ok() || !rb.readFrame(f, fb).ok())
      return "frame " + std::to_string(f) + " cannot be read";
    std::string found;
    const StateHeader& h = ra.header();
    forEachArray(h, fa,
                 [&](const FrameArray& x)
                 {
                   if (!found.empty())
                     return;
                   const FrameArray* y = nullptr;
                   FrameArray match;
                   forEachArray(h, fb,
                                [&](const FrameArray& z)
                                {
                                  if (z.name == x.name)
                                  {
                                    match = z;
                                    y = &match;
                                  }
                                });
                   if (!y || y->size != x.size ||
                       std::memcmp(x.data, y->data, x.size * sizeof(double)) != 0)
                     found = x.name + " differs at frame " + std::to_string(f);
                 });
    if (!found.empty())
      return found;
  }
  return {};
}

/// Discrete elastic rods on the same scene with static friction (anchors) and the halved
/// steps of a Newton solve that does not converge (smooth and wavy guides: a curly guide
/// curling from straight costs tens of Newton iterations a step).
Case discreteElasticRods()
{
  Case c;
  c.name = "discrete-elastic-rods";
  c.options.model = ModelType::DiscreteElasticRods;
  c.options.contacts.staticFriction = 0.4;
  c.options.threads = 2;
  // 20 edges: the wavy preset's curl (104 /m over 30 cm) needs 17 (DerSpec::MaxRestTurn).
  c.strands = guides(8, 20);
  for (std::size_t k = 0; k < c.strands.size(); ++k)
  {
    c.strands[k].hair = HairParameters::preset(static_cast<HairType>(k % 2));
  }
  c.frames = 16;
  return c;
}

Case named(const std::string& name)
{
  return name == "projective"              ? projective()
         : name == "discrete-elastic-rods" ? discreteElasticRods()
         : name == "super-helix-tolerance" ? superHelix(1e-4)
                                           : superHelix();
}

/// Runs `c` in a child process to `file` and kills it (SIGKILL) after it has stored frame
/// `frame`, `delayMs` later (within the next frame's step or write, or between them).
/// Returns the frames the child reported stored. The child is this program run again
/// (ResumeChild.RunsUntilKilled): a fork alone would inherit the run's threads' pool
/// without its threads.
int runAndKill(const Case& c, const std::string& file, int frame, int delayMs)
{
  int fds[2];
  EXPECT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  if (child == 0)
  {
    ::close(fds[0]);
    ::setenv("HAIR_RESUME_CHILD", (c.name + "\n" + file + "\n" + std::to_string(fds[1])).c_str(),
             1);
    ::execl("/proc/self/exe", "test_resume", "--gtest_filter=ResumeChild.RunsUntilKilled",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fds[1]);
  int stored = 0, got = 0;
  while (stored < frame && ::read(fds[0], &got, sizeof got) == sizeof got)
  {
    stored = got;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  while (::read(fds[0], &got, sizeof got) == sizeof got)
  {
    stored = got;
  }
  ::close(fds[0]);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the child ended before it was killed (status " << status << ")";
  return stored;
}

void killAndResume(const Case& c, int trials, std::uint32_t seed)
{
  const std::string whole = temp(c.name + "_whole.h5");
  ASSERT_TRUE(runTo(c, whole, c.frames).ok());
  std::mt19937 random(seed);
  for (int trial = 0; trial < trials; ++trial)
  {
    const int frame = std::uniform_int_distribution<int>(1, c.frames - 2)(random);
    const int delay = std::uniform_int_distribution<int>(0, 60)(random);
    const std::string file = temp(c.name + "_killed.h5");
    std::remove(file.c_str());
    const int stored = runAndKill(c, file, frame, delay);
    StateFileReader killed;
    ASSERT_TRUE(killed.open(file).ok()) << "trial " << trial;
    const std::int64_t whole_frames = killed.numberOfFrames();
    StateContinuation last;
    ASSERT_TRUE(killed.readContinuation(nullptr, last).ok());
    killed.close();
    EXPECT_EQ(last.frame, whole_frames - 1) << "the last whole frame has its continuation";
    const Status resumed = runTo(c, file, c.frames, true);
    ASSERT_TRUE(resumed.ok()) << "trial " << trial << ": " << resumed.message();
    EXPECT_EQ(difference(whole, file), "")
        << c.name << ", trial " << trial << ": killed " << delay << " ms after frame " << frame
        << " (the child had stored " << stored << " frames, the file " << whole_frames
        << " whole ones)";
  }
}
} // namespace

// The child of runAndKill: runs the case HAIR_RESUME_CHILD names into its file, telling the
// parent through the pipe after each frame is stored.
TEST(ResumeChild, RunsUntilKilled)
{
  const char* asked = std::getenv("HAIR_RESUME_CHILD");
  if (!asked)
  {
    GTEST_SKIP() << "run by the kill tests";
  }
  std::istringstream in(asked);
  std::string name, file, fd;
  std::getline(in, name);
  std::getline(in, file);
  std::getline(in, fd);
  const int pipe = std::atoi(fd.c_str());
  const Case c = named(name);
  Simulation sim;
  Status s = sim.initialize(c.strands, demoScene(body()), c.options, storage(file, c.frames));
  int stored = 1;
  ssize_t unused = ::write(pipe, &stored, sizeof stored);
  for (int f = 2; s && f <= c.frames; ++f)
  {
    s = sim.advanceTo(f);
    stored = f;
    unused = ::write(pipe, &stored, sizeof stored);
  }
  (void)unused;
  // Not killed in time: wait to be (the parent kills after the frame it chose).
  std::this_thread::sleep_for(std::chrono::seconds(600));
}

TEST(Resume, SuperHelixKilledAtRandomFramesGoesOnBitForBit)
{
  killAndResume(superHelix(), 10, 34);
}

TEST(Resume, SuperHelixWithATolerancesSubStepsGoesOnBitForBit)
{
  killAndResume(superHelix(1e-4), 3, 35);
}

TEST(Resume, ProjectiveKilledAtRandomFramesGoesOnBitForBit)
{
  killAndResume(projective(), 4, 36);
}

TEST(Resume, DiscreteElasticRodsKilledAtRandomFramesGoOnBitForBit)
{
  killAndResume(discreteElasticRods(), 3, 37);
}

TEST(Resume, AResumedRunResumedAgainStillEqualsTheUnbrokenOne)
{
  Case c = superHelix();
  c.frames = 20;
  const std::string whole = temp("again_whole.h5"), file = temp("again.h5");
  ASSERT_TRUE(runTo(c, whole, c.frames).ok());
  ASSERT_TRUE(runTo(c, file, 6).ok());
  ASSERT_TRUE(runTo(c, file, 13, true).ok());
  ASSERT_TRUE(runTo(c, file, c.frames, true).ok());
  EXPECT_EQ(difference(whole, file), "");
  // A finished run resumed: nothing to add, nothing lost.
  ASSERT_TRUE(runTo(c, file, c.frames, true).ok());
  EXPECT_EQ(difference(whole, file), "");
}

TEST(Resume, AResumedRunHasTheFramesSoFarAndItsEnergyTable)
{
  Case c = superHelix();
  c.frames = 12;
  const std::string file = temp("table.h5");
  ASSERT_TRUE(runTo(c, file, 7).ok());
  Simulation sim;
  ASSERT_TRUE(
      sim.initialize(c.strands, demoScene(body()), c.options, storage(file, 12, true)).ok());
  EXPECT_EQ(sim.numberOfFrames(), 7);
  StateFrame early;
  ASSERT_TRUE(sim.readFrame(2, early).ok()) << "a frame before the resume, read from the file";
  EXPECT_EQ(early.positions.size(), sim.header().numberOfPoints());
  ASSERT_TRUE(sim.advanceTo(12).ok());
  std::vector<double> times;
  std::map<std::string, std::vector<double>> table;
  sim.energyTable(times, table);
  ASSERT_EQ(times.size(), 12u);
  for (const auto& [name, column] : table)
  {
    EXPECT_EQ(column.size(), 12u) << name;
  }
  EXPECT_TRUE(std::isnan(table.at("substeps")[3])) << "not recorded before the resume";
  EXPECT_EQ(table.at("substeps")[10], 1.0);
}

namespace
{
/// The message of resuming `c` from `file`.
std::string refusal(const Case& c, const std::string& file)
{
  Simulation sim;
  const Status s =
      sim.initialize(c.strands, demoScene(body()), c.options, storage(file, c.frames, true));
  EXPECT_FALSE(s.ok());
  return s.message();
}
} // namespace

TEST(Resume, AChangedParameterIsRefusedByName)
{
  Case c = superHelix();
  c.frames = 8;
  const std::string file = temp("changed.h5");
  ASSERT_TRUE(runTo(c, file, 4).ok());
  Case stiffer = c;
  stiffer.options.contacts.stiffness *= 2;
  EXPECT_NE(refusal(stiffer, file).find("'contact_stiffness' is 10 in the file and 20 in this run"),
            std::string::npos)
      << refusal(stiffer, file);
  Case longer = c;
  longer.strands[5].length *= 1.1;
  EXPECT_NE(refusal(longer, file).find("strand 5"), std::string::npos) << refusal(longer, file);
  // The file is left as it was.
  StateFileReader r;
  ASSERT_TRUE(r.open(file).ok());
  EXPECT_EQ(r.numberOfFrames(), 4);
}

TEST(Resume, AChangedSceneIsRefused)
{
  Case c = superHelix();
  c.frames = 6;
  const std::string file = temp("scene.h5");
  ASSERT_TRUE(runTo(c, file, 3).ok());
  Scene moved = demoScene(body());
  moved.parts[0].table = moved.parts[1].table; // another body
  Simulation sim;
  const Status s = sim.initialize(c.strands, moved, c.options, storage(file, c.frames, true));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("the scene"), std::string::npos) << s.message();
}

TEST(Resume, AnotherRunsFileIsRefused)
{
  Case c = superHelix();
  c.frames = 6;
  const std::string file = temp("another.h5");
  ASSERT_TRUE(runTo(c, file, 3).ok());
  Case other = c;
  other.strands = guides(20, 10);
  EXPECT_NE(refusal(other, file).find("another run's file"), std::string::npos)
      << refusal(other, file);
  Case proj = projective();
  EXPECT_NE(refusal(proj, file).find("super-helix model"), std::string::npos)
      << refusal(proj, file);
}

TEST(Resume, AFileOfAnotherVersionIsRefused)
{
  Case c = superHelix();
  const std::string file = std::string(HAIR_STATE_FILES_DIR) + "/v2-super-helix.h5";
  const std::string m = refusal(c, file);
  EXPECT_NE(m.find("another version of HairDynamics (state-file format version 2"),
            std::string::npos)
      << m;
}

TEST(Resume, NoFileIsNothingToResume)
{
  const std::string m = refusal(superHelix(), temp("none.h5"));
  EXPECT_NE(m.find("nothing to resume"), std::string::npos) << m;
}

TEST(Resume, ARunWhosePairsTheFileDoesNotKeepIsRefused)
{
  Case c = superHelix();
  c.strands = guides(6, 6);
  c.frames = 4;
  c.options.hairHair.solver = HairHairSolver::GridAndNearField;
  const std::string file = temp("pairs.h5");
  ASSERT_TRUE(runTo(c, file, 2).ok());
  const std::string m = refusal(c, file);
  EXPECT_NE(m.find("grid and near field"), std::string::npos) << m;
}
