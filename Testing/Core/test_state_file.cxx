// The HDF5 state file: exact round trip, a writer killed with SIGKILL mid-run, a reader
// following a writer, and files that are not state files. The reference for the layout is
// docs/state-file.md (what h5py users read), checked here with HDF5's own C API.
#include "io/StateFile.h"
#include "simulation/GuideDrawing.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace hair;

namespace
{
StateHeader header(int strands, int pointsPerStrand, int coordinates)
{
  StateHeader h;
  h.model = "super-helix";
  h.coordinatesPerStrand = coordinates;
  for (int k = 0; k <= strands; ++k)
  {
    h.offsets.push_back(std::int64_t(k) * pointsPerStrand);
  }
  h.strandParameters["length"] = std::vector<double>(strands, 0.3);
  h.strandParameters["radius"] = std::vector<double>(strands, 5e-5);
  h.attributes["time_step"] = 1.0 / 30;
  h.pointData = {"curvature"};
  return h;
}

/// A frame whose every value is a known function of (frame, index), so a reader can check
/// each one without having kept them.
StateFrame frame(const StateHeader& h, int t)
{
  StateFrame f;
  f.time = t / 30.0;
  for (std::size_t i = 0; i < h.numberOfPoints(); ++i)
  {
    f.positions.emplace_back(t + 0.001 * i, -double(i), 0.5 * t);
    f.velocities.emplace_back(1e-3 * t, 2e-3 * i, -1.0);
  }
  for (std::size_t i = 0; i < h.numberOfPoints(); ++i)
  {
    f.pointData["curvature"].push_back(10.0 * t + 0.5 * i);
  }
  const std::size_t nq = h.numberOfStrands() * h.coordinatesPerStrand;
  for (std::size_t i = 0; i < nq; ++i)
  {
    f.q.push_back(0.01 * t + i);
    f.qdot.push_back(-0.02 * t + i);
  }
  f.energy = {{"kinetic", 1.0 * t},    {"elastic", 2.0 * t},        {"gravitational", -3.0 * t},
              {"dissipated", 0.5 * t}, {"external_work", 0.25 * t}, {"residual", 1e-9 * t}};
  return f;
}

/// A fresh path in the test's temporary folder: a file left there by an earlier run is
/// removed (the writer keeps existing files unless told otherwise).
std::string temp(const char* name)
{
  const std::string path = ::testing::TempDir() + "/" + name;
  std::remove(path.c_str());
  return path;
}

void expectFrameEquals(const StateFrame& a, const StateFrame& b)
{
  EXPECT_EQ(a.time, b.time);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i)
  {
    EXPECT_EQ(a.positions[i], b.positions[i]);
    EXPECT_EQ(a.velocities[i], b.velocities[i]);
  }
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.qdot, b.qdot);
  EXPECT_EQ(a.pointData, b.pointData);
  for (const auto& [name, value] : b.energy)
  {
    EXPECT_EQ(a.energy.at(name), value) << name;
  }
}
} // namespace

TEST(StateFile, RoundTripIsExact)
{
  const StateHeader h = header(7, 11, 30);
  const std::string path = temp("roundtrip.h5");
  {
    StateFileWriter w;
    ASSERT_TRUE(w.create(path, h, {"residual"}).ok());
    for (int t = 0; t < 25; ++t)
    {
      const Status s = w.append(frame(h, t));
      ASSERT_TRUE(s.ok()) << s.message();
    }
  }
  StateFileReader r;
  const Status s = r.open(path);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(r.numberOfFrames(), 25);
  EXPECT_EQ(r.header().model, "super-helix");
  EXPECT_EQ(r.header().offsets, h.offsets);
  EXPECT_EQ(r.header().coordinatesPerStrand, 30);
  EXPECT_EQ(r.header().strandParameters.at("length"), h.strandParameters.at("length"));
  EXPECT_EQ(r.header().attributes.at("time_step"), 1.0 / 30);
  for (int t = 0; t < 25; ++t)
  {
    StateFrame f;
    ASSERT_TRUE(r.readFrame(t, f).ok());
    expectFrameEquals(f, frame(h, t));
    EXPECT_EQ(r.energies().at("residual")[t], 1e-9 * t);
  }
  StateFrame f;
  EXPECT_FALSE(r.readFrame(25, f).ok());
}

