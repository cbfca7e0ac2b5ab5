// hair_soak: a long run of the demo's scene, checked for what a long run must keep (issue 34,
// docs/robustness.md, "The soak run"). The demo's guides (Testing/Fixtures/DemoScene: grown on
// the bundled body's scalp, 30 cm, combed), `strands` of each hair preset taking turns along
// the scalp, the head shaking about the neck (±0.5 rad at 3 Hz by default, faded in over the
// first second), the demo's 0.5 m/s wind, body contacts, hair–hair contacts as each model
// has them by default; one model, or both one after the other, through Core's Simulation at
// the 1/30 s step, streaming frames to a state file while a second process follows it.
//
//   hair_soak out=<file.h5> [model=both] [presets=all] [strands=200] [duration=3600]
//             [interval=1.1] [frequency=3] [amplitude=0.5] [fade=1] [settle=60] [memory=8]
//             [hairhair=on] [flat=strict] [step=1/30] [threads=1]
//
// model: super-helix, projective or both (one after the other, each to its own file:
// <file>-super-helix.h5 and <file>-projective.h5). presets: all, or a comma-separated list
// of smooth, wavy, curly, fuzzy. strands: guides of each preset. interval: seconds between
// stored frames (the default 1.1 s, 33 steps, is not a multiple of the shake's period, so
// the frames sample every phase of it). settle: the simulated seconds after which the
// resident memory must stay flat (the memory window fills before). memory: MB the frames
// may take in memory (the frame store's window; the others are in the file only). hairhair:
// off turns the Super-Helix model's hair–hair contacts off (on is its default; the
// projective model has none). flat: strict (memory growth beyond the known fails the run)
// or report (printed, not failing: the Super-Helix model's sample buffers grow beyond what
// is sampled at frames; docs/robustness.md).
//
// Checks, per model, printed one line per simulated minute and as a table at the end:
//   - no NaN or infinite value in any frame (positions, velocities, energy terms);
//   - energy bounded by the work done, at every frame:
//       E(t) − E(0) ≤ W(t) + 0.05 F(t) + 10⁻¹² J,
//     E = kinetic + elastic + gravitational, W = external_work (the sum of the model's work
//     terms), F = Σ |work terms| + dissipated (the energy that flowed through the hair);
//   - the resident memory after `settle` s grows by no more than 1.25 × what the run is
//     known to add, plus 1 MB: what the frame store keeps of each frame that leaves memory
//     (its time and energy terms, the model's step statistics, the frame's penetration,
//     from this run's own terms), whole frames while its window fills, the Super-Helix
//     strands' quadrature samples seen at frames (their buffers grow to the most curved
//     state seen), and what HDF5 keeps in its free lists (measured);
//   - the state file readable all along: a follower process (this program with follow=)
//     opens the file while it is written, reads the newest whole frame, and checks it is
//     finite and later than the one before; then every frame is read back at the end.
// Exit status 0 when every check holds, 1 when one fails, 2 on bad arguments.
//
//   hair_soak follow=<file.h5> frames=<n> interval=<s>
//
// The follower (started by the run): reads until it has read frame n − 1, or its parent goes
// away; prints one line "follower reads=… frames=… failures=… [first failure]" and exits 0
// when every read held.
#include "DemoScene.h"
#include "StudyArguments.h"
#include "io/StateFile.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <hdf5.h>
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace hair;

