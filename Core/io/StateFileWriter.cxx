// StateFileWriter (StateFile.h): creates the layout that StateFormat.h names, and appends
// frames in an order that leaves a killed run's file readable up to its last whole frame.
#include "io/StateFile.h"

#include "io/Hdf5.h"
#include "io/StateFormat.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>

namespace hair
{

using namespace hdf5;
namespace sf = stateformat;

namespace
{
bool finite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Creates (truncates) the file; an invalid handle if it cannot.
Handle createFile(const std::string& path)
{
  Handle file;
  H5E_BEGIN_TRY
  {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    // The latest format is what single-writer/multiple-reader mode needs.
    H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    file = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  }
  H5E_END_TRY;
  return file;
}

/// The root's attributes: the format, its version, the model, and the run attributes.
Status writeRootAttributes(hid_t f, const StateHeader& header)
{
  Status s = writeStringAttribute(f, sf::FormatAttribute, sf::Name);
  if (s)
  {
    s = writeScalarAttribute<int>(f, sf::VersionAttribute, H5T_NATIVE_INT, sf::Version);
  }
  if (s)
  {
    s = writeStringAttribute(f, sf::ModelAttribute, header.model);
  }
  if (s)
  {
    s = writeScalarAttribute<int>(f, sf::CoordinatesAttribute, H5T_NATIVE_INT,
                                  header.coordinatesPerStrand);
  }
  for (const auto& [name, value] : header.attributes)
  {
    if (s)
    {
      s = writeScalarAttribute<double>(f, name.c_str(), H5T_NATIVE_DOUBLE, value);
    }
  }
  return s;
}

/// One dataset [S, 3] of /strands per strand vector.
Status writeStrandVectors(hid_t strands, const StateHeader& header)
{
  for (const auto& [name, values] : header.strandVectors)
  {
    if (!writeRows(strands, name.c_str(), values.size(), 3,
                   values.empty() ? nullptr : values[0].data()))
    {
      return Status::Error("cannot write " + sf::inGroup(sf::Strands, name) + ".");
    }
  }
  return Status::Ok();
}

/// The growing root datasets of /frames, when the header asks for them.
bool createRootFrames(hid_t frames, const StateHeader& header, Handle& poses, Handle& rates)
{
  if (!header.rootFrames)
  {
    return true;
  }
  const hsize_t strands = header.numberOfStrands();
  poses = createGrowing(frames, sf::RootFrames, {strands, hsize_t(RootFrameValues)});
  rates = createGrowing(frames, sf::RootVelocities, {strands, hsize_t(RootVelocityValues)});
  return poses.valid() && rates.valid();
}

/// /strands: the offsets, then one dataset per strand parameter and per strand vector.
Status writeStrands(hid_t strands, const StateHeader& header)
{
  if (!writeArray(strands, sf::Offsets, H5T_NATIVE_INT64, header.offsets.size(),
                  header.offsets.data()))
  {
    return Status::Error(std::string("cannot write ") + sf::Offsets + ".");
  }
  for (const auto& [name, values] : header.strandParameters)
  {
    if (!writeArray(strands, name.c_str(), H5T_NATIVE_DOUBLE, values.size(), values.data()))
    {
      return Status::Error("cannot write " + sf::inGroup(sf::Strands, name) + ".");
    }
  }
  return writeStrandVectors(strands, header);
}

/// One growing dataset of /frames per per-point scalar.
Status createPointData(hid_t frames, const StateHeader& header,
                       std::map<std::string, Handle>& datasets)
{
  const hsize_t points = header.numberOfPoints();
  for (const std::string& name : header.pointData)
  {
    if (sf::isFrameDataset(name) || datasets.count(name))
    {
      return Status::Error("the per-point array name '" + name + "' is reserved or repeated.");
    }
    datasets[name] = createGrowing(frames, name.c_str(), {points});
    if (!datasets[name].valid())
    {
      return Status::Error("cannot create " + sf::inGroup(sf::Frames, name) + ".");
    }
  }
  return Status::Ok();
}

/// One growing dataset of /energy per term: the required ones and `extraTerms`.
Status createEnergy(hid_t energy, const std::vector<std::string>& extraTerms,
                    std::map<std::string, Handle>& datasets)
{
  std::vector<std::string> terms(std::begin(RequiredEnergyTerms), std::end(RequiredEnergyTerms));
  for (const auto& t : extraTerms)
  {
    if (std::find(terms.begin(), terms.end(), t) == terms.end())
    {
      terms.push_back(t);
    }
  }
  for (const auto& t : terms)
  {
    datasets[t] = createGrowing(energy, t.c_str(), {});
    if (!datasets[t].valid())
    {
      return Status::Error("cannot create " + sf::inGroup(sf::Energy, t) + ".");
    }
  }
  return Status::Ok();
}
} // namespace

struct StateFileWriter::Impl
{
  Handle File, Time, Positions, Velocities, Q, QDot, RootFrames, RootVelocities;
  std::map<std::string, Handle> PointData;
  std::map<std::string, Handle> Energy;
  StateHeader Header;
  std::string Path;
  hsize_t Frames = 0;
};

StateFileWriter::StateFileWriter() : P(std::make_unique<Impl>()) {}
StateFileWriter::~StateFileWriter()
{
  close();
}
bool StateFileWriter::isOpen() const
{
  return P->File.valid();
}
std::int64_t StateFileWriter::numberOfFrames() const
{
  return std::int64_t(P->Frames);
}

Status StateFileWriter::create(const std::string& path, const StateHeader& header,
                               const std::vector<std::string>& extraEnergyTerms, Existing existing)
{
  close();
  if (Status s = header.validate(); !s)
  {
    return s;
  }
  auto fail = [&](const std::string& what)
  {
    P = std::make_unique<Impl>();
    return Status::Error("the state file '" + path + "': " + what);
  };
  struct stat info;
  if (::stat(path.c_str(), &info) == 0)
  {
    if (!S_ISREG(info.st_mode))
    {
      return fail("exists and is not a regular file: not written over; choose another name.");
    }
    StateFileReader old;
    if (Status s = old.open(path); !s)
    {
      return fail("exists and is not a HairDynamics state file that can be read (" + s.message() +
                  "), or another run is writing it: it is not written over; choose another "
                  "name.");
    }
    if (existing != Existing::ReplaceStateFile)
    {
      return fail("exists (a state file of " + std::to_string(old.numberOfFrames()) +
                  " frames): it is kept; choose another name, or allow the run to replace it "
                  "(Hair Simulation's Overwrite State File).");
    }
  }
  P->File = createFile(path);
  if (!P->File.valid())
  {
    return fail("cannot be created: check that its folder exists and is writable, and that no "
                "other run is writing the same file.");
  }
  // HDF5's error stack is never printed: each failure is returned as a message.
  Status made = Status::Ok();
  H5E_BEGIN_TRY
  {
    made = [&]() -> Status
    {
      P->Header = header;
      P->Path = path;
      const hid_t f = P->File.get();
      if (Status s = writeRootAttributes(f, header); !s)
      {
        return fail(s.message());
      }
      Handle strands(H5Gcreate2(f, sf::Strands, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      Handle frames(H5Gcreate2(f, sf::Frames, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      Handle energy(H5Gcreate2(f, sf::Energy, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      if (Status s = writeStrands(strands.get(), header); !s)
      {
        return fail(s.message());
      }
      const hsize_t points = header.numberOfPoints(), strandCount = header.numberOfStrands();
      P->Time = createGrowing(f, sf::Time, {});
      P->Positions = createGrowing(frames.get(), sf::Positions, {points, 3});
      P->Velocities = createGrowing(frames.get(), sf::Velocities, {points, 3});
      if (header.coordinatesPerStrand > 0)
      {
        const hsize_t c = hsize_t(header.coordinatesPerStrand);
        P->Q = createGrowing(frames.get(), sf::Q, {strandCount, c});
        P->QDot = createGrowing(frames.get(), sf::QDot, {strandCount, c});
      }
      if (!createRootFrames(frames.get(), header, P->RootFrames, P->RootVelocities))
      {
        return fail("cannot create the root datasets.");
      }
      if (Status s = createPointData(frames.get(), header, P->PointData); !s)
      {
        return fail(s.message());
      }
      if (Status s = createEnergy(energy.get(), extraEnergyTerms, P->Energy); !s)
      {
        return fail(s.message());
      }
      if (!P->Time.valid() || !P->Positions.valid() || !P->Velocities.valid() ||
          (header.coordinatesPerStrand > 0 && (!P->Q.valid() || !P->QDot.valid())))
      {
        return fail("cannot create the per-frame datasets.");
      }
      strands.reset();
      frames.reset();
      energy.reset();
      return Status::Ok();
    }();
  }
  H5E_END_TRY;
  if (!made)
  {
    return made;
  }
  herr_t swmr;
  H5E_BEGIN_TRY
  {
    swmr = H5Fstart_swmr_write(P->File.get());
  }
  H5E_END_TRY;
  if (swmr < 0)
  {
    return fail("cannot start single-writer/multiple-reader mode.");
  }
  return Status::Ok();
}

Status StateFileWriter::append(const StateFrame& frame)
{
  if (!P->File.valid())
  {
    return Status::Error("the state file is not open: create it first.");
  }
  const StateHeader& h = P->Header;
  const std::string where = "the state file '" + P->Path + "', frame " + std::to_string(P->Frames) +
                            " (t = " + std::to_string(frame.time) + " s): ";
  if (frame.positions.size() != h.numberOfPoints() || frame.velocities.size() != h.numberOfPoints())
  {
    return Status::Error(where + "expected " + std::to_string(h.numberOfPoints()) +
                         " positions and velocities, got " +
                         std::to_string(frame.positions.size()) + " and " +
                         std::to_string(frame.velocities.size()) + ".");
  }
  const std::size_t nq = h.numberOfStrands() * std::size_t(h.coordinatesPerStrand);
  if (frame.q.size() != nq || frame.qdot.size() != nq)
  {
    return Status::Error(where + "expected " + std::to_string(nq) + " values of q and qdot.");
  }
  const std::size_t roots = h.rootFrames ? h.numberOfStrands() : 0;
  if (frame.rootFrames.size() != roots * RootFrameValues ||
      frame.rootVelocities.size() != roots * RootVelocityValues)
  {
    return Status::Error(where + "expected " + std::to_string(roots) +
                         " root frames and velocities.");
  }
  auto flat = [](const std::vector<Eigen::Vector3d>& v)
  {
    std::vector<double> out(3 * v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
    {
      out[3 * i] = v[i].x();
      out[3 * i + 1] = v[i].y();
      out[3 * i + 2] = v[i].z();
    }
    return out;
  };
  const std::vector<double> pos = flat(frame.positions), vel = flat(frame.velocities);
  if (!std::isfinite(frame.time) || !finite(pos) || !finite(vel) || !finite(frame.q) ||
      !finite(frame.qdot) || !finite(frame.rootFrames) || !finite(frame.rootVelocities))
  {
    return Status::Error(
        where + "NaN or infinite values: the frame is not written, the frames before it are kept.");
  }
  for (const auto& [name, dataset] : P->PointData)
  {
    const auto it = frame.pointData.find(name);
    if (it == frame.pointData.end() || it->second.size() != h.numberOfPoints() ||
        !finite(it->second))
    {
      return Status::Error(where + "the per-point array '" + name +
                           "' is missing, of the "
                           "wrong size, or not finite.");
    }
  }
  for (const auto& [name, value] : frame.energy)
  {
    if (P->Energy.find(name) == P->Energy.end())
    {
      return Status::Error(where + "the energy term '" + name +
                           "' was not declared when the file was created.");
    }
  }
  const hsize_t t = P->Frames;
  bool ok = true;
  H5E_BEGIN_TRY
  {
    ok = appendSlab(P->Positions.get(), t, pos.data()) &&
         appendSlab(P->Velocities.get(), t, vel.data());
    if (ok && h.coordinatesPerStrand > 0)
    {
      ok = appendSlab(P->Q.get(), t, frame.q.data()) &&
           appendSlab(P->QDot.get(), t, frame.qdot.data());
    }
    if (ok && h.rootFrames)
    {
      ok = appendSlab(P->RootFrames.get(), t, frame.rootFrames.data()) &&
           appendSlab(P->RootVelocities.get(), t, frame.rootVelocities.data());
    }
    for (auto& [name, dataset] : P->PointData)
    {
      ok = ok && appendSlab(dataset.get(), t, frame.pointData.at(name).data());
    }
    for (auto& [name, dataset] : P->Energy)
    {
      if (ok)
      {
        const auto it = frame.energy.find(name);
        const double value = it == frame.energy.end() ? 0.0 : it->second;
        ok = appendSlab(dataset.get(), t, &value);
      }
    }
    // The frame's data reach the disk before /time names the frame: /time's length is the
    // number of whole frames.
    ok = ok && H5Fflush(P->File.get(), H5F_SCOPE_GLOBAL) >= 0;
    ok = ok && appendSlab(P->Time.get(), t, &frame.time);
    ok = ok && H5Fflush(P->File.get(), H5F_SCOPE_GLOBAL) >= 0;
  }
  H5E_END_TRY;
  if (!ok)
  {
    return Status::Error(where + "writing failed (is the disk full?); the frames before it are "
                                 "kept.");
  }
  ++P->Frames;
  return Status::Ok();
}

Status StateFileWriter::close()
{
  if (!P->File.valid())
  {
    return Status::Ok();
  }
  P->Energy.clear();
  P->PointData.clear();
  P->Time.reset();
  P->Positions.reset();
  P->Velocities.reset();
  P->Q.reset();
  P->QDot.reset();
  P->RootFrames.reset();
  P->RootVelocities.reset();
  P->File.reset();
  P->Frames = 0;
  return Status::Ok();
}

} // namespace hair
