// The state-file reader against damaged and crafted files (issue 24; docs/bad-input.md has the
// table of inputs and messages): every attribute's type and shape, every dataset's type,
// rank and extents against each other and the file's size, non-finite or decreasing times,
// NaN values in a frame, special files, flipped bytes, and two readers of one growing file.
// Each file is a real state file (StateFileWriter) edited with HDF5's C API, as a user's
// script or a damaged disk would leave it.
#include "io/CheckedReadDriver.h"
#include "io/StateFile.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>

using namespace hair;

namespace
{
constexpr int Strands = 2, PerStrand = 3, Coordinates = 6, Frames = 3;

StateHeader header()
{
  StateHeader h;
  h.model = "super-helix";
  h.coordinatesPerStrand = Coordinates;
  for (int k = 0; k <= Strands; ++k)
  {
    h.offsets.push_back(std::int64_t(k) * PerStrand);
  }
  h.strandParameters["length"] = std::vector<double>(Strands, 0.3);
  h.strandVectors["rest_root"] = std::vector<Eigen::Vector3d>(Strands, Eigen::Vector3d(0, 1, 0));
  h.attributes["time_step"] = 1.0 / 30;
  h.pointData = {"curvature"};
  h.rootFrames = true;
  return h;
}

StateFrame frame(const StateHeader& h, int t)
{
  StateFrame f;
  f.time = t / 30.0;
  for (std::size_t i = 0; i < h.numberOfPoints(); ++i)
  {
    f.positions.emplace_back(t + 0.001 * i, -double(i), 0.5 * t);
    f.velocities.emplace_back(1e-3 * t, 2e-3 * i, -1.0);
    f.pointData["curvature"].push_back(10.0 * t + 0.5 * i);
  }
  f.q.assign(h.numberOfStrands() * h.coordinatesPerStrand, 0.01 * t);
  f.qdot.assign(f.q.size(), -0.02 * t);
  f.rootFrames.assign(h.numberOfStrands() * RootFrameValues, 0.5);
  f.rootVelocities.assign(h.numberOfStrands() * RootVelocityValues, 0.25);
  f.energy = {{"kinetic", 1.0 * t}, {"elastic", 2.0 * t}, {"gravitational", -3.0 * t}};
  return f;
}

std::string temp(const std::string& name)
{
  const std::string path = ::testing::TempDir() + "/bad-input-" + name;
  std::remove(path.c_str());
  return path;
}

/// A whole state file of `frames` frames, written by the writer, closed.
std::string stateFile(const std::string& name, int frames = Frames)
{
  const std::string path = temp(name);
  const StateHeader h = header();
  StateFileWriter w;
  EXPECT_TRUE(w.create(path, h).ok());
  for (int t = 0; t < frames; ++t)
  {
    EXPECT_TRUE(w.append(frame(h, t)).ok());
  }
  EXPECT_TRUE(w.close().ok());
  return path;
}

/// A state file, then `edit` applied to it through HDF5 (opened read-write, plainly).
std::string edited(const std::string& name, const std::function<void(hid_t)>& edit)
{
  const std::string path = stateFile(name);
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  EXPECT_GE(f, 0);
  edit(f);
  H5Fclose(f);
  return path;
}

/// Replaces attribute `name` of the root by one of `type` and `count` values (0: a null
/// dataspace; −1: a scalar).
void attribute(hid_t f, const char* name, hid_t type, long long count, const void* values)
{
  if (H5Aexists(f, name) > 0)
  {
    H5Adelete(f, name);
  }
  const hsize_t n = hsize_t(std::max(count, 1LL));
  const hid_t space = count < 0    ? H5Screate(H5S_SCALAR)
                      : count == 0 ? H5Screate(H5S_NULL)
                                   : H5Screate_simple(1, &n, nullptr);
  const hid_t a = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (count != 0)
  {
    H5Awrite(a, type, values);
  }
  H5Aclose(a);
  H5Sclose(space);
}

hid_t variableString()
{
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  return t;
}

hid_t fixedString(std::size_t size)
{
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, size);
  H5Tset_strpad(t, H5T_STR_NULLPAD);
  return t;
}

/// Replaces the dataset at `path` by one of `type` with dimensions `dims` (maximum
/// dimensions `maxDims`, chunked by `chunk` when given), written from `values` unless null.
void dataset(hid_t f, const char* path, hid_t type, const std::vector<hsize_t>& dims,
             const void* values, const std::vector<hsize_t>& chunk = {},
             std::vector<hsize_t> maxDims = {})
{
  if (H5Lexists(f, path, H5P_DEFAULT) > 0)
  {
    H5Ldelete(f, path, H5P_DEFAULT);
  }
  if (maxDims.empty())
  {
    maxDims = dims;
  }
  const hid_t space = dims.empty()
                          ? H5Screate(H5S_SCALAR)
                          : H5Screate_simple(int(dims.size()), dims.data(), maxDims.data());
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (!chunk.empty())
  {
    H5Pset_chunk(dcpl, int(chunk.size()), chunk.data());
  }
  const hid_t d = H5Dcreate2(f, path, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  EXPECT_GE(d, 0) << path;
  if (values)
  {
    EXPECT_GE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), 0) << path;
  }
  H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
}

/// Writes value `v` at flat index `i` of the double dataset at `path`.
void poke(hid_t f, const char* path, hsize_t i, double v)
{
  const hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<double> all(H5Sget_simple_extent_npoints(space));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  all.at(i) = v;
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data());
  H5Sclose(space);
  H5Dclose(d);
}