TEST(StateFile, LayoutIsTheDocumentedOne)
{
  // Read with HDF5's C API by the documented names only (what an h5py user does).
  const StateHeader h = header(3, 4, 6);
  const std::string path = temp("layout.h5");
  {
    StateFileWriter w;
    ASSERT_TRUE(w.create(path, h, {"residual"}).ok());
    for (int t = 0; t < 3; ++t)
    {
      ASSERT_TRUE(w.append(frame(h, t)).ok());
    }
  }
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* name :
       {"/time", "/strands/offsets", "/strands/length", "/frames/positions", "/frames/velocities",
        "/frames/curvature", "/frames/q", "/frames/qdot", "/energy/kinetic", "/energy/elastic",
        "/energy/gravitational", "/energy/dissipated", "/energy/external_work"})
  {
    EXPECT_GT(H5Lexists(f, name, H5P_DEFAULT), 0) << name;
  }
  hid_t d = H5Dopen2(f, "/frames/positions", H5P_DEFAULT);
  hid_t space = H5Dget_space(d);
  hsize_t dims[3];
  ASSERT_EQ(H5Sget_simple_extent_ndims(space), 3);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  EXPECT_EQ(dims[0], 3u);
  EXPECT_EQ(dims[1], 12u);
  EXPECT_EQ(dims[2], 3u);
  std::vector<double> all(3 * 12 * 3);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  // Frame 2, point 5: (2 + 0.005, −5, 1).
  EXPECT_EQ(all[(2 * 12 + 5) * 3 + 0], 2.005);
  EXPECT_EQ(all[(2 * 12 + 5) * 3 + 1], -5.0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

TEST(StateFile, WriterKilledWithSigkillLeavesEveryWholeFrame)
{
  const StateHeader h = header(20, 41, 30);
  const std::string path = temp("killed.h5");
  std::remove(path.c_str());
  int pipefd[2];
  ASSERT_EQ(pipe(pipefd), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0)
  {
    close(pipefd[0]);
    StateFileWriter w;
    if (!w.create(path, h, {"residual"}))
    {
      _exit(2);
    }
    for (int t = 0;; ++t) // forever, until killed
    {
      if (!w.append(frame(h, t)))
      {
        _exit(3);
      }
      if (t == 40)
      {
        const char c = 'x';
        (void)!write(pipefd[1], &c, 1); // 41 frames are on disk: the parent may kill now
      }
    }
  }
  close(pipefd[1]);
  char c;
  ASSERT_EQ(read(pipefd[0], &c, 1), 1);
  usleep(20000); // let it be somewhere in the middle of a later frame
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));

  StateFileReader r;
  const Status s = r.open(path);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_GE(r.numberOfFrames(), 41);
  std::printf("killed writer: %lld whole frames read back\n", (long long)r.numberOfFrames());
  for (std::int64_t t = 0; t < r.numberOfFrames(); ++t)
  {
    StateFrame f;
    ASSERT_TRUE(r.readFrame(t, f).ok());
    expectFrameEquals(f, frame(h, int(t)));
  }
}