namespace
{
/// Resident and peak resident memory of this process (MB), from /proc/self/status.
void memory(double& rss, double& peak)
{
  std::ifstream status("/proc/self/status");
  std::string key;
  rss = peak = 0;
  while (status >> key)
  {
    double kb = 0;
    if (key == "VmRSS:" && status >> kb)
      rss = kb / 1024;
    else if (key == "VmHWM:" && status >> kb)
      peak = kb / 1024;
  }
}

/// The heap in use (MB): what malloc has handed out and not been given back, in its arenas
/// and in blocks of their own (glibc's mallinfo2). RSS less this is what the allocator holds
/// free, the program's text and libraries, and what other allocators (none here) hold.
double heapInUse()
{
  const struct mallinfo2 m = mallinfo2();
  return double(m.uordblks + m.hblkhd) / (1024.0 * 1024.0);
}

/// What HDF5 holds in its free lists (MB): blocks it freed and keeps for reuse instead of
/// giving them back to malloc, up to its limits (H5set_free_list_limits; by default 1 MB of
/// regular, 4 MB of array, 16 MB of block and 16 MB of factory lists, 37 MB in all).
double hdf5FreeLists()
{
  size_t reg = 0, arr = 0, blk = 0, fac = 0;
  if (H5get_free_list_sizes(&reg, &arr, &blk, &fac) < 0)
    return 0;
  return double(reg + arr + blk + fac) / (1024.0 * 1024.0);
}

bool finite(const std::vector<Eigen::Vector3d>& v)
{
  return std::all_of(v.begin(), v.end(), [](const Eigen::Vector3d& x) { return x.allFinite(); });
}

bool finite(const std::map<std::string, double>& energy)
{
  return std::all_of(energy.begin(), energy.end(),
                     [](const auto& e) { return std::isfinite(e.second); });
}

double term(const StateFrame& f, const char* name)
{
  const auto found = f.energy.find(name);
  return found == f.energy.end() ? 0.0 : found->second;
}

double mechanical(const StateFrame& f)
{
  return term(f, "kinetic") + term(f, "elastic") + term(f, "gravitational");
}

/// The bytes glibc's malloc takes for a request of n bytes on a 64-bit system: n plus the
/// 8-byte size field, rounded up to 16, at least 32.
double chunk(std::size_t n)
{
  return static_cast<double>(std::max<std::size_t>(32, (n + 8 + 15) & ~std::size_t(15)));
}

/// The heap one entry of a std::map<std::string, double> takes: its node (the tree's three
/// pointers and colour, the string, the value), and the name's own buffer when it is longer
/// than the string's 15 characters held in place.
double mapEntry(const std::string& name)
{
  const double node = chunk(4 * sizeof(void*) + sizeof(std::string) + sizeof(double));
  return node + (name.size() > 15 ? chunk(name.size() + 1) : 0.0);
}

/// What the run keeps in memory of every frame, also of those that have left the memory
/// window (FrameStore::release keeps their time and energy; Simulation keeps their step
/// statistics and penetration for the energy table): a StateFrame with only its time and
/// energy, its energy terms, the step statistics map and its entries, two numbers.
double bytesKeptPerFrame(const StateFrame& frame, const std::map<std::string, double>& steps)
{
  double bytes = sizeof(StateFrame) + sizeof(std::map<std::string, double>) + 2 * sizeof(double);
  for (const auto& e : frame.energy)
    bytes += mapEntry(e.first);
  for (const auto& e : steps)
    bytes += mapEntry(e.first);
  return bytes;
}

/// The Super-Helix model's quadrature samples, summed over its strands (0 for the other
/// model). Each strand keeps its samples (SuperHelix::Kinematics::nodes, 256 bytes each,
/// and the StrandSample copy samples() hands out) in vectors that keep their capacity: as
/// many as the strand's most curved state so far needed (its quadrature rule takes more
/// samples the more an element turns). Their growth is the model's memory growing with
/// the most curved state seen, sampled here at each frame.
long superHelixSamples(const Simulation& sim, std::vector<long>& most)
{
  const auto* model = dynamic_cast<const SuperHelixModel*>(&sim.model());
  if (!model)
    return 0;
  most.resize(model->strands().size(), 0);
  long sum = 0;
  for (std::size_t k = 0; k < most.size(); ++k)
  {
    most[k] = std::max<long>(most[k], long(model->strands()[k].samples().size()));
    sum += most[k];
  }
  return sum;
}
constexpr double BytesPerSample = 256 + sizeof(StrandSample);

/// Frames held whole in memory (the frame store's window, which fills first).
int wholeFrames(const Simulation& sim)
{
  int n = 0;
  for (int f = 0; f < sim.numberOfFrames(); ++f)
    n += sim.hasFrameData(f);
  return n;
}

/// For a step that failed on a strand (its message names "(id k)"): the strand's preset,
/// root and distance from the shake's axis, and its first element's coordinates in the
/// frames still in memory (the Super-Helix model's twist and curvatures, 1/m), to see how
/// the failure came.
void describeFailure(const Simulation& sim, const std::vector<GuideStrand>& guides,
                     const std::string& message)
{
  const auto at = message.find("(id ");
  if (at == std::string::npos)
    return;
  const std::size_t k = std::strtoul(message.c_str() + at + 4, nullptr, 10);
  if (k >= guides.size())
    return;
  const GuideStrand& g = guides[k];
  const HairType types[] = {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy};
  const char* preset = "custom";
  for (HairType t : types)
    if (HairParameters::preset(t).helixRadius == g.hair.helixRadius &&
        HairParameters::preset(t).radius == g.hair.radius)
      preset = toString(t);
  std::printf("# strand %zu: %s, root (%.4f, %.4f, %.4f) m, %.3f m from the shake's axis\n", k,
              preset, g.root.x(), g.root.y(), g.root.z(),
              (g.root - bundled::neckPivot()).cross(Eigen::Vector3d::UnitY()).norm());
  const int width = sim.header().coordinatesPerStrand;
  if (width < 3)
    return;
  std::printf("# its first element's coordinates in the frames in memory:\n");
  for (int f = 0; f < sim.numberOfFrames(); ++f)
  {
    if (!sim.hasFrameData(f) || sim.frame(f).q.size() < (k + 1) * width)
      continue;
    const double* q = sim.frame(f).q.data() + k * width;
    std::printf("#   t = %8.2f s: %10.2f %10.2f %10.2f\n", sim.frame(f).time, q[0], q[1], q[2]);
  }
}

// ---------------------------------------------------------------------------------------
// The follower.

volatile std::sig_atomic_t stopFollowing = 0;

int follow(const std::string& path, long frames, double interval)
{
  // SIGTERM (the run stopped early): report what was read and stop.
  std::signal(SIGTERM, [](int) { stopFollowing = 1; });
  const pid_t parent = getppid();
  long reads = 0, seen = 0, failures = 0;
  std::int64_t lastCount = 0;
  double lastTime = -1;
  std::string firstFailure;
  auto fail = [&](const std::string& what)
  {
    if (failures++ == 0)
      firstFailure = what;
  };
  while (lastCount < frames && getppid() == parent && !stopFollowing)
  {
    StateFileReader reader;
    ++reads;
    if (Status s = reader.open(path); !s)
      fail("open: " + s.message());
    else if (const std::int64_t n = reader.numberOfFrames(); n < lastCount)
      fail("the file has " + std::to_string(n) + " frames after " + std::to_string(lastCount));
    else if (n > 0)
    {
      StateFrame f;
      const std::int64_t k = n - 1;
      if (Status r = reader.readFrame(k, f); !r)
        fail("frame " + std::to_string(k) + ": " + r.message());
      else if (!finite(f.positions) || !finite(f.velocities) || !finite(f.energy))
        fail("frame " + std::to_string(k) + " is not finite");
      else if (std::abs(f.time - k * interval) > 1e-6 ||
               (n > lastCount ? !(f.time > lastTime) : f.time != lastTime))
        fail("frame " + std::to_string(k) + " at t = " + std::to_string(f.time) +
             " s after t = " + std::to_string(lastTime) + " s");
      else
      {
        seen += n > lastCount;
        lastCount = n;
        lastTime = f.time;
      }
    }
    reader.close();
    if (lastCount < frames && !stopFollowing)
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  std::printf("follower reads=%ld frames=%ld last=%lld failures=%ld%s%s\n", reads, seen,
              static_cast<long long>(lastCount), failures, failures ? " first: " : "",
              firstFailure.c_str());
  return failures == 0 && lastCount == frames ? 0 : 1;
}

/// Starts `hair_soak follow=...` on `path`; its report comes through the pipe `fd`.
pid_t startFollower(const std::string& path, int frames, double interval, int& fd)
{
  int p[2];
  if (pipe(p) != 0)
    return -1;
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0)
  {
    dup2(p[1], STDOUT_FILENO);
    // Nothing of the writer's: the follower opens the file as any other process would.
    for (int k = 3; k < 1024; ++k)
      close(k);
    const std::string a = "follow=" + path, b = "frames=" + std::to_string(frames);
    char c[64];
    std::snprintf(c, sizeof c, "interval=%.17g", interval);
    const char* argv[] = {"hair_soak", a.c_str(), b.c_str(), c, nullptr};
    execv("/proc/self/exe", const_cast<char* const*>(argv));
    _exit(127);
  }
  close(p[1]);
  fd = p[0];
  return pid;
}

/// Waits for the follower and returns its report line and whether it passed.
bool finishFollower(pid_t pid, int fd, std::string& report)
{
  std::string text;
  char buffer[512];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;)
    text.append(buffer, std::size_t(n));
  close(fd);
  int status = 0;
  waitpid(pid, &status, 0);
  while (!text.empty() && text.back() == '\n')
    text.pop_back();
  report = text.empty() ? "the follower said nothing" : text;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

long field(const std::string& report, const std::string& key)
{
  const auto at = report.find(key + "=");
  return at == std::string::npos ? -1 : std::atol(report.c_str() + at + key.size() + 1);
}

// ---------------------------------------------------------------------------------------
// The run.

struct Settings
{
  std::vector<HairType> presets;
  int strands = 200;
  double duration = 3600, interval = 1.1, frequency = 3, amplitude = 0.5, fade = 1, settle = 60;
  int threads = 1;
  double memory = 8;      ///< MB the frames may take in memory (the frame store's window)
  double step = 1.0 / 30; ///< s, the Super-Helix model's step (the projective one: ≤ 1 ms)
  bool hairHair = true;   ///< the Super-Helix model's hair–hair contacts (its default: on)
  bool gateMemory = true; ///< flat=strict: memory growth fails the run (report: printed only)
};

struct Result
{
  std::string model, file;
  bool ran = false;
  int frames = 0;
  double wall = 0, simulated = 0;
  int nanFrame = -1;
  // Energy: the largest E − E0 − W over the run (J), and as a share of F then; the end.
  double excess = -1e300, excessShare = 0, excessTime = 0;
  bool bounded = true;
  double e0 = 0, deltaE = 0, work = 0, dissipated = 0, residual = 0, flow = 0;
  double kineticMax = 0;
  // Memory (MB), and the growth after `settle` against what the frames keep.
  double rssStart = 0, rssSettle = 0, rssEnd = 0, peak = 0, heapSettle = 0, heapEnd = 0;
  double hdf5Settle = 0, hdf5End = 0; ///< HDF5's free lists (MB)
  int settleFrame = -1;
  double keptPerFrame = 0, bytesPerFrame = 0, predicted = 0, predictedFrames = 0,
         predictedSamples = 0;
  int wholeSettle = 0, wholeEnd = 0;      ///< frames whole in memory then
  long samplesSettle = 0, samplesEnd = 0; ///< the most quadrature samples seen (Super-Helix)
  bool flat = true;
  // The file.
  std::string follower;
  long followerReads = 0, followerFrames = 0;
  bool followed = false;
  long readBack = 0;
  int unreadable = -1;
  bool whole = false;
  std::string error;
  bool gateMemory = true;
  bool ok() const
  {
    return ran && nanFrame < 0 && bounded && (flat || !gateMemory) && followed && whole;
  }
};

std::string name(ModelType m)
{
  return findModel(m)->name;
}

Result run(ModelType model, const std::string& file, const BundledBody& body, const Settings& c)
{
  Result r;
  r.gateMemory = c.gateMemory;
  r.model = name(model);
  r.file = file;
  // The model's number for the demo's guides of the run's presets, the largest (the rods'
  // depends on the curl: 65 edges for the fuzzy preset, DerModel::edgesFor).
  int elements = 1;
  for (HairType preset : c.presets)
    elements = std::max(
        elements, findModel(model)->elementsFor(HairParameters::preset(preset), DemoGuideLength));
  std::vector<GuideStrand> guides;
  Status s = demoGuides(body, c.strands, elements, c.presets, guides);
  Scene scene = demoScene(body);
  // The demo's shake at `frequency`, faded in: started at full speed, the head would jerk
  // from rest to 2π f A (9.4 rad/s at 3 Hz) in one step.
  RigidMotion shake =
      RigidMotion::shake(bundled::neckPivot(), Eigen::Vector3d::UnitY(), c.amplitude, c.frequency);
  if (c.fade > 0)
    shake.during(0).fading(c.fade);
  scene.rootMotion = shake;
  scene.parts[0].motion = shake;
  SimulationOptions o;
  o.model = model;
  o.timeStep = c.step;
  o.frameInterval = c.interval;
  o.threads = c.threads;
  o.hairHair.enabled = c.hairHair; // the projective model has no hair–hair contacts
  StorageOptions storage;
  storage.stateFile = file;
  storage.replaceStateFile = true;       // the soak run writes its own output again
  storage.memoryBudget = c.memory * 1e6; // a few frames in memory, the others in the file only
  const int frames = static_cast<int>(std::lround(c.duration / c.interval)) + 1;
  storage.frames = frames;
  Simulation sim;
  if (s)
    s = sim.initialize(guides, scene, o, storage);
  if (!s)
  {
    r.error = s.message();
    return r;
  }
  int fd = -1;
  const pid_t follower = startFollower(file, frames, c.interval, fd);
  if (follower < 0)
  {
    r.error = "the follower could not be started";
    return r;
  }

  const auto start = std::chrono::steady_clock::now();
  auto wall = [&]
  { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  double peak = 0;
  memory(r.rssStart, peak);
  std::printf("\n# %s: %zu guides (%d of each of %zu presets, %d elements), shake ±%g rad at "
              "%g Hz, step %.4g s%s, a frame every %g s, %g s simulated, %d thread(s), "
              "state file %s\n",
              r.model.c_str(), guides.size(), c.strands, c.presets.size(), elements, c.amplitude,
              c.frequency, c.step, model == ModelType::Projective ? " (1 ms steps inside)" : "",
              c.interval, c.duration, c.threads, file.c_str());
  // How hard the shake is where the hair is: the roots' largest distance from its axis,
  // the speed and acceleration there (θ = A sin 2πft: ω ≤ 2πfA, α ≤ (2πf)²A).
  double reach = 0;
  for (const GuideStrand& g : guides)
    reach = std::max(reach, (g.root - bundled::neckPivot()).cross(Eigen::Vector3d::UnitY()).norm());
  const double w = 2 * M_PI * c.frequency;
  std::printf("# roots up to %.3f m from the shake's axis: up to %.2f m/s, %.1f m/s² (%.1f g) "
              "there; %.0f °/s at most\n",
              reach, w * c.amplitude * reach, w * w * c.amplitude * reach,
              w * w * c.amplitude * reach / 9.81, w * c.amplitude * 180 / M_PI);
  std::printf("# energy terms:");
  for (const auto& e : sim.frame(0).energy)
    std::printf(" %s", e.first.c_str());
  std::printf("\n");
  std::printf("%8s %9s %9s %9s %9s %11s %11s %11s %11s %11s %10s\n", "sim (s)", "wall (s)",
              "RSS (MB)", "heap (MB)", "HDF5 (MB)", "kinetic (J)", "E-E0 (J)", "work W (J)",
              "dissip. (J)", "residual (J)", "excess/F");
  const StateFrame& first = sim.frame(0);
  r.e0 = mechanical(first);
  const std::vector<std::string> extra = sim.extraEnergyTerms();
  const int perMinute = std::max(1, static_cast<int>(std::lround(60 / c.interval)));
  r.frames = 1;
  std::vector<long> most; // per strand, the most quadrature samples seen at a frame
  for (int f = 1; f < frames; ++f)
  {
    if (s = sim.advanceTo(f + 1); !s)
    {
      r.error = s.message();
      describeFailure(sim, guides, r.error);
      break;
    }
    const StateFrame& frame = sim.frame(f);
    superHelixSamples(sim, most);
    if (r.nanFrame < 0 &&
        (!finite(frame.energy) ||
         (sim.hasFrameData(f) && (!finite(frame.positions) || !finite(frame.velocities)))))
      r.nanFrame = f;
    // Energy bounded by the work done.
    double flow = term(frame, "dissipated");
    for (const std::string& t : extra)
    {
      // Works are the terms the budget sums into external_work; the model names them
      // *_work. The parts of a work ("projection work") are not among the terms.
      if (t.size() > 5 && t.compare(t.size() - 5, 5, "_work") == 0)
        flow += std::abs(term(frame, t.c_str()));
    }
    const double deltaE = mechanical(frame) - r.e0, work = term(frame, "external_work");
    const double excess = deltaE - work;
    if (excess > 0.05 * flow + 1e-12)
      r.bounded = false;
    if (excess > r.excess)
    {
      r.excess = excess;
      r.excessShare = flow > 0 ? excess / flow : 0;
      r.excessTime = frame.time;
    }
    r.kineticMax = std::max(r.kineticMax, term(frame, "kinetic"));
    r.frames = f + 1;
    r.simulated = frame.time;
    const bool settled = r.settleFrame < 0 && frame.time >= c.settle - 1e-9;
    if (f % perMinute == 0 || f == frames - 1 || settled)
    {
      double rss = 0;
      memory(rss, peak);
      if (settled)
      {
        r.settleFrame = f;
        r.rssSettle = rss;
        r.heapSettle = heapInUse();
        r.hdf5Settle = hdf5FreeLists();
        r.wholeSettle = wholeFrames(sim);
        r.samplesSettle = superHelixSamples(sim, most);
      }
      if (f % perMinute == 0 || f == frames - 1)
      {
        std::printf("%8.0f %9.1f %9.1f %9.1f %9.2f %11.4e %11.4e %11.4e %11.4e %11.4e %10.4f\n",
                    frame.time, wall(), rss, heapInUse(), hdf5FreeLists(), term(frame, "kinetic"),
                    deltaE, work, term(frame, "dissipated"), term(frame, "residual"),
                    r.excessShare);
        std::fflush(stdout);
      }
    }
  }
  r.wall = wall();
  memory(r.rssEnd, r.peak);
  r.heapEnd = heapInUse();
  r.hdf5End = hdf5FreeLists();
  if (!r.error.empty())
    kill(follower, SIGTERM); // by its pid: the follower this run started
  finishFollower(follower, fd, r.follower);
  r.followerReads = field(r.follower, "reads");
  r.followerFrames = field(r.follower, "frames");
  // A run that stopped (a step that failed) still has its frames so far checked: its
  // follower, stopped, must have read them without a failure.
  r.followed = r.follower.find("failures=0") != std::string::npos &&
               (!r.error.empty() || field(r.follower, "last") == frames);
  r.ran = r.error.empty();

  const StateFrame& last = sim.frame(r.frames - 1);
  r.deltaE = mechanical(last) - r.e0;
  r.work = term(last, "external_work");
  r.dissipated = term(last, "dissipated");
  r.residual = term(last, "residual");
  r.flow = r.dissipated;
  for (const std::string& t : extra)
    if (t.size() > 5 && t.compare(t.size() - 5, 5, "_work") == 0)
      r.flow += std::abs(term(last, t.c_str()));
  // Flat: after `settle` s the memory grows by what the frames keep, and by no more.
  r.keptPerFrame = bytesKeptPerFrame(last, sim.model().stepStatistics());
  r.bytesPerFrame = sim.bytesPerFrame();
  r.wholeEnd = wholeFrames(sim);
  r.samplesEnd = superHelixSamples(sim, most);
  if (r.settleFrame > 0)
  {
    // Frames added since: those still whole in memory (the window filling) took a whole
    // frame each, the others what is kept of a released frame.
    const int added = r.frames - 1 - r.settleFrame, whole = r.wholeEnd - r.wholeSettle;
    r.predictedFrames =
        (whole * r.bytesPerFrame + (added - whole) * r.keptPerFrame) / (1024.0 * 1024.0);
    // And the Super-Helix strands' sample buffers, to their most curved state seen.
    r.predictedSamples = (r.samplesEnd - r.samplesSettle) * BytesPerSample / (1024.0 * 1024.0);
    // And HDF5's free lists, measured.
    r.predicted = r.predictedFrames + r.predictedSamples + std::max(0.0, r.hdf5End - r.hdf5Settle);
    // 1 MB: the allocator's granularity (glibc grows its heap by 128 kB and more, and
    // moves the growing vectors of kept frames whole).
    r.flat = r.rssEnd - r.rssSettle <= 1.25 * r.predicted + 1.0;
  }

  // The state file whole, once the run is over: every frame read back, finite, at its time.
  StateFileReader reader;
  if (s = reader.open(file); s)
  {
    StateFrame f;
    for (std::int64_t k = 0; k < reader.numberOfFrames() && r.unreadable < 0; ++k)
    {
      if (!reader.readFrame(k, f) || !finite(f.positions) || !finite(f.velocities) ||
          std::abs(f.time - k * c.interval) > 1e-6)
        r.unreadable = static_cast<int>(k);
      else
        ++r.readBack;
    }
  }
  r.whole = s && reader.numberOfFrames() == r.frames && r.unreadable < 0;
  return r;
}

void report(const std::vector<Result>& results, const Settings& c)
{
  std::printf("\n# the checks (E(t) − E(0) ≤ W(t) + 0.05 F(t) at every frame; memory growth "
              "after %g s against what the frames keep)\n",
              c.settle);
  for (const Result& r : results)
  {
    std::printf("\n%s: %s\n", r.model.c_str(), r.ok() ? "every check holds" : "A CHECK FAILED");
    if (!r.error.empty())
      std::printf("  stopped: %s\n", r.error.c_str());
    std::printf("  %-22s %g s simulated, %d frames, %.0f s wall (%.2f ms per 1/30 s simulated)\n",
                "run", r.simulated, r.frames, r.wall,
                r.simulated > 0 ? 1000 * r.wall / (r.simulated * 30) : 0.0);
    std::printf("  %-22s %s\n", "no NaN",
                r.nanFrame < 0 ? "yes" : ("NO (frame " + std::to_string(r.nanFrame) + ")").c_str());
    std::printf("  %-22s %s: at the end E − E0 = %.4e J, W = %.4e J, dissipated %.4e J, "
                "residual %.4e J (%.1f %% of F = %.4e J); largest E − E0 − W = %.3e J = %.4f F "
                "at t = %g s; kinetic at most %.4e J\n",
                "energy <= work", r.bounded ? "yes" : "NO", r.deltaE, r.work, r.dissipated,
                r.residual, r.flow > 0 ? 100 * r.residual / r.flow : 0.0, r.flow, r.excess,
                r.excessShare, r.excessTime, r.kineticMax);
    const int after = r.frames - 1 - r.settleFrame;
    const double grew = r.rssEnd - r.rssSettle;
    std::printf("  %-22s %s: RSS %.1f MB at start, %.1f MB at %g s, %.1f MB at the end (peak "
                "%.1f MB); grew %.2f MB over %d frames (%.0f B a frame), predicted %.2f MB "
                "(%.0f B a released frame)\n",
                "memory flat",
                r.flat ? "yes" : (r.gateMemory ? "NO" : "no (reported, not a failure)"), r.rssStart,
                r.rssSettle, c.settle, r.rssEnd, r.peak, grew, after,
                after > 0 ? grew * 1048576 / after : 0.0, r.predicted, r.keptPerFrame);
    std::printf("  %-22s predicted: %.2f MB of frames (%d whole in memory at %g s, %d at the "
                "end, %.0f kB each) and %.2f MB of quadrature samples (%ld at %g s, %ld at the "
                "end, %.0f B each) and %.2f MB more in HDF5's free lists (%.2f MB at %g s, "
                "%.2f MB at the end); heap in use %.2f MB at %g s, %.2f MB at the end\n",
                "", r.predictedFrames, r.wholeSettle, c.settle, r.wholeEnd, r.bytesPerFrame / 1024,
                r.predictedSamples, r.samplesSettle, c.settle, r.samplesEnd, BytesPerSample,
                r.hdf5End - r.hdf5Settle, r.hdf5Settle, c.settle, r.hdf5End, r.heapSettle, c.settle,
                r.heapEnd);
    std::printf("  %-22s %s: %s\n", "followed", r.followed ? "yes" : "NO", r.follower.c_str());
    std::printf("  %-22s %s: %ld of %d frames read back (%s)\n", "file whole",
                r.whole ? "yes" : "NO", r.readBack, r.frames, r.file.c_str());
  }
}

bool parsePresets(const std::string& text, std::vector<HairType>& out)
{
  out.clear();
  const HairType all[] = {HairType::Smooth, HairType::Wavy, HairType::Curly, HairType::Fuzzy};
  if (text == "all")
  {
    out.assign(std::begin(all), std::end(all));
    return true;
  }
  std::stringstream in(text);
  for (std::string word; std::getline(in, word, ',');)
  {
    const auto found = std::find_if(std::begin(all), std::end(all),
                                    [&](HairType t) { return word == toString(t); });
    if (found == std::end(all))
      return false;
    out.push_back(*found);
  }
  return !out.empty();
}

std::string withSuffix(const std::string& file, const std::string& suffix)
{
  const auto dot = file.rfind(".h5");
  return dot != std::string::npos && dot + 3 == file.size()
             ? file.substr(0, dot) + "-" + suffix + ".h5"
             : file + "-" + suffix + ".h5";
}
} // namespace

/// The keys of hair_soak, with their defaults, ranges and meaning (StudyArguments.h);
/// follow= and frames= are the follower process's (the run starts it with them).
const hair::tools::Keys& soakKeys()
{
  using namespace hair::tools;
  static const Keys keys = {
      textKey("out", "", "the state file of the run (required)").as("<file.h5>"),
      modelKey("model", "both", "the model, or both: Super-Helix then projective", {"both"}),
      textKey("presets", "all", "all, or a comma-separated list of smooth, wavy, curly, fuzzy"),
      integerKey("strands", "200", 1, 5000, "guides per preset"),
      numberKey("duration", "3600", 1, 86400, "s simulated"),
      numberKey("interval", "1.1", 1.0 / 30, 60, "s between stored frames"),
      numberKey("frequency", "3", 0, 20, "Hz of the head's shake").openBelow(),
      numberKey("amplitude", "0.5", 0, 1.5, "rad of the head's shake"),
      numberKey("fade", "1", 0, 10, "s over which the shake fades in"),
      numberKey("settle", "60", 0, 86400, "s after which the memory must be flat (< duration)"),
      numberKey("memory", "8", 0.1, 1e5, "MB of frames the run keeps in memory"),
      choiceKey("hairhair", "on", {"on", "off"}, "the Super-Helix's hair–hair interaction"),
      choiceKey("flat", "strict", {"strict", "report"},
                "strict: a memory growth beyond what the run accounts for fails the run"),
      numberKey("step", "0.0333333333333333333", 1e-4, 60, "s, the model's step (≤ interval)"),
      integerKey("threads", "1", 1, 256, "threads"),
      textKey("follow", "", "the follower process's file").hide(),
      integerKey("frames", "0", 0, 1e9, "the follower process's frames").hide()};
  return keys;
}

int main(int argc, char** argv)
{
  hair::tools::Arguments args;
  if (argc == 2 && std::string(argv[1]) == "help")
  {
    std::cout << "hair_soak: the soak run, a model or both under a shake for a long time.\n";
    hair::tools::describe(std::cout, soakKeys());
    return 0;
  }
  if (Status s = args.parse(argc, argv, 1, soakKeys(), "hair_soak"); !s)
  {
    std::cerr << "hair_soak: " << s.message() << "\n";
    return 2;
  }
  if (args.has("follow"))
    return follow(args.text("follow"), args.integer("frames"), args.number("interval"));

  Settings c;
  c.duration = args.number("duration");
  c.interval = args.number("interval");
  c.strands = args.integer("strands");
  c.threads = args.integer("threads");
  c.frequency = args.number("frequency");
  c.amplitude = args.number("amplitude");
  c.fade = args.number("fade");
  c.settle = args.number("settle");
  c.memory = args.number("memory");
  c.step = args.number("step");
  c.hairHair = args.text("hairhair") == "on";
  c.gateMemory = args.text("flat") == "strict";
  std::vector<ModelType> models;
  if (args.text("model") == "both")
    models = {ModelType::SuperHelix, ModelType::Projective};
  else
    models.push_back(args.model("model"));
  std::string problem;
  if (!args.has("out"))
    problem = "give the output file: out=<file.h5>.";
  else if (!parsePresets(args.text("presets"), c.presets))
    problem = "presets=" + args.text("presets") +
              " is not all or a comma-separated list of smooth, wavy, curly, fuzzy.";
  else if (!(c.settle < c.duration))
    problem = "settle=" + args.written("settle") +
              " is not below duration=" + args.written("duration") + ".";
  else if (!(c.step <= c.interval))
    problem = "step=" + args.written("step") +
              " is longer than interval=" + args.written("interval") + ".";
  if (!problem.empty())
  {
    std::cerr << "hair_soak: " << problem << "\n"
              << "usage: hair_soak " << hair::tools::usageLine(soakKeys(), 18) << "\n";
    return 2;
  }

  BundledBody body;
  if (Status s = loadBundledBody(HAIR_DATA_DIR, body); !s)
  {
    std::cerr << "hair_soak: " << s.message() << "\n";
    return 1;
  }
  std::vector<Result> results;
  for (ModelType model : models)
  {
    const std::string out = args.text("out");
    const std::string file = models.size() > 1 ? withSuffix(out, name(model)) : out;
    results.push_back(run(model, file, body, c));
  }
  report(results, c);
  return std::all_of(results.begin(), results.end(), [](const Result& r) { return r.ok(); }) ? 0
                                                                                             : 1;
}