/// Opens `path` and expects a refusal whose message names the file and contains `what`.
void expectRefused(const std::string& path, const std::string& what)
{
  StateFileReader r;
  const Status s = r.open(path);
  ASSERT_FALSE(s.ok()) << path << " was read; expected: " << what;
  std::printf("refused: %s\n", s.message().c_str()); // the messages of docs/bad-input.md
  EXPECT_NE(s.message().find(what), std::string::npos) << s.message();
  EXPECT_NE(s.message().find(path), std::string::npos) << s.message();
  EXPECT_EQ(r.numberOfFrames(), 0);
}

void expectRead(const std::string& path)
{
  StateFileReader r;
  const Status s = r.open(path);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(r.numberOfFrames(), Frames);
  for (int t = 0; t < Frames; ++t)
  {
    StateFrame f;
    EXPECT_TRUE(r.readFrame(t, f).ok()) << t;
  }
}
} // namespace

TEST(StateFileBadInput, TheUneditedFileReads)
{
  expectRead(stateFile("plain.h5"));
}

TEST(StateFileBadInput, AttributesOfAnotherTypeOrShapeAreRefusedByName)
{
  const hid_t vls = variableString();
  const char* two[2] = {"HairDynamics states", "HairDynamics states"};
  expectRefused(edited("format-two.h5", [&](hid_t f) { attribute(f, "format", vls, 2, two); }),
                "its attribute 'format' holds 2 values where one is expected");
  const int number = 1;
  expectRefused(edited("format-int.h5",
                       [&](hid_t f) { attribute(f, "format", H5T_NATIVE_INT, -1, &number); }),
                "'format' is an integer where a string is expected");
  expectRefused(edited("format-null.h5", [&](hid_t f) { attribute(f, "format", vls, 0, nullptr); }),
                "'format' holds 0 values");
  const int versions[4] = {1, 1, 1, 1};
  expectRefused(edited("version-array.h5", [&](hid_t f)
                       { attribute(f, "format_version", H5T_NATIVE_INT, 4, versions); }),
                "'format_version' holds 4 values");
  const double one = 1.0;
  expectRefused(edited("version-float.h5", [&](hid_t f)
                       { attribute(f, "format_version", H5T_NATIVE_DOUBLE, -1, &one); }),
                "'format_version' is a floating-point number where an integer is expected");
  const char* version[1] = {"1"};
  expectRefused(edited("version-string.h5",
                       [&](hid_t f) { attribute(f, "format_version", vls, -1, version); }),
                "'format_version' is a string where an integer is expected");
  const char* models[3] = {"super-helix", "projective", "x"};
  expectRefused(edited("model-three.h5", [&](hid_t f) { attribute(f, "model", vls, 3, models); }),
                "'model' holds 3 values");
  expectRefused(edited("model-missing.h5", [&](hid_t f) { H5Adelete(f, "model"); }),
                "'model' is missing");
  const int coordinates[8] = {3, 3, 3, 3, 3, 3, 3, 3};
  expectRefused(edited("coordinates-array.h5", [&](hid_t f)
                       { attribute(f, "coordinates_per_strand", H5T_NATIVE_INT, 8, coordinates); }),
                "'coordinates_per_strand' holds 8 values");
  const long long huge = 5000000000LL;
  expectRefused(edited("coordinates-huge.h5", [&](hid_t f)
                       { attribute(f, "coordinates_per_strand", H5T_NATIVE_LLONG, -1, &huge); }),
                "'coordinates_per_strand' is 5000000000, out of range");
  const int negative = -6;
  expectRefused(edited("coordinates-negative.h5", [&](hid_t f)
                       { attribute(f, "coordinates_per_strand", H5T_NATIVE_INT, -1, &negative); }),
                "coordinates_per_strand is -6, outside [0, 3000]");
  H5Tclose(vls);
}

TEST(StateFileBadInput, FixedLengthStringsAndArrayRunAttributesRead)
{
  // What h5py writes for numpy bytes: fixed-length strings, without a terminating null.
  const hid_t fixed = fixedString(19);
  const std::string path = edited("fixed-strings.h5",
                                  [&](hid_t f)
                                  {
                                    attribute(f, "format", fixed, -1, "HairDynamics states");
                                    H5Tset_size(fixed, 11);
                                    attribute(f, "model", fixed, -1, "super-helix");
                                    const double g[3] = {0, -9.81, 0};
                                    attribute(f, "gravity", H5T_NATIVE_DOUBLE, 3, g);
                                  });
  H5Tclose(fixed);
  expectRead(path);
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  EXPECT_EQ(r.header().model, "super-helix");
  EXPECT_EQ(r.header().attributes.count("gravity"), 0u); // not one value: not a run attribute
}