TEST(StateFile, ForeignDamagedAndMissingFilesAreRefused)
{
  const std::string text = temp("foreign.txt");
  std::ofstream(text) << "this is not HDF5\n";
  StateFileReader r;
  Status s = r.open(text);
  EXPECT_NE(s.message().find("not an HDF5 file"), std::string::npos) << s.message();

  // An HDF5 file without the format attribute.
  const std::string other = temp("other.h5");
  hid_t f = H5Fcreate(other.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Fclose(f);
  s = r.open(other);
  EXPECT_NE(s.message().find("not a HairDynamics state file"), std::string::npos) << s.message();

  // A state file cut in half.
  const StateHeader h = header(5, 9, 0);
  const std::string whole = temp("whole.h5"), cut = temp("cut.h5");
  {
    StateFileWriter w;
    ASSERT_TRUE(w.create(whole, h, {"residual"}).ok());
    for (int t = 0; t < 10; ++t)
    {
      ASSERT_TRUE(w.append(frame(h, t)).ok());
    }
  }
  {
    std::ifstream in(whole, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  s = r.open(cut);
  EXPECT_FALSE(s.ok());
  std::printf("cut file: %s\n", s.message().c_str());
  EXPECT_NE(s.message().find("damaged"), std::string::npos) << s.message();

  s = r.open(temp("does-not-exist.h5"));
  EXPECT_NE(s.message().find("cannot be opened"), std::string::npos) << s.message();
  EXPECT_EQ(r.numberOfFrames(), 0);
}

TEST(StateFile, BadFramesAreRefusedAndEarlierFramesKept)
{
  const StateHeader h = header(2, 3, 0);
  const std::string path = temp("nan.h5");
  StateFileWriter w;
  ASSERT_TRUE(w.create(path, h, {"residual"}).ok());
  ASSERT_TRUE(w.append(frame(h, 0)).ok());
  StateFrame bad = frame(h, 1);
  bad.positions[2].y() = std::nan("");
  Status s = w.append(bad);
  EXPECT_NE(s.message().find("NaN"), std::string::npos) << s.message();
  bad = frame(h, 1);
  bad.velocities.pop_back();
  s = w.append(bad);
  EXPECT_NE(s.message().find("/frames/velocities: expected 18 values, got 15"), std::string::npos)
      << s.message();
  bad = frame(h, 1);
  bad.energy["made_up"] = 1;
  EXPECT_FALSE(w.append(bad).ok());
  w.close();
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  EXPECT_EQ(r.numberOfFrames(), 1);

  StateHeader none;
  EXPECT_NE(w.create(path, none).message().find("no strands"), std::string::npos);
  EXPECT_NE(w.create("/nonexistent-folder/x.h5", h).message().find("cannot be created"),
            std::string::npos);
}

TEST(StateFile, AttributesOfAnotherShapeAreNotReadIntoOneValue)
{
  // A user (or h5py) may store a root attribute as an array: the reader takes one value
  // only from an attribute that holds exactly one, and ignores or refuses the others
  // instead of reading past a scalar (which overflowed the stack before).
  const StateHeader h = header(2, 3, 0);
  StateFileReader r;
  auto withAttribute = [&](const char* name, hid_t type, const void* values, hsize_t count)
  {
    r.close();
    const std::string path = temp("array-attribute.h5");
    {
      StateFileWriter w;
      EXPECT_TRUE(w.create(path, h, {"residual"}).ok());
      EXPECT_TRUE(w.append(frame(h, 0)).ok());
    }
    hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (H5Aexists(f, name) > 0)
      H5Adelete(f, name);
    hid_t space = H5Screate_simple(1, &count, nullptr);
    hid_t a = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, values);
    H5Aclose(a);
    H5Sclose(space);
    H5Fclose(f);
    return path;
  };
  const double gravity[3] = {0, -9.81, 0};
  Status s = r.open(withAttribute("gravity", H5T_NATIVE_DOUBLE, gravity, 3));
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(r.header().attributes.count("gravity"), 0u); // not a scalar run attribute
  EXPECT_EQ(r.numberOfFrames(), 1);

  const int versions[4] = {1, 1, 1, 1};
  s = r.open(withAttribute("format_version", H5T_NATIVE_INT, versions, 4));
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("format version"), std::string::npos) << s.message();

  const int coordinates[8] = {3, 3, 3, 3, 3, 3, 3, 3};
  s = r.open(withAttribute("coordinates_per_strand", H5T_NATIVE_INT, coordinates, 8));
  EXPECT_EQ(r.header().coordinatesPerStrand, 0) << s.message();

  hid_t strings = H5Tcopy(H5T_C_S1);
  H5Tset_size(strings, H5T_VARIABLE);
  const char* formats[2] = {"HairDynamics states", "HairDynamics states"};
  s = r.open(withAttribute("format", strings, formats, 2));
  H5Tclose(strings);
  EXPECT_NE(s.message().find("not a HairDynamics state file"), std::string::npos) << s.message();
}

TEST(StateFile, NothingButAStateFileIsWrittenOverAndThatOnlyWhenAsked)
{
  // A user's notes, another program's HDF5 file, a folder: never written over, whatever the
  // caller asks (issue 24: a State File Name naming an existing file overwrote it).
  const StateHeader h = header(7, 11, 30);
  const std::string notes = temp("notes.h5");
  {
    std::ofstream(notes) << "my notes\n";
  }
  const std::string other = temp("other-program.h5");
  {
    const hid_t f = H5Fcreate(other.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 4;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d =
        H5Dcreate2(f, "data", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dclose(d);
    H5Sclose(space);
    H5Fclose(f);
  }
  for (const std::string& path : {notes, other, ::testing::TempDir()})
  {
    for (auto existing :
         {StateFileWriter::Existing::Refuse, StateFileWriter::Existing::ReplaceStateFile})
    {
      StateFileWriter w;
      const Status s = w.create(path, h, {}, existing);
      ASSERT_FALSE(s.ok()) << path;
      EXPECT_NE(s.message().find("not written over"), std::string::npos) << s.message();
    }
  }
  std::ifstream kept(notes);
  std::string line;
  std::getline(kept, line);
  EXPECT_EQ(line, "my notes");

  // A state file: kept unless the caller says to replace it.
  const std::string state = temp("existing-state.h5");
  {
    StateFileWriter w;
    ASSERT_TRUE(w.create(state, h, {"residual"}).ok());
    ASSERT_TRUE(w.append(frame(h, 0)).ok());
    ASSERT_TRUE(w.close().ok());
  }
  StateFileWriter again;
  const Status refused = again.create(state, h, {"residual"});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("exists (a state file of 1 frames)"), std::string::npos)
      << refused.message();
  const Status replaced =
      again.create(state, h, {"residual"}, StateFileWriter::Existing::ReplaceStateFile);
  EXPECT_TRUE(replaced.ok()) << replaced.message();
}

TEST(StateFile, EarlierVersionsReadAsBefore)
{
  // Files written before format version 3 (Testing/Fuzz/corpus: version 1 by one writer, both
  // models, at 4 points per element; Testing/Fixtures/StateFiles: version 2 by two ranks, at
  // 2): they open, and drawn at
  // their stored resolution they give back their stored points, velocities and curvature, as
  // the reader showed them before (the Super-Helix's were drawn by the same code from the
  // same q and roots; the projective model's are its nodes, its curvature the turning angle
  // over the segment length, here over the chord: equal to round-off).
  struct Fixture
  {
    const char* dir;
    const char* name;
    int version;
    std::size_t strands, points, frames;
  };
  for (const Fixture& x : {Fixture{HAIR_CORPUS_DIR, "v1-super-helix.h5", 1, 2, 9, 2},
                           Fixture{HAIR_CORPUS_DIR, "v1-projective.h5", 1, 2, 3, 2},
                           Fixture{HAIR_STATE_FILES_DIR, "v2-super-helix.h5", 2, 6, 21, 3}})
  {
    SCOPED_TRACE(x.name);
    StateFileReader r;
    const Status opened = r.open(std::string(x.dir) + "/" + x.name);
    ASSERT_TRUE(opened.ok()) << opened.message();
    EXPECT_EQ(r.version(), x.version);
    EXPECT_EQ(r.numberOfFrames(), std::int64_t(x.frames));
    const StateHeader& h = r.header();
    ASSERT_EQ(h.numberOfStrands(), x.strands);
    EXPECT_EQ(std::size_t(h.offsets[1]), x.points);
    EXPECT_FALSE(h.singlePrecisionPoints);
    EXPECT_TRUE(h.rootFrames);
    for (std::int64_t f = 0; f < r.numberOfFrames(); ++f)
    {
      StateFrame stored;
      ASSERT_TRUE(r.readFrame(f, stored).ok());
      GuideDrawing same;
      ASSERT_TRUE(drawGuides(h, stored, 0, 1, same).ok());
      EXPECT_TRUE(same.warning.empty()) << same.warning;
      ASSERT_EQ(same.frame.positions.size(), stored.positions.size());
      EXPECT_EQ(same.frame.positions, stored.positions);
      EXPECT_EQ(same.frame.velocities, stored.velocities);
      const std::vector<double>& drawn = same.frame.pointData.at("curvature");
      const std::vector<double>& kept = stored.pointData.at("curvature");
      ASSERT_EQ(drawn.size(), kept.size());
      for (std::size_t i = 0; i < kept.size(); ++i)
      {
        EXPECT_NEAR(drawn[i], kept[i], 1e-12 * std::max(1.0, std::abs(kept[i]))) << i;
      }
      // And at any other resolution (the Super-Helix), with every stored array.
      GuideDrawing fine;
      ASSERT_TRUE(drawGuides(h, stored, 16, 1, fine).ok());
      for (const char* name : {"curvature", "twist", "contact_depth"})
      {
        EXPECT_EQ(fine.frame.pointData.at(name).size(), fine.frame.positions.size()) << name;
      }
    }
    // A piece reads as the same strands of the whole frame.
    StateFrame whole, piece;
    ASSERT_TRUE(r.readFrame(1, whole).ok());
    ASSERT_TRUE(r.readPiece(1, {1}, piece).ok());
    ASSERT_EQ(piece.positions.size(), x.points);
    EXPECT_EQ(piece.positions[0], whole.positions[x.points]);
  }
}