TEST(StateFileBadInput, DatasetsOfAnotherTypeOrShapeAreRefusedBeforeReading)
{
  const double offsets[3] = {0, 3, 6};
  expectRefused(edited("offsets-float.h5", [&](hid_t f)
                       { dataset(f, "/strands/offsets", H5T_NATIVE_DOUBLE, {3}, offsets); }),
                "/strands/offsets holds floating-point numbers where integers are expected");
  const std::int64_t square[4] = {0, 3, 3, 6};
  expectRefused(edited("offsets-2d.h5",
                       [&](hid_t f) {
                         dataset(f, "/strands/offsets", H5T_NATIVE_INT64, {2, 2}, square);
                       }),
                "/strands/offsets has 2 dimensions where 1 are expected");
  const std::int64_t decreasing[3] = {0, 3, 2};
  expectRefused(edited("offsets-decreasing.h5", [&](hid_t f)
                       { dataset(f, "/strands/offsets", H5T_NATIVE_INT64, {3}, decreasing); }),
                "strand 1 has no points");
  const hid_t vls = variableString();
  const char* words[3] = {"a", "b", "c"};
  expectRefused(edited("time-strings.h5", [&](hid_t f) { dataset(f, "/time", vls, {3}, words); }),
                "/time holds strings where numbers are expected");
  expectRefused(
      edited("energy-strings.h5", [&](hid_t f) { dataset(f, "/energy/kinetic", vls, {3}, words); }),
      "/energy/kinetic holds strings where numbers are expected");
  H5Tclose(vls);
  const double scalar = 0;
  expectRefused(edited("time-scalar.h5",
                       [&](hid_t f) { dataset(f, "/time", H5T_NATIVE_DOUBLE, {}, &scalar); }),
                "/time has 0 dimensions where 1 are expected");
  std::vector<double> wide(Frames * (Strands * PerStrand + 1) * 3, 0.0);
  expectRefused(edited("positions-wide.h5",
                       [&](hid_t f)
                       {
                         dataset(f, "/frames/positions", H5T_NATIVE_DOUBLE,
                                 {Frames, Strands * PerStrand + 1, 3}, wide.data());
                       }),
                "/frames/positions is [3, 7, 3] where [T, 6, 3] with T ≥ 3");
  std::vector<double> short2(2 * Strands * PerStrand * 3, 0.0);
  expectRefused(edited("velocities-short.h5",
                       [&](hid_t f)
                       {
                         dataset(f, "/frames/velocities", H5T_NATIVE_DOUBLE,
                                 {2, Strands * PerStrand, 3}, short2.data());
                       }),
                "/frames/velocities is [2, 6, 3]");
  expectRefused(edited("q-missing.h5", [&](hid_t f) { H5Ldelete(f, "/frames/q", H5P_DEFAULT); }),
                "/frames/q is missing (coordinates_per_strand is 6)");
  expectRefused(
      edited("kinetic-missing.h5", [&](hid_t f) { H5Ldelete(f, "/energy/kinetic", H5P_DEFAULT); }),
      "/energy/kinetic is missing");
  expectRefused(edited("energy-short.h5",
                       [&](hid_t f)
                       {
                         const double two[2] = {0, 0};
                         dataset(f, "/energy/elastic", H5T_NATIVE_DOUBLE, {2}, two);
                       }),
                "/energy/elastic is shorter than /time");
}

TEST(StateFileBadInput, DeclaredSizesBeyondTheFileAreRefusedBeforeAllocating)
{
  // A file of a few kilobytes that declares 10^8 points: the reader took 12.8 GB (issue 24).
  const std::int64_t offsets[2] = {0, 100000000};
  const std::string huge =
      edited("1e8-points.h5",
             [&](hid_t f)
             {
               dataset(f, "/strands/offsets", H5T_NATIVE_INT64, {2}, offsets);
               for (const char* d :
                    {"/strands/length", "/strands/rest_root", "/frames/q", "/frames/qdot",
                     "/frames/curvature", "/frames/root_frames", "/frames/root_velocities"})
               {
                 H5Ldelete(f, d, H5P_DEFAULT);
               }
               H5Adelete(f, "coordinates_per_strand");
               const int none = 0;
               attribute(f, "coordinates_per_strand", H5T_NATIVE_INT, -1, &none);
               // Chunked and never written: HDF5 stores nothing, and reads would give zeros.
               for (const char* d : {"/frames/positions", "/frames/velocities"})
               {
                 dataset(f, d, H5T_NATIVE_DOUBLE, {Frames, 100000000, 3}, nullptr, {1, 1000, 3},
                         {H5S_UNLIMITED, 100000000, 3});
               }
             });
  expectRefused(huge, "/frames/positions declares 7.2e+03 MB of values but the file has");
  // Offsets of 10^8 strands in a file of kilobytes.
  expectRefused(
      edited("1e8-strands.h5", [&](hid_t f)
             { dataset(f, "/strands/offsets", H5T_NATIVE_INT64, {100000001}, nullptr, {1024}); }),
      "/strands/offsets declares 800 MB of values but the file has");
  // Chunks of 10^6 frames each (never written, so the file stays small).
  expectRefused(edited("huge-chunks.h5",
                       [&](hid_t f)
                       {
                         dataset(f, "/frames/positions", H5T_NATIVE_DOUBLE,
                                 {Frames, Strands * PerStrand, 3}, nullptr,
                                 {1000000, Strands * PerStrand, 3},
                                 {H5S_UNLIMITED, Strands * PerStrand, 3});
                       }),
                "/frames/positions declares chunks of 144 MB");
}

TEST(StateFileBadInput, NonFiniteOrDecreasingTimesAreRefused)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expectRefused(edited("time-nan.h5", [&](hid_t f) { poke(f, "/time", 1, nan); }),
                "/time: the time of frame 1 is nan");
  expectRefused(edited("time-inf.h5", [&](hid_t f) { poke(f, "/time", 2, inf); }),
                "/time: the time of frame 2 is inf");
  expectRefused(edited("time-decreasing.h5", [&](hid_t f) { poke(f, "/time", 2, -1.0); }),
                "/time does not increase: frame 2 is at -1.000000 s, frame 1 at 0.033333 s");
  expectRefused(edited("time-repeated.h5", [&](hid_t f) { poke(f, "/time", 1, 0.0); }),
                "/time does not increase: frame 1");
  expectRefused(edited("length-nan.h5", [&](hid_t f) { poke(f, "/strands/length", 1, nan); }),
                "/strands/length holds a NaN or infinite value (strand 1)");
}

TEST(StateFileBadInput, AFrameWithNaNIsRefusedAndTheOthersRead)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Frame 1, point 4, y.
  const std::string path =
      edited("position-nan.h5",
             [&](hid_t f)
             {
               poke(f, "/frames/positions", (1 * Strands * PerStrand + 4) * 3 + 1, nan);
               poke(f, "/frames/q", 2 * Strands * Coordinates + 7, nan);
             });
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  StateFrame f;
  EXPECT_TRUE(r.readFrame(0, f).ok());
  Status s = r.readFrame(1, f);
  EXPECT_NE(s.message().find("frame 1 is damaged: the position of point 4 is NaN or infinite"),
            std::string::npos)
      << s.message();
  s = r.readFrame(2, f);
  EXPECT_NE(s.message().find("frame 2 is damaged: q of strand 1 is NaN or infinite"),
            std::string::npos)
      << s.message();
  EXPECT_NE(s.message().find(path), std::string::npos) << s.message();
}

/// A state file made version 2 (written by several MPI ranks, docs/state-file.md): the root
/// says so and `/whole_frames` counts `whole` whole frames (−1: no /whole_frames; `type`
/// and `dims` its type and shape).
std::string version2(const std::string& name, long long whole, hid_t type = H5T_NATIVE_INT64,
                     const std::vector<hsize_t>& dims = {})
{
  return edited(name,
                [&](hid_t f)
                {
                  const int two = 2;
                  attribute(f, "format_version", H5T_NATIVE_INT, -1, &two);
                  if (whole >= 0)
                  {
                    const std::vector<long long> values(dims.empty() ? 1 : dims[0], whole);
                    const std::vector<double> asDoubles(values.begin(), values.end());
                    dataset(f, "/whole_frames", type, dims,
                            type == H5T_NATIVE_DOUBLE ? static_cast<const void*>(asDoubles.data())
                                                      : values.data());
                  }
                });
}

TEST(StateFileBadInput, Version2ReadsItsWholeFramesOnly)
{
  // /time and the frames are as long as the run; /whole_frames = 2 of the 3: frame 2 is
  // not read, so its NaNs (a frame the ranks had not finished) are never seen.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string path = version2("v2-two.h5", 2);
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    poke(f, "/time", 2, nan);
    poke(f, "/frames/positions", (2 * Strands * PerStrand + 1) * 3, nan);
    H5Fclose(f);
  }
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  EXPECT_EQ(r.version(), 2);
  EXPECT_EQ(r.numberOfFrames(), 2);
  StateFrame whole, piece;
  ASSERT_TRUE(r.readFrame(1, whole).ok());
  ASSERT_TRUE(r.readPiece(1, {1}, piece).ok());
  ASSERT_EQ(piece.positions.size(), std::size_t(PerStrand));
  EXPECT_EQ(piece.positions[0], whole.positions[PerStrand]);
  EXPECT_FALSE(r.readFrame(2, whole).ok());
  EXPECT_FALSE(r.readPiece(2, {1}, piece).ok());
  // None whole yet (killed before the first frame's count): a file of no frames.
  StateFileReader none;
  ASSERT_TRUE(none.open(version2("v2-none.h5", 0)).ok());
  EXPECT_EQ(none.numberOfFrames(), 0);
}

TEST(StateFileBadInput, Version2WithoutAValidCountIsRefused)
{
  expectRefused(version2("v2-missing.h5", -1), "/whole_frames is missing");
  expectRefused(version2("v2-array.h5", 1, H5T_NATIVE_INT64, {2}),
                "/whole_frames is not one integer");
  expectRefused(version2("v2-double.h5", 1, H5T_NATIVE_DOUBLE), "/whole_frames is not one integer");
  expectRefused(edited("v2-negative.h5",
                       [&](hid_t f)
                       {
                         const int two = 2;
                         const long long negative = -5;
                         attribute(f, "format_version", H5T_NATIVE_INT, -1, &two);
                         dataset(f, "/whole_frames", H5T_NATIVE_INT64, {}, &negative);
                       }),
                "/whole_frames is -5, not a count of whole frames");
  expectRefused(version2("v2-beyond.h5", Frames + 1),
                "/whole_frames is " + std::to_string(Frames + 1) +
                    ", not a count of whole frames between 0 and the length of /time, " +
                    std::to_string(Frames));
  const int four = 4;
  expectRefused(
      edited("v4.h5", [&](hid_t f) { attribute(f, "format_version", H5T_NATIVE_INT, -1, &four); }),
      "has state-file format version 4; this HairDynamics reads versions 1, 2 and 3");
}

TEST(StateFileBadInput, APieceWithNaNIsRefused)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string path =
      edited("piece-nan.h5", [&](hid_t f)
             { poke(f, "/frames/positions", (1 * Strands * PerStrand + PerStrand + 2) * 3, nan); });
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  StateFrame f;
  EXPECT_TRUE(r.readPiece(1, {0}, f).ok()); // strand 0 of frame 1 is whole
  const Status s = r.readPiece(1, {1}, f);
  EXPECT_NE(s.message().find("frame 1 is damaged: the position of point 2 is NaN or infinite"),
            std::string::npos)
      << s.message();
}

TEST(StateFileBadInput, UnknownDatasetsAreSkipped)
{
  // A later format (or another helper's writer) may add datasets: the reader skips what it
  // does not know rather than refusing the file.
  const hid_t vls = variableString();
  const char* words[2] = {"a", "b"};
  const std::string path =
      edited("unknown.h5",
             [&](hid_t f)
             {
               dataset(f, "/strands/names", vls, {2}, words);
               const double m[4] = {1, 2, 3, 4};
               dataset(f, "/strands/matrix", H5T_NATIVE_DOUBLE, {2, 2}, m);
               H5Gclose(H5Gcreate2(f, "/frames/extra", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
               dataset(f, "/frames/labels", vls, {2}, words);
               dataset(f, "/other", H5T_NATIVE_DOUBLE, {4}, m);
             });
  H5Tclose(vls);
  expectRead(path);
  StateFileReader r;
  ASSERT_TRUE(r.open(path).ok());
  EXPECT_EQ(r.header().strandParameters.count("names"), 0u);
  EXPECT_EQ(r.header().pointData, std::vector<std::string>{"curvature"});
  EXPECT_TRUE(r.header().rootFrames);
}

TEST(StateFileBadInput, SpecialFilesAreRefusedBeforeHdf5SeesThem)
{
  // A FIFO made the reader wait for a writer for ever (issue 24).
  const std::string fifo = temp("fifo.h5");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  expectRefused(fifo, "is not a regular file (a pipe, a device or a socket)");
  std::remove(fifo.c_str());
  StateFileReader r;
  Status s = r.open("/dev/zero");
  EXPECT_NE(s.message().find("'/dev/zero' is not a regular file"), std::string::npos)
      << s.message();
  s = r.open(::testing::TempDir());
  EXPECT_NE(s.message().find("is a folder"), std::string::npos) << s.message();
  const std::string empty = temp("empty.h5");
  std::ofstream(empty).close();
  expectRefused(empty, "is not an HDF5 file");
}

TEST(StateFileBadInput, FlippedBytesAreRefusedOrReadNeverHang)
{
  // 200 copies of a real state file (one being written: its writer was never closed, as after
  // a crash, so it opens in SWMR mode with HDF5's metadata retries), each with 1 to 4 bytes
  // overwritten at seeded random places. Each must be refused or read within the test; before
  // the bounded retries about two thirds waited for minutes (issue 24). CTest's timeout is the
  // hang detector; the slowest open is printed.
  const std::string path = temp("swmr-source.h5");
  std::string bytes;
  {
    const StateHeader h = header();
    StateFileWriter w;
    ASSERT_TRUE(w.create(path, h).ok());
    for (int t = 0; t < Frames; ++t)
    {
      ASSERT_TRUE(w.append(frame(h, t)).ok());
    }
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::mt19937 random(24);
  int refused = 0, read = 0;
  double slowest = 0;
  for (int copy = 0; copy < 200; ++copy)
  {
    std::string damaged = bytes;
    const int flips = 1 + int(random() % 4);
    for (int k = 0; k < flips; ++k)
    {
      damaged[random() % damaged.size()] = char(random() % 256);
    }
    const std::string copyPath = temp("flipped.h5");
    std::ofstream(copyPath, std::ios::binary) << damaged;
    const auto start = std::chrono::steady_clock::now();
    StateFileReader r;
    Status s = r.open(copyPath);
    for (std::int64_t t = 0; s && t < r.numberOfFrames(); ++t)
    {
      StateFrame f;
      s = r.readFrame(t, f);
    }
    slowest = std::max(
        slowest, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    (s ? read : refused) += 1;
    // Nothing of the file left open by the reader, refused or not.
    EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0)
        << "copy " << copy << ": " << s.message();
    if (!s)
    {
      EXPECT_NE(s.message().find(copyPath), std::string::npos) << s.message();
    }
  }
  std::printf("flipped bytes: %d refused, %d read whole; slowest open and read %.3f s\n", refused,
              read, slowest);
  EXPECT_GT(refused, 0);
}

namespace
{
/// A global heap collection of `size` bytes (8-byte lengths) holding `objects` (index, size)
/// after its header, each object's data zeros padded to 8 bytes.
std::vector<unsigned char> collection(std::uint64_t size,
                                      const std::vector<std::pair<int, std::uint64_t>>& objects)
{
  std::vector<unsigned char> c(std::max<std::uint64_t>(size, 16), 0);
  std::memcpy(c.data(), "GCOL", 4);
  c[4] = 1;
  auto put = [&](std::size_t at, std::uint64_t v, int bytes)
  {
    for (int k = 0; k < bytes && at + k < c.size(); ++k)
    {
      c[at + k] = static_cast<unsigned char>(v >> (8 * k));
    }
  };
  put(8, size, 8);
  std::size_t at = 16;
  for (const auto& [index, bytes] : objects)
  {
    put(at, std::uint64_t(index), 2);
    put(at + 8, bytes, 8);
    at += index > 0 ? 16 + ((bytes + 7) & ~std::uint64_t(7)) : bytes;
  }
  return c;
}

bool decodable(const std::vector<unsigned char>& c)
{
  return hdf5::checkGlobalHeapCollection(c.data(), c.size()).ok();
}
} // namespace

TEST(StateFileBadInput, GlobalHeapCollectionsAreCheckedAsHdf5WalksThem)
{
  // The layout of HDF5's File Format Specification 3.0, III.E: a 16-byte header, objects of
  // a 16-byte header and data padded to 8 bytes, the free space (object 0) counting its header.
  EXPECT_TRUE(decodable(collection(4096, {{1, 19}, {2, 11}, {0, 4096 - 16 - 40 - 32}})));
  EXPECT_TRUE(decodable(collection(64, {{1, 32}})));            // full: no free space
  EXPECT_TRUE(decodable(collection(64, {{1, 24}})));            // 8 bytes left: too short to be one
  EXPECT_FALSE(decodable(collection(4096, {{1, 19}, {0, 0}}))); // HDF5 1.10.8 loops on it
  EXPECT_FALSE(decodable(collection(4096, {{1, 19}, {0, 8}}))); // shorter than its header
  EXPECT_FALSE(decodable(collection(4096, {{1, 4096}})));       // runs past the collection
  EXPECT_FALSE(decodable(collection(4096, {{1, ~std::uint64_t(0) - 3}}))); // wraps around
  EXPECT_FALSE(decodable(collection(4096, {{1, 19}, {0, 8192}})));
  std::vector<unsigned char> cut = collection(4096, {{0, 4080}});
  cut.resize(2048); // the declared size is not all given
  EXPECT_FALSE(hdf5::checkGlobalHeapCollection(cut.data(), cut.size()).ok());
  const unsigned char notOne[32] = "GCOX";
  EXPECT_TRUE(hdf5::checkGlobalHeapCollection(notOne, sizeof(notOne)).ok());
}

TEST(StateFileBadInput, ADamagedGlobalHeapIsRefusedNotLoopedOn)
{
  // The strings `format` and `model` live in the file's global heap. A fuzzed file whose
  // free-space object had size 0 made H5Aread loop for ever inside HDF5 1.10.8 (CI's fuzzer,
  // Testing/Fuzz/regressions/timeout-global-heap-free-space-zero); the checked driver now
  // refuses the read. Each open runs in a child process with a 20-s alarm, so that a hang
  // fails this test instead of stalling it.
  const std::string path = stateFile("heap-source.h5");
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::size_t heap = bytes.find("GCOL\x01", 0, 5);
  ASSERT_NE(heap, std::string::npos) << "the writer's strings are variable-length";
  auto u64 = [&](std::size_t at)
  {
    std::uint64_t v = 0;
    std::memcpy(&v, bytes.data() + at, 8);
    return v;
  };
  auto set = [](std::string& b, std::size_t at, std::uint64_t v) { std::memcpy(&b[at], &v, 8); };
  // Walk to the free-space object as HDF5 would.
  const std::uint64_t size = u64(heap + 8);
  std::size_t at = heap + 16, freeSpace = 0;
  while (at + 16 <= heap + size)
  {
    const int index = static_cast<unsigned char>(bytes[at]) | (bytes[at + 1] << 8);
    if (index == 0)
    {
      freeSpace = at;
      break;
    }
    at += 16 + ((u64(at + 8) + 7) & ~std::uint64_t(7));
  }
  ASSERT_GT(freeSpace, 0u);
  const std::size_t firstObject = heap + 16;

  std::vector<std::pair<std::string, std::string>> cases;
  cases.push_back({"heap-free-zero.h5", bytes});
  set(cases.back().second, freeSpace + 8, 0);
  cases.push_back({"heap-object-long.h5", bytes});
  set(cases.back().second, firstObject + 8, size);
  cases.push_back({"heap-past-end.h5", bytes});
  set(cases.back().second, heap + 8, 1u << 30);
  cases.push_back({"heap-free-zero-large.h5", bytes}); // declared larger than its 4 KiB read
  set(cases.back().second, heap + 8, bytes.size() - heap);
  set(cases.back().second, freeSpace + 8, 0);
  for (const auto& [name, content] : cases)
  {
    const std::string copy = temp(name);
    std::ofstream(copy, std::ios::binary) << content;
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0)
    {
      alarm(20);
      StateFileReader r;
      const Status s = r.open(copy);
      std::printf("%s: %s\n", name.c_str(), s ? "read" : s.message().c_str());
      std::fflush(stdout);
      _exit(!s && s.message().find(copy) != std::string::npos ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status)) << name << ": the open did not end (signal "
                                   << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << name << " was not refused";
  }
  expectRead(path); // the undamaged file still reads through the checked driver
}

TEST(StateFileBadInput, DamagedFilesOfMpiRanksAreRefusedNotCrashedOn)
{
  // Files written by MPI ranks together (version 1 object headers, no checksum) with one byte
  // changed, as Scripts/hostile_files.py found them (Testing/Fuzz/regressions/). Before the
  // checks, HDF5 1.10.8 crashed or spent 18-43 s on each (the last under the sanitizers);
  // each open runs in a child process with a 20-s alarm, so that a crash or a hang fails
  // this test instead of ending it.
  struct Damage
  {
    const char* source;
    std::size_t at;
    unsigned char was, now;
    const char* refusal;
  };
  const Damage damages[] = {
      // The flags of a root attribute's message (after coordinates_per_strand) made
      // "shared": its decode fails in the middle of H5Aiterate2's table of attributes.
      {"v3-shared-super-helix.h5", 0x4a4, 0x00, 0x13, "the root's attributes cannot be listed"},
      // The heap object index of `format`'s value, 1, made 0x3c000001.
      {"v3-shared-super-helix.h5", 0x37f, 0x00, 0x3c, "HDF5 cannot open it"},
      // The length of `model`'s value, 11, made 0x8400000b (2.2 GB cleared by HDF5).
      {"v2-super-helix.h5", 0x3fb, 0x00, 0x84, "HDF5 cannot open it"},
      // The length of the root header's continuation chunk, 1224, made 0xff0004c8: 4 GB
      // allocated by HDF5 on each of 24 read attempts (43 s under AddressSanitizer).
      {"v3-shared-super-helix.h5", 0x83, 0x00, 0xff, "HDF5 cannot open it"},
  };
  for (const Damage& d : damages)
  {
    const std::string source = std::string(HAIR_STATE_FILES_DIR) + "/" + d.source;
    std::string bytes;
    {
      std::ifstream in(source, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ASSERT_GT(bytes.size(), d.at);
    ASSERT_EQ(static_cast<unsigned char>(bytes[d.at]), d.was) << d.source << " changed";
    {
      StateFileReader intact;
      const Status s = intact.open(source);
      ASSERT_TRUE(s.ok()) << s.message();
    }
    bytes[d.at] = static_cast<char>(d.now);
    const std::string copy = temp("mpi-damaged.h5");
    std::ofstream(copy, std::ios::binary) << bytes;
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0)
    {
      alarm(20);
      StateFileReader r;
      const Status s = r.open(copy);
      std::printf("%s, byte %zu: %s\n", d.source, d.at, s ? "read" : s.message().c_str());
      std::fflush(stdout);
      _exit(!s && s.message().find(copy) != std::string::npos &&
                    s.message().find(d.refusal) != std::string::npos
                ? 0
                : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status))
        << d.source << ", byte " << d.at << ": the open did not end "
        << "(signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0)
        << d.source << ", byte " << d.at << " was not refused as expected";
  }
}

TEST(StateFileBadInput, TwoReadersOfOneFileSeeItsNewFrames)
{
  // Issue 24: the second Hair State Reader of a file stayed at the frames it first saw, even
  // after Reload Files and after the writer finished: HDF5 shares one open file between the
  // handles of a process, with the metadata of its first open. The writer here is another
  // process (as a run elsewhere is): it writes 2 frames, waits, writes 2 more and finishes.
  const std::string path = temp("growing.h5");
  int toParent[2], toChild[2];
  ASSERT_EQ(pipe(toParent), 0);
  ASSERT_EQ(pipe(toChild), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0)
  {
    const StateHeader h = header();
    StateFileWriter w;
    char c = 'x';
    bool ok = w.create(path, h).ok() && w.append(frame(h, 0)).ok() && w.append(frame(h, 1)).ok();
    ok = ok && write(toParent[1], &c, 1) == 1 && read(toChild[0], &c, 1) == 1;
    ok = ok && w.append(frame(h, 2)).ok() && w.append(frame(h, 3)).ok() && w.close().ok();
    _exit(ok ? 0 : 1);
  }
  char c = 'x';
  ASSERT_EQ(read(toParent[0], &c, 1), 1);
  StateFileReader a, b;
  ASSERT_TRUE(a.open(path).ok());
  ASSERT_TRUE(b.open(path).ok());
  EXPECT_EQ(a.numberOfFrames(), 2);
  EXPECT_EQ(b.numberOfFrames(), 2);
  ASSERT_EQ(write(toChild[1], &c, 1), 1);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  // Each opened again (Reload Files) while the other is open too.
  ASSERT_TRUE(a.open(path).ok());
  EXPECT_EQ(a.numberOfFrames(), 4);
  ASSERT_TRUE(b.open(path).ok());
  EXPECT_EQ(b.numberOfFrames(), 4);
  StateFrame f;
  ASSERT_TRUE(b.readFrame(3, f).ok());
  EXPECT_EQ(f.positions[1], frame(header(), 3).positions[1]);
}

TEST(StateFileBadInput, NoHdf5HandleIsLeftOpen)
{
  // After reads and refusals of every kind (CTest runs each test in its own process, so this
  // one makes its own): no file, group, dataset, datatype or attribute of HDF5's left open by
  // the reader or the writer (a leaked handle keeps a file open and memory held for the rest
  // of a ParaView session).
  expectRead(stateFile("left-open-good.h5"));
  const int number = 1;
  expectRefused(edited("left-open-format.h5",
                       [&](hid_t f) { attribute(f, "format", H5T_NATIVE_INT, -1, &number); }),
                "'format' is an integer");
  expectRefused(edited("left-open-q.h5", [&](hid_t f) { H5Ldelete(f, "/frames/q", H5P_DEFAULT); }),
                "/frames/q is missing");
  expectRefused(edited("left-open-time.h5", [&](hid_t f) { poke(f, "/time", 2, -1.0); }),
                "/time does not increase");
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  // The count sees an open file (the check can fail).
  const std::string path = stateFile("count.h5");
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 1);
  H5Fclose(f);
}

TEST(StateFileBadInput, ADatasetWithoutItsValuesInTheFileIsRefused)
{
  // A contiguous dataset whose storage does not hold its values: here never written (HDF5
  // allocates it late), as a damaged layout message may also say (the fuzzer's
  // crash-compact-layout-size-zero: a compact layout of 0 bytes for 96, which HDF5 1.10.8
  // read past its buffer). Refused before any value is read.
  const hsize_t points = Strands * PerStrand;
  expectRefused(
      edited("unwritten-positions.h5",
             [&](hid_t f) {
               dataset(f, "/frames/positions", H5T_NATIVE_DOUBLE, {Frames, points, 3}, nullptr);
             }),
      "/frames/positions: the space it has in the file does not hold its values");
}

namespace
{
/// A version 1 object header's attribute message (File Format Specification 3.0, IV.A.2.m,
/// version 1: each part padded to 8 bytes) holding `values` 4-byte integers in a dataspace of
/// rank 1, its 8-byte message header first.
std::vector<unsigned char> attributeMessage(std::uint32_t values, std::uint16_t spaceBytes = 16)
{
  std::vector<unsigned char> d = {1, 0, 2, 0, 12, 0, 0, 0, 'n', 0, 0, 0, 0, 0, 0, 0};
  d[6] = static_cast<unsigned char>(spaceBytes);
  d[7] = static_cast<unsigned char>(spaceBytes >> 8);
  const unsigned char type[16] = {0x10, 0x08, 0, 0, 4, 0, 0, 0, 0, 0, 32, 0}; // 32-bit integer
  d.insert(d.end(), type, type + 16);
  unsigned char space[16] = {1, 1, 0, 0, 0, 0, 0, 0}; // version 1, rank 1, then the extent
  std::memcpy(space + 8, &values, 4);
  d.insert(d.end(), space, space + 16);
  d.resize(d.size() + 4 * std::size_t(values));
  d.resize((d.size() + 7) & ~std::size_t(7));
  // The header, then d: built in one buffer of the final size (GCC 12 warns of a
  // -Wstringop-overread, wrongly, when a vector of 8 bytes is grown by insert).
  std::vector<unsigned char> m(8 + d.size(), 0);
  m[0] = 0x0C; // attribute
  m[2] = static_cast<unsigned char>(d.size());
  m[3] = static_cast<unsigned char>(d.size() >> 8);
  std::copy(d.begin(), d.end(), m.begin() + 8);
  return m;
}

bool messagesDecodable(const std::vector<unsigned char>& m)
{
  return hdf5::checkObjectHeaderMessages(m.data(), m.size()).ok();
}
} // namespace

TEST(StateFileBadInput, Version1ObjectHeaderMessagesAreCheckedAsHdf5DecodesThem)
{
  // HDF5 1.10.8 decodes an attribute message with the sizes its fields declare; CI's fuzzer
  // found a file whose dataspace size field said 2048 where 8 bytes were there, and HDF5
  // copied the value from 928 bytes past its buffer (Testing/Fuzz/regressions/
  // crash-v1-attribute-dataspace-size).
  EXPECT_TRUE(messagesDecodable(attributeMessage(1)));
  EXPECT_TRUE(messagesDecodable(attributeMessage(5)));
  EXPECT_FALSE(messagesDecodable(attributeMessage(1, 2048))); // the fuzzer's
  std::vector<unsigned char> m = attributeMessage(3);
  std::uint32_t more = 1000;                // values past the message
  std::memcpy(m.data() + 8 + 40, &more, 4); // the extent, after the 8-byte space header
  EXPECT_FALSE(messagesDecodable(m));
  m = attributeMessage(1);
  m[8 + 8] = 'x'; // a name without its terminating zero
  m[8 + 9] = 'y';
  EXPECT_FALSE(messagesDecodable(m));
  m = attributeMessage(1);
  m[8 + 4] = 200; // a datatype running past the message
  EXPECT_FALSE(messagesDecodable(m));
  m = attributeMessage(1);
  m[8 + 32 + 1] = 33; // rank above HDF5's 32
  EXPECT_FALSE(messagesDecodable(m));
  m = attributeMessage(1);
  m[4] = 0x02; // shared: a reference HDF5 reads on its own
  m[8 + 6] = 0xff;
  EXPECT_TRUE(messagesDecodable(m));
  m = attributeMessage(1);
  m[0] = 0x03; // a datatype message: left to HDF5
  m[8 + 6] = 0xff;
  EXPECT_TRUE(messagesDecodable(m));
  m = attributeMessage(1);
  m.resize(m.size() - 8); // a message longer than the bytes given: HDF5 checks it itself
  EXPECT_TRUE(messagesDecodable(m));
}

namespace sf = stateformat;

TEST(StateFileBadInput, ADamagedVersion1AttributeIsRefusedNotOverread)
{
  // A file in HDF5's default (earliest) format, as h5py and the C library write by default:
  // version 1 object headers, no checksums.
  const std::string path = temp("v1-header.h5");
  {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t text = H5Tcopy(H5T_C_S1);
    H5Tset_size(text, std::strlen(sf::Name));
    const hid_t a = H5Acreate2(f, sf::FormatAttribute, text, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, text, sf::Name);
    H5Aclose(a);
    const int version = sf::Version;
    const hid_t b =
        H5Acreate2(f, sf::VersionAttribute, H5T_STD_I32LE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(b, H5T_NATIVE_INT, &version);
    H5Aclose(b);
    H5Tclose(text);
    H5Sclose(scalar);
    H5Fclose(f);
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // The version attribute's message: its name follows the 8 bytes of the message's fields.
  const std::size_t name = bytes.find(std::string(sf::VersionAttribute) + '\0');
  ASSERT_NE(name, std::string::npos);
  ASSERT_EQ(bytes[name - 8], 1) << "a version 1 attribute message";
  const auto open = [](const std::string& file)
  {
    StateFileReader r;
    return r.open(file);
  };
  const Status intact = open(path);
  ASSERT_FALSE(intact.ok()); // no datasets: refused, but past the attributes
  EXPECT_EQ(intact.message().find("cannot be read"), std::string::npos) << intact.message();

  std::string damaged = bytes;
  damaged[name - 2] = 0; // the dataspace's size, 8 bytes, declared 2048
  damaged[name - 1] = 8;
  const std::string copy = temp("v1-header-sized.h5");
  std::ofstream(copy, std::ios::binary) << damaged;
  const Status s = open(copy);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(copy), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("is damaged"), std::string::npos) << s.message();
}
